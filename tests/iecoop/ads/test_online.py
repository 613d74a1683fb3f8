"""TwinCAT's online write and force over ADS, with pyads on 127.0.0.1: off by default, ``AdsServer(online=True)``.

With it, a client writes any variable but a CONSTANT (outputs, internals,
an FB's members) and forces by handle (``IndexGroup.FORCE_BYHND``), as
``rt.force`` does: the force is the runtime's own, seen by every client
and by the program, listed in ``rt.forced``, released by
``RELEASE_BYHND`` (one byte: 1 restores the value from before the force).
"""

from __future__ import annotations

import struct
from collections.abc import Iterator
from typing import Any

import pytest

from iecoop.ads import AdsError, AdsServer
from iecoop.ads.protocol import IndexGroup
from iecoop.runtime import Runtime, Task
from iecoop import T
from tests.iecoop.ads.test_server import AdsMain, GVL_AdsIO, ads_code, client

pyads = pytest.importorskip("pyads")

FORCE, RELEASE = int(IndexGroup.FORCE_BYHND), int(IndexGroup.RELEASE_BYHND)


@pytest.fixture
def rt() -> Iterator[Runtime]:
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), AdsMain())
    GVL_AdsIO.bStart = False
    GVL_AdsIO.stRecipe.rTarget, GVL_AdsIO.stRecipe.nSteps = 0.0, 0
    yield runtime
    runtime.stop()


@pytest.fixture
def plc(rt: Runtime) -> Iterator[Any]:
    with AdsServer(rt, port=0, online=True) as server, client(server) as connection:
        yield connection


def test_online_write_and_force_are_off_by_default(rt: Runtime) -> None:
    with AdsServer(rt, port=0) as server, client(server) as plc:
        assert ads_code(lambda: plc.write_by_name("MAIN.nCount", 5, pyads.PLCTYPE_INT)) == AdsError.ACCESSDENIED
        handle = plc.get_handle("MAIN.bEnable")
        assert ads_code(lambda: plc.write(FORCE, handle, True, pyads.PLCTYPE_BOOL)) == AdsError.ACCESSDENIED
        rt.run(cycles=1)
        assert rt.forced == {}


def test_online_a_client_writes_outputs_and_internals_but_never_a_constant(rt: Runtime, plc: Any) -> None:
    plc.write_by_name("MAIN.fbStation.nBottles", 40)  # an FB's output
    rt.run(cycles=1)
    plc.write_by_name("MAIN.nCount", 7)  # the program's own VAR: the program overwrites it in the same cycle
    plc.write_by_name("MAIN.bEnable", True)
    rt.run(cycles=1)
    assert plc.read_by_name("MAIN.fbStation.nBottles") == 41 and plc.read_by_name("MAIN.nCount") == 41
    assert ads_code(lambda: plc.write_by_name("GVL_AdsIO.nLimit", 5, pyads.PLCTYPE_INT)) == AdsError.ACCESSDENIED
    symbols = {s.name: s for s in plc.get_all_symbols()}
    assert "MAIN.nCount" in symbols and "GVL_AdsIO.nLimit" in symbols


def test_a_force_by_handle_holds_until_released_and_every_reader_sees_it(rt: Runtime, plc: Any) -> None:
    bottles = plc.get_handle("MAIN.fbStation.nBottles")
    plc.write_by_name("MAIN.bEnable", True)
    rt.run(cycles=2)
    plc.write(FORCE, bottles, 100, pyads.PLCTYPE_INT)
    assert rt.forced == {}  # taken; forced from the next cycle start, in the PLC's thread
    rt.run(cycles=3)
    assert rt.forced == {"MAIN.fbStation.nBottles": 100}
    # The FB counts every cycle, the force puts 100 back before and after the code: the count is 101 inside.
    assert plc.read_by_name("MAIN.fbStation.nBottles") == 100 and plc.read_by_name("MAIN.nCount") == 101
    plc.write(RELEASE, bottles, 0, pyads.PLCTYPE_BYTE)  # <Unforce>: the forced value stays, then counts on
    rt.run(cycles=2)
    assert rt.forced == {} and plc.read_by_name("MAIN.fbStation.nBottles") == 102


def test_a_release_with_restore_and_a_struct_forced_whole(rt: Runtime, plc: Any) -> None:
    recipe = plc.get_handle("GVL_AdsIO.stRecipe")
    target = plc.get_handle("GVL_AdsIO.stRecipe.rTarget")
    GVL_AdsIO.stRecipe.rTarget = 1.25
    rt.run(cycles=1)
    plc.write(FORCE, recipe, list(struct.pack("<fh2x", 3.5, 9)), pyads.PLCTYPE_BYTE * 8)
    rt.run(cycles=1)
    assert rt.forced == {"GVL_AdsIO.stRecipe.rTarget": 3.5, "GVL_AdsIO.stRecipe.nSteps": 9}
    plc.write(RELEASE, target, 1, pyads.PLCTYPE_BYTE)  # <Unforce and restore>: 1.25 again
    rt.run(cycles=1)
    assert rt.forced == {"GVL_AdsIO.stRecipe.nSteps": 9}
    assert (GVL_AdsIO.stRecipe.rTarget, GVL_AdsIO.stRecipe.nSteps) == (1.25, 9)
    assert ads_code(lambda: plc.write(RELEASE, target, 2, pyads.PLCTYPE_BYTE)) == AdsError.INVALIDDATA


def test_a_refused_force_forces_nothing_and_a_sum_write_forces_all_or_nothing(rt: Runtime, plc: Any) -> None:
    mode = plc.get_handle("MAIN.eMode")
    enable = plc.get_handle("MAIN.bEnable")
    assert ads_code(lambda: plc.write(FORCE, mode, 3, pyads.PLCTYPE_INT)) == AdsError.INVALIDDATA  # no E_AdsMode 3
    assert ads_code(lambda: plc.write(FORCE, enable, 1, pyads.PLCTYPE_INT)) == AdsError.INVALIDSIZE
    assert ads_code(lambda: plc.write(FORCE, 999_999, True, pyads.PLCTYPE_BOOL)) == AdsError.SYMBOLNOTFOUND
    rt.run(cycles=1)
    assert rt.forced == {}
    # One sum write: a force and a refused write; neither is done.
    requests = struct.pack("<III", FORCE, enable, 1) + struct.pack("<III", int(IndexGroup.SYM_VALBYHND), mode, 2)
    data = requests + b"\x01" + struct.pack("<h", 3)
    answer = plc.read_write(int(IndexGroup.SUMUP_WRITE), 2, pyads.PLCTYPE_UDINT * 2, bytearray(data),
                            pyads.PLCTYPE_BYTE * len(data))
    assert struct.unpack("<II", bytes(answer)) == (AdsError.ABORTED, AdsError.INVALIDDATA)
    rt.run(cycles=1)
    assert rt.forced == {} and plc.read_by_name("MAIN.bEnable") is False
