# quatspline — build / demo / test / lint / docs / wheel / bench.
# Every target sets itself up on a fresh machine: it creates .venv/ and installs what it needs.
# `make demo` installs only what the demo needs (maturin, numpy, tqdm, matplotlib for the
# figures); `make test` adds the `test` and `docs` extras of pyproject.toml.

PY      ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
BASE    := $(VENV)/.base-stamp
DEV     := $(VENV)/.dev-stamp
# maturin finds zig (the pip package `ziglang`) through the venv's python on PATH
export PATH := $(abspath $(VENV))/bin:$(PATH)

.PHONY: viewer-assets browser blender blender-bpy build demo test test-rust test-python test-wheel lint typecheck docs wheel sdist \
	bench accuracy fuzz clean

$(BASE):
	test -x $(VPY) || $(PY) -m venv $(VENV)
	$(VPY) -m pip install --quiet --disable-pip-version-check "maturin>=1.5,<2"
	touch $(BASE)

# The package's own dependencies (numpy, tqdm) and the plot extra come with `maturin develop`.
build: $(BASE)
	$(VPY) -m maturin develop --release --quiet --extras plot

demo: build
	$(VENV)/bin/quatspline demo

# Test and docs extras, read from pyproject.toml by maturin (one list of dependencies).
$(DEV): pyproject.toml $(BASE)
	$(VPY) -m maturin develop --release --quiet --extras plot,test,docs
	touch $(DEV)

# typecheck and docs join once their sources (examples/, docs/conf.py) exist.
test: build $(DEV) test-rust test-python lint $(if $(wildcard examples),typecheck) \
	$(if $(wildcard docs/conf.py),docs) test-wheel

test-rust:
	cargo test --workspace --release
	# the same workspace feature set as the line above: the scalar-kernel run reuses its build
	QUATSPLINE_SIMD=scalar cargo test --workspace --release --test simd_kernels --test simd_slerp_kernels

# The Khronos glTF validator (test-only), installed into the project, never used by the library.
GLTF_VALIDATOR := .npm/node_modules/gltf-validator/package.json
$(GLTF_VALIDATOR):
	npm install --prefix .npm --no-audit --no-fund --silent gltf-validator@2.0.0-dev.3.10

# Unit and property tests, and every docstring example as a doctest.
# The viewer's JavaScript (three.js, uPlot) from npm, copied into the package at build time.
VIEWER_VENDOR := python/quatspline/viewer/static/vendor
# (the camera's orbit and the rotation gizmo are three.js's OrbitControls and TransformControls)
$(VIEWER_VENDOR)/TransformControls.js: viewer-js/package.json viewer-js/package-lock.json
	cd viewer-js && npm ci --no-audit --no-fund --silent
	mkdir -p $(VIEWER_VENDOR)
	cp viewer-js/node_modules/three/build/three.module.js viewer-js/node_modules/three/build/three.core.js \
		viewer-js/node_modules/three/examples/jsm/controls/OrbitControls.js \
		viewer-js/node_modules/three/examples/jsm/controls/TransformControls.js \
		viewer-js/node_modules/uplot/dist/uPlot.iife.min.js viewer-js/node_modules/uplot/dist/uPlot.min.css \
		$(VIEWER_VENDOR)/
viewer-assets: $(VIEWER_VENDOR)/TransformControls.js

# Headless Chromium for the viewer's browser tests: Debian's package, installed when root.
browser:
	@command -v chromium >/dev/null 2>&1 || { \
		if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
			apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; \
		else echo "make: no chromium and no way to install it here: browser tests will skip"; fi; }

# Headless Blender for the add-on's and the glTF importer's tests (tests/blender): Debian's
# package (system Python; python3-numpy for its glTF importer), installed when root.
blender:
	@command -v blender >/dev/null 2>&1 || { \
		if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
			apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq blender python3-numpy; \
		else echo "make: no blender and no way to install it here: Blender tests will skip"; fi; }

