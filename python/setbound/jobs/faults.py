"""The fault tables of a job (issue 24, :mod:`setbound.fault`): ``[[fault]]`` injects a fault into
the simulated plant, ``[[hypothesis]]`` adds a model to the isolation bank.

::

    [[fault]]                 # the simulated plant's sensor 0 is off by +0.8 from step 120 on
    kind = "sensor_bias"      # sensor_bias | stuck_sensor | actuator_loss | parameter_change
    output = 0                # sensor faults: the output; actuator_loss: input = j
    start = 120
    magnitude = 0.8           # bias; lost fraction (actuator_loss); stuck value (with value = true)

    [[hypothesis]]            # the isolation bank (segment minimisation per hypothesis)
    kind = "sensor_bias"      # nominal | sensor_bias | stuck_sensor | actuator_loss | parameter_change
    output = 0
    bound = 2.0               # sensor_bias: |bias| <= bound; actuator_loss: max_loss, u_max;
                              # parameter_change: A = [[...]]; name = "..." (optional)

Every estimator of the job that tests its readings is a detector: its alarm is its first flagged
step. Faults need a ``[simulation]`` of a ``linear`` system with a known ``A``.
"""
from __future__ import annotations

import numpy as np

from .schema import ConfigError, as_choice, as_float, as_int, check_keys, matrix, require

__all__ = ["parse_faults", "parse_hypotheses"]

_HYPOTHESES = ("nominal", "sensor_bias", "stuck_sensor", "actuator_loss", "parameter_change")


def _tables(lst, name: str) -> list:
    if lst is None:
        return []
    if isinstance(lst, dict):
        lst = [lst]
    if not isinstance(lst, list) or not all(isinstance(t, dict) for t in lst):
        raise ConfigError(f"{name}: expected [[{name}]] tables")
    return lst


def _index(t: dict, key: str, where: str, size: int, what: str) -> int:
    i = as_int(require(t, key, where), f"{where}.{key}", lo=0)
    if i >= size:
        raise ConfigError(f"{where}.{key}: {i} is out of range, the system has {size} {what}")
    return i


def parse_faults(lst, system, system_kind: str, has_simulation: bool) -> list:
    """The ``[[fault]]`` tables as :class:`setbound.fault.Fault` objects (validated against
    ``system``)."""
    from ..fault import FAULT_KINDS, Fault

    tables = _tables(lst, "fault")
    if not tables:
        return []
    if not has_simulation:
        raise ConfigError("fault: faults are injected into a simulated plant; a job with [data] has none")
    if system_kind != "linear" or getattr(system, "uncertain_A", False):
        raise ConfigError("fault: faults need a [simulation] of a linear system with a known A")
    out = []
    for n, t in enumerate(tables):
        where = f"fault[{n}]"
        check_keys(t, {"kind", "start", "output", "input", "magnitude", "delta_A", "value"}, where)
        kind = as_choice(require(t, "kind", where), f"{where}.kind", FAULT_KINDS)
        start = as_int(require(t, "start", where), f"{where}.start", lo=0)
        kw = {"kind": kind, "start": start}
        if kind in ("sensor_bias", "stuck_sensor"):
            kw["output"] = _index(t, "output", where, system.ny, "outputs")
        if kind == "actuator_loss":
            kw["input"] = _index(t, "input", where, system.nu, "inputs")
        if kind == "parameter_change":
            kw["delta_A"] = matrix(require(t, "delta_A", where), f"{where}.delta_A", shape=(system.nx, system.nx))
        if kind == "stuck_sensor" and "value" in t:
            kw["magnitude"], kw["value_given"] = as_float(t["value"], f"{where}.value"), True
        elif kind == "sensor_bias":
            kw["magnitude"] = as_float(require(t, "magnitude", where), f"{where}.magnitude")
        elif kind == "actuator_loss":
            kw["magnitude"] = as_float(require(t, "magnitude", where), f"{where}.magnitude", lo=0.0, hi=1.0)
        unused = {"output", "input", "magnitude", "delta_A", "value"} & set(t) - {
            "sensor_bias": {"output", "magnitude"}, "stuck_sensor": {"output", "value"},
            "actuator_loss": {"input", "magnitude"}, "parameter_change": {"delta_A"}}[kind]
        if unused:
            raise ConfigError(f"{where}: {', '.join(sorted(unused))} does not apply to a {kind} fault")
        out.append(Fault(**kw))
    return out


