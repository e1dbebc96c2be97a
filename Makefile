# Thin wrappers: every target installs what is missing, then builds.
BUILD ?= build
JOBS ?= $(shell nproc)
VKPATH = $(BUILD)/vkpath

.PHONY: all deps configure build demo test test-long bench bench-peer bench-suite bench-scale bench-ray fuzz fuzz-smoke format clean

all: build

deps:
	@tools/install-deps

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null

# Everything: vkpath, the tests and the benchmarks.
build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The bundled Cornell box (mirror and glass spheres, ceiling lamp) at 256 spp,
# enough samples that its caustics no longer speckle every wall: tens of
# seconds on two CPU cores through lavapipe, tens of milliseconds on a data
# centre GPU (docs/BENCHMARKS.md, "An NVIDIA H200").
demo: configure
	@cmake --build $(BUILD) -j $(JOBS) --target vkpath
	@$(VKPATH) render assets/cornell_box.gltf -d 400x300 -s 256 -m 8 -o out/cornell_box.exr --png out/cornell_box.png

# Open Image Denoise for the denoiser's tests (PyPI's pyoidn in $(BUILD)/oidn-venv)
# and the Python package in $(BUILD)/py-venv (tools/python-package, exit 3 where
# PyPI cannot be reached): without PyPI, their tests skip and say why.
test: build
	@tools/oidn-venv $(BUILD)/oidn-venv >/dev/null || echo "make test: no Open Image Denoise (PyPI's pyoidn); the denoiser's tests skip" >&2
	@tools/python-package $(BUILD) >/dev/null || { [ $$? = 3 ] && echo "make test: the Python package's dependencies are not on reach (PyPI); its tests skip" >&2; }
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 600
	@tools/fuzz-smoke

# The same suite with the full counts each issue asks for (tests/support/
# test_scale.h; docs/ACCURACY.md lists both counts). Not in CI: it takes hours
# on two cores.
test-long: build
	@cd $(BUILD) && VKPATH_TEST_LONG=1 ctest --output-on-failure -j $(JOBS) --timeout 14400

# The scene loaders' libFuzzer harnesses (fuzz/; clang, in build-fuzz): each
# for 20 s in `make test` (fuzz-smoke), for FUZZ_SECONDS each in `make fuzz`.
FUZZ_SECONDS ?= 600
fuzz-smoke: deps
	@tools/fuzz-smoke

fuzz: deps
	@tools/fuzz-smoke $(FUZZ_SECONDS)

# Benchmarks (not part of `make test`): the BVH and the samplers (Google Benchmark), the path
# tracer on CBspheres.dae (its kernel forms and builds side by side) and the
# start-up time with and without caches. Figures and commands: docs/BENCHMARKS.md.
bench: build
	@$(BUILD)/bvh_bench
	@$(BUILD)/sampler_bench
	@tools/bench/render-bench --vkpath $(VKPATH)
	@tools/bench/startup-bench --vkpath $(VKPATH)

# vkpath side by side with Mitsuba 3 (not in CI): installs Debian's libllvm19 and a
# venv in build-peer/ with mitsuba from PyPI, checks that the exported scenes
# render the same, then plots error against time (PEER_ARGS=--size 800x600 etc.;
# docs/TRADEOFFS.md), then races both on the scene suite (bench-suite), then races
# render --auto against converge's fixed settings on the suite (AUTO_ARGS=--scenes a,b etc.;
# docs/TRADEOFFS.md, "Settings chosen by measurement"), then races Blender's Cycles on the
# suite's glTF scenes, each renderer to its own image by the two-seed estimate (a venv in
# build-peer/cycles-venv with bpy from PyPI; CYCLES_ARGS=--quick, --size 128 etc.;
# docs/SUITE.md, "Against Blender's Cycles").
PEER_ARGS ?=
AUTO_ARGS ?=
CYCLES_ARGS ?=
bench-peer: build
	@tools/bench/peer-bench --vkpath $(VKPATH) $(PEER_ARGS)
	@tools/bench/suite-race --vkpath $(VKPATH) --mitsuba on $(SUITE_ARGS)
	@tools/bench/auto-race --vkpath $(VKPATH) $(AUTO_ARGS)
	@tools/bench/cycles-race --vkpath $(VKPATH) $(CYCLES_ARGS)

# The scene suite (tools/bench/suite/suite.json): per scene, vkpath's time to a relMSE on
# lavapipe and --device cpu and Mitsuba 3's, their ratio and the geometric mean; references
# cached in build/suite-refs/. SUITE_ARGS=--quick, --scenes a,b, --size 640 etc.; figures and
# commands: docs/SUITE.md.
SUITE_ARGS ?=
bench-suite: build
	@tools/bench/suite-race --vkpath $(VKPATH) $(SUITE_ARGS)

# How vkpath grows with the scene beside Mitsuba 3 (not in CI: tens of minutes, up to ~10 GiB
# of memory): spheres of 10 k to 32 M triangles, load and set-up time, host and device memory,
# Mpaths/s, one log-log plot (docs/images/scale.png). SCALE_ARGS=--sizes 10k,1M etc.; figures
# and commands: docs/BENCHMARKS.md, "Growth, drawn".
SCALE_ARGS ?=
bench-scale: build
	@tools/bench/scale-bench --vkpath $(VKPATH) $(SCALE_ARGS)

# The Ray driver's overhead (not in CI: tens of minutes on two cores): the
# 1024-spp CBspheres 800x600 render in 8, 16 and 32 chunks against one process.
# Makes a venv in build/ray-venv with ray from PyPI. RAY_ARGS=--spp 256 etc.;
# figures and commands: docs/BENCHMARKS.md.
RAY_ARGS ?=
bench-ray: build
	@tools/bench/ray-bench --vkpath $(VKPATH) $(RAY_ARGS)

# The C++ files as .clang-format has them (CI checks with tools/check-format).
format: deps
	@tools/check-format --fix

clean:
	rm -rf $(BUILD) build-fuzz out
