"""Job files (setbound.config): malformed files give messages that name the key, the registry
of estimator and system kinds, measured data from CSV/NPZ. (The examples run end to end in
test_cli.py.)"""

import numpy as np
import pytest

from setbound import cli, config

BASE = """
[system]
A = [[0.5, 0.1], [0, 0.7]]
C = [[1, 0]]
E = [[0.1, 0], [0, 0.1]]
F = [[0, 0.1]]
[initial]
center = [0, 0]
rho = 1.0
[simulation]
horizon = 5
[[estimator]]
method = "offline"
"""


def load_text(tmp_path, text):
    p = tmp_path / "job.toml"
    p.write_text(text)
    return config.load(p)


def test_base_is_valid(tmp_path):
    job = load_text(tmp_path, BASE)
    assert job.y.shape == (5, 1)


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[0.5, 0.1], [0]]"), r"system\.A: expected a numeric"),
    (lambda t: t.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[0.5, 0.1, 0], [0, 0.7, 0]]"), r"system\.A: must be square"),
    (lambda t: t.replace("C = [[1, 0]]", "C = [[1, 0, 0]]"), r"system\.C: expected shape"),
    (lambda t: t.replace("C = [[1, 0]]\n", ""), r"system\.C: missing"),
    (lambda t: t.replace("F = [[0, 0.1]]", 'F = "zero"'), r"system\.F: expected a numeric"),
    (lambda t: t.replace("[system]", "[system]\nAA = 1"), r"system\.AA: unknown key"),
    (lambda t: t.replace("[system]", '[system]\nkind = "quadratic"'), r"system\.kind"),
    (lambda t: t.replace("rho = 1.0", "rho = -1.0"), r"initial\.rho: expected a number in \(0, inf\)"),
    (lambda t: t.replace("center = [0, 0]", "center = [0, 0, 0]"), r"initial\.center: expected shape"),
    (lambda t: t.replace("horizon = 5", "horizon = 0"), r"simulation\.horizon"),
    (lambda t: t.replace("horizon = 5", 'horizon = 5\ndisturbance = "laplace"'), r"simulation\.disturbance"),
    (lambda t: t.replace('method = "offline"', 'method = "magic"'), r"estimator\[0\]\.method: unknown method"),
    (lambda t: t.replace('method = "offline"', 'method = "offline"\nspeed = 3'), r"estimator\[0\]\.speed: unknown key"),
    (lambda t: t.replace('method = "offline"', 'method = "descriptor"'), r"estimator\[0\]\.method: 'descriptor' does not apply"),
    (lambda t: t.replace("[[estimator]]\nmethod = \"offline\"\n", ""), r"estimator: at least one"),
    (lambda t: t.replace("[simulation]\nhorizon = 5\n", ""), r"job: exactly one of \[simulation\] and \[data\]"),
    (lambda t: t + "[data]\nfile = 'x.csv'\n", r"job: exactly one of"),
    (lambda t: t.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[0.5, nan], [0, 0.7]]"), r"system\.A\[0\]\[1\]: not a finite number"),
    (lambda t: t.replace("[[estimator]]", "[[estimator]]\nmethod = \"online\"\n[[estimator]]\nname = \"online\""),
     r"estimator\[1\]\.name: duplicate"),
    (lambda t: t.replace("[simulation]\nhorizon = 5\n", "[data]\nfile = 'missing.csv'\n"), r"data\.file: no such file"),
    (lambda t: t.replace("horizon = 5", "horizon = 5\ninputs = ['sin(t)']"), r"simulation\.inputs: the system has no input"),
    (lambda t: t + "extra = 1\n", None),  # a key inside [[estimator]] (TOML puts it there)
    (lambda t: "title = 3\n[system\n", r"not valid TOML"),
    # [plots] and estimator names (keys added with the plots of `setbound run`)
    (lambda t: t.replace("[[estimator]]", "[plots]\nreference = 'online'\n[[estimator]]"),
     r"plots\.reference: 'online' is not the name of an estimator"),
    (lambda t: t.replace("[[estimator]]", "[plots]\nsteps = [0, 5]\n[[estimator]]"), r"plots\.steps\[1\]: expected an integer in \[0, 4\], got 5"),
    (lambda t: t.replace("[[estimator]]", "[plots]\nsteps = []\n[[estimator]]"), r"plots\.steps: expected a non-empty"),
    (lambda t: t.replace("[[estimator]]", "[plots]\ndims = [0, 0]\n[[estimator]]"), r"plots\.dims: expected two distinct"),
    (lambda t: t.replace("[[estimator]]", "[plots]\ndims = [0, 2]\n[[estimator]]"), r"plots\.dims\[1\]: expected an integer in \[0, 1\]"),
    (lambda t: t.replace("[[estimator]]", "[plots]\nenabled = 'yes'\n[[estimator]]"), r"plots\.enabled: expected true or false"),
    (lambda t: t.replace("[[estimator]]", "[plots]\ncolour = 'red'\n[[estimator]]"), r"plots\.colour: unknown key"),
    (lambda t: t.replace('method = "offline"', 'method = "offline"\nname = "a/b"'), r"estimator\[0\]\.name: must be"),
    (lambda t: t.replace('method = "offline"', 'method = "segment_min"\nreduction = 3'), r"estimator\[0\]\.reduction: expected one of 'combastel'"),
    (lambda t: t.replace('method = "offline"', 'method = "offline"\nbeta = 1.5'), r"estimator\[0\]\.beta: expected a number in \(0, 1\)"),
    (lambda t: t.replace('method = "offline"', 'method = "pradius"\napproach = 3'), r"estimator\[0\]\.approach: expected one of 1, 2"),
    # explicit bounds of omega
    (lambda t: t.replace("F = [[0, 0.1]]", "F = [[0, 0.1]]\nomega = {lower = [0, 1], upper = [1, 0]}"),
     r"system\.omega\.lower: entry 1 is above system\.omega\.upper"),
    (lambda t: t.replace("F = [[0, 0.1]]", "F = [[0, 0.1]]\nomega = {lower = [0], upper = [1]}"),
     r"system\.omega\.lower: expected shape \(2,\)"),
    (lambda t: t.replace("F = [[0, 0.1]]", "F = [[0, 0.1]]\nomega = {lower = [0, 0], upper = [1, 1], center = [0, 0]}"),
     r"system\.omega: give a box"),
    (lambda t: t.replace("F = [[0, 0.1]]", "F = [[0, 0.1]]\nomega = {center = [0, 0]}"), r"system\.omega\.generators: missing"),
    (lambda t: t.replace("F = [[0, 0.1]]", "F = [[0, 0.1]]\nomega = {radius = 1}"), r"system\.omega\.radius: unknown key"),
])
def test_malformed_files_name_the_key(tmp_path, edit, message):
    text = edit(BASE)
    if message is None:  # 'extra' lands in the last table
        message = r"estimator\[0\]\.extra: unknown key"
    with pytest.raises(config.ConfigError, match=message):
        load_text(tmp_path, text)


