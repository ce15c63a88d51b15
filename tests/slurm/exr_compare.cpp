// tests/slurm/exr_compare.cpp: `pathview_exr_compare A.exr B.exr [REL]`: exit 0 if both images have the same size
// and every R, G, B value agrees within REL (default 1e-6) relative to the larger of the two; prints the largest
// difference and the count of bit-identical values. For the scripted tests (tests/slurm/run.sh).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/base/error.h"
#include "core/image/image_io.h"

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: pathview_exr_compare A.exr B.exr [REL]\n");
        return 2;
    }
    try {
        const pv::Image a = pv::read_exr(argv[1]), b = pv::read_exr(argv[2]);
        const double rel = argc > 3 ? std::atof(argv[3]) : 1e-6;
        if (a.width != b.width || a.height != b.height) {
            std::fprintf(stderr, "pathview_exr_compare: %dx%d against %dx%d\n", a.width, a.height, b.width, b.height);
            return 1;
        }
        double worst = 0.0;
        size_t identical = 0;
        for (size_t i = 0; i < a.rgb.size(); ++i) {
            const double x = a.rgb[i], y = b.rgb[i], scale = std::max(std::fabs(x), std::fabs(y));
            identical += a.rgb[i] == b.rgb[i];
            if (std::isnan(x) || std::isnan(y))
                worst = INFINITY;
            else if (scale > 0.0)
                worst = std::max(worst, std::fabs(x - y) / scale);
        }
        std::printf("pathview_exr_compare: %zu of %zu values bit-identical, largest relative difference %.3g\n",
                    identical, a.rgb.size(), worst);
        return worst <= rel ? 0 : 1;
    } catch (const pv::Error& e) {
        std::fprintf(stderr, "pathview_exr_compare: %s\n", e.what());
        return 1;
    }
}
