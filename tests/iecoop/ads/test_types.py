"""The ADS server's PLC types with pyads on 127.0.0.1: LREAL, WSTRING-free STRINGs, arrays, whole STRUCTs, by name.

A STRUCT is read and written whole, as pyads's ``read_structure_by_name``
/ ``write_structure_by_name`` do (pyads lays a structure out without
padding, so the STRUCTs here have none), and so is an ARRAY of them; each
member is checked, and one that does not fit stores nothing of the write.
"""

from __future__ import annotations

import struct
from collections.abc import Iterator
from typing import Any

import pytest

from iecoop import (
    ARRAY, BOOL, DINT, INT, LREAL, REAL, STRING, VAR, VAR_INPUT, ExceptionCode, GlobalVariables, PlcException, Program,
    Struct, T, gvl,
)
from iecoop.ads import AdsError, AdsServer
from iecoop.runtime import Runtime, Task
from tests.iecoop.ads.test_server import ads_code, client

pyads = pytest.importorskip("pyads")


class ST_TyPoint(Struct):
    fX: LREAL = 0.0
    nId: DINT = 0
    rWeight: REAL = 0.0
    sTag: STRING = VAR("", length=7)  # 8 bytes: the STRUCT is 24 bytes, without padding


class ST_TyLimits(Struct):
    nLow: INT = 0
    nHigh: INT = VAR(100, constant=True)


@gvl
class GVL_Types(GlobalVariables):
    fLength: LREAL = 0.0
    stPoint: ST_TyPoint = VAR()
    aPoints: ARRAY[ST_TyPoint] = VAR(bounds=(1, 2))
    aMatrix: ARRAY[INT] = VAR([1, 2, 3, 4], bounds=((0, 1), (0, 1)))
    stLimits: ST_TyLimits = VAR()


class TyMain(Program, st_name="MAIN"):
    bGo: BOOL = VAR_INPUT(False)
    fRate: LREAL = VAR_INPUT(0.125)
    nDivisor: INT = VAR_INPUT(1)
    nShare: INT = VAR(0)

    def body(self) -> None:
        if self.bGo:
            GVL_Types.fLength += self.fRate
        self.nShare = 100 // self.nDivisor


POINT = (("fX", pyads.PLCTYPE_LREAL, 1), ("nId", pyads.PLCTYPE_DINT, 1), ("rWeight", pyads.PLCTYPE_REAL, 1),
         ("sTag", pyads.PLCTYPE_STRING, 1, 7))


@pytest.fixture
def rt() -> Iterator[Runtime]:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), TyMain())
    GVL_Types.fLength = 0.0  # a GVL is one per process: each test starts from its initial values
    GVL_Types.stPoint.fX, GVL_Types.stPoint.nId, GVL_Types.stPoint.rWeight, GVL_Types.stPoint.sTag = 0.0, 0, 0.0, ""
    GVL_Types.stLimits.nLow = 0
    for index, value in enumerate((1, 2, 3, 4)):
        runtime.symbol(f"GVL_Types.aMatrix[{index // 2},{index % 2}]").store(value)
    yield runtime
    runtime.stop()


@pytest.fixture
def plc(rt: Runtime) -> Iterator[Any]:
    with AdsServer(rt, port=0) as server, client(server) as connection:
        yield connection


def test_lreal_keeps_its_64_bits_and_real_its_32(rt: Runtime, plc: Any) -> None:
    plc.write_by_name("MAIN.fRate", 0.1)
    plc.write_by_name("MAIN.bGo", True)
    rt.run(cycles=3)
    assert plc.read_by_name("MAIN.fRate") == 0.1  # an LREAL: no rounding to single precision
    assert plc.read_by_name("GVL_Types.fLength") == 0.1 + 0.1 + 0.1
    plc.write_by_name("GVL_Types.stPoint.rWeight", 0.1)
    rt.run(cycles=1)
    weight = plc.read_by_name("GVL_Types.stPoint.rWeight")
    assert weight != 0.1 and weight == pytest.approx(0.1, rel=1e-7)  # a REAL: single precision
    symbols = {s.name: s for s in plc.get_all_symbols()}
    assert (symbols["MAIN.fRate"].symbol_type, symbols["MAIN.fRate"].plc_type) == ("LREAL", pyads.PLCTYPE_LREAL)
    assert symbols["GVL_Types.stPoint"].symbol_type == "ST_TyPoint"
    info = pyads.pyads_ex.adsGetSymbolInfo(plc._port, plc._adr, "GVL_Types.stPoint")
    assert (info.size, info.dataType) == (24, pyads.constants.ADST_BIGTYPE)


def test_a_struct_is_read_and_written_whole(rt: Runtime, plc: Any) -> None:
    rt.run(cycles=1)
    assert plc.read_structure_by_name("GVL_Types.stPoint", POINT) == {"fX": 0.0, "nId": 0, "rWeight": 0.0, "sTag": ""}
    plc.write_structure_by_name("GVL_Types.stPoint", {"fX": 2.5, "nId": -7, "rWeight": 1.5, "sTag": "probe"}, POINT)
    assert GVL_Types.stPoint.nId == 0  # taken: stored at the next cycle start
    rt.run(cycles=1)
    point = GVL_Types.stPoint
    assert (point.fX, point.nId, point.rWeight, point.sTag) == (2.5, -7, 1.5, "probe")
    assert plc.read_structure_by_name("GVL_Types.stPoint", POINT) == {
        "fX": 2.5, "nId": -7, "rWeight": 1.5, "sTag": "probe"}


