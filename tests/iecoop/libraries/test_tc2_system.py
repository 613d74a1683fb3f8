"""Tc2_System: the ADS log, time on the task clock, DRAND, task index, and the file blocks' sandbox and handshake."""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from iecoop import ARRAY, BYTE, DINT, Program, T, VAR, adr, sizeof
from iecoop.libraries import known, module_of
from iecoop.libraries import tc2_system as tc2
from iecoop.runtime import Runtime, Task
from iecoop.runtime.clock import VirtualClock, default_clock, use_clock


@pytest.fixture(autouse=True)
def clean() -> Iterator[None]:
    default_clock().set(0)
    tc2.clear_adslog()
    yield
    tc2.close_files()
    tc2.set_file_root(None)
    default_clock().set(0)


def test_the_module_is_the_known_library_and_exports_its_st_names() -> None:
    library = known("Tc2_System")
    assert library is not None and module_of(library) is tc2
    for name in tc2.__all__:
        assert hasattr(tc2, name), name


def test_string_aliases_have_twincat_lengths() -> None:
    from iecoop import Struct

    class Names(Struct):
        long: tc2.T_MaxString = ""
        net: tc2.T_AmsNetId = ""
        ip: tc2.T_IPv4Addr = ""

    names = Names()
    names.long = "x" * 300
    names.net = "1.2.3.4.5.6.7.8.9.10.11.12"
    assert len(names.long) == 255
    assert len(names.net) == 23
    assert sizeof(Names) == 256 + 24 + 16


# --- the ADS log ---


def test_adslog_renders_its_placeholder_as_twincat_and_records_the_mask(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.INFO, logger="iecoop.libraries.tc2_system"):
        assert tc2.ADSLOGSTR(tc2.ADSLOG_MSGTYPE_HINT, "Axis %s ready", "X1") == 0
        assert tc2.ADSLOGDINT(tc2.ADSLOG_MSGTYPE_WARN | tc2.ADSLOG_MSGTYPE_LOG, "count %d", -17) == 0
        assert tc2.ADSLOGLREAL(tc2.ADSLOG_MSGTYPE_ERROR, "temp %f C", 21.5) == 0
    messages = tc2.adslog_messages()
    assert [m.text for m in messages] == ["Axis X1 ready", "count -17", "temp 21.500000 C"]
    assert [m.msg_ctrl_mask for m in messages] == [0x01, 0x12, 0x04]
    assert [r.levelno for r in caplog.records] == [logging.INFO, logging.WARNING, logging.ERROR]
    assert caplog.records[2].getMessage() == "temp 21.500000 C"


def test_adslog_keeps_a_format_it_cannot_render_as_written() -> None:
    tc2.ADSLOGDINT(tc2.ADSLOG_MSGTYPE_HINT, "bad %q", 1)
    assert tc2.adslog_messages()[-1].text == "bad %q"
    tc2.clear_adslog()
    assert tc2.adslog_messages() == []


def test_adslog_flag_values_are_beckhoffs() -> None:
    assert (tc2.ADSLOG_MSGTYPE_HINT, tc2.ADSLOG_MSGTYPE_WARN, tc2.ADSLOG_MSGTYPE_ERROR) == (1, 2, 4)
    assert (tc2.ADSLOG_MSGTYPE_LOG, tc2.ADSLOG_MSGTYPE_MSGBOX, tc2.ADSLOG_MSGTYPE_STRING) == (0x10, 0x20, 0x80)


# --- time ---


def test_system_time_is_the_task_clock_as_filetime_from_1970() -> None:
    assert tc2.F_GetSystemTime() == 116_444_736_000_000_000
    default_clock().set(1_500_000_000)  # 1.5 s after 1970-01-01
    assert tc2.F_GetSystemTime() == 116_444_736_000_000_000 + 15_000_000
    fb = tc2.GETSYSTEMTIME()
    fb()
    assert (fb.timeHiDW << 32) | fb.timeLoDW == tc2.F_GetSystemTime()


def test_cpu_counter_counts_100ns_ticks_of_the_task_clock() -> None:
    default_clock().set((5 << 32) * 100 + 700)
    fb = tc2.GETCPUCOUNTER()
    fb()
    assert (fb.cpuCntHiDW, fb.cpuCntLoDW) == (5, 7)


