"""Sphinx configuration of the setbound documentation site (``make docs``; output in build/docs).

The site is built from the code: the API reference by autodoc/autosummary from the numpydoc
docstrings, the gallery by sphinx-gallery from ``examples/gallery/plot_*.py`` (run at build time),
and the Markdown pages of ``docs/`` through myst-parser. ``make docs`` runs it with ``-W
--keep-going``: a warning fails the build.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# The package from this checkout (``make docs`` has it installed editable in .venv already; this
# only matters for a bare ``sphinx-build`` with SETBOUND_LIBRARY pointing at a built library).
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))  # setbound_docs (the gallery scraper)
os.environ.setdefault("MPLBACKEND", "Agg")

import setbound  # noqa: E402

project = "setbound"
author = "the setbound developers"
copyright = "2026, the setbound developers"
release = setbound.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "setbound_docs",  # docs/_ext: method citations in docstrings become links
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = ["_build", "gallery/README.md", "Thumbs.db", ".DS_Store", "**/README.md",
                    "auto_examples/*.ipynb", "auto_examples/*.py", "auto_examples/*.zip",
                    "auto_examples/*.json", "auto_examples/*.md5", "auto_examples/*.codeobj.json"]

# --- myst: the Markdown pages keep their GitHub-style links (page.md#heading-slug)
myst_heading_anchors = 4
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]

# --- autodoc / autosummary / numpydoc
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc sections carry the types
numpydoc_show_class_members = False  # the autosummary class template lists them
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = True

# --- sphinx-gallery: examples/gallery/plot_*.py, executed at build time


sphinx_gallery_conf = {
    "examples_dirs": [str(ROOT / "examples" / "gallery")],
    "gallery_dirs": ["auto_examples"],
    "filename_pattern": r"/plot_",
    "doc_module": ("setbound",),
    "backreferences_dir": "api/backrefs",
    "reference_url": {"setbound": None},
    "within_subsection_order": "FileNameSortKey",
    "remove_config_comments": True,
    "download_all_examples": False,
    "show_memory": False,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib", "setbound_docs.figure_scraper"),
    "abort_on_example_error": True,
}

# --- HTML
html_theme = "pydata_sphinx_theme"
html_title = f"setbound {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
}
html_static_path: list[str] = []
html_show_sourcelink = False
