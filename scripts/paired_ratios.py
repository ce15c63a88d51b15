#!/usr/bin/env python3
"""scripts/paired_ratios.py: medians of paired ratios from scripts/ray_rates.sh output.

    scripts/paired_ratios.py BASE NEW run1.txt [run2.txt ...]

For each scene, the ratio NEW / BASE of the path tracer's Mrays/s within each round (both binaries ran in that
round, minutes apart at most), pooled over the files given: median and quartiles, and each binary's median rate
and fraction of Embree's rate on its own ray mix. Rounds of one file pair with rounds of the same file only.
"""
import collections
import statistics
import sys


def main(argv):
    if len(argv) < 4:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    base, new, files = argv[1], argv[2], argv[3:]
    rounds = collections.defaultdict(dict)  # (file, scene, round) -> name -> (mrays, fraction)
    order = []
    for f in files:
        with open(f) as fh:
            for line in fh:
                t = line.split()
                if len(t) != 8:
                    continue  # a bench that failed prints no figures
                r, scene, name = t[0], t[1], t[2]
                rounds[(f, scene, r)][name] = (float(t[3]), float(t[5]))
                if scene not in order:
                    order.append(scene)
    for scene in order:
        pairs = [v for k, v in rounds.items() if k[1] == scene and base in v and new in v]
        if not pairs:
            continue
        ratios = sorted(v[new][0] / v[base][0] for v in pairs)
        q = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else [ratios[0]] * 3
        med = statistics.median
        print(f"{scene}: {len(pairs)} rounds, {new} / {base} = {med(ratios):.3f} (quartiles {q[0]:.3f}-{q[2]:.3f}); "
              f"{base} {med(v[base][0] for v in pairs):.2f} Mrays/s at {med(v[base][1] for v in pairs):.3f} of Embree, "
              f"{new} {med(v[new][0] for v in pairs):.2f} at {med(v[new][1] for v in pairs):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