def test_task_time_is_the_cycle_start_in_a_runtime() -> None:
    seen: list[int] = []

    class Main(Program):
        n: DINT = VAR(0)

        def body(self) -> None:
            seen.append(tc2.F_GetTaskTime())

    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), Main())
    rt.run(cycles=3)
    assert [t - seen[0] for t in seen] == [0, 100_000, 200_000]  # 10 ms = 100 000 × 100 ns


def test_current_task_index_in_a_runtime() -> None:
    seen: dict[str, int] = {}

    def program(task: str) -> Program:
        class Watch(Program):
            n: DINT = VAR(0)

            def body(self) -> None:
                fb = tc2.GETCURTASKINDEX()
                fb()
                seen[task] = fb.index

        return Watch()

    rt = Runtime(store=":memory:")
    rt.add_task(Task("IdxFast", interval=T("10ms"), priority=10), program("IdxFast"))
    rt.add_task(Task("IdxSlow", interval=T("20ms"), priority=20), program("IdxSlow"))
    rt.run(cycles=2)
    assert seen["IdxFast"] != seen["IdxSlow"]
    assert {seen["IdxFast"], seen["IdxSlow"]} <= set(range(1, 256))
    assert tc2.GETCURTASKINDEXEX() == 1  # outside a cycle


def test_drand_is_reproducible_and_in_range() -> None:
    a, b, c = tc2.DRAND(), tc2.DRAND(), tc2.DRAND()
    first = []
    for _ in range(50):
        a(Seed=7)
        b(Seed=7)
        c(Seed=8)
        assert a.Num == b.Num
        assert 0.0 <= a.Num < 1.0
        first.append(c.Num)
    assert len(set(first)) == 50
    a(Seed=7)  # a new Seed restarts the sequence
    fresh = tc2.DRAND()
    fresh(Seed=9)
    a(Seed=9)
    assert a.Num == fresh.Num


def test_version_record_and_function() -> None:
    version = tc2.stLibVersion_Tc2_System
    assert (version.iMajor, version.iMinor, version.iBuild, version.sVersion) == (3, 4, 26, "3.4.26.0")
    assert [tc2.F_GetVersionTcSystem(i) for i in (1, 2, 3, 9)] == [3, 4, 26, 0]


def test_e_open_path_values() -> None:
    assert (tc2.E_OpenPath.PATH_GENERIC, tc2.E_OpenPath.PATH_BOOTPATH, tc2.E_OpenPath.PATH_USERPATH9) == (1, 4, 19)


# --- files ---


def finish(fb: Any, **inputs: Any) -> None:
    """A rising edge, then calls until the request is done (bounded: one call here)."""
    fb(bExecute=False)
    fb(bExecute=True, **inputs)
    assert fb.bBusy
    for _ in range(10):
        fb()
        if not fb.bBusy:
            return
    raise AssertionError("the request never finished")


def test_without_a_sandbox_every_file_block_answers_not_found() -> None:
    opener = tc2.FB_FileOpen()
    finish(opener, sPathName="data.txt", nMode=tc2.FOPEN_MODEWRITE)
    assert (opener.bError, opener.nErrId, opener.hFile) == (True, 0x70C, 0)
    deleter = tc2.FB_FileDelete()
    finish(deleter, sPathName="data.txt")
    assert deleter.nErrId == 0x70C


