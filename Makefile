# setbound — the two commands of the README:
#   make demo   set up this machine and run the main job
#   make test   set up this machine and run every test (C++ then Python, then packaging)
# Each target installs what is missing (Debian packages, .venv with the package) first.

PYTHON   ?= python3
VENV     := .venv
PY       := $(VENV)/bin/python
CPP_BUILD := build/cpp
JOBS     ?= 2

# One compiler name for every CMake build (the C++ tests in build/cpp, the Python package and the
# wheel in build/<wheel tag>): ccache keys on the compiler's name, and CMake from PyPI picks g++
# where Debian's picks c++, so without this the library was compiled twice from scratch.
export CC
export CXX
# Paths under the checkout enter ccache's hash relative to it, so another clone of the project
# (a CI checkout, a second worktree) reuses the same cache entries.
export CCACHE_BASEDIR := $(CURDIR)

.PHONY: all deps venv install build-cpp test test-cpp test-python test-wheel demo bench fuzz clean

all: test

deps:
	@bash scripts/install-deps.sh

$(VENV)/.created: | deps
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q "scikit-build-core>=0.10" "cmake>=3.20" ninja
	touch $@

venv: $(VENV)/.created

# Editable install with the test and plot extras; the CMake build is incremental
# (build/<wheel tag>), so re-running this after a C++ change only rebuilds what changed.
install: venv
	$(PY) -m pip install -q --no-build-isolation -e ".[test,plot]"

build-cpp: deps
	cmake -S . -B $(CPP_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release
	cmake --build $(CPP_BUILD) -j $(JOBS)

test-cpp: build-cpp
	ctest --test-dir $(CPP_BUILD) --output-on-failure -j $(JOBS)

test-python: install
	$(PY) -m pytest -q tests/python

# Install path (a): build the wheel, install it into a fresh venv, use it from elsewhere.
test-wheel: install
	bash scripts/test-wheel.sh $(PY)

test: test-cpp test-python test-wheel

demo: install
	$(VENV)/bin/setbound demo --out out/demo

bench: install
	$(PY) -m pip install -q ".[bench]" --no-build-isolation --no-deps
	$(PY) -m pip install -q cvxpy clarabel scs
	$(PY) bench/bench_lmi.py

# The long fuzz run (docs/reliability.md): the hypothesis profile "fuzz" (random seeds,
# FUZZ_SCALE times the CI examples) over the Python API and the raw C ABI; prints the count.
FUZZ_SCALE ?= 20
fuzz: install
	SETBOUND_HYPOTHESIS_PROFILE=fuzz SETBOUND_FUZZ_SCALE=$(FUZZ_SCALE) \
	  $(PY) -m pytest -q -p no:cacheprovider tests/python/test_fuzz_api.py tests/python/test_fuzz_capi.py

clean:
	rm -rf build dist out
