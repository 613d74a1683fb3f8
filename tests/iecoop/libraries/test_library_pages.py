"""Every library page of the docs names every name its module provides, and links the vendor's pages."""

from __future__ import annotations

import importlib
import pathlib
import re

import pytest

from iecoop.libraries import KNOWN

DOCS = pathlib.Path(__file__).parents[3] / "docs" / "libraries"
PAGES = {
    "iecoop.libraries.tc2_standard": "tc2_standard.md", "iecoop.libraries.tc2_system": "tc2_system.md",
    "iecoop.libraries.tc2_utilities": "tc2_utilities.md", "iecoop.libraries.tc2_mc2": "tc2_mc2.md",
    "iecoop.libraries.codesys_standard": "codesys_standard.md", "iecoop.libraries.codesys_util": "codesys_util.md",
    "iecoop.libraries.tc3_module": "tc3_module.md", "iecoop.libraries.tcunit": "tcunit.md",
}


def test_every_shipped_library_has_a_page() -> None:
    assert {library.module for library in KNOWN} == set(PAGES)


@pytest.mark.parametrize(("module", "page"), sorted(PAGES.items()))
def test_the_page_names_every_name_and_links_the_vendor(module: str, page: str) -> None:
    text = (DOCS / page).read_text(encoding="utf-8")
    missing = [name for name in importlib.import_module(module).__all__
               if not re.search(rf"`{re.escape(name)}[`(\s]", text)]
    assert missing == []
    assert re.search(r"https://(infosys\.beckhoff\.com|content\.helpme-codesys\.com|tcunit\.org)/", text)