def test_write_then_read_lines_and_bytes(tmp_path: Path) -> None:
    opener, closer, puts, gets = tc2.FB_FileOpen(), tc2.FB_FileClose(), tc2.FB_FilePuts(), tc2.FB_FileGets()
    with tc2.file_root(tmp_path):
        finish(opener, sPathName="log.txt", nMode=tc2.FOPEN_MODEWRITE | tc2.FOPEN_MODETEXT)
        assert not opener.bError and opener.hFile > 0
        for line in ("first\n", "second\n"):
            finish(puts, hFile=opener.hFile, sLine=line)
            assert not puts.bError
        finish(closer, hFile=opener.hFile)
        assert not closer.bError
        assert (tmp_path / "log.txt").read_bytes() == b"first\nsecond\n"

        finish(opener, nMode=tc2.FOPEN_MODEREAD)
        lines = []
        for _ in range(3):
            finish(gets, hFile=opener.hFile)
            lines.append((gets.sLine, gets.bEOF))
        assert lines == [("first\n", False), ("second\n", False), ("", True)]

        class Buffer(Program):
            data: ARRAY[BYTE] = VAR(bounds=(0, 15))

        buffer = Buffer()
        reader, writer = tc2.FB_FileRead(), tc2.FB_FileWrite()
        finish(closer, hFile=opener.hFile)
        finish(opener, sPathName="log.txt", nMode=tc2.FOPEN_MODEREAD | tc2.FOPEN_MODEBINARY)
        finish(reader, hFile=opener.hFile, pReadBuff=adr(buffer, "data"), cbReadLen=16)
        assert (reader.bError, reader.cbRead, reader.bEOF) == (False, 13, True)
        assert bytes(buffer.data[i] for i in range(13)) == b"first\nsecond\n"
        finish(closer, hFile=opener.hFile)

        finish(opener, sPathName="copy.bin", nMode=tc2.FOPEN_MODEAPPEND | tc2.FOPEN_MODEBINARY)
        finish(writer, hFile=opener.hFile, pWriteBuff=adr(buffer, "data"), cbWriteLen=5)
        assert (writer.bError, writer.cbWrite) == (False, 5)
        finish(closer, hFile=opener.hFile)
        assert (tmp_path / "copy.bin").read_bytes() == b"first"

        deleter = tc2.FB_FileDelete()
        finish(deleter, sPathName="copy.bin")
        assert not deleter.bError and not (tmp_path / "copy.bin").exists()
        finish(deleter, sPathName="copy.bin")
        assert (deleter.bError, deleter.nErrId) == (True, 0x70C)


def test_the_handshake_over_runtime_cycles(tmp_path: Path) -> None:
    trace: list[tuple[int, bool, bool, int]] = []

    class Main(Program):
        step: DINT = VAR(0)
        opener: tc2.FB_FileOpen = VAR()

        def body(self) -> None:
            self.opener(sPathName="cycle.txt", nMode=tc2.FOPEN_MODEWRITE, bExecute=self.step >= 1)
            trace.append((self.step, self.opener.bBusy, self.opener.bError, self.opener.hFile))
            self.step += 1

    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), Main())
    with tc2.file_root(tmp_path):
        rt.run(cycles=4)
    assert [row[1] for row in trace] == [False, True, False, False]  # busy for the one cycle after the edge
    assert trace[2][3] > 0 and trace[3][3] == trace[2][3]  # the handle stays until the next edge
    assert (tmp_path / "cycle.txt").exists()


def test_an_edge_while_busy_is_ignored_and_outputs_stay_until_the_next_edge(tmp_path: Path) -> None:
    opener = tc2.FB_FileOpen()
    with tc2.file_root(tmp_path):
        opener(sPathName="missing.txt", nMode=tc2.FOPEN_MODEREAD, bExecute=True)
        opener(bExecute=False)  # the request still completes
        assert (opener.bBusy, opener.bError, opener.nErrId) == (False, True, 0x70C)
        opener(bExecute=False)
        assert opener.bError
        opener(bExecute=True)
        assert (opener.bBusy, opener.bError, opener.nErrId) == (True, False, 0)


@pytest.mark.parametrize(
    ("name", "code"),
    [
        ("../outside.txt", 0x704),
        ("sub/../../outside.txt", 0x704),
        ("/etc/passwd", 0x704),
        ("C:\\TwinCAT\\data.txt", 0x704),
        ("\\\\server\\share\\x", 0x704),
        ("", 0x70C),
        ("nofolder/x.txt", 0x70C),
    ],
)
def test_paths_outside_the_sandbox_are_refused_with_twincats_codes(tmp_path: Path, name: str, code: int) -> None:
    opener = tc2.FB_FileOpen()
    with tc2.file_root(tmp_path / "root") as root:
        root.mkdir()
        finish(opener, sPathName=name, nMode=tc2.FOPEN_MODEWRITE)
    assert (opener.bError, opener.nErrId, opener.hFile) == (True, code, 0)
    assert list(tmp_path.iterdir()) == [tmp_path / "root"]


