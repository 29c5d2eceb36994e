"""The documentation site's Python API reference (docs/api/, built by ``make docs``) is complete:

* every public class and function of setbound appears in an ``autosummary`` list of
  ``docs/api/*.rst`` (so it has a page on the site);
* every public function, class (its constructor) and method documents each of its parameters in a
  numpydoc ``Parameters`` section (dataclasses may use ``Attributes``), and its summary line is
  not empty.

"Public" is what a user can reach: the names of ``setbound.__all__`` and of every module of the
package whose name does not start with ``_`` (their ``__all__``, or else the names they define).
``PENDING`` lists the callables whose parameters are not documented yet; it may only shrink (the
test fails when a name in it has become complete, so that it is removed).
"""
from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

import setbound

ROOT = Path(__file__).resolve().parents[2]
API = ROOT / "docs" / "api"

# Callables whose numpydoc Parameters section is still missing or incomplete (see the module
# docstring). Keep sorted; remove names as they are documented.
PENDING: set[str] = set()


def public_modules():
    """``setbound`` and its public modules (packages included, the C library excluded)."""
    yield setbound
    for m in pkgutil.iter_modules(setbound.__path__):
        if m.name.startswith("_"):
            continue
        spec = importlib.util.find_spec(f"setbound.{m.name}")
        if not m.ispkg and not (spec and spec.origin and spec.origin.endswith(".py")):
            continue  # libsetbound.so in an installed package
        yield importlib.import_module(f"setbound.{m.name}")


def public_names(mod) -> list[str]:
    names = getattr(mod, "__all__", None)
    if names is None:
        names = [n for n, o in vars(mod).items()
                 if not n.startswith("_") and getattr(o, "__module__", None) == mod.__name__]
    return list(names)


def _preference(module: str, obj) -> int:
    """How well ``module.name`` names ``obj``: its defining module first, then the public package
    holding it (``setbound.jobs`` for ``setbound.jobs.loader``), then any other public module."""
    if module == obj.__module__:
        return 0
    if obj.__module__.startswith(module + ".") and module != "setbound":
        return 1
    return 2 if module not in ("setbound", "setbound.config") else 3


def public_objects() -> dict[int, tuple[str, object]]:
    """``id(obj) -> (canonical public name, obj)`` for every public class and function of
    setbound (each object once, however many modules re-export it)."""
    out: dict[int, tuple[int, str, object]] = {}
    for mod in public_modules():
        for n in public_names(mod):
            obj = getattr(mod, n)
            if (inspect.isclass(obj) or inspect.isfunction(obj)) and obj.__module__.startswith("setbound"):
                rank = _preference(mod.__name__, obj)
                if id(obj) not in out or rank < out[id(obj)][0]:
                    out[id(obj)] = (rank, f"{mod.__name__}.{n}", obj)
    return {k: (name, obj) for k, (_, name, obj) in out.items()}


def reference_entries(text: str) -> list[str]:
    """The fully qualified names listed by the ``autosummary`` directives of an rst page."""
    names, module, in_list = [], None, False
    for line in text.splitlines():
        m = re.match(r"\.\. (?:currentmodule|automodule|module):: (\S+)", line)
        if m:
            module, in_list = m.group(1), False
            continue
        if line.startswith(".. autosummary::"):
            in_list = True
            continue
        if in_list:
            if line.strip() and not line.startswith(" "):
                in_list = False
            elif line.strip() and not line.strip().startswith(":"):
                name = line.strip()
                names.append(name if "." in name and name.startswith("setbound") else f"{module}.{name}")
    return names


def _resolve(qualname: str):
    parts = qualname.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for p in parts[i:]:
            obj = getattr(obj, p)
        return obj
    raise ImportError(qualname)


def test_every_public_object_is_in_the_api_reference():
    listed = {}
    for page in sorted(API.glob("*.rst")):
        for name in reference_entries(page.read_text()):
            listed[name] = _resolve(name)  # a stale entry fails here, with its name
    documented = {id(o) for o in listed.values()}
    missing = sorted(name for k, (name, _) in public_objects().items() if k not in documented)
    assert not missing, ("public names missing from the API reference (docs/api/<module>.rst, an autosummary "
                         "list of the module that defines them):\n  " + "\n  ".join(missing))
    assert len(listed) == len(documented), "an object is listed twice in docs/api (document it once)"


def test_reference_parser_reads_autosummary_lists():
    text = (".. currentmodule:: setbound.sets\n\nClasses\n-------\n\n.. autosummary::\n   :toctree: generated/\n\n"
            "   Ellipsoid\n   Zonotope\n\nFunctions\n---------\n")
    assert reference_entries(text) == ["setbound.sets.Ellipsoid", "setbound.sets.Zonotope"]