def test_cli_reports_errors_with_exit_code_2(tmp_path, capsys):
    p = tmp_path / "bad.toml"
    p.write_text(BASE.replace("rho = 1.0", "rho = 'big'"))
    assert cli.main(["check", str(p)]) == 2
    assert "initial.rho" in capsys.readouterr().err


def test_expressions_of_t(tmp_path):
    t = np.linspace(0, 1, 5)
    np.testing.assert_allclose(config.eval_expression("0.5*sin(t) + 1", t, "k"), 0.5 * np.sin(t) + 1)
    np.testing.assert_allclose(config.eval_expression("-2*cos(pi*t)**2", t, "k"), -2 * np.cos(np.pi * t) ** 2)
    for bad in ("__import__('os')", "t.real", "x + 1", "lambda: 1", "[1, 2]"):
        with pytest.raises(config.ConfigError, match="k:"):
            config.eval_expression(bad, t, "k")


def test_data_files(tmp_path):
    """Measured data: NPZ (arrays y, u, x) and CSV (columns y0…, u0…, x0…) files."""
    rng = np.random.default_rng(0)
    y = rng.standard_normal((7, 1))
    np.savez(tmp_path / "run.npz", y=y)
    job = load_text(tmp_path, BASE.replace("[simulation]\nhorizon = 5\n", "[data]\nfile = 'run.npz'\n"))
    np.testing.assert_array_equal(job.y, y)
    assert job.x_true is None
    (tmp_path / "run.csv").write_text("y0,x0,x1\n" + "\n".join(f"{v},0,0" for v in y[:, 0]) + "\n")
    job = load_text(tmp_path, BASE.replace("[simulation]\nhorizon = 5\n", "[data]\nfile = 'run.csv'\n"))
    np.testing.assert_allclose(job.y, y)
    assert job.x_true.shape == (7, 2)


