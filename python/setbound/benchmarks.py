"""Loaders for literature benchmark data: CORA's ``linearSysDT`` observer examples.

CORA's model (its README): ``x(k+1) = A x(k) + B u(k) + c + w(k)``, ``w ∈ W``;
``y(k) = C x(k) + D u(k) + v(k)``, ``v ∈ V``; ``x(0) ∈ R0``, with ``W``, ``V``, ``R0``
zonotopes (centre + generators). In setbound's form the disturbance is stacked,
``ω = [w; v]`` with ``E = [G_W, 0]`` and ``F = [0, G_V]``, and the constant terms ``c + c_W``
and ``c_V`` enter as one extra input column whose input is always 1. Columns of CORA's
``u``/``y`` are time steps; here rows are (the library's time indexing: row k is step k).
CORA's loop intersects R0 with y(:,1) first, which is ``use_first_measurement=True``, and
reduces after the strips of every step with its zonotope order and reduction technique
(:meth:`CoraBenchmark.estimator_options`).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .sets import Zonotope
from .system import LinearSystem


@dataclass
class CoraBenchmark:
    """One of CORA's observer examples (``linearSysDT/observe``), as setbound objects.

    Parameters
    ----------
    name : str
        Example name.
    system : LinearSystem
        The model.
    x0 : Zonotope
        Initial set.
    y : ndarray, shape (N, n_y)
        Measurements.
    u : ndarray, shape (N, n_u + 1)
        CORA's inputs and the constant 1.
    truth : ndarray, shape (N, n_x) or None
        True trajectory (3 decimals) when the file has one.
    zonotope_order : float
        CORA's zonotope order.
    reduction : str
        CORA's reduction method.
    golden : dict, optional
        CORA's saved results per observer: ``(lower, upper)`` arrays.
    dt : float, optional
        Sampling time.
    c : ndarray, shape (n_x,), optional
        CORA's constant term ``c`` of the dynamics (in ``B``'s last column with ``W``'s centre);
        None when unknown.
    v_center : ndarray, shape (n_y,), optional
        The centre of ``V`` (``D``'s last column); None when unknown.
    """
    name: str
    system: LinearSystem
    x0: Zonotope
    y: np.ndarray  # (N, n_y)
    u: np.ndarray  # (N, n_u + 1): CORA's inputs and the constant 1
    truth: np.ndarray | None  # (N, n_x) when the file has a true trajectory (3 decimals)
    zonotope_order: float
    reduction: str
    golden: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    dt: float = 1.0
    c: np.ndarray | None = None
    v_center: np.ndarray | None = None

    @property
    def max_generators(self) -> int:
        """CORA's zonotope order as a generator count."""
        return max(int(self.zonotope_order * self.system.nx), self.system.nx)

    @property
    def reduction_method(self) -> str:
        """CORA's reduction technique as the estimators' ``reduction`` keyword (``"pca"`` or
        ``"girard"``, CORA's default)."""
        return "pca" if self.reduction.startswith("pca") else "girard"

    def estimator_options(self) -> dict:
        """Keyword arguments that run setbound's zonotopic estimators with CORA's settings."""
        return {"max_generators": self.max_generators, "reduction": self.reduction_method}


def _golden(d) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    out = {}
    for k, v in d.get("golden_final_interval_hull", {}).get("values", {}).items():
        if isinstance(v, dict):
            out[k] = (np.asarray(v["lower"], float).ravel(), np.asarray(v["upper"], float).ravel())
        else:
            a = np.asarray(v, float)  # [lower; upper]
            out[k] = (a[0], a[1])
    return out


def load_cora(path: str | Path) -> CoraBenchmark:
    """Reads one JSON file of CORA's observer examples (see the data's README).

    Parameters
    ----------
    path : str or Path
        The JSON file.

    Returns
    -------
    CoraBenchmark
    """
    path = Path(path)
    d = json.loads(path.read_text())
    A = np.asarray(d["A"], float)
    n = A.shape[0]
    C = np.atleast_2d(np.asarray(d["C"], float))
    ny = C.shape[0]
    B = np.asarray(d["B"], float).reshape(n, -1)
    c = np.asarray(d.get("c", np.zeros(n)), float).reshape(n)
    Wc = np.asarray(d["W"]["center"], float).reshape(n)
    Wg = np.asarray(d["W"]["generators"], float).reshape(n, -1)
    Vc = np.asarray(d["V"]["center"], float).reshape(ny)
    Vg = np.asarray(d["V"]["generators"], float).reshape(ny, -1)
    D = np.asarray(d["D"], float).reshape(ny, -1) if "D" in d else np.zeros((ny, B.shape[1]))
    nw, nv = Wg.shape[1], Vg.shape[1]
    E = np.hstack([Wg, np.zeros((n, nv))])
    F = np.hstack([np.zeros((ny, nw)), Vg])
    system = LinearSystem(A, C, B=np.hstack([B, (c + Wc)[:, None]]), D=np.hstack([D, Vc[:, None]]), E=E, F=F)
    u = np.asarray(d["u"], float).reshape(B.shape[1], -1).T
    y = np.asarray(d["y"], float).reshape(ny, -1).T
    x0 = Zonotope(np.asarray(d["R0"]["center"], float).reshape(n),
                  np.asarray(d["R0"]["generators"], float).reshape(n, -1))
    truth = np.asarray(d["traj_x"], float) if "traj_x" in d else None
    return CoraBenchmark(
        name=path.stem, system=system, x0=x0, y=y, u=np.hstack([u, np.ones((u.shape[0], 1))]), truth=truth,
        zonotope_order=float(d.get("zonotopeOrder", 20)), reduction=str(d.get("reductionTechnique", "girard")),
        golden=_golden(d), dt=float(d.get("dt", d.get("timeStep", 1.0))), c=c, v_center=Vc)
