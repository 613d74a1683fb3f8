"""One frozen record per declared class (``cls.__iec__``), made by each class builder."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from iecoop import (
    INT, FunctionBlock, GlobalVariables, IecEnum, Interface, Program, Struct, Union, VAR_STAT, gvl, method, prop,
)
from iecoop.metadata import IecClass, Kind, iec_class, kind_of
from iecoop.pou import pou_members


class IMeter(Interface):
    @prop
    def level(self) -> INT: ...


class Meter(FunctionBlock, IMeter, final=True):
    reading: INT = 0
    made: INT = VAR_STAT(0)

    @prop
    def level(self) -> INT:
        return self.reading

    @method
    def reset(self) -> None:
        self.reading = 0


class Reading(Struct):
    value: INT = 0


class Word(Union):
    whole: INT = 0


class Mode(IecEnum):
    AUTO = 0


@gvl
class GVL_Meta(GlobalVariables):
    meta_count: INT = 0


class Cell(Program):
    meter: Meter = Meter()


def test_each_builder_gives_its_class_a_record_of_its_kind() -> None:
    kinds = {
        Meter: Kind.FUNCTION_BLOCK, Cell: Kind.PROGRAM, Reading: Kind.STRUCT, Word: Kind.UNION,
        type(GVL_Meta): Kind.GVL, IMeter: Kind.INTERFACE, Mode: Kind.ENUM,
    }
    for cls, kind in kinds.items():
        assert "__iec__" in cls.__dict__, cls
        assert kind_of(cls) is kind
        assert not iec_class(cls).root  # type: ignore[union-attr]


def test_the_library_bases_are_roots() -> None:
    for root, kind in ((FunctionBlock, Kind.FUNCTION_BLOCK), (Program, Kind.PROGRAM), (Struct, Kind.STRUCT),
                       (Union, Kind.UNION), (GlobalVariables, Kind.GVL), (Interface, Kind.INTERFACE)):
        record = iec_class(root)
        assert record is not None and record.root and record.kind is kind and record.layout is None


def test_a_block_record_holds_its_keywords_variables_members_and_statics() -> None:
    record = Meter.__iec__
    assert (record.abstract, record.final, record.internal) == (False, True, False)
    assert record.layout is not None and record.layout is Meter._iec_layout_
    assert [f.name for f in record.layout.fields] == ["reading"]
    assert set(record.members) == {"level", "reset"} == set(pou_members(Meter))
    assert [f.name for f in record.static_fields] == ["made"]
    assert set(IMeter.__iec__.members) == {"level"}
    assert Reading.__iec__.layout is not None and Reading.__iec__.layout.by_name["value"].owner == "Reading"


def test_the_record_is_frozen_and_its_members_read_only() -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        Meter.__iec__.final = False  # type: ignore[misc]
    with pytest.raises(TypeError):
        Meter.__iec__.members["other"] = Meter.__iec__.members["reset"]  # type: ignore[index]


def test_other_objects_have_no_record() -> None:
    assert iec_class(int) is None and kind_of(object()) is None and kind_of(Meter()) is Kind.FUNCTION_BLOCK


def test_a_derived_block_gets_a_record_of_its_own() -> None:
    class Base(FunctionBlock, abstract=True):
        pass

    class Derived(Base):
        pass

    assert Base.__iec__.abstract and not Derived.__iec__.abstract
    assert Derived.__iec__ is not Base.__iec__ and isinstance(Derived.__iec__, IecClass)


def test_layout_of_fields_of_and_field_record_read_a_class_layout() -> None:
    from iecoop.metadata import field_record, fields_of, layout_of

    class Base(Struct):
        low: INT = 0

    class Derived(Base):
        high: INT = 10

    assert [r.name for r in fields_of(Derived)] == ["low", "high"]
    assert field_record(Derived, "high").spec.initial == 10
    assert layout_of(Derived, own=True) is layout_of(Derived) and layout_of(object) is None
    with pytest.raises(TypeError, match="is not a STRUCT, UNION, FUNCTION_BLOCK, PROGRAM or GVL class"):
        fields_of(int)


def test_only_the_builders_read_the_layout_attribute() -> None:
    # Everything else asks iecoop.metadata (layout_of, fields_of, field_record): one place knows where it is kept.
    import iecoop

    root = Path(iecoop.__file__).parent
    builders = {root / "pou.py", root / "metadata.py", root / "gvl.py"}
    readers = [str(path.relative_to(root)) for path in sorted(root.rglob("*.py"))
               if path not in builders and "memory" not in path.relative_to(root).parts
               and "_iec_layout_" in path.read_text(encoding="utf-8")]
    assert readers == []
