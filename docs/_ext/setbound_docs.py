"""Helpers of the documentation build (docs/conf.py names them by string, so the Sphinx
configuration stays picklable)."""
from __future__ import annotations


_SEEN: dict[str, set[int]] = {}  # per example file: the figures already saved


def figure_scraper(block, block_vars, gallery_conf, **kwargs):
    """setbound's plotting functions return ``matplotlib.figure.Figure`` objects made without
    pyplot (so a library call never opens a window), which sphinx-gallery's matplotlib scraper
    does not see. This one saves every Figure the block left in the example's namespace (a
    variable, or a list/tuple/dict of them) that no earlier block saved."""
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    done = _SEEN.setdefault(block_vars["src_file"], set())
    found = []
    for value in list(block_vars["example_globals"].values()):
        items = value.values() if isinstance(value, dict) else value if isinstance(value, (list, tuple)) else [value]
        for fig in items:
            if isinstance(fig, Figure) and not hasattr(fig, "number") and id(fig) not in done:  # pyplot's: scraped already
                done.add(id(fig))
                found.append(fig)
    paths = []
    for fig, path in zip(found, block_vars["image_path_iterator"]):
        fig.savefig(path, dpi=80)
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])