def parse_hypotheses(lst, system, system_kind: str, initial) -> list:
    """The ``[[hypothesis]]`` tables as :class:`setbound.fault.Hypothesis` objects."""
    from .. import fault
    from .linear import zonotopic_initial

    tables = _tables(lst, "hypothesis")
    if not tables:
        return []
    if system_kind != "linear":
        raise ConfigError("hypothesis: the isolation bank needs a linear system")
    x0 = zonotopic_initial(initial)
    out = []
    for n, t in enumerate(tables):
        where = f"hypothesis[{n}]"
        check_keys(t, {"kind", "name", "output", "input", "bound", "max_loss", "u_max", "A"}, where)
        kind = as_choice(require(t, "kind", where), f"{where}.kind", _HYPOTHESES)
        name = t.get("name")
        if name is not None and (not isinstance(name, str) or not name):
            raise ConfigError(f"{where}.name: expected a non-empty string")
        allowed = {"nominal": set(), "sensor_bias": {"output", "bound"}, "stuck_sensor": {"output"},
                   "actuator_loss": {"input", "max_loss", "u_max"}, "parameter_change": {"A"}}[kind]
        unused = {"output", "input", "bound", "max_loss", "u_max", "A"} & set(t) - allowed
        if unused:
            raise ConfigError(f"{where}: {', '.join(sorted(unused))} does not apply to a {kind} hypothesis")
        try:
            if kind == "nominal":
                h = fault.nominal(system, x0, name=name or "nominal")
            elif kind == "sensor_bias":
                h = fault.sensor_bias(system, x0, _index(t, "output", where, system.ny, "outputs"),
                                      as_float(require(t, "bound", where), f"{where}.bound", lo=0.0, lo_open=True),
                                      name=name)
            elif kind == "stuck_sensor":
                h = fault.stuck_sensor(system, x0, _index(t, "output", where, system.ny, "outputs"), name=name)
            elif kind == "actuator_loss":
                h = fault.actuator_loss(system, x0, _index(t, "input", where, system.nu, "inputs"),
                                        as_float(require(t, "max_loss", where), f"{where}.max_loss", lo=0.0, hi=1.0),
                                        as_float(require(t, "u_max", where), f"{where}.u_max", lo=0.0), name=name)
            else:
                A = matrix(require(t, "A", where), f"{where}.A", shape=(system.nx, system.nx))
                h = fault.parameter_change(system, x0, A, name=name or "parameter_change")
        except ConfigError:
            raise
        except Exception as exc:  # a library error (e.g. a system it cannot build): name the table
            raise ConfigError(f"{where}: {exc}") from None
        out.append(h)
    names = [h.name for h in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ConfigError(f"hypothesis: the names must be distinct ({', '.join(dup)} twice; set name = \"...\")")
    return out


def fault_lines(job) -> list[str]:
    """Report lines: the injected faults and the isolation result."""
    lines = []
    for f in job.faults:
        where = (f"y{f.output}" if f.output is not None else f"u{f.input}" if f.input is not None else "A")
        if f.kind == "sensor_bias":
            what = f"bias {f.magnitude:+g}"
        elif f.kind == "stuck_sensor":
            what = "stuck" + (f" at {f.magnitude:g}" if f.value_given else " at its last reading")
        elif f.kind == "actuator_loss":
            what = f"{100 * f.magnitude:g} % effectiveness lost"
        else:
            what = f"A changed by up to {np.abs(np.asarray(f.delta_A)).max():g} per entry"
        lines.append(f"fault: {f.kind} on {where} from step {f.start} ({what})")
    if job.faults:
        lines.append(f"  (truth inside: checked on steps 0 … {job.fault_start - 1}, where the model holds)")
    if job.isolation is not None:
        lines.append("isolation (hypotheses still consistent with the data at the end):")
        lines += ["  " + ln for ln in job.isolation.table().splitlines()]
    return lines