def test_an_array_of_structs_and_a_two_dimensional_array(rt: Runtime, plc: Any) -> None:
    points = [{"fX": 1.0, "nId": 1, "rWeight": 0.5, "sTag": "a"}, {"fX": 2.0, "nId": 2, "rWeight": 0.25, "sTag": "b"}]
    plc.write_structure_by_name("GVL_Types.aPoints", points, POINT, array_size=2)
    plc.write_by_name("GVL_Types.aMatrix", [4, 3, 2, 1], pyads.PLCTYPE_INT * 4)
    rt.run(cycles=1)
    assert plc.read_structure_by_name("GVL_Types.aPoints", POINT, array_size=2) == points
    assert plc.read_by_name("GVL_Types.aPoints[2].sTag") == "b"
    assert plc.read_by_name("GVL_Types.aMatrix", pyads.PLCTYPE_INT * 4) == [4, 3, 2, 1]  # pyads reads one dimension
    assert plc.read_by_name("GVL_Types.aMatrix[1,0]") == 2  # row-major, as TwinCAT lays it out


def test_a_whole_write_with_one_bad_member_stores_nothing(rt: Runtime, plc: Any) -> None:
    # A STRING(7) member given 8 characters and no terminator: the whole STRUCT is refused.
    raw = bytearray(plc.read_by_name("GVL_Types.stPoint", pyads.PLCTYPE_BYTE * 24))
    raw[0:8] = struct.pack("<d", 9.0)
    raw[16:24] = b"12345678"
    assert ads_code(lambda: plc.write_by_name("GVL_Types.stPoint", list(raw), pyads.PLCTYPE_BYTE * 24)) \
        == AdsError.INVALIDDATA
    # A member of a STRUCT may be a CONSTANT: the STRUCT is not written whole, its other members are.
    assert ads_code(lambda: plc.write_by_name("GVL_Types.stLimits", [1, 2], pyads.PLCTYPE_INT * 2)) \
        == AdsError.ACCESSDENIED
    plc.write_by_name("GVL_Types.stLimits.nLow", 5)
    rt.run(cycles=1)
    assert GVL_Types.stPoint.fX == 0.0 and GVL_Types.stPoint.sTag == ""
    assert (GVL_Types.stLimits.nLow, GVL_Types.stLimits.nHigh) == (5, 100)


def test_the_state_is_stop_after_a_fault_and_run_again_after_a_reset(rt: Runtime, plc: Any) -> None:
    rt.run(cycles=1)
    assert plc.read_state() == (pyads.ADSSTATE_RUN, 0)
    plc.write_by_name("MAIN.nDivisor", 0)
    with pytest.raises(PlcException) as fault:
        rt.run(cycles=1)
    assert fault.value.code is ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    assert plc.read_state() == (pyads.ADSSTATE_STOP, 0)
    assert plc.read_by_name("MAIN.nDivisor") == 0  # stopped by the fault: clients read where it stopped
    rt.reset_cold()
    assert plc.read_state() == (pyads.ADSSTATE_RUN, 0)


def test_the_raw_symbol_upload_gives_each_size_type_and_address(rt: Runtime, plc: Any) -> None:
    count, length = plc.read(0xF00C, 0, pyads.PLCTYPE_UDINT * 2)  # SYM_UPLOADINFO
    data = bytes(plc.read(0xF00B, 0, pyads.PLCTYPE_BYTE * length))  # SYM_UPLOAD
    entries = {}
    position = 0
    while position < len(data):
        size, group, offset, nbytes, ads_type, _flags, name_len, type_len, _comment = struct.unpack_from(
            "<IIIIIIHHH", data, position)
        name = data[position + 30 : position + 30 + name_len].decode()
        type_name = data[position + 31 + name_len : position + 31 + name_len + type_len].decode()
        entries[name] = (group, offset, nbytes, ads_type, type_name)
        position += size
    assert len(entries) == count
    assert {name: entry[2:] for name, entry in entries.items() if name.startswith(("MAIN.", "GVL_Types."))} == {
        "MAIN.bGo": (1, pyads.constants.ADST_BIT, "BOOL"),
        "MAIN.fRate": (8, pyads.constants.ADST_REAL64, "LREAL"),
        "MAIN.nDivisor": (2, pyads.constants.ADST_INT16, "INT"),
        "MAIN.nShare": (2, pyads.constants.ADST_INT16, "INT"),
        "GVL_Types.fLength": (8, pyads.constants.ADST_REAL64, "LREAL"),
        "GVL_Types.stPoint": (24, pyads.constants.ADST_BIGTYPE, "ST_TyPoint"),
        "GVL_Types.aPoints": (48, pyads.constants.ADST_BIGTYPE, "ARRAY [1..2] OF ST_TyPoint"),
        "GVL_Types.aMatrix": (8, pyads.constants.ADST_INT16, "ARRAY [0..1,0..1] OF INT"),
        "GVL_Types.stLimits": (4, pyads.constants.ADST_BIGTYPE, "ST_TyLimits"),
    }
    rt.run(cycles=1)
    group, offset = entries["MAIN.fRate"][:2]
    assert plc.read(group, offset, pyads.PLCTYPE_LREAL) == 0.125 == plc.read_by_name("MAIN.fRate")
    group, offset = entries["GVL_Types.aMatrix"][:2]
    assert plc.read(group, offset + 2 * 3, pyads.PLCTYPE_INT) == plc.read_by_name("GVL_Types.aMatrix[1,1]") == 4
