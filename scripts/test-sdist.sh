#!/usr/bin/env bash
# The source distribution builds on a machine with the README's Debian packages: make the sdist
# (scikit-build-core, through PyPA's `build`), unpack it, build a wheel from the unpacked tree alone
# and import that wheel's package (its own libsetbound.so) from another directory. A file the
# build needs but the sdist leaves out fails here. Unpacked under build/ so that, with the Makefile's
# CCACHE_BASEDIR, the compile commands match the editable build's and ccache serves them.
set -euo pipefail
PY=${1:-python3}
case "$PY" in /*) ;; */*) PY="$PWD/$PY" ;; esac  # the script changes directory
root=$(cd "$(dirname "$0")/.." && pwd)
work="$root/build/sdist-test"
rm -rf "$work" && mkdir -p "$work"
"$PY" -m build --sdist --no-isolation -o "$work/dist" "$root" >/dev/null 2>&1 \
  || "$PY" -m build --sdist --no-isolation -o "$work/dist" "$root"  # quiet unless it fails
sdist=$(ls "$work"/dist/setbound-*.tar.gz)
tar xzf "$sdist" -C "$work"
src=$(ls -d "$work"/setbound-*/)
(cd "$src" && "$PY" -m pip wheel -q --no-build-isolation --no-deps . -w "$work/wheel")
mkdir -p "$work/site" && "$PY" -m zipfile -e "$(ls "$work"/wheel/setbound-*.whl)" "$work/site"
cd "$work"
# -S: no site processing, so an editable install of setbound in this venv (a .pth finder) cannot
# shadow the unpacked wheel; the venv's packages (numpy, cffi, ...) come in as a plain path.
purelib=$("$PY" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
env -u SETBOUND_LIBRARY PYTHONPATH="$work/site:$purelib" "$PY" -S - "$work/site" <<'PYEOF'
import pathlib, sys
import setbound, setbound._native as n
site = pathlib.Path(sys.argv[1]).resolve()
assert pathlib.Path(setbound.__file__).resolve().parent == site / "setbound", setbound.__file__
assert pathlib.Path(n.library_path).resolve().parent == site / "setbound", n.library_path
assert setbound.__version__ == n.version()
print(f"test-sdist: the sdist built a wheel whose setbound {setbound.__version__} loads its own library")
PYEOF
echo "1 passed, 0 failed"
