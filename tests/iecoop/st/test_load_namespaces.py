"""Loading never leaks into exporting or into other projects: each load is a namespace of its own globals."""

from __future__ import annotations

import pathlib
import tempfile

import pytest

pytest.importorskip("blark")

from iecoop import st  # noqa: E402
from iecoop.exceptions import DefinitionError  # noqa: E402
from iecoop.gvl import find_global  # noqa: E402

PROJECT = """
// GVL {gvl}
VAR_GLOBAL
    bStart : BOOL;
    nCount : INT := {initial};
END_VAR

PROGRAM MAIN
VAR_EXTERNAL
    nCount : INT;
END_VAR
IF bStart THEN
    nCount := nCount + 1;
END_IF
END_PROGRAM
"""


def _project(initial: int, gvl: str = "GVL_NsCell") -> str:
    return PROJECT.format(initial=initial, gvl=gvl)


def test_two_loaded_projects_each_keep_their_own_globals() -> None:
    first = st.load(_project(10))
    # The same globals in another list of another project: a second namespace, not a redeclaration.
    second = st.load(_project(500, gvl="GVL_NsPlant"))
    first.GVL_NsCell.bStart = True
    first.MAIN()
    first.MAIN()
    second.MAIN()
    assert (first.GVL_NsCell.nCount, second.GVL_NsPlant.nCount) == (12, 500)
    second.GVL_NsPlant.bStart = True
    second.MAIN()
    assert (first.GVL_NsCell.nCount, second.GVL_NsPlant.nCount) == (12, 501)


def test_a_python_module_exports_after_its_own_export_was_loaded_back() -> None:
    import patterns.creational.singleton as module

    with tempfile.TemporaryDirectory() as first, tempfile.TemporaryDirectory() as second:
        st.export(module, first, format="st")
        loaded = st.load(first)
        assert loaded.PlantLog is not module.PlantLog
        st.export(module, second, format="st")  # no clash with the loaded PlantLog
        names = sorted(p.name for p in pathlib.Path(first).iterdir() if p.suffix == ".st")  # not the parse cache
        assert names == sorted(p.name for p in pathlib.Path(second).iterdir())
        for name in names:
            assert (pathlib.Path(first) / name).read_text() == (pathlib.Path(second) / name).read_text()


def test_var_external_outside_its_namespace_binds_only_a_unique_name() -> None:
    first = st.load(_project(1))
    second = st.load(_project(2))
    block, _record = find_global("nCount", "Somewhere.nCount", first.__name__)
    assert block is first.GVL_NsCell
    with pytest.raises(DefinitionError, match=r"Somewhere\.nCount.*several global lists outside its namespace"):
        find_global("nCount", "Somewhere.nCount", "elsewhere")
    assert second.GVL_NsCell.nCount == 2


def test_a_runtime_resolves_symbols_in_its_programs_project() -> None:
    from iecoop.runtime import Runtime, Task

    first = st.load(_project(7))
    st.load(_project(900))  # loaded later: its GVL_NsCell would win by name alone
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=10), first.MAIN)
    rt.write("GVL_NsCell.bStart", True)
    rt.run(cycles=3)
    assert rt.symbol("GVL_NsCell.nCount").load() == 10
    assert first.GVL_NsCell.nCount == 10
