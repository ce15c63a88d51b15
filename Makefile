# pathview: the two set-up commands of README.md.
#   make run   installs what is missing, builds Release, opens the viewer on the built-in Cornell box
#              (with no display: says so and renders the Cornell box headless).
#   make test  installs what is missing, builds, runs every test (ctest), then the sanitizer suites and the fuzzer.
SHELL := /bin/bash
BUILD ?= build
JOBS ?= $(shell nproc)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian 12 packages: build, libraries, and the tools the GUI tests use.
PACKAGES := build-essential cmake pkg-config ccache libglfw3-dev libimgui-dev libstb-dev libgl-dev \
  libembree-dev libtbb-dev libglm-dev libtinyobjloader-dev libopenexr-dev libgtest-dev libbenchmark-dev \
  libcli11-dev nlohmann-json3-dev libjpeg62-turbo-dev libpng-dev openexr xvfb xauth libgl1-mesa-dri xdotool imagemagick x11-apps \
  clang libclang-rt-14-dev clang-format libeigen3-dev libtinygltf-dev shellcheck \
  libopencolorio-dev libdraco-dev libmeshoptimizer-dev gltfpack libwebp-dev

CMAKE_FLAGS := -DCMAKE_BUILD_TYPE=Release -DPATHVIEW_WERROR=ON
# ccache: paths below the project are hashed relative to it, so a fresh clone (CI) reuses earlier compilations.
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1

.PHONY: deps build run test format-check format test-slurm test-release test-sanitize build-asan-fuzz test-asan test-tsan test-fuzz bench benchmarks clean

deps:
	@missing=$$(for p in $(PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "make: installing missing Debian packages:" $$missing; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi

build: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) > $(BUILD).configure.log 2>&1 || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@if [ -n "$$DISPLAY" ] || [ -n "$$WAYLAND_DISPLAY" ]; then \
	  ./$(BUILD)/pathview; \
	else \
	  echo "make run: no display (DISPLAY is not set); rendering the built-in Cornell box headless instead."; \
	  ./$(BUILD)/pathview render --spp 64 -o cornell.exr -o cornell.png && \
	  echo "make run: wrote $$(pwd)/cornell.exr and $$(pwd)/cornell.png"; \
	fi

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test: format-check test-release test-sanitize test-fuzz test-slurm

# Every C++ file as the root .clang-format (Google-based, 4 spaces, 120 columns) formats it; `make format` applies it.
format-check: deps
	@git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run --Werror && echo "make format-check: every C++ file is formatted"

format: deps
	git ls-files '*.cpp' '*.h' | xargs clang-format -i

# A one-node Slurm 22.05 cluster on this machine (munged, slurmctld, slurmd as root, everything in a temporary
# folder): deploy/slurm's 4-task array job renders the shards of a small render, the dependent job merges them, and
# the result must equal a single-process render (tests/slurm/run.sh; about 15 s, bounded by timeout, torn down
# whatever happens). Installs Debian's slurm-wlm and munge when missing.
SLURM_PACKAGES := slurm-wlm munge
test-slurm: build
	@$(MAKE) --no-print-directory deps PACKAGES="$(SLURM_PACKAGES)"
	$(SUDO) timeout --kill-after=30 600 tests/slurm/run.sh $(BUILD)/pathview $(BUILD)/tests/pathview_exr_compare

# Sanitizer builds: no micro-benchmarks; RelWithDebInfo for readable reports. The ASan+UBSan build uses clang with
# libFuzzer instrumentation so that the suite and the fuzzer share one build (build-asan-fuzz); it builds the viewer's
# library too, so the window-free UI tests (pathview_ui_tests) run under ASan+UBSan; the Xvfb tests of the real window
# (label gui) do not (Mesa's own allocations would be reported as leaks). The TSan build has no viewer.
SAN_FLAGS := -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHVIEW_BUILD_MICROBENCH=OFF -DPATHVIEW_WERROR=ON

# The suite under ASan+UBSan (suites whose name ends in Slow skipped), then the renderer's threading suites
# (names starting with Threading or Progressive) under TSan. TBB and Embree are not built with TSan: core/base/tsan.h
# annotates pathview's fork/join edges and tests/tsan.supp suppresses reports inside those libraries only.
test-sanitize: test-asan test-tsan

build-asan-fuzz: deps
	@cmake -S . -B build-asan-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ $(SAN_FLAGS) -DPATHVIEW_BUILD_UI=ON \
	  -DPATHVIEW_SANITIZE=address,undefined -DPATHVIEW_BUILD_FUZZER=ON > build-asan-fuzz.configure.log 2>&1 || \
	  { cat build-asan-fuzz.configure.log; exit 1; }
	@cmake --build build-asan-fuzz -j $(JOBS) --target pathview_tests pathview_ui_tests pathview fuzz_obj fuzz_image fuzz_scene_json fuzz_partial fuzz_gltf \
	  fuzz_meshopt fuzz_draco

test-asan: build-asan-fuzz
	cd build-asan-fuzz && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS) -E 'Slow[./]' -LE '^gui$$'

