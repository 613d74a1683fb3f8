"""Tc2_Utilities: FB_FormatString and its format errors, T_Arg helpers, time structures, strings, FB_MemRingBuffer."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import ARRAY, BYTE, DINT, Program, Struct, T, VAR, adr, sizeof
from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.libraries import known, module_of
from iecoop.libraries import tc2_utilities as tu
from iecoop.libraries.tc2_system import T_MaxString
from iecoop.literals import parse_dt
from iecoop.memory import Pointer
from iecoop.runtime import Runtime, Task
from iecoop.runtime.clock import default_clock


@pytest.fixture(autouse=True)
def clock_at_zero() -> Iterator[None]:
    default_clock().set(0)
    yield
    default_clock().set(0)


def fmt(text: str, *args: tu.T_Arg) -> tuple[str, bool, int]:
    block = tu.FB_FormatString()
    block(sFormat=text, **{f"arg{i}": arg for i, arg in enumerate(args, 1)})
    return block.sOut, block.bError, block.nErrId


def test_the_module_is_the_known_library_and_exports_its_st_names() -> None:
    library = known("tc2_utilities")
    assert library is not None and module_of(library) is tu
    for name in tu.__all__:
        assert hasattr(tu, name), name


def test_t_arg_and_timestruct_have_their_twincat_x64_sizes() -> None:
    assert sizeof(tu.T_Arg) == 16  # eType INT, cbLen UDINT, pData PVOID (8 bytes)
    assert sizeof(tu.TIMESTRUCT) == 16
    assert sizeof(tu.T_FILETIME) == 8


def test_helpers_fill_t_arg_as_beckhoff_documents() -> None:
    arg = tu.F_STRING("abc")
    assert (arg.eType, arg.cbLen) == (tu.E_ArgType.ARGTYPE_STRING, 4)  # length + 1 for the null
    assert (tu.F_INT(5).eType, tu.F_INT(5).cbLen) == (tu.E_ArgType.ARGTYPE_INT, 2)
    assert (tu.F_LREAL(1.0).eType, tu.F_LREAL(1.0).cbLen) == (tu.E_ArgType.ARGTYPE_LREAL, 8)
    assert tu.F_ULINT(1).eType == tu.E_ArgType.ARGTYPE_ULARGE and tu.F_LINT(1).eType == tu.E_ArgType.ARGTYPE_LARGE


@pytest.mark.parametrize(
    ("text", "args", "out"),
    [
        ("Measure X: %+.10d, Y: %+.10d", (tu.F_DINT(1234), tu.F_DINT(-23)), "Measure X: +0000001234, Y: -0000000023"),
        ("%d|%5d|%-5d|%05d|% d", (tu.F_INT(-7), tu.F_INT(42), tu.F_INT(42), tu.F_INT(-42), tu.F_INT(3)), "-7|   42|42   |-0042| 3"),
        ("%u %u", (tu.F_SINT(-1), tu.F_INT(-2)), "255 65534"),
        ("%x %X %#x %#X %08x", (tu.F_WORD(0xBEEF), tu.F_BYTE(0xAB), tu.F_DWORD(255), tu.F_UDINT(255), tu.F_DINT(-1)), "beef AB 0xff 0XFF ffffffff"),
        ("%o %#o %b %B", (tu.F_USINT(8), tu.F_USINT(8), tu.F_BYTE(10), tu.F_UINT(5)), "10 010 1010 101"),
        ("%x", (tu.F_REAL(1.0),), "3f800000"),
        ("%f %.2f %.0f %+.1f", (tu.F_LREAL(3.14159265), tu.F_LREAL(2.675), tu.F_LREAL(2.5), tu.F_REAL(1.25)), "3.141593 2.67 2 +1.2"),
        ("%10.3f|%-10.3f|%010.3f", (tu.F_LREAL(-1.5), tu.F_LREAL(1.5), tu.F_LREAL(-1.5)), "    -1.500|1.500     |-00001.500"),
        ("%e %E %.2e", (tu.F_LREAL(12345.678), tu.F_LREAL(-0.00012), tu.F_LREAL(0.0)), "1.234568e+004 -1.200000E-004 0.00e+000"),
        ("%f %f %f", (tu.F_LREAL(float("inf")), tu.F_LREAL(float("-inf")), tu.F_LREAL(float("nan"))), "#INF -#INF #QNAN"),
        ("[%s] [%8s] [%-8s] [%.3s]", (tu.F_STRING("ab"), tu.F_STRING("ab"), tu.F_STRING("ab"), tu.F_STRING("abcdef")), "[ab] [      ab] [ab      ] [abc]"),
        ("%s/%s", (tu.F_BOOL(True), tu.F_BOOL(False)), "TRUE/FALSE"),
        ("%c%c%c", (tu.F_BYTE(80), tu.F_USINT(76), tu.F_BYTE(67)), "PLC"),
        ("100%% done, no args", (), "100% done, no args"),
        ("%d %d %d %d %d %d %d %d %d %d", tuple(tu.F_INT(i) for i in range(10)), "0 1 2 3 4 5 6 7 8 9"),
        ("%d", (tu.F_LINT(-(2**40)),), "-1099511627776"),
    ],
)
def test_format_string_renders_as_beckhoff_documents(text: str, args: tuple[tu.T_Arg, ...], out: str) -> None:
    assert fmt(text, *args) == (out, False, 0)


@pytest.mark.parametrize(
    ("text", "args", "code"),
    [
        ("abc %", (), 0x10 + 1),  # percent sign at invalid position
        ("%d %5%", (tu.F_INT(1), tu.F_INT(2)), 0x10 + 2),
        ("%*d", (tu.F_INT(1),), 0x20 + 1),  # asterisk
        ("%300d", (tu.F_INT(1),), 0x40 + 1),  # invalid width
        ("%.300f", (tu.F_LREAL(1.0),), 0x80 + 1),  # invalid precision
        ("%5-d", (tu.F_INT(1),), 0x100 + 1),  # flag at invalid position
        ("%1.2.3f", (tu.F_LREAL(1.0),), 0x400 + 1),  # second dot
        ("%d %q", (tu.F_INT(1), tu.F_INT(2)), 0x800 + 2),  # unsupported type field
        ("%d", (tu.F_REAL(1.0),), 0x1000 + 1),  # type field and argument differ
        ("%f", (tu.F_INT(1),), 0x1000 + 1),
        ("%s", (tu.F_DINT(1),), 0x1000 + 1),
        ("%c", (tu.F_INT(65),), 0x1000 + 1),
        ("%d %d", (tu.F_INT(1),), 0x1000 + 2),  # argument 2 not given
        ("%s" * 11, tuple(tu.F_STRING("x") for _ in range(10)), 0x4000 + 11),  # more fields than arguments
        ("%s%s", (tu.F_STRING("x" * 200), tu.F_STRING("y" * 100)), 0x8000 + 2),  # sOut overflow
    ],
)
def test_format_errors_carry_beckhoffs_code_plus_the_argument_number(text: str, args: tuple[tu.T_Arg, ...], code: int) -> None:
    assert fmt(text, *args) == ("", True, code)


def test_an_error_clears_after_a_good_format() -> None:
    block = tu.FB_FormatString()
    block(sFormat="%q", arg1=tu.F_INT(1))
    assert block.bError
    block(sFormat="%d", arg1=tu.F_INT(1))
    assert (block.sOut, block.bError, block.nErrId) == ("1", False, 0)


@given(value=st.integers(-(2**31), 2**31 - 1), width=st.integers(0, 30), flags=st.sampled_from(["", "-", "+", "0", " ", "+0", "-+"]))
def test_integer_fields_match_c_printf(value: int, width: int, flags: str) -> None:
    spec = f"%{flags}{width or ''}d"
    assert fmt(spec, tu.F_DINT(value)) == (spec % value, False, 0)


@given(
    value=st.floats(-1e12, 1e12, allow_nan=False),
    width=st.integers(0, 20),
    precision=st.integers(0, 8),
    flags=st.sampled_from(["", "-", "+", "0", " ", "#", "+0"]),
)
def test_float_fields_match_c_printf(value: float, width: int, precision: int, flags: str) -> None:
    spec = f"%{flags}{width or ''}.{precision}f"
    assert fmt(spec, tu.F_LREAL(value)) == (spec % value, False, 0)


def test_format_string_reads_arguments_set_in_st_style_in_a_program() -> None:
    class Main(Program):
        count: DINT = VAR(0)
        text: T_MaxString = VAR("")
        fmt: tu.FB_FormatString = VAR()

        def body(self) -> None:
            self.count += 1
            self.fmt(sFormat="cycle %d", arg1=tu.F_DINT(self.count))
            self.text = self.fmt.sOut

    main = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    rt.run(cycles=3)
    assert main.text == "cycle 3"


def test_format_arg_to_str() -> None:
    class Out(Struct):
        text: T_MaxString = ""

    out = Out()
    code = tu.F_FormatArgToStr(
        True, False, True, False, False, True, 8, True, 2, tu.E_TypeFieldParam.TYPEFIELD_F, tu.F_LREAL(3.14159),
        sOut=adr(out, "text"),
    )
    assert (code, out.text) == (0, "+0003.14")
    code = tu.F_FormatArgToStr(
        False, False, False, True, False, False, 0, False, 0, tu.E_TypeFieldParam.TYPEFIELD_XU, tu.F_WORD(0xAB),
        sOut=adr(out, "text"),
    )
    assert (code, out.text) == (0, "0XAB")
    assert tu.F_FormatArgToStr(
        False, False, False, False, False, False, 0, False, 0, tu.E_TypeFieldParam.TYPEFIELD_D, tu.F_LREAL(1.0),
        sOut=adr(out, "text"),
    ) == 0x1001
    assert tu.F_FormatArgToStr(
        False, False, False, False, False, False, 0, False, 0, tu.E_TypeFieldParam.TYPEFIELD_UNKNOWN, tu.F_INT(1),
        sOut=adr(out, "text"),
    ) == 0x801


# --- time ---


def test_dt_and_timestruct_conversions() -> None:
    value = parse_dt("DT#2024-02-29-13:45:07")
    stamp = tu.DT_TO_SYSTEMTIME(value)
    assert (stamp.wYear, stamp.wMonth, stamp.wDay, stamp.wDayOfWeek) == (2024, 2, 29, 4)  # a Thursday
    assert (stamp.wHour, stamp.wMinute, stamp.wSecond, stamp.wMilliseconds) == (13, 45, 7, 0)
    assert tu.SYSTEMTIME_TO_DT(stamp) == value
    assert tu.SYSTEMTIME_TO_STRING(stamp) == "2024-02-29-13:45:07.000"
    assert tu.SYSTEMTIME_TO_DT(tu.TIMESTRUCT(wYear=2024, wMonth=2, wDay=30)) == 0  # no such date
    sunday = tu.DT_TO_SYSTEMTIME(parse_dt("DT#1970-01-04-00:00:00"))
    assert sunday.wDayOfWeek == 0


def test_filetime_conversions() -> None:
    stamp = tu.TIMESTRUCT(wYear=1970, wMonth=1, wDay=1, wHour=0, wMinute=0, wSecond=1, wMilliseconds=500)
    filetime = tu.SYSTEMTIME_TO_FILETIME(stamp)
    assert (filetime.dwHighDateTime << 32) | filetime.dwLowDateTime == 116_444_736_000_000_000 + 15_000_000
    back = tu.FILETIME_TO_SYSTEMTIME(filetime)
    assert tu.SYSTEMTIME_TO_STRING(back) == "1970-01-01-00:00:01.500"
    assert tu.SYSTEMTIME_TO_FILETIME64(stamp) == 116_444_736_000_000_000 + 15_000_000
    assert tu.SYSTEMTIME_TO_STRING(tu.FILETIME64_TO_SYSTEMTIME(116_444_736_000_000_000)) == "1970-01-01-00:00:00.000"


def test_nt_get_time_is_busy_one_call_then_gives_the_task_clock() -> None:
    default_clock().set(86_400_000_000_000 + 3_723_456_000_000)  # 1970-01-02 01:02:03.456
    block = tu.NT_GetTime()
    block(START=True)
    assert block.BUSY
    block(START=True)
    assert (block.BUSY, block.ERR) == (False, False)
    assert tu.SYSTEMTIME_TO_STRING(block.TIMESTR) == "1970-01-02-01:02:03.456"


def test_local_system_time_is_valid_after_its_first_synchronisation() -> None:
    block = tu.FB_LocalSystemTime()
    valid = []
    block(bEnable=True)
    valid.append(block.bValid)
    default_clock().advance(1_000_000_000)
    block(bEnable=True)
    valid.append(block.bValid)
    assert valid == [False, True]
    assert tu.SYSTEMTIME_TO_STRING(block.systemTime) == "1970-01-01-00:00:01.000"
    assert block.tzID == tu.E_TimeZoneID.eTimeZoneID_Unknown
    block(bEnable=False)
    assert not block.bValid


# --- strings and numbers ---


def test_case_and_trim_helpers() -> None:
    assert tu.F_ToLCase("Motor AXIS-1 Äö") == "motor axis-1 Äö"  # A..Z only
    assert tu.F_ToUCase("motor axis-1 äö") == "MOTOR AXIS-1 äö"
    assert (tu.F_LTrim("  a b  "), tu.F_RTrim("  a b  ")) == ("a b  ", "  a b")


def test_lreal_to_fmtstr_rounds_or_cuts() -> None:
    assert tu.LREAL_TO_FMTSTR(1234.56789, 2, True) == "1234.57"
    assert tu.LREAL_TO_FMTSTR(1234.56789, 2, False) == "1234.56"
    assert tu.LREAL_TO_FMTSTR(-1234.56789, 2, False) == "-1234.56"
    assert tu.LREAL_TO_FMTSTR(2.5, 0, True) == "3"
    assert tu.LREAL_TO_FMTSTR(1.0, 40, True) == "1." + "0" * 15
    assert tu.LREAL_TO_FMTSTR(float("inf"), 2, True) == "#INF"


def test_dword_to_hexstr() -> None:
    assert tu.DWORD_TO_HEXSTR(0xA1, 4, False) == "00A1"
    assert tu.DWORD_TO_HEXSTR(0xDEADBEEF, 2, True) == "deadbeef"
    assert tu.F_GetVersionTcUtilities(1) == 3


# --- FB_MemRingBuffer ---


class Buffers(Struct):
    ring: ARRAY[BYTE] = VAR(bounds=(0, 19))
    data: ARRAY[BYTE] = VAR(bounds=(0, 9))
    got: ARRAY[BYTE] = VAR(bounds=(0, 9))


def add(fifo: tu.FB_MemRingBuffer, memory: Buffers, payload: bytes) -> bool:
    for i, value in enumerate(payload):
        memory.data[i] = value
    fifo(pWrite=adr(memory, "data"), cbWrite=len(payload), pBuffer=adr(memory, "ring"), cbBuffer=20)
    fifo.A_AddTail()
    return fifo.bOk


def remove(fifo: tu.FB_MemRingBuffer, memory: Buffers, room: int = 10) -> tuple[bool, int, bytes]:
    fifo(pRead=adr(memory, "got"), cbRead=room)
    fifo.A_RemoveHead()
    return fifo.bOk, fifo.cbReturn, bytes(memory.got[i] for i in range(fifo.cbReturn if fifo.bOk else 0))


def test_mem_ring_buffer_is_a_fifo_of_records_that_wraps() -> None:
    memory, fifo = Buffers(), tu.FB_MemRingBuffer()
    assert add(fifo, memory, b"abc") and add(fifo, memory, b"defgh")
    assert (fifo.nCount, fifo.cbSize) == (2, 4 + 3 + 4 + 5)
    assert not add(fifo, memory, b"xyz")  # 16 + 7 > 20: full
    assert remove(fifo, memory) == (True, 3, b"abc")
    assert add(fifo, memory, b"xyz")  # wraps round the end of the buffer
    assert remove(fifo, memory, room=2) == (False, 5, b"")  # too small: cbReturn is the size needed
    assert remove(fifo, memory) == (True, 5, b"defgh")
    fifo.A_GetHead()
    assert (fifo.bOk, fifo.cbReturn, fifo.nCount) == (True, 3, 1)
    assert remove(fifo, memory) == (True, 3, b"xyz")
    assert remove(fifo, memory) == (False, 0, b"")
    assert (fifo.nCount, fifo.cbSize) == (0, 0)
    add(fifo, memory, b"q")
    fifo.A_Reset()
    assert (fifo.bOk, fifo.nCount, fifo.cbSize) == (True, 0, 0)


def test_mem_ring_buffer_without_a_buffer_is_not_ok() -> None:
    fifo = tu.FB_MemRingBuffer()
    fifo.A_AddTail()
    assert not fifo.bOk
    fifo.A_RemoveHead()
    assert (fifo.bOk, fifo.cbReturn) == (False, 0)





def test_filetime_to_dt_and_back_as_st_calls_them() -> None:
    from iecoop import st as iecoop_st

    stamp = parse_dt("DT#2024-01-28-11:05:43")
    filetime = tu.DT_TO_FILETIME(stamp)
    # 2024-01-28 11:05:43 UTC is 1706439943 s after 1970; FILETIME counts 100 ns from 1601
    ticks = (filetime.dwHighDateTime << 32) | filetime.dwLowDateTime
    assert ticks == 1_706_439_943 * 10_000_000 + 116_444_736_000_000_000
    assert tu.FILETIME_TO_DT(filetime) == stamp
    assert tu.FILETIME_TO_DT(tu.T_FILETIME(dwLowDateTime=5, dwHighDateTime=0)) == 0  # 1601 is before DT's range
    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR stFileTime : T_FILETIME; dtStamp : DT; END_VAR
    stFileTime := DT_TO_FILETIME(DTIN := DT#2024-01-28-11:05:43);
    stFileTime.dwLowDateTime := stFileTime.dwLowDateTime + 9999999;  (* 0.9999999 s later: still that second *)
    dtStamp := Tc2_Utilities.FILETIME_TO_DT(fileTime := stFileTime);
    END_PROGRAM
    """, libraries={"Tc2_Utilities": tu})
    plc.MAIN()
    assert plc.MAIN.dtStamp == stamp