def test_links_are_refused_even_inside_the_sandbox(tmp_path: Path) -> None:
    root = tmp_path / "root"
    root.mkdir()
    (tmp_path / "secret.txt").write_text("secret")
    (root / "link.txt").symlink_to(tmp_path / "secret.txt")
    (root / "dir").symlink_to(tmp_path)
    (root / "inner.txt").write_text("ok")
    (root / "alias.txt").symlink_to(root / "inner.txt")
    opener = tc2.FB_FileOpen()
    with tc2.file_root(root):
        for name in ("link.txt", "dir/secret.txt", "alias.txt"):
            finish(opener, sPathName=name, nMode=tc2.FOPEN_MODEREAD)
            assert (opener.bError, opener.nErrId) == (True, 0x704), name
        deleter = tc2.FB_FileDelete()
        finish(deleter, sPathName="link.txt")
        assert deleter.nErrId == 0x704
    assert (tmp_path / "secret.txt").read_text() == "secret"


def test_bad_modes_handles_and_net_ids(tmp_path: Path) -> None:
    opener, closer, gets = tc2.FB_FileOpen(), tc2.FB_FileClose(), tc2.FB_FileGets()
    with tc2.file_root(tmp_path):
        finish(opener, sPathName="a.txt", nMode=tc2.FOPEN_MODEREAD | tc2.FOPEN_MODEWRITE)
        assert opener.nErrId == 0x70B
        finish(opener, sPathName="a.txt", nMode=0)
        assert opener.nErrId == 0x70B
        finish(closer, hFile=42)
        assert (closer.bError, closer.nErrId) == (True, 0x70B)
        finish(gets, hFile=0)
        assert (gets.bError, gets.nErrId, gets.sLine) == (True, 0x70B, "")
        finish(opener, sNetId="5.1.2.3.1.1", sPathName="a.txt", nMode=tc2.FOPEN_MODEWRITE)
        assert (opener.bError, opener.nErrId) == (True, 0x7)
        finish(opener, sNetId="", sPathName=".", nMode=tc2.FOPEN_MODEREAD)
        assert opener.nErrId == 0x70C
        (tmp_path / "folder").mkdir()
        finish(opener, sPathName="folder", nMode=tc2.FOPEN_MODEREAD)
        assert opener.nErrId == 0x704


def test_leaving_file_root_closes_its_files_and_restores_the_folder(tmp_path: Path) -> None:
    opener, puts = tc2.FB_FileOpen(), tc2.FB_FilePuts()
    with tc2.file_root(tmp_path) as root:
        assert tc2.get_file_root() == root
        finish(opener, sPathName="x.txt", nMode=tc2.FOPEN_MODEWRITE)
    assert tc2.get_file_root() is None
    finish(puts, hFile=opener.hFile, sLine="late")
    assert puts.nErrId == 0x70B


