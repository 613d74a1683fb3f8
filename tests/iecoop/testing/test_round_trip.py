"""iecoop.testing.round_trip: a module's names bound to its own classes loaded back from ST, and restored."""

from __future__ import annotations

import importlib
import sys
import textwrap
import types
from collections.abc import Iterator
from pathlib import Path

import pytest

from iecoop.gvl import global_lists
from iecoop.st.export import StExportError
from iecoop.testing.round_trip import load_back, loaded_names, rebound, round_trip

PLANT = '''
from iecoop import INT, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, Program, prop


class Scaler(FunctionBlock):
    raw: INT = VAR_INPUT(0)
    scaled: INT = VAR_OUTPUT(0)
    factor_internal: INT = VAR(3)

    def body(self) -> None:
        self.scaled = self.raw * self.factor_internal

    @prop
    def factor(self) -> INT:
        return self.factor_internal

    @factor.setter
    def factor(self, value: INT) -> None:
        self.factor_internal = max(value, 1)


class Line(Program):
    scaler: Scaler = VAR()
    total: INT = VAR(0)

    def body(self) -> None:
        self.scaler(raw=self.total + 1)
        self.total = self.scaler.scaled


def scenario() -> tuple[int, int]:
    """Three cycles of Line, the factor set to 0 (the setter makes it 1) then 2."""
    line = Line()
    line.scaler.factor = 0
    line()
    line.scaler.factor = 2
    line()
    line()
    return line.total, line.scaler.factor
'''

BROKEN = '''

class Broken(FunctionBlock):
    n: INT = VAR(0)

    def body(self) -> None:
        self.n = len([1, 2])
'''


def _module(folder: Path, name: str, source: str) -> types.ModuleType:
    (folder / f"{name}.py").write_text(textwrap.dedent(source))
    sys.path.insert(0, str(folder))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(folder))


@pytest.fixture
def plant(tmp_path: Path) -> Iterator[types.ModuleType]:
    module = _module(tmp_path, "round_trip_plant", PLANT)
    yield module
    del sys.modules[module.__name__]


@pytest.mark.parametrize("fmt", ["twincat", "st"])
def test_the_module_runs_its_loaded_classes_then_its_own_again(plant: types.ModuleType, fmt: str) -> None:
    line, scaler = plant.Line, plant.Scaler
    assert plant.scenario() == (10, 2)  # raw 1 * 1, raw 2 * 2, raw 5 * 2
    with round_trip(plant, format=fmt) as (loaded,):
        assert plant.Line is type(loaded.Line) and plant.Scaler is loaded.Scaler
        assert plant.Line.__module__ == plant.Scaler.__module__ == loaded.__name__ != plant.__name__
        assert plant.scenario() == (10, 2)
    assert plant.Line is line and plant.Scaler is scaler
    assert plant.scenario() == (10, 2)


def test_only_what_the_st_declares_is_rebound(plant: types.ModuleType) -> None:
    loaded = load_back(plant, "st")
    declared = loaded_names(loaded)
    assert sorted(declared) == ["Line", "Scaler"]
    assert isinstance(declared["Line"], type)  # the PROGRAM's class, not st.load's single instance
    assert "INT" in vars(loaded) and "FunctionBlock" in vars(loaded)  # imported by the generated code, left alone
    with rebound(plant, loaded) as names:
        assert names == ["Scaler", "Line"]
        assert plant.scenario.__module__ == plant.__name__ and plant.INT is not None


GLOBALS = '''
from iecoop import INT, VAR_EXTERNAL, GlobalVariables, Program, gvl


@gvl
class GVL_RoundTrip(GlobalVariables):
    round_trip_count: INT = 0


class Counting(Program):
    round_trip_count: INT = VAR_EXTERNAL()

    def body(self) -> None:
        self.round_trip_count += 1
'''


def test_a_gvl_is_rebound_and_its_registration_given_back(tmp_path: Path) -> None:
    plant = _module(tmp_path, "round_trip_globals", GLOBALS)
    python_list = plant.GVL_RoundTrip
    try:
        with round_trip(plant, format="st") as (loaded,):
            assert plant.GVL_RoundTrip is loaded.GVL_RoundTrip is not python_list
            assert global_lists()["GVL_RoundTrip"] is loaded.GVL_RoundTrip
            plant.Counting()()
            assert (loaded.GVL_RoundTrip.round_trip_count, python_list.round_trip_count) == (1, 0)
        assert plant.GVL_RoundTrip is python_list and global_lists()["GVL_RoundTrip"] is python_list
        plant.Counting()()
        assert python_list.round_trip_count == 1
    finally:
        del sys.modules[plant.__name__]


def test_names_come_back_when_the_block_raises(plant: types.ModuleType) -> None:
    scaler = plant.Scaler
    with pytest.raises(ZeroDivisionError):
        with round_trip(plant, format="st"):
            assert plant.Scaler is not scaler
            raise ZeroDivisionError
    assert plant.Scaler is scaler


def test_a_format_st_load_cannot_read_is_refused(plant: types.ModuleType) -> None:
    with pytest.raises(ValueError, match="format must be one of 'twincat', 'st', got 'plcopen'"):
        load_back(plant, "plcopen")


def test_a_statement_without_st_form_names_the_file_and_line(tmp_path: Path) -> None:
    broken = _module(tmp_path, "round_trip_broken", PLANT + BROKEN)
    scaler = broken.Scaler
    try:
        with pytest.raises(StExportError, match=r"round_trip_broken\.py:\d+: .*Broken\.body"):
            with round_trip(broken):
                pass
        assert broken.Scaler is scaler
    finally:
        del sys.modules[broken.__name__]
