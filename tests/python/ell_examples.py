"""The ellipsoidal papers' example systems (papers.md §1.4, §2.5, §4.2) and a generator of
random detectable systems, shared by the ellipsoidal tests."""
import numpy as np

import setbound as sb


def ex_bc14() -> sb.LinearSystem:
    """EX-BC14 (papers.md §1.4): 3 states, 2 outputs, 5 disturbances."""
    A = [[1, 0, 0.2], [0, 0.8, 1], [0, 0, 1]]
    E = [[0.1, 0, 0, 0, 0], [0, 0.05, 0, 0, 0], [0, 0, 0.05, 0, 0]]
    C = [[1, 0, 2], [0, -1, 1]]
    F = [[0, 0, 0, 0.15, 0], [0, 0, 0, 0, 0.15]]
    return sb.LinearSystem(A, C, E=E, F=F)


def ex_me17(stable: bool = True) -> sb.LinearSystem:
    """EX-ME17a (stable) / EX-ME17b (unstable) (papers.md §2.5)."""
    A = [[-0.8, 0.2], [-0.3, 0.1]] if stable else [[-1.5, 0.2], [-0.3, 0.1]]
    return sb.LinearSystem(A, [[-2.0, 1.0]], E=[[-0.12, 0.0], [0.02, 0.0]], F=[[0.0, 0.2]])


def ex_me19() -> sb.DescriptorSystem:
    """EX-ME19 (papers.md §4.2)."""
    E = np.diag([1.0, 1.0, 0.0])
    A = [[0.5, 0, 0], [0.8, 0.95, 0], [-1, 0.5, 1]]
    B = [[1, 0], [0, 1], [0, 0]]
    C = [[1, 0, 1], [1, -1, 0]]
    D = [[0.1, 0, 0, 0, 0], [0, 1.5, 0, 0, 0], [0, 0, 0.6, 0, 0]]
    F = [[0, 0, 0, 0.5, 0], [0, 0, 0, 0, 1.5]]
    return sb.DescriptorSystem(E, A, C, B=B, D=D, F=F)


def me19_inputs(N: int) -> np.ndarray:
    t = np.linspace(0.0, 5 * np.pi, N)
    return np.column_stack([0.5 * np.sin(t) + 1.0, -2.0 * np.cos(t)])


def random_detectable_systems(count: int, seed: int):
    """`count` random detectable systems (half with an unstable A), n_x 2..4, n_y 1..2: a state
    disturbance of 1..3 columns that reaches the outputs too in one system out of three (coupled,
    E and F both non-zero), plus independent output noise 0.1·I, as the papers stack ω = [w; v].

    Without its own output noise a system can have a gain with E − L F = 0 (the disturbance is
    cancelled exactly); its minimum-volume design is then unbounded — see the design tests."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        nx = int(rng.integers(2, 5))
        ny = int(rng.integers(1, 3))
        nw = int(rng.integers(1, 4))
        A = rng.standard_normal((nx, nx))
        target = rng.uniform(1.02, 1.3) if len(out) % 2 else rng.uniform(0.4, 0.95)
        A *= target / max(abs(np.linalg.eigvals(A)))
        C = rng.standard_normal((ny, nx))
        Ew = 0.1 * rng.standard_normal((nx, nw))
        Fw = 0.1 * rng.standard_normal((ny, nw)) if len(out) % 3 == 0 else np.zeros((ny, nw))
        E = np.hstack([Ew, np.zeros((nx, ny))])
        F = np.hstack([Fw, 0.1 * np.eye(ny)])
        sys_ = sb.LinearSystem(A, C, E=E, F=F)
        if not sys_.is_detectable():
            continue
        # Keep systems whose observer can really be tuned (well-conditioned observability).
        O = np.vstack([C @ np.linalg.matrix_power(A, k) for k in range(nx)])
        if np.linalg.svd(O, compute_uv=False)[-1] < 0.05:
            continue
        out.append(sys_)
    return out
