"""Helpers of the documentation build (docs/conf.py names them by string, so the Sphinx
configuration stays picklable)."""
from __future__ import annotations


_SEEN: dict[str, set[int]] = {}  # per example file: the figures already saved


def figure_scraper(block, block_vars, gallery_conf, **kwargs):
    """setbound's plotting functions return ``matplotlib.figure.Figure`` objects made without
    pyplot (so a library call never opens a window), which sphinx-gallery's matplotlib scraper
    does not see. This one saves every Figure the block left in the example's namespace (a
    variable holding a Figure or an Axes, or a list/tuple/dict of them) that no earlier block saved."""
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    done = _SEEN.setdefault(block_vars["src_file"], set())
    found = []
    for value in list(block_vars["example_globals"].values()):
        items = value.values() if isinstance(value, dict) else value if isinstance(value, (list, tuple)) else [value]
        for fig in items:
            fig = fig.figure if isinstance(fig, Axes) else fig  # e.g. Detection.plot returns its axes
            if isinstance(fig, Figure) and not hasattr(fig, "number") and id(fig) not in done:  # pyplot's: scraped already
                done.add(id(fig))
                found.append(fig)
    paths = []
    for fig, path in zip(found, block_vars["image_path_iterator"]):
        fig.savefig(path, dpi=80)
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])


# --------------------------------------------------------------------------- method citations
def _method_targets(theory_dir):
    """``{(page title, section title or None): rst role}`` from docs/theory/*.md: each page's
    ``# Title`` (a :doc: target) and each ``(label)=`` + ``## Section`` (a :ref: target)."""
    import re
    from pathlib import Path

    targets = {}
    for page in sorted(Path(theory_dir).glob("*.md")):
        text = page.read_text()
        title = re.search(r"^# (.+)$", text, flags=re.M).group(1).strip()
        targets[(title, None)] = f":doc:`Methods › {title} </theory/{page.stem}>`"
        for label, section in re.findall(r"^\(([\w-]+)\)=\n## (.+)$", text, flags=re.M):
            targets[(title, section.strip())] = f":ref:`Methods › {title} › {section.strip()} <{label}>`"
    return targets


def _link_citations(app, what, name, obj, options, lines):
    """Docstrings cite the method pages as plain text ("Methods › page › section", readable in
    ``help()``); on the site the citation becomes a link to that page or section."""
    targets = app.env.setbound_method_targets
    keys = sorted(targets, key=lambda k: -len(f"{k[0]} › {k[1]}" if k[1] else k[0]))
    for i, line in enumerate(lines):
        if "Methods › " not in line or "`" in line.split("Methods › ", 1)[0][-1:]:
            continue
        for page, section in keys:
            text = f"Methods › {page}" + (f" › {section}" if section else "")
            if text in line:
                lines[i] = line.replace(text, targets[(page, section)], 1)
                break


def _load_targets(app):
    from pathlib import Path

    app.env.setbound_method_targets = _method_targets(Path(app.srcdir) / "theory")


def setup(app):
    app.connect("builder-inited", _load_targets)
    app.connect("autodoc-process-docstring", _link_citations)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
