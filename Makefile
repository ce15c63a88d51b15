# pathview: the two set-up commands of README.md.
#   make run   installs what is missing, builds Release, opens the viewer on the built-in Cornell box
#              (with no display: says so and renders the Cornell box headless).
#   make test  installs what is missing, builds, runs every test (ctest), then the sanitizer suites.
SHELL := /bin/bash
BUILD ?= build
JOBS ?= $(shell nproc)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian 12 packages: build, libraries, and the tools the GUI tests use.
PACKAGES := build-essential cmake pkg-config ccache libglfw3-dev libimgui-dev libstb-dev libgl-dev \
  libembree-dev libtbb-dev libglm-dev libtinyobjloader-dev libopenexr-dev libgtest-dev libbenchmark-dev \
  libcli11-dev nlohmann-json3-dev openexr xvfb xauth libgl1-mesa-dri xdotool imagemagick x11-apps \
  clang libclang-rt-14-dev

CMAKE_FLAGS := -DCMAKE_BUILD_TYPE=Release

.PHONY: deps build run test test-release test-sanitize bench clean

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
	  ./$(BUILD)/pathview render --spp 64 -o cornell.exr && ./$(BUILD)/pathview render --spp 64 -o cornell.png && \
	  echo "make run: wrote $$(pwd)/cornell.exr and $$(pwd)/cornell.png"; \
	fi

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test: test-release test-sanitize

# The suite under ASan+UBSan, and the renderer's threading tests under TSan (see tests/CMakeLists.txt labels).
test-sanitize: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHVIEW_SANITIZE=address,undefined -DPATHVIEW_BUILD_UI=OFF > build-asan.configure.log 2>&1 || { cat build-asan.configure.log; exit 1; }
	@cmake --build build-asan -j $(JOBS) --target pathview_tests
	cd build-asan && ctest --output-on-failure -j $(JOBS) -L sanitize
	@cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHVIEW_SANITIZE=thread -DPATHVIEW_BUILD_UI=OFF > build-tsan.configure.log 2>&1 || { cat build-tsan.configure.log; exit 1; }
	@cmake --build build-tsan -j $(JOBS) --target pathview_tests
	cd build-tsan && ctest --output-on-failure -j $(JOBS) -L threading

bench: build
	./$(BUILD)/pathview bench

# Regenerates BENCHMARKS.md and bench/*.csv|svg in one run (about 10 minutes on 2 cores; scripts/benchmarks.sh).
benchmarks: build
	scripts/benchmarks.sh $(BUILD)

clean:
	rm -rf $(BUILD) build-asan build-tsan *.configure.log
