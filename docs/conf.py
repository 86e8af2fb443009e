"""Sphinx configuration of the novelty documentation site.

Build it offline with one command (the ``docs`` extra installs Sphinx)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

``-W`` turns every warning into an error, as CI does. The API reference is
generated from the docstrings (autosummary + autodoc, numpydoc sections read
by napoleon); the user guide pages are the Markdown files of ``docs/`` and
the README, read by MyST.
"""

import os
import sys

sys.path.insert(0, os.path.abspath(".."))  # document the checkout, not an installed copy
sys.path.insert(0, os.path.abspath("_ext"))  # the site's own extension: the command-line pages

import novelty  # noqa: E402  (after the path is set)

project = "novelty"
author = "the novelty developers"
copyright = "2026, the novelty developers"
release = novelty.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "myst_parser",
    "cli_pages",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# docs/reproduction/ holds the tables that docs/reproduction.md includes; not pages of their own
exclude_patterns = ["_build", "_ext", "Thumbs.db", ".DS_Store", "reproduction/*.md"]
templates_path = ["_templates"]

# API reference: one page per public module, generated at build time.
autosummary_generate = True
autosummary_ignore_module_all = True
# Members defined in each module only: a package's re-exports are documented
# once, in the module that defines them.
autodoc_default_options = {"members": True, "ignore-module-all": True, "show-inheritance": True,
                           "member-order": "bysource"}
autodoc_typehints = "description"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True  # Attributes as fields: a NamedTuple's fields are not documented twice

# MyST: $...$ maths, heading anchors for the README's in-page links.
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

# Furo: a maintained theme whose content column fits code and parameter
# tables. MathJax is loaded by the reader's browser; nothing is fetched at
# build time.
html_theme = "furo"
html_title = f"novelty {release}"
html_static_path = ["_static"]
html_css_files = ["novelty.css"]

# Cross-references to the Python objects that Sphinx cannot resolve offline
# (numpy, scikit-learn) are written as plain literals; nitpicky mode is off.
nitpicky = False


def _skip_sklearn_request_methods(app, what, name, obj, skip, options):
    # scikit-learn adds set_*_request methods (metadata routing) to every
    # estimator; they are scikit-learn's, documented there.
    if name.startswith("set_") and name.endswith("_request"):
        return True
    return None


def setup(app):
    app.connect("autodoc-skip-member", _skip_sklearn_request_methods)