@pytest.mark.parametrize("source", ["BYTE", "WORD", "DWORD", "LWORD"])
def test_number_to_string_conversions_fill_never_cut_and_give_empty_for_zero(source: str) -> None:
    hexstr, binstr = getattr(tu, f"{source}_TO_HEXSTR"), getattr(tu, f"{source}_TO_BINSTR")
    octstr, decstr = getattr(tu, f"{source}_TO_OCTSTR"), getattr(tu, f"{source}_TO_DECSTR")
    # Infosys BYTE_TO_HEXSTR: zeros from the left up to iPrecision, never cut; 0 with iPrecision 0 is ''
    assert (hexstr(0xAB, 4), hexstr(0xAB, 4, True), hexstr(0xAB, 1), hexstr(0, 0), hexstr(0, 1)) == (
        "00AB", "00ab", "AB", "", "0")
    assert (binstr(5, 8), binstr(5, 0), octstr(8, 3), decstr(123, 5), decstr(0, 0)) == (
        "00000101", "101", "010", "00123", "")
    assert hexstr(-1, 0) == "F" * {"BYTE": 2, "WORD": 4, "DWORD": 8, "LWORD": 16}[source]  # the type's width


def test_conversions_are_called_by_their_st_input_names_in_and_iprecision() -> None:
    from iecoop import st as iecoop_st

    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR sHex, sBin, sUpper : STRING; nCode : BYTE := 16#0F; END_VAR
    sHex := Tc2_Utilities.WORD_TO_HEXSTR(in := 16#BEEF, iPrecision := 6, bLoCase := TRUE);
    sBin := BYTE_TO_BINSTR(in := nCode, iPrecision := 0);
    sUpper := F_ToUCase(in := 'ok');
    END_PROGRAM
    """, libraries={"Tc2_Utilities": tu})
    plc.MAIN()
    assert (plc.MAIN.sHex, plc.MAIN.sBin, plc.MAIN.sUpper) == ("00beef", "1111", "OK")


def test_calendar_functions_follow_the_gregorian_rules() -> None:
    assert [tu.F_YearIsLeapYear(y) for y in (1900, 2000, 2023, 2024)] == [False, True, False, True]
    assert [tu.F_GetMaxMonthDays(2024, m) for m in (1, 2, 4, 12)] == [31, 29, 30, 31]
    assert (tu.F_GetMaxMonthDays(2023, 2), tu.F_GetMaxMonthDays(2023, 0), tu.F_GetMaxMonthDays(2023, 13)) == (28, 0, 0)
    assert (tu.F_GetDOYOfYearMonthDay(2024, 1, 1), tu.F_GetDOYOfYearMonthDay(2024, 12, 31),
            tu.F_GetDOYOfYearMonthDay(2023, 12, 31), tu.F_GetDOYOfYearMonthDay(2024, 3, 1)) == (1, 366, 365, 61)
    assert (tu.F_GetDOYOfYearMonthDay(2023, 2, 29), tu.F_GetDOYOfYearMonthDay(2023, 13, 1)) == (0, 0)


def test_find_and_replace_replaces_every_occurrence_into_the_destination_and_counts_them() -> None:
    from iecoop import st as iecoop_st

    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR
        sSrc : STRING(300) := 'a<b<c'; sFind : STRING := '<'; sInsert : STRING := '&lt;'; sNone : STRING := '#';
        sDst : STRING(300); sShort : STRING(5); sSame : STRING(300);
        nAll, nShort, nNone : UDINT;
    END_VAR
    nAll := FindAndReplace(pSrcString := ADR(sSrc), pDeleteString := ADR(sFind), pInsertString := ADR(sInsert),
                           pDstString := ADR(sDst), nDstSize := SIZEOF(sDst));
    nShort := Tc2_Utilities.FindAndReplace(pSrcString := ADR(sSrc), pSrcFindString := ADR(sFind),
                                           pSrcReplaceWithString := ADR(sInsert), pDstString := ADR(sShort),
                                           cbDstString := SIZEOF(sShort));
    nNone := FindAndReplace(ADR(sSrc), ADR(sNone), ADR(sInsert), ADR(sSame), SIZEOF(sSame));
    END_PROGRAM
    """, libraries={"Tc2_Utilities": tu})
    plc.MAIN()
    main = plc.MAIN
    assert (main.nAll, main.sDst) == (2, "a&lt;b&lt;c")
    assert (main.nShort, main.sShort) == (2, "a&lt;")  # cut to the destination's size, its terminator included
    assert (main.nNone, main.sSame) == (0, "a<b<c")  # not found: 0, and the destination is the source


