# quatspline — build / demo / test / lint / bench.
# Every target sets itself up on a fresh machine: it creates .venv/ and installs what it needs.

PY      ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
STAMP   := $(VENV)/.deps-stamp

.PHONY: build demo test test-rust test-python lint bench accuracy fuzz clean

$(STAMP): pyproject.toml
	test -x $(VPY) || $(PY) -m venv $(VENV)
	$(VPY) -m pip install --quiet --upgrade pip
	$(VPY) -m pip install --quiet "maturin>=1.5,<2" numpy scipy pytest hypothesis mpmath \
		numpy-quaternion pytransform3d splines ruff matplotlib tqdm
	touch $(STAMP)

build: $(STAMP)
	$(VPY) -m maturin develop --release --quiet

demo: build
	$(VENV)/bin/quatspline demo

test: build test-rust test-python lint

test-rust:
	cargo test --workspace --release
	QUATSPLINE_SIMD=scalar cargo test -p quatspline --release --test simd_kernels

test-python: build
	$(VPY) -m pytest
	QUATSPLINE_SIMD=scalar $(VPY) -m pytest -q tests/test_simd.py tests/test_engine.py tests/test_splines.py

lint: $(STAMP)
	cargo fmt --all --check
	cargo clippy --workspace --all-targets --release -- -D warnings
	$(VENV)/bin/ruff check python tests benchmarks fuzz
	$(VENV)/bin/ruff format --check python tests benchmarks fuzz

bench: build
	$(VPY) benchmarks/bench.py
	cargo bench -p quatspline --bench core -- --warm-up-time 0.5 --measurement-time 2

# Bounded fuzzing: FUZZ_SECONDS per target (cargo-fuzz needs a nightly toolchain).
FUZZ_SECONDS ?= 60
fuzz: build
	command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz
	mkdir -p fuzz/corpus/splines fuzz/corpus/readers
	cd fuzz && cargo +nightly fuzz run splines corpus/splines -- -max_total_time=$(FUZZ_SECONDS) -max_len=512
	$(VENV)/bin/python -m pip install --quiet atheris
	$(VPY) fuzz/readers_fuzz.py fuzz/corpus/readers -max_total_time=$(FUZZ_SECONDS)

accuracy: build
	$(VPY) benchmarks/accuracy.py

clean:
	rm -rf target $(VENV) out
