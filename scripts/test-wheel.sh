#!/usr/bin/env bash
# The wheel a user installs (`make wheel`, scripts/build-wheel.sh), tested as a user gets it:
#  1. contents: the manylinux tag, libsetbound.so and setbound.h inside the package, the bundled
#     libnlopt_cxx / libqhull_r / libgomp in setbound.libs/ with their licence texts;
#  2. installed into a fresh venv and imported from another directory, it loads its own library;
#  3. with the system's copies of the bundled libraries hidden (a private mount namespace in which
#     empty files cover them) it runs an estimator that needs each of them
#     (scripts/check_bundled_libraries.py), and the plain, unrepaired wheel fails that same test:
#     proof that the hiding works and that the repair is what makes the wheel portable.
# Needs `unshare` (util-linux) with mount namespaces: as root, or with unprivileged user
# namespaces; SETBOUND_SKIP_HIDDEN_LIBS=1 skips step 3 where neither exists (it says so loudly).
set -euo pipefail
PY=${1:-python3}
root=$(cd "$(dirname "$0")/.." && pwd)
plat=${SETBOUND_WHEEL_PLAT:-manylinux_2_34_$(uname -m)}
work="$root/build/wheel-test"
rm -rf "$work" && mkdir -p "$work"
wheel=$(ls "$root"/dist/setbound-*-py3-none-"$plat".whl)
plain=$(ls "$root"/build/wheel-raw/setbound-*-py3-none-linux_*.whl)

"$PY" - "$wheel" <<'PYEOF'
import re, sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
for need in ("setbound/libsetbound.so", "setbound/setbound.h", "setbound/__init__.py"):
    if not any(n == need or n.startswith(need + ".") for n in names):
        sys.exit(f"test-wheel: {need} missing from the wheel: {names}")
for stem in ("libnlopt_cxx", "libqhull_r", "libgomp"):
    if not any(re.fullmatch(rf"setbound\.libs/{stem}-[0-9a-f]+\.so[.0-9]*", n) for n in names):
        sys.exit(f"test-wheel: {stem} is not bundled in setbound.libs/: {names}")
    if not any(re.fullmatch(rf"setbound-[^/]+\.dist-info/licenses/bundled/{stem}\.[^/]+\.copyright", n) for n in names):
        sys.exit(f"test-wheel: the licence of the bundled {stem} is missing")
if not any(re.fullmatch(r"setbound-[^/]+\.dist-info/licenses/LICENSE", n) for n in names):
    sys.exit("test-wheel: setbound's own LICENSE is missing from the wheel")
print("test-wheel: wheel contents ok (manylinux tag, bundled libraries and their licences)")
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

if [ "${SETBOUND_SKIP_HIDDEN_LIBS:-0}" = 1 ]; then
  echo "test-wheel: SKIPPED the hidden-libraries test (SETBOUND_SKIP_HIDDEN_LIBS=1)"
  echo "2 passed, 0 failed, 1 skipped"
  exit 0
fi
# The system files behind the libraries the plain wheel links (symlinks resolved, so every name
# that leads to them is covered).
sonames=(libnlopt_cxx.so.0 libqhull_r.so.8.0 libgomp.so.1)
files=()
for so in "${sonames[@]}"; do
  # awk reads to the end: an early `exit` closes the pipe while ldconfig still writes, and with
  # pipefail its SIGPIPE (status 141) stopped this script (seen 2026-11-27).
  f=$(ldconfig -p | awk -v so="$so" '$1 == so && !found {print $NF; found = 1}')
  [ -n "$f" ] || { echo "test-wheel: $so is not installed on this machine (nothing to hide)"; exit 1; }
  files+=("$(readlink -f "$f")")
done
if [ "$(id -u)" -eq 0 ]; then ns=(unshare -m); else ns=(unshare -r -m); fi
if ! "${ns[@]}" true 2>/dev/null; then
  echo "test-wheel: cannot create a mount namespace here (${ns[*]}); set SETBOUND_SKIP_HIDDEN_LIBS=1 to skip"
  exit 1
fi
hidden_run() {  # hidden_run PYTHON: run the check with the system libraries covered
  "${ns[@]}" bash -c 'py=$1; shift; n=$1; shift
    for f in "${@:1:$n}"; do mount --bind /dev/null "$f"; done
    shift "$n"; exec "$py" "$@"' _ "$1" "${#files[@]}" "${files[@]}" \
    "$root/scripts/check_bundled_libraries.py" "${sonames[@]}"
}
hidden_run "$work/venv/bin/python"
echo "test-wheel: the repaired wheel runs without the system libraries"

"$work/venv/bin/python" -m pip install -q --force-reinstall --no-deps "$plain"
if out=$(hidden_run "$work/venv/bin/python" 2>&1); then
  echo "$out"
  echo "test-wheel: the plain wheel ran with the system libraries hidden: the test proves nothing"
  exit 1
fi
if ! grep -q -E "libnlopt_cxx|libqhull_r|libgomp" <<<"$out"; then
  echo "$out"
  echo "test-wheel: the plain wheel failed, but not for a missing library"
  exit 1
fi
echo "test-wheel: the plain wheel fails the same test as it should:"
tail -n 1 <<<"$out"
echo "3 passed, 0 failed"
