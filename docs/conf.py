"""Sphinx configuration for the iecoop documentation."""

from __future__ import annotations

import sys
from pathlib import Path

_DOCS = Path(__file__).resolve().parent
# The repository root (the packages when the docs are built from a checkout) and the local extensions.
sys.path[:0] = [str(_DOCS.parent), str(_DOCS / "_ext")]

project = "iecoop"
author = "the iecoop authors"
copyright = "2026, the iecoop authors"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.viewcode",
    "sphinx_copybutton",
    "iecoop_pages",
    "iecoop_plots",
]
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_ext", "_static"]

html_theme = "furo"
html_title = "iecoop"
html_static_path = ["_static"]
html_css_files = ["iecoop.css"]

# Each code block gets a copy button that copies what a file or a REPL takes: the
# ">>> " and "... " prompts are stripped and the output lines of an example left out.
copybutton_prompt_text = r">>> |\.\.\. "
copybutton_prompt_is_regexp = True
copybutton_only_copy_prompt_lines = True

# Every cross-reference must land somewhere.
nitpicky = True
nitpick_ignore = [
    # Standard-library and third-party types in signatures; this site has no pages for them.
    ("py:class", "collections.abc.Callable"),
    ("py:class", "collections.abc.Iterable"),
    ("py:class", "collections.abc.Iterator"),
    ("py:class", "collections.abc.Mapping"),
    ("py:class", "collections.abc.Sequence"),
    ("py:class", "os.PathLike"),
    ("py:class", "pathlib.Path"),
    ("py:class", "types.ModuleType"),
    ("py:class", "hypothesis.strategies.SearchStrategy"),
    ("py:class", "_pytest.config.Config"),
    ("py:class", "_pytest.fixtures.FixtureRequest"),
    ("py:class", "_pytest.nodes.Item"),
    ("py:class", "_pytest.nodes.Collector"),
    ("py:class", "_pytest.config.argparsing.Parser"),
    ("py:class", "_pytest._code.code.ExceptionInfo"),
    # A TcUnit failure record: documented with the library ({doc}`/libraries/tcunit`), not in the API pages.
    ("py:class", "iecoop.libraries.tcunit.AssertFailure"),
    # Type variables of generic signatures (typing internals, not API).
    ("py:class", "iecoop.declarations._T"),
    ("py:class", "iecoop.functions._N"),
    ("py:class", "iecoop.functions._T"),
    ("py:class", "iecoop.gvl._G"),
    ("py:class", "iecoop.interfaces._I"),
    ("py:class", "iecoop.lifecycle._T"),
    ("py:class", "iecoop.members._F"),
    ("py:class", "iecoop.memory.references._T"),
    ("py:class", "iecoop.parameters._F"),
    ("py:class", "iecoop.memory.arrays._T"),
    ("py:class", "iecoop.memory.pointers._T"),
    ("py:class", "iecoop.testing._P"),
    # The runtime's own table a Trace is given by Runtime.trace (users never make a Trace themselves).
    ("py:class", "iecoop.runtime.online.OnlineTable"),
]

autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
autodoc_default_options = {"members": True, "undoc-members": False}
python_use_unqualified_type_names = True

# Signatures show the IEC type names, linked to their entries in the reference.
_IEC_TYPES = (
    "BOOL", "SINT", "USINT", "INT", "UINT", "DINT", "UDINT", "LINT", "ULINT", "BYTE", "WORD", "DWORD", "LWORD",
    "REAL", "LREAL", "STRING", "WSTRING", "TIME", "LTIME", "DATE", "TOD", "DT",
)
autodoc_type_aliases = {name: f"iecoop.{name}" for name in (*_IEC_TYPES, "REFERENCE_TO")}

# Keep the table of contents to the pages' own headings: thousands of documented
# objects in the sidebar would make every page slow to build and to read.
toc_object_entries = False
add_module_names = False