def test_plots_table(tmp_path):
    job = load_text(tmp_path, BASE.replace("[[estimator]]", "[plots]\nreference = 'offline'\nsteps = [1, 4]\n"
                                                              "dims = [1, 0]\nenabled = false\n[[estimator]]"))
    assert job.plots == config.PlotSpec(reference="offline", steps=[1, 4], dims=(1, 0), enabled=False)
    assert load_text(tmp_path, BASE).plots == config.PlotSpec()


def test_registry_adds_a_system_kind_and_an_estimator_in_one_place(tmp_path, request):
    """A new model kind and a new estimator kind are usable from job files once registered."""
    from setbound import LinearSystem, Trajectory

    # the registries are the shared dicts of setbound.jobs.registry: restore their contents after
    for d in (config.SYSTEMS, config.ESTIMATORS, config.METHODS):
        request.addfinalizer(lambda d=d, saved=dict(d): (d.clear(), d.update(saved)))

    class Scalar(LinearSystem):
        pass

    def build_scalar(tab):
        a = tab["a"]
        if not isinstance(a, (int, float)):
            raise config.ConfigError(f"system.a: must be a number, got {a!r}")
        return Scalar([[a]], [[1.0]], E=[[0.1, 0.0]], F=[[0.0, 0.1]])

    class Hold:
        """Returns the measurement ± the noise bound: guaranteed for y = x + 0.1 v."""

        def run(self, y, u=None):
            y = np.asarray(y, float)
            return Trajectory(y.copy(), y - 0.1, y + 0.1, [])

    config.register_system("scalar", {"a"}, build_scalar, Scalar)
    config.register_estimator("hold", "test", {"margin": 0.0}, lambda job, o: (Hold(), None),
                              systems=("scalar", "linear"))
    text = """
[system]
kind = "scalar"
a = 0.9
[initial]
center = [0]
rho = 1.0
[simulation]
horizon = 6
seed = 3
[[estimator]]
method = "hold"
[[estimator]]
method = "segment_min"
"""
    with pytest.raises(config.ConfigError, match=r"estimator\[1\]\.method: 'segment_min' does not apply to a "
                                                 r"scalar system"):
        load_text(tmp_path, text)
    job = load_text(tmp_path, text.replace('[[estimator]]\nmethod = "segment_min"\n', ""))
    assert job.system_kind == "scalar" and isinstance(job.system, Scalar)
    assert config.METHODS["hold"] == ("test", {"margin": 0.0})
    (res,) = config.run(job)
    assert res.ok and res.contained is True
    with pytest.raises(config.ConfigError, match=r"system\.a: must be a number"):
        load_text(tmp_path, text.replace("a = 0.9", "a = 'x'"))
    with pytest.raises(config.ConfigError, match=r"system\.kind: expected one of 'linear', 'descriptor', .*'scalar', got 'other'"):
        load_text(tmp_path, text.replace('kind = "scalar"', 'kind = "other"'))
    with pytest.raises(ValueError, match="already registered"):
        config.register_estimator("hold", "test", {}, lambda job, o: (Hold(), None))


def test_every_registered_estimator_is_documented_and_buildable():
    assert {"offline", "online", "scaled", "improved", "descriptor", "kalman", "segment_min", "volume_min",
            "pradius"} <= set(config.ESTIMATORS)
    for name, kind in config.ESTIMATORS.items():
        assert kind.description and kind.systems and set(kind.systems) <= set(config.SYSTEMS), name
        assert config.METHODS[name] == (kind.family, kind.options)