# The official Blender 4.2 build as a Python module (PyPI's bpy, for Python 3.11 only) in its
# own environment, .venv-bpy/, with the numpy Blender 4.2 bundles (1.26) and quatspline's
# pure-Python dependencies; the tests put quatspline itself on its path. Built in a scratch
# folder and moved into place only when complete; where python3.11 or PyPI is missing, its
# tests skip with a message.
BPY_PY   ?= python3.11
BPY_VENV := .venv-bpy
blender-bpy:
	@test -x $(BPY_VENV)/bin/python || { \
		if command -v $(BPY_PY) >/dev/null 2>&1; then \
			rm -rf $(BPY_VENV).partial && $(BPY_PY) -m venv $(BPY_VENV).partial && \
			$(BPY_VENV).partial/bin/python -m pip install --quiet --disable-pip-version-check \
				"bpy==4.2.0" "numpy>=1.26,<2" "tqdm>=4.60" && \
			mv $(BPY_VENV).partial $(BPY_VENV) || { rm -rf $(BPY_VENV).partial; \
			echo "make: could not install bpy==4.2.0: the Blender 4.2 tests will skip"; }; \
		else echo "make: no $(BPY_PY) for PyPI's bpy 4.2: the Blender 4.2 tests will skip"; fi; }

test-python: build $(DEV) $(GLTF_VALIDATOR) viewer-assets browser blender blender-bpy
	$(VPY) -m pytest
	QUATSPLINE_SIMD=scalar $(VPY) -m pytest -q tests/core/test_simd.py tests/core/test_engine.py tests/splines/test_splines.py

PYDIRS := $(wildcard python tests tests_installed benchmarks fuzz examples docs)

lint: $(BASE) $(DEV)
	cargo fmt --all --check
	cargo clippy --workspace --all-targets --release -- -D warnings
	$(VENV)/bin/ruff check $(PYDIRS)
	$(VENV)/bin/ruff format --check $(PYDIRS)

# The gallery examples type-check against the package's annotations and stubs.
typecheck: build $(DEV)
	$(VPY) -m mypy --strict examples

# The documentation site (Sphinx + numpydoc + sphinx-gallery); warnings are errors.
docs: build $(DEV)
	$(VPY) -m sphinx -W --keep-going -q -b html docs docs/_build/html
	$(VPY) -m pytest docs/test_api_reference.py -q -p no:cacheprovider

# An abi3 wheel (CPython >= 3.9) for manylinux2014 (glibc 2.17), linked with zig, and an sdist.
wheel: $(BASE) viewer-assets
	$(VPY) -m pip install --quiet --disable-pip-version-check "ziglang>=0.11"
	rm -f dist/quatspline-*.whl dist/quatspline-*.tar.gz
	$(VPY) -m maturin build --release --zig --compatibility manylinux2014 --out dist --quiet
	$(VPY) -m maturin sdist --out dist

# The built wheel installed into a fresh venv outside the source tree (import, quick start,
# CLI, demo without matplotlib).
test-wheel: wheel $(DEV)
	$(VPY) -m pytest tests_installed -q

bench: build
	$(VPY) -m maturin develop --release --quiet --extras plot,bench
	$(VPY) benchmarks/bench.py
	$(VPY) benchmarks/fit.py --scale 1000000
	$(VPY) benchmarks/imu.py
	$(VPY) benchmarks/imu_calibration.py
	$(VPY) benchmarks/readers.py
	$(VPY) benchmarks/batch.py --files 100
	cargo bench -p quatspline --bench core -- --warm-up-time 0.5 --measurement-time 2

# Bounded fuzzing: FUZZ_SECONDS per target (cargo-fuzz needs a nightly toolchain).
FUZZ_SECONDS ?= 60
fuzz: build
	command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz
	mkdir -p fuzz/corpus/splines fuzz/corpus/readers
	cd fuzz && cargo +nightly fuzz run splines corpus/splines -- -max_total_time=$(FUZZ_SECONDS) -max_len=65536
	$(VENV)/bin/python -m pip install --quiet atheris
	$(VPY) fuzz/readers_fuzz.py fuzz/corpus/readers fuzz/regressions/readers -max_total_time=$(FUZZ_SECONDS)

accuracy: build $(DEV)
	$(VPY) benchmarks/accuracy.py

clean:
	rm -rf target $(VENV) $(BPY_VENV) out dist docs/_build docs/api/generated docs/auto_examples