def test_csv_fields_double_their_quotation_marks_and_are_enclosed_on_request() -> None:
    from iecoop import st as iecoop_st

    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR s1, s2, s3, s4, s5 : STRING; END_VAR
    s1 := STRING_TO_CSVFIELD('Valve "A"; open', TRUE);
    s2 := STRING_TO_CSVFIELD('Pump_50', FALSE);
    s3 := CSVFIELD_TO_STRING('"Valve ""A""; open"', TRUE);
    s4 := CSVFIELD_TO_STRING('Pump_50', TRUE);
    s5 := CSVFIELD_TO_STRING('ab""cd', FALSE);
    END_PROGRAM
    """, libraries={"Tc2_Utilities": tu})
    plc.MAIN()
    main = plc.MAIN
    assert (main.s1, main.s2, main.s3, main.s5) == ('"Valve ""A""; open"', "Pump_50", 'Valve "A"; open', 'ab"cd')
    assert main.s4 == ""  # bQM, but the field is not enclosed: an error
    assert tu.CSVFIELD_TO_STRING('a"b', False) == ""  # a quotation mark not doubled
    assert tu.STRING_TO_CSVFIELD('"' * 200, False) == ""  # 400 characters do not fit T_MaxString
    assert tu.CSVFIELD_TO_STRING(tu.STRING_TO_CSVFIELD('x;"y"', True), True) == 'x;"y"'


def test_the_pointer_string_functions_measure_and_convert_to_the_terminator() -> None:
    # LEN2 / WLEN2 count characters up to the 0 (a STRING(300) beyond 255 too); WSTRING_TO_STRING2 and
    # STRING_TO_WSTRING2 convert into nDstSize bytes, the terminator included, and say whether all of it fitted
    from iecoop import st as iecoop_st

    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR
        sLong : STRING(300); wsText : WSTRING := "Grüße"; sBack : STRING; sCut : STRING(3);
        wsBack : WSTRING; wsCut : WSTRING(2); sPlain : STRING := 'abc';
        nLong, nW, nEmpty : UDINT; bAll, bCutOk, bWide, bWideCut : BOOL; i : INT;
    END_VAR
    FOR i := 1 TO 26 DO sLong := CONCAT(sLong, '0123456789'); END_FOR
    nLong := LEN2(ADR(sLong));
    nW := Tc2_Utilities.WLEN2(ADR(wsText));
    nEmpty := LEN2(ADR(sBack));
    bAll := WSTRING_TO_STRING2(ADR(sBack), ADR(wsText), SIZEOF(sBack));
    bCutOk := WSTRING_TO_STRING2(pDstString := ADR(sCut), pSrcWString := ADR(wsText), nDstSize := SIZEOF(sCut));
    bWide := STRING_TO_WSTRING2(ADR(wsBack), ADR(sPlain), SIZEOF(wsBack));
    bWideCut := STRING_TO_WSTRING2(pDstWSTRING := ADR(wsCut), pSrcSTRING := ADR(sPlain), nDstSize := SIZEOF(wsCut));
    END_PROGRAM
    """, libraries={"Tc2_Utilities": tu})
    plc.MAIN()
    main = plc.MAIN
    assert (main.nLong, main.nW, main.nEmpty) == (260, 5, 0)
    assert (main.bAll, main.sBack) == (True, "Grüße")
    assert (main.bCutOk, main.sCut) == (False, "Grü")  # 4 bytes: 3 characters and the 0
    assert (main.bWide, main.wsBack) == (True, "abc")
    assert (main.bWideCut, main.wsCut) == (False, "ab")  # 6 bytes: 2 characters and the 0
    with pytest.raises(PlcException) as caught:
        tu.LEN2(Pointer(0))
    assert caught.value.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION and "LEN2: pSTRING is a null pointer" in str(caught.value)


