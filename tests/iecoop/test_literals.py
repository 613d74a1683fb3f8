"""TIME, LTIME, DATE, TOD and DT literals: known values, round trips, and every refusal."""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import literals
from iecoop.literals import (
    D,
    T,
    format_date,
    format_dt,
    format_ltime,
    format_time,
    format_tod,
    parse_date,
    parse_dt,
    parse_ltime,
    parse_tod,
)

U32_MAX = 2**32 - 1
U64_MAX = 2**64 - 1
LAST_DAY = 49_710  # 2106-02-07, the last whole day a 32-bit second count reaches


# --- known values ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "ms"),
    [
        ("1d2h3m4s5ms", 93_784_005),
        ("T#1.5s", 1_500),
        ("T#0ms", 0),
        ("t#500MS", 500),
        ("TIME#1h", 3_600_000),
        ("time#1_000ms", 1_000),
        ("90m", 5_400_000),
        ("1.5d", 129_600_000),
        ("1m0.25s", 60_250),
        ("T#49d17h2m47s295ms", U32_MAX),
    ],
)
def test_time_known_values(text: str, ms: int) -> None:
    assert T(text) == ms


@pytest.mark.parametrize(
    ("text", "ns"),
    [
        ("1ms500us", 1_500_000),
        ("LTIME#1ms", 1_000_000),
        ("lt#2.5us", 2_500),
        ("LTIME#1d", 86_400 * 10**9),
        ("LTIME#213503d23h34m33s709ms551us615ns", U64_MAX),
        ("0ns", 0),
    ],
)
def test_ltime_known_values(text: str, ns: int) -> None:
    assert parse_ltime(text) == ns


def test_date_tod_dt_known_values() -> None:
    assert D("1970-01-01") == 0
    assert D("D#2024-01-28") == 1_706_400_000
    assert D("date#2024-1-5") == D("2024-01-05")
    assert D("2106-02-07") == LAST_DAY * 86_400
    assert parse_date is D
    assert parse_tod("12:30:00.5") == 45_000_500
    assert parse_tod("TOD#0:0:0") == 0
    assert parse_tod("TIME_OF_DAY#23:59:59.999") == 86_399_999
    assert parse_tod("00:00:00.05") == 50
    assert parse_dt("DT#2024-01-28-11:05:43") == 1_706_439_943
    assert parse_dt("date_and_time#1970-1-1-0:0:0") == 0
    assert parse_dt("2106-02-07-06:28:15") == U32_MAX
    assert D("2024-02-29") == parse_dt("2024-02-29-00:00:00")


def test_formatters_write_canonical_form() -> None:
    assert format_time(93_784_005) == "T#1d2h3m4s5ms"
    assert format_time(0) == "T#0ms"
    assert format_time(3_600_005) == "T#1h5ms"
    assert format_time(U32_MAX) == "T#49d17h2m47s295ms"
    assert format_ltime(1_500_000) == "LTIME#1ms500us"
    assert format_ltime(0) == "LTIME#0ns"
    assert format_ltime(U64_MAX) == "LTIME#213503d23h34m33s709ms551us615ns"
    assert format_date(1_706_400_000) == "D#2024-01-28"
    assert format_date(1_706_439_943) == "D#2024-01-28"  # a DATE shows only the day
    assert format_tod(45_000_500) == "TOD#12:30:00.5"
    assert format_tod(45_000_050) == "TOD#12:30:00.05"
    assert format_tod(45_000_000) == "TOD#12:30:00"
    assert format_dt(1_706_439_943) == "DT#2024-01-28-11:05:43"
    assert format_dt(U32_MAX) == "DT#2106-02-07-06:28:15"


# --- round trips over each type's full range -----------------------------------------------


@given(st.integers(0, U32_MAX))
def test_time_round_trip(ms: int) -> None:
    assert T(format_time(ms)) == ms


@given(st.integers(0, U64_MAX))
def test_ltime_round_trip(ns: int) -> None:
    assert parse_ltime(format_ltime(ns)) == ns


@given(st.integers(0, LAST_DAY))
def test_date_round_trip(day: int) -> None:
    seconds = day * 86_400
    assert D(format_date(seconds)) == seconds


@given(st.integers(0, 86_399_999))
def test_tod_round_trip(ms: int) -> None:
    assert parse_tod(format_tod(ms)) == ms


