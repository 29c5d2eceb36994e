"""Add the licence texts of the libraries a repaired wheel bundles (scripts/build-wheel.sh).

auditwheel copies libnlopt_cxx, libqhull_r and libgomp into ``setbound.libs/`` but not their
licences; redistributing them requires those. Each bundled library is traced back to the system
file it was copied from (``ldd`` of the plain wheel's libsetbound.so), that file to its Debian
package (``dpkg -S``) and the package to its ``/usr/share/doc/<package>/copyright``, which goes into
``<dist-info>/licenses/bundled/``; so does Eigen's (its templates are compiled into libsetbound).
A bundled library whose licence cannot be found stops the build: the wheel is never left without it.

Usage: python wheel_licences.py REPAIRED_WHEEL PLAIN_WHEEL
"""
from __future__ import annotations

import base64
import hashlib
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile


def debian_copyright(path: str) -> tuple[str, pathlib.Path]:
    """The Debian package owning ``path`` and its copyright file."""
    real = os.path.realpath(path)
    out = subprocess.run(["dpkg", "-S", real], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"wheel_licences: no Debian package owns {real}: {out.stderr.strip()}")
    package = out.stdout.split(":", 1)[0].strip()
    copyright_file = pathlib.Path("/usr/share/doc") / package / "copyright"
    if not copyright_file.is_file():
        sys.exit(f"wheel_licences: {copyright_file} (licence of {real}) does not exist")
    return package, copyright_file


def linked_libraries(plain_wheel: str) -> dict[str, str]:
    """soname -> system path of every library the plain wheel's libsetbound.so loads."""
    with tempfile.TemporaryDirectory() as tmp, zipfile.ZipFile(plain_wheel) as z:
        member = next(n for n in z.namelist() if re.fullmatch(r"setbound/libsetbound\.so[.0-9]*", n))
        lib = z.extract(member, tmp)
        out = subprocess.run(["ldd", lib], capture_output=True, text=True, check=True).stdout
    found = {}
    for line in out.splitlines():
        m = re.match(r"\s*(\S+) => (/\S+)", line)
        if m:
            found[m.group(1)] = m.group(2)
    return found


def record_line(name: str, data: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def main(repaired: str, plain: str) -> None:
    linked = linked_libraries(plain)
    with zipfile.ZipFile(repaired) as z:
        names = z.namelist()
        entries = [(info, z.read(info)) for info in z.infolist()]
    dist_info = next(n.split("/", 1)[0] for n in names if n.split("/", 1)[0].endswith(".dist-info"))
    bundled = sorted(pathlib.PurePosixPath(n).name for n in names
                     if n.startswith("setbound.libs/") and not n.endswith("/"))
    if not bundled:
        sys.exit(f"wheel_licences: {repaired} bundles no library (was it repaired?)")
    texts: dict[str, bytes] = {}
    for name in bundled:
        stem = name.split("-", 1)[0]  # auditwheel: <stem>-<hash>.so.<version>
        sources = [p for so, p in linked.items() if so.split(".so", 1)[0] == stem]
        if len(sources) != 1:
            sys.exit(f"wheel_licences: cannot tell which system library {name} came from "
                     f"(ldd of the plain wheel: {sorted(linked)})")
        package, copyright_file = debian_copyright(sources[0])
        texts[f"{stem}.{package}.copyright"] = copyright_file.read_bytes()
    eigen = pathlib.Path("/usr/include/eigen3/Eigen/Core")
    if not eigen.exists():
        sys.exit("wheel_licences: Eigen's headers (libeigen3-dev) are not installed")
    package, copyright_file = debian_copyright(str(eigen))
    texts[f"eigen3.{package}.copyright"] = copyright_file.read_bytes()

    added = {f"{dist_info}/licenses/bundled/{k}": v for k, v in sorted(texts.items())}
    record = f"{dist_info}/RECORD"
    tmp = repaired + ".tmp"
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as out:
        for info, data in entries:
            if info.filename == record:
                lines = data.decode().rstrip("\n").split("\n")
                lines = [ln for ln in lines if ln.split(",", 1)[0] not in added]
                lines += [record_line(n, d) for n, d in added.items()]
                data = ("\n".join(lines) + "\n").encode()
            if info.filename in added:
                continue
            out.writestr(info, data)
        for n, d in added.items():
            out.writestr(n, d)
    shutil.move(tmp, repaired)
    print(f"wheel_licences: added {', '.join(sorted(texts))} to {pathlib.Path(repaired).name}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
