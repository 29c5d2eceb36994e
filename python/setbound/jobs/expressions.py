"""The expressions of job files (inputs ``u(t)``, the thesis kinds' ``h(p, x, k)``, scheduling
signals, disturbance profiles): an AST whitelist evaluated in float64.

A job file is input from anyone, so an expression is bounded before it is evaluated: at most
:data:`MAX_LENGTH` characters, :data:`MAX_NODES` syntax nodes and :data:`MAX_DEPTH` levels of
nesting (a chain of 100 000 minus signs or terms is refused, not fed to a recursive
evaluator), literals within the float range (a 400-digit integer is refused), and arithmetic
in numpy float64, never in Python integers: ``10**10**10`` cannot run for ever or allocate a
huge integer, it overflows and is reported. Sub-expressions without variables are evaluated
once when the expression is compiled, so ``1/0`` or ``(-1)**0.5`` is refused at load time;
a failure that depends on the variables (``1/(k-2)`` at k = 2) is reported by
:func:`evaluate` with the key, the step and the cause (division by zero, overflow, an invalid
operation), never as a Python exception or a silent NaN.
"""
from __future__ import annotations

import ast
import math
from typing import Any, Callable

import numpy as np

from .schema import ConfigError, describe

__all__ = ["compile_expression", "eval_expression", "evaluate", "MAX_LENGTH", "MAX_NODES", "MAX_DEPTH"]

#: Longest expression (characters). Longer ones are refused before parsing.
MAX_LENGTH = 1000
#: Most syntax nodes of one expression.
MAX_NODES = 200
#: Deepest nesting of operators and calls.
MAX_DEPTH = 32

_BINOPS = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.true_divide,
           ast.Pow: np.power}
_FUNCS = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "sqrt": np.sqrt, "abs": np.abs,
          "log": np.log, "sign": np.sign, "floor": np.floor, "tanh": np.tanh}
_CONSTS = {"pi": math.pi, "e": math.e}

# numpy's floating-point error words -> the user's
_CAUSES = (("divide by zero", "division by zero"),
           ("overflow", "overflow (a value beyond ±1.8e308)"),
           ("invalid value", "an invalid operation (0/0, inf − inf, the square root or logarithm of a negative "
                             "number, a negative number to a fractional power)"))


def _cause(exc: FloatingPointError) -> str:
    msg = str(exc)
    for word, text in _CAUSES:
        if word in msg:
            return text
    return msg


def _short(expr: str) -> str:
    return describe(expr, 60)