@given(st.integers(0, U32_MAX))
def test_dt_round_trip(seconds: int) -> None:
    assert parse_dt(format_dt(seconds)) == seconds


@given(st.integers(0, U32_MAX))
def test_date_formats_the_day_of_any_second(seconds: int) -> None:
    assert D(format_date(seconds)) == seconds - seconds % 86_400


@given(
    st.integers(0, 49), st.integers(0, 23), st.integers(0, 59), st.integers(0, 59), st.integers(0, 999)
)
def test_time_sums_its_units(d: int, h: int, m: int, s: int, ms: int) -> None:
    expected = (((d * 24 + h) * 60 + m) * 60 + s) * 1000 + ms
    if expected <= U32_MAX:
        assert T(f"T#{d}d{h}h{m}m{s}s{ms}ms") == expected


# --- refusals ------------------------------------------------------------------------------------

Parser = Callable[[str], int]


def test_seconds_may_be_left_out_of_a_time_of_day() -> None:
    """TwinCAT's DT_TO_STRING(DT#1998-02-13-14:20) is 'DT#1998-02-13-14:20:00': the seconds are 0."""
    assert parse_dt("DT#1998-02-13-14:20") == parse_dt("DT#1998-02-13-14:20:00")
    assert format_dt(parse_dt("dt#2000-01-01-00:00")) == "DT#2000-01-01-00:00:00"
    assert parse_tod("TOD#12:30") == parse_tod("TOD#12:30:00") == 45_000_000


@pytest.mark.parametrize(
    ("parse", "text", "why"),
    [
        (T, "T#5x", r"bad TIME literal 'T#5x': unknown unit 'x'"),
        (T, "5us", r"bad TIME literal '5us': unknown unit 'us'"),
        (T, "1s1s", r"unit 's' appears twice"),
        (T, "1ms1ms", r"unit 'ms' appears twice"),
        (T, "1s2m", r"unit 'm' after 's'; units must run in the order d h m s ms"),
        (T, "5ms1s", r"unit 's' after 'ms'"),
        (T, "T#49d17h2m47s296ms", r"bad TIME literal .*: out of range \(T#0ms \.\. T#49d17h2m47s295ms\)"),
        (T, "50d", r"out of range"),
        (T, "T#-5s", r"bad TIME literal 'T#-5s': negative duration; TIME is unsigned"),
        (T, "-1ms", r"negative"),
        (T, "", r"bad TIME literal '': empty"),
        (T, "T#", r"bad TIME literal 'T#': empty"),
        (T, "hello", r"unexpected 'h'"),
        (T, "T#5", r"number '5' has no unit"),
        (T, "1.5s200ms", r"only the last unit may have a fraction, 's' has one"),
        (T, "1.0005s", r"finer than the TIME resolution of 1 ms"),
        (T, "1__0ms", r"unexpected '_' after '1'"),
        (T, "_1s", r"unexpected '_'"),
        (T, "1s ", r"unexpected ' '"),
        (T, "LT#1s", r"prefix 'LT#' does not start a TIME literal \(use T# or TIME#\)"),
        (parse_ltime, "LTIME#1x", r"bad LTIME literal 'LTIME#1x': unknown unit 'x'"),
        (parse_ltime, "1us1ms", r"unit 'ms' after 'us'"),
        (parse_ltime, "1.5ns", r"finer than the LTIME resolution of 1 ns"),
        (parse_ltime, "LTIME#213503d23h34m33s709ms551us616ns", r"out of range"),
        (parse_ltime, "LTIME#-1ns", r"negative duration; LTIME is unsigned"),
        (parse_ltime, "T#1s", r"prefix 'T#' does not start a LTIME literal"),
        (D, "2024-02-30", r"bad DATE literal '2024-02-30': day out of range"),
        (D, "2023-02-29", r"bad DATE literal '2023-02-29': day out of range \(2023-02 has 28 days\)"),
        (D, "2024-13-01", r"month out of range"),
        (D, "2024-00-10", r"month out of range"),
        (D, "1969-12-31", r"bad DATE literal '1969-12-31': out of range \(D#1970-01-01 \.\. D#2106-02-07\)"),
        (D, "2106-02-08", r"out of range"),
        (D, "D#", r"empty"),
        (D, "28.01.2024", r"expected YYYY-MM-DD"),
        (D, "DT#2024-01-28", r"prefix 'DT#' does not start a DATE literal"),
        (parse_tod, "24:00:00", r"bad TOD literal '24:00:00': hour out of range"),
        (parse_tod, "12:60:00", r"minute out of range"),
        (parse_tod, "12:00:60", r"second out of range"),
        (parse_tod, "12:00:00.1234", r"more than 3 digits; TOD resolution is 1 ms"),
        (parse_tod, "12", r"expected hh:mm:ss"),
        (parse_tod, "12:00:", r"expected hh:mm:ss"),
        (parse_tod, "12:00.5", r"expected hh:mm:ss"),
        (parse_tod, "", r"empty"),
        (parse_dt, "2106-02-07-06:28:16", r"bad DT literal .*: out of range"),
        (parse_dt, "1969-12-31-23:59:59", r"out of range"),
        (parse_dt, "2023-02-29-00:00:00", r"day out of range"),
        (parse_dt, "2024-01-28-25:00:00", r"hour out of range"),
        (parse_dt, "2024-01-28-11:05:43.5", r"fraction '\.5' not allowed; DT resolution is 1 s"),
        (parse_dt, "2024-01-28 11:05:43", r"expected YYYY-MM-DD-hh:mm:ss"),
        (parse_dt, "2024-01-28-11", r"expected YYYY-MM-DD-hh:mm:ss"),
        (parse_dt, "2024-01-28-11:61", r"minute out of range"),
    ],
)
def test_bad_literals_say_what_is_wrong(parse: Parser, text: str, why: str) -> None:
    with pytest.raises(ValueError, match=why):
        parse(text)