# ----------------------------------------------------------------------------- numpydoc sections
_HEADER = re.compile(r"^([A-Z][A-Za-z ]+)\n-{3,}\s*$", re.M)


def numpydoc_sections(doc: str) -> dict[str, str]:
    """``{section title: body}`` of a numpydoc docstring (``"Summary"``: the text before the first)."""
    doc = inspect.cleandoc(doc or "")
    heads = list(_HEADER.finditer(doc))
    out = {"Summary": doc[: heads[0].start()] if heads else doc}
    for h, nxt in zip(heads, heads[1:] + [None]):
        out[h.group(1).strip()] = doc[h.end(): nxt.start() if nxt else len(doc)]
    return out


def documented_parameters(body: str) -> set[str]:
    """Names of a Parameters-like section: its unindented lines ``name : type`` (``a, b : ...``
    documents both; ``*args``/``**kwargs`` keep their stars)."""
    names = set()
    for line in body.splitlines():
        if line and not line[0].isspace():
            for n in line.split(" : ")[0].split(","):
                names.add(n.strip())
    return names


def signature_parameters(obj) -> list[str]:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    out = []
    for p in sig.parameters.values():
        if p.name in ("self", "cls") or p.name.startswith("_"):
            continue  # the instance, and private dataclass fields
        out.append({p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "") + p.name)
    return out


def docstring_problems(name: str, obj, doc: str | None, params: list[str], *, dataclass: bool = False) -> list[str]:
    secs = numpydoc_sections(doc or "")
    if not secs["Summary"].strip():
        return [f"{name}: no summary line"]
    body = secs.get("Parameters", "") + ("\n" + secs.get("Attributes", "") if dataclass else "")
    have = documented_parameters(body)
    lacking = [p for p in params if p not in have and p.lstrip("*") not in have]
    if lacking:
        return [f"{name}: parameters not documented in a numpydoc 'Parameters' section: {', '.join(lacking)}"]
    return []


def callables_to_check():
    """``(name, obj, docstring, parameters, is_dataclass)`` for every public callable and method.

    A class's methods are its own and those it inherits from private classes of setbound (the
    estimators' ``step``/``run`` live in private base classes); each function is checked once."""
    objects = public_objects()
    seen: set[int] = set()
    for name, obj in sorted(objects.values(), key=lambda t: t[0]):
        if inspect.isfunction(obj):
            yield name, obj, obj.__doc__, signature_parameters(obj), False
            continue
        is_dc = dataclasses.is_dataclass(obj)
        own_init = "__init__" in vars(obj) or is_dc
        yield name, obj, obj.__doc__, signature_parameters(obj) if own_init else [], is_dc
        for klass in obj.__mro__:
            if klass is not obj and (id(klass) in objects or not klass.__module__.startswith("setbound")):
                continue  # a public base is checked under its own name; builtins are not ours
            for an, av in vars(klass).items():
                if an.startswith("_") or an in vars(obj) and klass is not obj:
                    continue
                f = av.__func__ if isinstance(av, (staticmethod, classmethod)) else av
                if inspect.isfunction(f) and id(f) not in seen:
                    seen.add(id(f))
                    yield f"{name}.{an}", f, f.__doc__, signature_parameters(
                        f if isinstance(av, staticmethod) else getattr(obj, an)), False


def test_every_public_callable_documents_its_parameters():
    problems, complete = [], set()
    for name, obj, doc, params, is_dc in callables_to_check():
        p = docstring_problems(name, obj, doc, params, dataclass=is_dc)
        if name in PENDING:
            if not p:
                complete.add(name)
            continue
        problems += p
    assert not problems, "numpydoc docstrings incomplete:\n  " + "\n  ".join(problems)
    assert not complete, ("documented now, remove from PENDING in tests/python/test_docs_api.py:\n  "
                          + "\n  ".join(sorted(complete)))


def test_parameter_check_finds_an_undocumented_parameter():
    def f(a, b, *args, c=1, **kw):
        """Summary.

        Parameters
        ----------
        a, b : float
            Two numbers.
        *args
            More.
        kw : dict
            Options.
        """

    assert docstring_problems("f", f, f.__doc__, signature_parameters(f)) == [
        "f: parameters not documented in a numpydoc 'Parameters' section: c"]

    def g(x):
        """Summary without sections."""

    assert docstring_problems("g", g, g.__doc__, signature_parameters(g)) == [
        "g: parameters not documented in a numpydoc 'Parameters' section: x"]
    assert docstring_problems("h", g, "", []) == ["h: no summary line"]


@pytest.mark.parametrize("page", ["c_api", "cpp_usage", "bibliography", "user_guide", "methods"])
def test_site_pages_are_in_the_index(page):
    index = (ROOT / "docs" / "index.md").read_text()
    assert re.search(rf"^{page}$", index, flags=re.M), f"docs/index.md has no toctree entry for {page}"