_names = st.lists(
    st.one_of(st.sampled_from(["..", ".", "", "sub", "C:", "/", "\\", "~", "link"]), st.text(st.characters(min_codepoint=1, max_codepoint=255), min_size=1, max_size=6)),
    min_size=1,
    max_size=5,
).map(lambda parts: "/".join(parts))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=_names, absolute=st.booleans(), backslash=st.booleans())
def test_no_path_name_reaches_a_file_outside_the_sandbox(tmp_path: Path, name: str, absolute: bool, backslash: bool) -> None:
    root = tmp_path / "root"
    root.mkdir(exist_ok=True)
    (root / "sub").mkdir(exist_ok=True)
    if not (root / "link").is_symlink():
        (root / "link").symlink_to(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    if absolute:
        name = "/" + name
    if backslash:
        name = name.replace("/", "\\")
    opener, deleter = tc2.FB_FileOpen(), tc2.FB_FileDelete()
    with tc2.file_root(root):
        finish(opener, sPathName=name, nMode=tc2.FOPEN_MODEAPPEND)
        if not opener.bError:
            path = Path(os.path.realpath(tc2.sandbox_path(name)))
            assert path.is_relative_to(root) and path != root
        finish(deleter, sPathName=name)
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    for path in root.rglob("*"):
        assert os.path.realpath(path).startswith(str(root)) or path.is_symlink()


def test_open_files_are_limited(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(tc2, "MAX_OPEN_FILES", 3)
    opener = tc2.FB_FileOpen()
    with tc2.file_root(tmp_path):
        handles = []
        for i in range(4):
            finish(opener, sPathName=f"f{i}.txt", nMode=tc2.FOPEN_MODEWRITE)
            handles.append((opener.hFile, opener.nErrId))
        assert [code for _, code in handles] == [0, 0, 0, 0x70A]
        closer = tc2.FB_FileClose()
        finish(closer, hFile=handles[0][0])
        finish(opener, sPathName="f3.txt", nMode=tc2.FOPEN_MODEWRITE)
        assert not opener.bError


def test_a_read_longer_than_the_buffer_faults_at_its_end(tmp_path: Path) -> None:
    from iecoop import ExceptionCode, PlcException, Struct

    class Small(Struct):
        data: ARRAY[BYTE] = VAR(bounds=(0, 3))

    (tmp_path / "big.bin").write_bytes(bytes(range(100)))
    small = Small()
    opener, reader = tc2.FB_FileOpen(), tc2.FB_FileRead()
    with tc2.file_root(tmp_path):
        finish(opener, sPathName="big.bin", nMode=tc2.FOPEN_MODEREAD)
        reader(hFile=opener.hFile, pReadBuff=adr(small, "data"), cbReadLen=50, bExecute=True)
        with pytest.raises(PlcException) as info:
            reader()
    assert info.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION
    assert [small.data[i] for i in range(4)] == [0, 1, 2, 3]


def test_the_adslog_list_keeps_the_latest_messages() -> None:
    for i in range(tc2.ADSLOG_KEEP + 5):
        tc2.ADSLOGDINT(tc2.ADSLOG_MSGTYPE_HINT, "%d", i)
    messages = tc2.adslog_messages()
    assert len(messages) == tc2.ADSLOG_KEEP
    assert (messages[0].text, messages[-1].text) == ("5", str(tc2.ADSLOG_KEEP + 4))


# --- memory, bits and characters (Infosys values) ---------------------------------------------


def _load(body: str, declarations: str) -> Any:
    from iecoop import st as iecoop_st

    return iecoop_st.load(f"PROGRAM MAIN\nVAR {declarations} END_VAR\n{body}\nEND_PROGRAM\n", libraries={"Tc2_System": tc2})


def test_memcpy_memmove_memset_memcmp_as_st_calls_them_plain_and_qualified() -> None:
    plc = _load(
        "nCopied := Tc2_System.MEMCPY(destAddr := ADR(aTo), srcAddr := ADR(aFrom), n := SIZEOF(aFrom));\n"
        "nSame := MEMCMP(ADR(aTo), ADR(aFrom), 4);\n"
        "nMoved := MEMMOVE(ADR(aFrom[1]), ADR(aFrom), 3);\n"
        "nLess := Tc2_System.MEMCMP(pBuf1 := ADR(aFrom), pBuf2 := ADR(aTo), n := 4);\n"
        "nFilled := MEMSET(ADR(aTo), 16#FF, 2);\n"
        "nMore := MEMCMP(ADR(aTo), ADR(aFrom), 4);\n"
        "nNothing := MEMCPY(ADR(aTo), 0, 4) + MEMSET(ADR(aTo), 1, 0);\n"
        "nRefused := MEMCMP(ADR(aTo), ADR(aFrom), 0);\n",
        "aFrom : ARRAY[0..3] OF BYTE := [1, 2, 3, 4]; aTo : ARRAY[0..3] OF BYTE; nCopied, nMoved, nFilled, nNothing : UDINT;"
        " nSame, nLess, nMore, nRefused : DINT;",
    )
    plc.MAIN()
    main = plc.MAIN
    assert (main.nCopied, main.nSame) == (4, 0)
    assert list(main.aFrom) == [1, 1, 2, 3] and main.nMoved == 3  # overlapping areas: the source is read first
    assert main.nLess == -1  # 1 1 2 3 against 1 2 3 4
    assert list(main.aTo) == [0xFF, 0xFF, 3, 4] and main.nFilled == 2 and main.nMore == 1
    assert main.nNothing == 0  # a 0 address or a count of 0: nothing done, 0 returned
    assert main.nRefused == 0xFF


def test_the_bit_functions_take_the_bit_number_modulo_32() -> None:
    assert tc2.SETBIT32(0, 31) == 0x8000_0000  # Infosys SETBIT32: bit 31 of 0 is 16#80000000
    assert tc2.CSETBIT32(0x8000_0000, 15, True) == 0x8000_8000  # Infosys CSETBIT32
    assert tc2.CSETBIT32(0x8000_8000, 31, False) == 0x8000
    assert tc2.CLEARBIT32(0xFFFF_FFFF, 0) == 0xFFFF_FFFE
    assert tc2.SETBIT32(0, 33) == 2 and tc2.GETBIT32(0x8, 35) and not tc2.GETBIT32(0x8, 2)
    plc = _load("nOut := Tc2_System.SETBIT32(inVal32 := 16#10, bitNo := 0); bBit := GETBIT32(nOut, 4);",
                "nOut : DWORD; bBit : BOOL;")
    plc.MAIN()
    assert (plc.MAIN.nOut, plc.MAIN.bBit) == (0x11, True)


def test_f_toasc_and_f_tochr_convert_one_character() -> None:
    assert tc2.F_ToASC("1") == 0x31 and tc2.F_ToASC("AB") == 0x41 and tc2.F_ToASC("") == 0
    assert tc2.F_ToCHR(0x31) == "1" and tc2.F_ToCHR(0xE9) == "é" and tc2.F_ToCHR(0) == ""
    plc = _load("c := F_ToASC(str := 'Z'); s := Tc2_System.F_ToCHR(c := c + 1);", "c : BYTE; s : STRING(1);")
    plc.MAIN()
    assert (plc.MAIN.c, plc.MAIN.s) == (0x5A, "[")


def test_seek_and_tell_move_the_file_pointer_from_each_origin(tmp_path: Path) -> None:
    (tmp_path / "data.txt").write_bytes(b"0123456789")
    opener, gets, seek, tell = tc2.FB_FileOpen(), tc2.FB_FileGets(), tc2.FB_FileSeek(), tc2.FB_FileTell()
    with tc2.file_root(tmp_path):
        finish(opener, sPathName="data.txt", nMode=tc2.FOPEN_MODEREAD)
        handle = opener.hFile
        finish(seek, hFile=handle, nSeekPos=4, eOrigin=tc2.E_SeekOrigin.SEEK_SET)
        finish(tell, hFile=handle)
        assert (seek.bError, tell.bError, tell.nSeekPos) == (False, False, 4)
        finish(seek, nSeekPos=2, eOrigin=tc2.E_SeekOrigin.SEEK_CUR)
        finish(gets, hFile=handle)
        assert gets.sLine == "6789"
        finish(seek, nSeekPos=-3, eOrigin=tc2.E_SeekOrigin.SEEK_END)
        finish(tell)
        assert tell.nSeekPos == 7
        finish(seek, nSeekPos=-1, eOrigin=tc2.E_SeekOrigin.SEEK_SET)  # before the start
        assert (seek.bError, seek.nErrId) == (True, 0x70B)
        finish(tell, hFile=handle + 1)  # no such handle
        assert (tell.bError, tell.nErrId, tell.nSeekPos) == (True, 0x70B, -1)


def test_rename_create_and_remove_folders_in_the_sandbox(tmp_path: Path) -> None:
    (tmp_path / "old.txt").write_text("x")
    rename, mkdir, rmdir = tc2.FB_FileRename(), tc2.FB_CreateDir(), tc2.FB_RemoveDir()
    with tc2.file_root(tmp_path):
        finish(mkdir, sPathName="logs")
        assert not mkdir.bError and (tmp_path / "logs").is_dir()
        finish(mkdir, sPathName="logs")
        assert (mkdir.bError, mkdir.nErrId) == (True, 0x70F)  # exists
        finish(rename, sOldName="old.txt", sNewName="logs\\new.txt")
        assert not rename.bError and (tmp_path / "logs" / "new.txt").read_text() == "x"
        finish(rename, sOldName="old.txt", sNewName="again.txt")
        assert (rename.bError, rename.nErrId) == (True, 0x70C)  # gone
        (tmp_path / "taken.txt").write_text("y")
        finish(rename, sOldName="logs/new.txt", sNewName="taken.txt")
        assert (rename.bError, rename.nErrId) == (True, 0x70F)
        finish(rename, sOldName="logs/new.txt", sNewName="..\\outside.txt")
        assert (rename.bError, rename.nErrId) == (True, 0x704)
        finish(rmdir, sPathName="logs")
        assert (rmdir.bError, rmdir.nErrId) == (True, 0x704)  # not empty
        (tmp_path / "logs" / "new.txt").unlink()
        finish(rmdir, sPathName="logs")
        assert not rmdir.bError and not (tmp_path / "logs").exists()
        finish(rmdir, sPathName="logs")
        assert (rmdir.bError, rmdir.nErrId) == (True, 0x70C)
    assert not (tmp_path.parent / "outside.txt").exists()