test-tsan: deps
	@cmake -S . -B build-tsan $(SAN_FLAGS) -DPATHVIEW_BUILD_UI=OFF -DPATHVIEW_SANITIZE=thread > build-tsan.configure.log 2>&1 || { cat build-tsan.configure.log; exit 1; }
	@cmake --build build-tsan -j $(JOBS) --target pathview_tests
	cd build-tsan && TSAN_OPTIONS="suppressions=$(CURDIR)/tests/tsan.supp halt_on_error=1 second_deadlock_stack=1" \
	  ctest --output-on-failure -j $(JOBS) -R '(^|/)(Threading|Progressive)'

# libFuzzer under ASan+UBSan from the seed corpora in tests/fuzz (only read; new inputs go to
# build-asan-fuzz/corpus-*.new): the OBJ import path (corpus), the image loaders (corpus-image: seeds, the issue-15
# reproducers and every crash found since), the JSON scene reader (corpus-json), merge's reader of partial renders
# (corpus-partial), the glTF loader (corpus-gltf, written by tests/fuzz/make_gltf_corpus.py) and its decompressors
# (corpus-meshopt, corpus-draco: tests/fuzz/make_compressed_corpus.py). A fixed seed and a
# fixed number of runs per fuzzer (at most about 30 s each on these machines; FUZZ_SECONDS caps the time), so a run
# is deterministic for a given build: CI repeats exactly what was run before submitting, and a crash input
# (./crash-*) reproduces. fuzz_gltf runs twice: as the others, then (the entry ending in :large) with inputs up to
# 1 MiB and a dictionary of glTF's keys (tests/fuzz/gltf.dict), where large counts and deep nesting live.
FUZZ_SECONDS ?= 120
FUZZ_LARGE_FLAGS := -max_len=1048576 -dict=tests/fuzz/gltf.dict
FUZZERS := fuzz_obj:corpus:150000 fuzz_image:corpus-image:150000 fuzz_scene_json:corpus-json:400000 \
  fuzz_partial:corpus-partial:6000 fuzz_gltf:corpus-gltf:30000 fuzz_gltf:corpus-gltf:2000:large \
  fuzz_meshopt:corpus-meshopt:7000 fuzz_draco:corpus-draco:7000
test-fuzz: build-asan-fuzz
	@set -e; for f in $(FUZZERS); do name=$${f%%:*}; rest=$${f#*:}; seeds=$${rest%%:*}; runs=$${rest#*:}; \
	  extra=""; case $$runs in *:large) runs=$${runs%:large}; extra="$(FUZZ_LARGE_FLAGS)";; esac; \
	  rm -rf build-asan-fuzz/$$seeds.new && mkdir -p build-asan-fuzz/$$seeds.new; \
	  echo "make test-fuzz: $$name, $$runs runs from tests/fuzz/$$seeds $$extra"; \
	  ./build-asan-fuzz/tests/fuzz/$$name -seed=1 -runs=$$runs -max_total_time=$(FUZZ_SECONDS) -timeout=60 \
	    -rss_limit_mb=2048 -print_final_stats=1 $$extra build-asan-fuzz/$$seeds.new tests/fuzz/$$seeds; \
	done

bench: build
	./$(BUILD)/pathview bench

# Regenerates the generated sections of BENCHMARKS.md (in place) and bench/*.csv|svg in one run (about 10 minutes
# on 2 cores; scripts/benchmarks.sh).
benchmarks: build
	scripts/benchmarks.sh $(BUILD)

clean:
	rm -rf $(BUILD) build-asan build-asan-fuzz build-tsan *.configure.log