@pytest.mark.parametrize(
    ("fmt", "value", "why"),
    [
        (format_time, -1, r"-1 is outside the TIME range 0 \.\. 4294967295 \(ms\)"),
        (format_time, U32_MAX + 1, r"outside the TIME range"),
        (format_ltime, U64_MAX + 1, r"outside the LTIME range"),
        (format_ltime, -1, r"outside the LTIME range"),
        (format_date, U32_MAX + 1, r"outside the DATE range"),
        (format_date, -86_400, r"outside the DATE range"),
        (format_tod, 86_400_000, r"outside the TOD range 0 \.\. 86399999"),
        (format_tod, -1, r"outside the TOD range"),
        (format_dt, U32_MAX + 1, r"outside the DT range"),
        (format_dt, -1, r"outside the DT range"),
    ],
)
def test_formatters_refuse_values_out_of_range(fmt: Callable[[int], str], value: int, why: str) -> None:
    with pytest.raises(ValueError, match=why):
        fmt(value)


def test_wrong_argument_types_are_type_errors() -> None:
    # cast: the untyped caller is what the runtime checks are for.
    with pytest.raises(TypeError, match="a TIME literal is text, got int"):
        T(cast(str, 5))
    with pytest.raises(TypeError, match="a TIME value is an int"):
        format_time(cast(int, 1.5))
    with pytest.raises(TypeError, match="a TOD value is an int"):
        format_tod(cast(int, True))


# --- parsed once --------------------------------------------------------------------------------


@given(st.integers(0, U32_MAX))
def test_a_repeated_literal_gives_the_value_of_its_first_parse(ms: int) -> None:
    text = format_time(ms)
    assert T(text) == T(text) == ms
    assert literals._SEEN_TIME[text] == ms


@pytest.mark.parametrize("parse", [T, parse_ltime, D, parse_tod, parse_dt])
def test_a_bad_literal_is_refused_every_time(parse: Parser) -> None:
    for _ in range(2):
        with pytest.raises(ValueError, match="bad"):
            parse("T#5x-not-a-literal")
    for _ in range(2):
        with pytest.raises(TypeError, match="literal is text, got list"):
            parse(cast(str, ["1s"]))


def test_the_memo_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(literals, "_SEEN_TIME", {})
    for ms in range(literals._SEEN_MAX + 50):
        assert T(f"{ms}ms") == ms
    assert len(literals._SEEN_TIME) == literals._SEEN_MAX
    assert T(f"{literals._SEEN_MAX + 10}ms") == literals._SEEN_MAX + 10


def test_public_names() -> None:
    assert sorted(literals.__all__) == sorted(
        [
            "D", "T", "format_date", "format_dt", "format_ltime", "format_time", "format_tod",
            "parse_date", "parse_dt", "parse_ltime", "parse_tod",
        ]
    )