def compile_expression(expr: str, key: str, names=("t",)) -> Callable[[dict], Any]:
    """Parses a simple expression once and returns ``f(env)`` evaluating it with the variables of
    ``env`` (a dict name -> number or array). Allowed: numbers, the variables ``names``, + − * /
    ``**``, sin cos tan exp sqrt abs log sign floor tanh, pi, e; nothing else (an AST whitelist, no
    attribute access, no other calls), within the bounds of the module docstring. ``f`` returns
    float64 values; a non-finite result is for the caller to report (see :func:`evaluate`).
    Errors are :class:`ConfigError` naming ``key``.

    Parameters
    ----------
    expr : str
        The expression.
    key : str
        Job-file key (for messages).
    names : tuple of str, optional
        Allowed variables.

    Returns
    -------
    callable

    Examples
    --------
    >>> f = setbound.jobs.compile_expression("0.5*sin(t) + 1", "inputs")
    >>> float(f({"t": 0.0}))
    1.0
    """
    if not isinstance(expr, str):
        raise ConfigError(f"{key}: expected an expression (a string), got {describe(expr)}")
    if len(expr) > MAX_LENGTH:
        raise ConfigError(f"{key}: the expression is {len(expr)} characters long (at most {MAX_LENGTH})")
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as exc:
        raise ConfigError(f"{key}: cannot parse the expression {_short(expr)} ({exc.msg})") from None
    except (RecursionError, MemoryError, ValueError):  # the parser's own limits (nesting, null bytes)
        raise ConfigError(f"{key}: cannot parse the expression {_short(expr)} (too deeply nested)") from None
    allowed = tuple(names)

    # validate once, iteratively (a hostile tree must not exhaust the stack of the check itself)
    count, stack = 0, [(tree.body, 1)]
    while stack:
        node, depth = stack.pop()
        count += 1
        if count > MAX_NODES:
            raise ConfigError(f"{key}: the expression {_short(expr)} has more than {MAX_NODES} terms and operators")
        if depth > MAX_DEPTH:
            raise ConfigError(f"{key}: the expression {_short(expr)} is nested more than {MAX_DEPTH} levels deep")
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            try:
                v = float(node.value)
            except OverflowError:
                v = math.inf
            if not math.isfinite(v):
                raise ConfigError(f"{key}: a number in {_short(expr)} is beyond the floating-point range (±1.8e308): "
                                  f"{describe(node.value)}")
            continue
        if isinstance(node, ast.Name):
            if node.id in allowed or node.id in _CONSTS:
                continue
            raise ConfigError(f"{key}: unknown name {node.id!r} in {_short(expr)} (only {', '.join(allowed)}, pi, e)")
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            stack += [(node.left, depth + 1), (node.right, depth + 1)]
            continue
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            stack.append((node.operand, depth + 1))
            continue
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS \
                and len(node.args) == 1 and not node.keywords:
            stack.append((node.args[0], depth + 1))
            continue
        raise ConfigError(f"{key}: unsupported construct in {_short(expr)} (numbers, {', '.join(allowed)}, "
                          f"+ - * / **, {', '.join(sorted(_FUNCS))})")

    def ev(node, env):
        if isinstance(node, ast.Constant):
            return np.float64(node.value)
        if isinstance(node, ast.Name):
            return env[node.id] if node.id in allowed else np.float64(_CONSTS[node.id])
        if isinstance(node, ast.BinOp):
            return _BINOPS[type(node.op)](ev(node.left, env), ev(node.right, env))
        if isinstance(node, ast.UnaryOp):
            v = ev(node.operand, env)
            return -v if isinstance(node.op, ast.USub) else v
        return _FUNCS[node.func.id](ev(node.args[0], env))

    # sub-expressions without variables: evaluated now, so `1/0` is an error of the file, not of step 0
    def constant(node) -> bool:
        return not any(isinstance(n, ast.Name) and n.id in allowed for n in ast.walk(node))

    for node in ast.walk(tree.body):
        if isinstance(node, (ast.BinOp, ast.Call)) and constant(node):
            with np.errstate(all="raise", under="ignore"):
                try:
                    ev(node, {})
                except FloatingPointError as exc:
                    raise ConfigError(f"{key}: {_cause(exc)} in {_short(expr)}") from None

    def f(env):
        env = {k: np.asarray(v, dtype=float) for k, v in env.items()}
        with np.errstate(all="ignore"):
            return ev(tree.body, env)

    def raising(env):
        env = {k: np.asarray(v, dtype=float) for k, v in env.items()}
        with np.errstate(all="raise", under="ignore"):
            return ev(tree.body, env)

    f.names = frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and n.id in allowed)
    f.expr = expr
    f.raising = raising
    return f


def _why(f, env) -> str:
    """The cause of a non-finite value: the evaluation repeated with floating-point errors raised."""
    try:
        f.raising(env)
    except FloatingPointError as exc:
        return _cause(exc)
    return "a non-finite value"


def evaluate(f, env: dict, key: str, *, step: int | None = None) -> float:
    """``f(env)`` as one finite float; otherwise a ConfigError naming ``key``, the step and the cause."""
    v = np.asarray(f(env), dtype=float)
    if v.size != 1:
        raise ConfigError(f"{key}: expected one value, got {v.size}")
    x = float(v.reshape(()))
    if not math.isfinite(x):
        at = f" at step k = {step}" if step is not None else ""
        raise ConfigError(f"{key}: {_why(f, env)}{at} in {_short(f.expr)}")
    return x


def eval_expression(expr: str, t: np.ndarray, key: str) -> np.ndarray:
    """Evaluates a simple expression of ``t`` (numbers, + − * / ``**``, sin cos tan exp sqrt abs log
    sign floor tanh, pi, e) on the array ``t``; nothing else is allowed. A non-finite value is
    a ConfigError naming ``key``, the first step where it occurs and its cause.

    Parameters
    ----------
    expr : str
        The expression.
    t : ndarray
        Time values.
    key : str
        Job-file key (for messages).

    Returns
    -------
    ndarray
    """
    t = np.asarray(t, dtype=float)
    f = compile_expression(expr, key, ("t",))
    v = np.broadcast_to(np.asarray(f({"t": t}), dtype=float), t.shape).copy()
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        k = int(bad[0])
        raise ConfigError(f"{key}: {_why(f, {'t': t[k]})} at step k = {k} (t = {t[k]:.6g}) in {_short(expr)}")
    return v
