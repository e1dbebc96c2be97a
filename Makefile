# Thin wrappers: every target installs what is missing, then builds.
BUILD ?= build
JOBS ?= $(shell nproc)
VKPATH = $(BUILD)/vkpath

.PHONY: all deps build demo test bench clean

all: build

deps:
	@tools/install-deps

build: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	@mkdir -p out
	@$(VKPATH) rays -d 640x480 --eye 0 1 4 --target 0 0 0 -o out/demo.exr --png out/demo.png

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) out
