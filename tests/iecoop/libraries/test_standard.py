"""Tc2_Standard and CODESYS Standard: the standard blocks and string functions under the library's name."""

from __future__ import annotations

import pathlib
import types

import pytest

import iecoop.functions as functions
import iecoop.stdlib as stdlib
from iecoop import st
from iecoop.libraries import codesys_standard, known, module_of, tc2_standard

DOCS = pathlib.Path(__file__).parents[3] / "docs" / "libraries"
STANDARD_NAMES = {
    "TON", "TOF", "TP", "LTON", "LTOF", "LTP", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "SR", "RS",
    "CONCAT", "DELETE", "FIND", "INSERT", "LEFT", "LEN", "MID", "REPLACE", "RIGHT",
}


@pytest.mark.parametrize("module", [tc2_standard, codesys_standard])
def test_the_module_lists_the_standard_names_as_iecoop_s_own(module: object) -> None:
    names = set(getattr(module, "__all__"))
    assert names == STANDARD_NAMES
    for name in names:
        assert getattr(module, name) is getattr(stdlib, name, None) or getattr(module, name) is getattr(functions, name)


@pytest.mark.parametrize(("title", "module"), [("Tc2_Standard", tc2_standard), ("Standard", codesys_standard)])
def test_the_table_of_shipped_libraries_finds_the_module(title: str, module: object) -> None:
    library = known(title)
    assert library is not None and module_of(library) is module


@pytest.mark.parametrize(("page", "module"), [("tc2_standard.md", tc2_standard), ("codesys_standard.md", codesys_standard)])
def test_the_library_page_lists_every_name(page: str, module: object) -> None:
    text = (DOCS / page).read_text()
    for name in getattr(module, "__all__"):
        assert f"| `{name}` |" in text


@pytest.mark.parametrize(("namespace", "module"), [("Tc2_Standard", tc2_standard), ("Standard", codesys_standard)])
def test_qualified_and_plain_names_are_the_same_block(namespace: str, module: types.ModuleType) -> None:
    plc = st.load(f"""
    PROGRAM MAIN
    VAR fbQualified : {namespace}.CTU; fbPlain : CTU; sText : STRING; END_VAR
    fbQualified(CU := TRUE, PV := 3);
    fbPlain(CU := TRUE, PV := 3);
    sText := {namespace}.LEFT({namespace}.CONCAT('abc', 'def'), 4);
    END_PROGRAM
    """, libraries={namespace: module})
    plc.MAIN()
    assert (plc.MAIN.fbQualified.CV, plc.MAIN.fbPlain.CV, plc.MAIN.sText) == (1, 1, "abcd")
    assert type(plc.MAIN.fbQualified) is type(plc.MAIN.fbPlain) is stdlib.CTU