def test_the_string_ring_buffer_keeps_strings_first_in_first_out() -> None:
    # 24 bytes hold two 'abcd'-long records (4 + 5 bytes each): the third is refused, or with bOverwrite it
    # pushes the oldest out; A_GetHead leaves the head, A_RemoveHead takes it
    from iecoop import st as iecoop_st

    plc = iecoop_st.load("""
    PROGRAM MAIN
    VAR
        aMem : ARRAY[0..23] OF BYTE; fifo : FB_StringRingBuffer; nStep : INT;
        bThird, bForced : BOOL; sPeek, sFirst, sSecond : STRING; nAfter : UDINT; bEmpty : BOOL := TRUE;
    END_VAR
    nStep := nStep + 1;
    fifo(pBuffer := ADR(aMem), cbBuffer := SIZEOF(aMem));
    IF nStep = 1 THEN
        fifo.putValue := 'abcd'; fifo.A_AddTail();
        fifo.putValue := 'efgh'; fifo.A_AddTail();
        fifo.putValue := 'ijkl'; fifo.A_AddTail(); bThird := fifo.bOk;
    ELSE
        fifo(bOverwrite := TRUE, putValue := 'mnop'); fifo.A_AddTail(); bForced := fifo.bOk;
        fifo.A_GetHead(); sPeek := fifo.getValue;
        fifo.A_RemoveHead(); sFirst := fifo.getValue;
        fifo.A_RemoveHead(); sSecond := fifo.getValue; nAfter := fifo.nCount;
        fifo.A_RemoveHead(); bEmpty := fifo.bOk;
    END_IF
    END_PROGRAM
    """, libraries={"Tc2_Utilities": tu})
    plc.MAIN()
    main = plc.MAIN
    assert (main.bThird, main.fifo.nCount, main.fifo.cbSize) == (False, 2, 18)
    plc.MAIN()
    assert (main.bForced, main.sPeek, main.sFirst, main.sSecond) == (True, "efgh", "efgh", "mnop")
    assert (main.nAfter, main.bEmpty) == (0, False)
