#!/usr/bin/env bash
# Install path (a): build a wheel, check the shared library and header are inside the
# package, install it into a fresh virtual environment and use it from another directory.
set -euo pipefail
PY=${1:-python3}
root=$(cd "$(dirname "$0")/.." && pwd)
work="$root/build/wheel-test"
rm -rf "$work" && mkdir -p "$work"
"$PY" -m pip wheel -q --no-build-isolation --no-deps "$root" -w "$work/dist"
wheel=$(ls "$work"/dist/setbound-*.whl)
case "$wheel" in
  *-py3-none-*) ;;
  *) echo "test-wheel: expected a py3-none wheel (one for all CPython versions), got $wheel"; exit 1 ;;
esac
"$PY" - "$wheel" <<'PYEOF'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
for need in ("setbound/libsetbound.so", "setbound/setbound.h", "setbound/__init__.py"):
    if not any(n == need or n.startswith(need + ".") for n in names):
        sys.exit(f"test-wheel: {need} missing from the wheel: {names}")
print("test-wheel: wheel contents ok")
PYEOF
"$PY" -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q "$wheel"
cd "$work"
"$work/venv/bin/python" - <<'PYEOF'
import pathlib, setbound, setbound._native as n
pkg = pathlib.Path(setbound.__file__).resolve().parent
lib = pathlib.Path(n.library_path).resolve()
assert lib.parent == pkg, f"library loaded from {lib}, not from the installed package {pkg}"
assert "site-packages" in str(pkg), pkg
assert setbound.__version__ == n.version()
print(f"test-wheel: setbound {setbound.__version__} imported from {pkg}")
PYEOF
echo "1 passed, 0 failed"
