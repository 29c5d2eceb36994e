"""Run setbound with the system's copies of its native dependencies hidden (scripts/test-wheel.sh).

Started by test-wheel.sh inside a private mount namespace in which the files of libnlopt_cxx,
libqhull_r and libgomp are covered by empty files. First it proves they are really unusable (each
must fail to load by its soname), then it imports setbound and runs code that needs each of them:
an offline ellipsoidal design (NLopt's scalar search), a polytope hull (Qhull), an LMI solved on two
threads (OpenMP) and the README's zonotopic example with its containment check. Finally it reads
/proc/self/maps: every one of those libraries must have been loaded from the wheel's
``setbound.libs``. The repaired wheel passes; the plain one fails at import.

Usage: python check_bundled_libraries.py SONAME [SONAME ...]
"""
import ctypes
import pathlib
import sys

sonames = sys.argv[1:]
for so in sonames:
    try:
        ctypes.CDLL(so)
    except OSError:
        continue
    sys.exit(f"check-bundled: {so} still loads from the system: the hiding did not work")

import numpy as np  # noqa: E402

import setbound  # noqa: E402
from setbound import LinearSystem, Zonotope, lmi  # noqa: E402
from setbound.ellipsoidal import OfflineEstimator, design_offline  # noqa: E402
from setbound.invariant import Polytope  # noqa: E402
from setbound.simulation import simulate  # noqa: E402
from setbound.zonotopic import SegmentMinEstimator  # noqa: E402

system = LinearSystem([[0, -0.5], [1, 1]], C=[[-2, 1], [1, 1]],
                      E=[[-0.12, 0, 0], [0.02, 0, 0]], F=[[0, 0.2, 0], [0, 0, 0.2]])
x0 = Zonotope([0, 0], 3 * np.eye(2))
sim = simulate(system, x0, 30, disturbance="vertex", rng=1)
assert SegmentMinEstimator(system, x0).run(sim.y).contains(sim.x).all()
design = design_offline(system)                      # NLopt (scalar search over the LMI family)
assert OfflineEstimator(design, x0).run(sim.y).contains(sim.x).all()
square = Polytope(np.array([[0, 0], [1, 0], [0, 1], [1, 1], [0.5, 0.5]]))  # Qhull
assert square.num_vertices == 4, square.vertices
blocks = [(np.eye(3) * (1 + i), [np.diag(np.r_[1.0, 0.0, 0.0] * (-1) ** i)]) for i in range(40)]
res = lmi.solve([1.0], blocks, threads=2)            # OpenMP
assert res.status == "optimal", res.status

maps = pathlib.Path("/proc/self/maps").read_text().splitlines()
package = pathlib.Path(setbound.__file__).resolve().parent
for so in sonames:
    stem = so.split(".so", 1)[0]
    paths = {line.split()[-1] for line in maps if pathlib.Path(line.split()[-1]).name.startswith(stem)}
    if not paths or not all(pathlib.Path(p).parent == package.parent / "setbound.libs" for p in paths):
        sys.exit(f"check-bundled: {so} mapped from {sorted(paths)}, not from the wheel's setbound.libs")
print(f"check-bundled: setbound {setbound.__version__} ran with the system's "
      f"{', '.join(sonames)} hidden, using the wheel's own copies")