@pytest.mark.parametrize("bounds", ["box", "zonotope"])
def test_explicit_omega_bounds_are_converted_exactly_and_contain_the_truth(tmp_path, bounds):
    """[system.omega]: ω in a non-centred box or zonotope. The converted unit-box model, driven by
    measurements of the ORIGINAL model with ω at the vertices of its bounds, contains the truth."""
    E = np.array([[0.1, 0.0], [0.0, 0.1]])
    F = np.array([[0.0, 0.1]])
    if bounds == "box":
        spec = "omega = {lower = [0.5, -1.0], upper = [1.5, 2.0]}"
        c, G = np.array([1.0, 0.5]), np.diag([0.5, 1.5])
    else:
        spec = "omega = {center = [1.0, 0.5], generators = [[0.5, 0.2], [0.0, 1.5]]}"
        c, G = np.array([1.0, 0.5]), np.array([[0.5, 0.2], [0.0, 1.5]])
    text = BASE.replace("F = [[0, 0.1]]", "F = [[0, 0.1]]\n" + spec).replace(
        '[[estimator]]\nmethod = "offline"\n', '[[estimator]]\nmethod = "offline"\n[[estimator]]\nmethod = "segment_min"\n')
    job = load_text(tmp_path, text)
    s = job.system
    assert job.constant_input and s.nu == 1
    np.testing.assert_allclose(s.E, E @ G)
    np.testing.assert_allclose(s.F, F @ G)
    np.testing.assert_allclose(s.B[:, 0], E @ c)
    np.testing.assert_allclose(s.D[:, 0], F @ c)
    np.testing.assert_array_equal(job.u, np.ones((5, 1)))
    assert all(r.contained for r in config.run(job))
    # independent truth: the original model, ω at vertices of its bounds (box corners / zonotope vertices)
    rng = np.random.default_rng(7)
    A = np.array([[0.5, 0.1], [0, 0.7]])
    N = 40
    x = np.empty((N, 2))
    y = np.empty((N, 1))
    x[0] = [0.3, -0.2]
    for k in range(N):
        w = c + G @ rng.choice([-1.0, 1.0], size=G.shape[1])
        y[k] = F @ w + x[k, :1]  # C = [1, 0]
        if k + 1 < N:
            x[k + 1] = A @ x[k] + E @ w
    job.y, job.u, job.x_true = y, np.ones((N, 1)), x
    job.t = np.arange(N, dtype=float)
    for r in config.run(job):
        assert r.contained is True, r.name


# ---------------------------------------------------------------- the import graph (issue 26 point 8)
def _import_graph():
    """``module -> set of setbound modules it imports`` (at module level or inside functions),
    read from the sources with ast, so a circle hidden in a function-level import counts too."""
    import ast
    from pathlib import Path

    import setbound

    root = Path(setbound.__file__).resolve().parent
    modules = {}
    for f in root.rglob("*.py"):
        rel = f.relative_to(root).with_suffix("")
        parts = ["setbound", *rel.parts]
        is_pkg = parts[-1] == "__init__"
        if is_pkg:
            parts = parts[:-1]
        modules[".".join(parts)] = (f, is_pkg)
    graph = {}
    for name, (f, is_pkg) in modules.items():
        package = name if is_pkg else name.rsplit(".", 1)[0]
        deps = set()
        for node in ast.walk(ast.parse(f.read_text(), str(f))):
            if isinstance(node, ast.Import):
                deps.update(a.name for a in node.names if a.name.startswith("setbound"))
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")
                    base = base[:len(base) - (node.level - 1)]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if not target.startswith("setbound"):
                    continue
                for a in node.names:  # `from . import x`: the submodule x when there is one
                    sub = f"{target}.{a.name}"
                    deps.add(sub if sub in modules else target)
        graph[name] = {d for d in deps if d in modules and d != name}
    return graph


def _cycles(graph):
    """The strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


JOB_MODULES = ("setbound.config", "setbound.thesis_jobs", "setbound.cli", "setbound.demo", "setbound.report",
               "setbound.campaign", "setbound.__main__", "setbound._validate")


def test_job_modules_import_each_other_one_way():
    """No import circle through the job-file, CLI and demo modules: config/thesis_jobs are
    façades over setbound.jobs, whose modules are layered; the CLI and the demo share the
    writers of setbound.report instead of importing each other."""
    graph = _import_graph()
    assert "setbound.jobs.loader" in graph and "setbound.report" in graph
    mine = [c for c in _cycles(graph) if any(m in JOB_MODULES or m.startswith("setbound.jobs") for m in c)]
    assert mine == [], f"import circles: {mine}"
    # the layering the package docstring states
    assert "setbound.cli" not in graph["setbound.demo"] and "setbound.demo" not in graph["setbound.report"]
    assert not any(d.startswith(("setbound.config", "setbound.thesis_jobs", "setbound.cli"))
                   for m, deps in graph.items() if m.startswith("setbound.jobs") for d in deps)
    assert graph["setbound.jobs.schema"] <= {"setbound._validate", "setbound.errors"}


def test_cycle_finder_finds_a_circle():
    """The check above can fail: a planted circle is found."""
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
