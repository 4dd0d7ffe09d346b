"""Sphinx configuration of the documentation site (``make docs``: HTML in build/docs, warnings as
errors). Pages are Markdown (myst-parser) or reStructuredText; the API reference is autodoc of the
public API with numpydoc; the generated reports (docs/reports) and the dated design notes
(docs/notes) are pages as they are."""
from __future__ import annotations

import re
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "fmu_src")]

project = "contact_core"
author = "contact_core contributors"
copyright = "2026, contact_core contributors"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]
myst_heading_anchors = 3
# Headings of generated reports and notes may jump a level (a broken link still fails the build).
suppress_warnings = ["myst.header"]

autodoc_member_order = "bysource"
autodoc_typehints = "none"
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# numpydoc also reads the raw docstrings (for signatures) and does not know the methods' "Options"
# section, which _escape_docstring renders as "Other Parameters".
warnings.filterwarnings("ignore", message="Unknown section Options", category=UserWarning)

html_theme = "alabaster"
html_title = "contact_core"
html_static_path: list[str] = []
html_theme_options = {"description": "The wheel–rail rolling-contact law, as a library and an FMU",
                      "page_width": "1100px", "sidebar_width": "240px"}

# The docstrings are plain text with mathematics in Unicode: |F|, |p| <= μ p_n, E* ...; in
# reStructuredText a |word| is a substitution and a lone * starts emphasis. Escape both outside
# literals (``...``, `...`) and literal blocks before numpydoc reads the docstring.
# (emphasis, *a title*, is kept: a star pair around words, not inside a word)
_LITERAL = re.compile(r"(``.*?``|`[^`]*`|(?<![\w*])\*\*?[^\s*](?:[^*]*?[^\s*])?\*\*?(?![\w*]))")


def _escape(text: str) -> str:
    parts = _LITERAL.split(text)
    for i in range(0, len(parts), 2):
        parts[i] = parts[i].replace("\\", "\\\\").replace("|", "\\|").replace("*", "\\*")
    return "".join(parts)


_SECTION_RENAMES = {"Options": "Other Parameters"}   # the methods' options: keyword arguments


def _escape_docstring(app, what, name, obj, options, lines: list[str]) -> None:
    """Escape ``|`` and ``*`` outside literals; end an indented block with a blank line where
    the text goes on unindented (the docstrings' aligned lists, which reStructuredText would
    otherwise warn about: the blank line changes nothing else); name the ``Options`` section as
    numpydoc's ``Other Parameters``."""
    out: list[str] = []
    literal_indent = None       # inside a literal block (after "::"): its introducing indent
    doctest = False             # inside a doctest block (from ">>>" to the next blank line)
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        prev = out[-1] if out else ""
        if literal_indent is not None:
            if stripped and indent <= literal_indent:
                literal_indent = None
            else:
                out.append(line)
                continue
        if stripped.startswith(">>>"):
            doctest = True
        if doctest:
            doctest = bool(stripped)
            out.append(line)
            continue
        if (stripped in _SECTION_RENAMES and i + 1 < len(lines)
                and set(lines[i + 1].strip()) == {"-"}):
            new = _SECTION_RENAMES[stripped]
            out.append(" " * indent + new)
            lines[i + 1] = " " * indent + "-" * len(new)
            continue
        if stripped and prev.strip() and indent < len(prev) - len(prev.lstrip()) \
                and not set(stripped) <= set("-=~^"):
            out.append("")
        out.append(_escape(line))
        if line.rstrip().endswith("::"):
            literal_indent = indent
    lines[:] = out


def setup(app):
    app.connect("autodoc-process-docstring", _escape_docstring, priority=100)
