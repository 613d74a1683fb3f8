"""Time and date literals: ``T#1s500ms``, ``LTIME#1ms``, ``D#2024-01-28``, ``TOD#12:30:00.5``, ``DT#...``.

Each parser turns the text of an IEC 61131-3 literal into the integer a PLC
variable of that type holds: TIME in milliseconds, LTIME in nanoseconds, DATE
and DT in seconds since 1970-01-01 (UTC, no time zone), TOD in milliseconds
since midnight. The prefix (``T#``, ``TIME#`` ...) is optional and its case does
not matter. Each formatter is the inverse and writes TwinCAT's canonical form.

ST: ``tDelay : TIME := T#1s500ms;``  Python: ``tDelay: TIME = VAR(T("1s500ms"))``

>>> T("T#1s500ms"), parse_ltime("1ms500us"), D("2024-01-28")
(1500, 1500000, 1706400000)
>>> format_time(T("90m")), format_tod(parse_tod("12:30:00.5"))
('T#1h30m', 'TOD#12:30:00.5')
>>> T("T#5x")
Traceback (most recent call last):
    ...
ValueError: bad TIME literal 'T#5x': unknown unit 'x' (TIME units: d h m s ms)
"""

from __future__ import annotations

import calendar
import dataclasses
import datetime
import re
from typing import Final

__all__ = [
    "D",
    "T",
    "format_date",
    "format_dt",
    "format_ltime",
    "format_time",
    "format_tod",
    "parse_date",
    "parse_dt",
    "parse_ltime",
    "parse_tod",
]

_MS_PER_DAY: Final = 86_400_000
_S_PER_DAY: Final = 86_400
_U32_MAX: Final = (1 << 32) - 1
_U64_MAX: Final = (1 << 64) - 1
_TOD_MAX: Final = _MS_PER_DAY - 1
_EPOCH: Final = datetime.date(1970, 1, 1)
# The last day a 32-bit count of seconds since 1970 reaches.
_LAST_DATE: Final = (2106, 2, 7)
_MONTH_DAYS: Final = (31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)

_PREFIX = re.compile(r"([A-Za-z_]+)#")
# IEC allows single underscores between digits ("1_000ms"), never leading or doubled.
_DIGITS = r"\d(?:_?\d)*"
_NUMBER = re.compile(rf"{_DIGITS}(?:\.{_DIGITS})?")
_DURATION_PART = re.compile(rf"(?P<int>{_DIGITS})(?:\.(?P<frac>{_DIGITS}))?(?P<unit>[A-Za-z]+)")
_DATE = re.compile(r"(\d{4})-(\d{1,2})-(\d{1,2})")
# The seconds may be left out (``DT#1998-02-13-14:20`` is 14:20:00, as TwinCAT's DT_TO_STRING shows).
_TIME_OF_DAY = re.compile(r"(\d{1,2}):(\d{1,2})(?::(\d{1,2})(?:\.(\d+))?)?")
_DATE_AND_TIME = re.compile(r"(\d{4})-(\d{1,2})-(\d{1,2})-(\d{1,2}):(\d{1,2})(?::(\d{1,2})(?:\.(\d+))?)?")


@dataclasses.dataclass(frozen=True)
class _DurationKind:
    """What distinguishes TIME from LTIME: prefixes, units (largest first) and range."""

    kind: str
    prefixes: tuple[str, ...]
    units: tuple[tuple[str, int], ...]
    high: int

    @property
    def unit_names(self) -> str:
        return " ".join(name for name, _ in self.units)

    @property
    def resolution(self) -> str:
        return "1 " + self.units[-1][0]


_TIME: Final = _DurationKind(
    "TIME",
    ("T", "TIME"),
    (("d", _MS_PER_DAY), ("h", 3_600_000), ("m", 60_000), ("s", 1_000), ("ms", 1)),
    _U32_MAX,
)
_LTIME: Final = _DurationKind(
    "LTIME",
    ("LTIME", "LT"),
    (
        ("d", _MS_PER_DAY * 1_000_000),
        ("h", 3_600_000_000_000),
        ("m", 60_000_000_000),
        ("s", 1_000_000_000),
        ("ms", 1_000_000),
        ("us", 1_000),
        ("ns", 1),
    ),
    _U64_MAX,
)


def _bad(kind: str, text: str, why: str) -> ValueError:
    return ValueError(f"bad {kind} literal {text!r}: {why}")


def _check_text(kind: str, text: object) -> str:
    if not isinstance(text, str):
        raise TypeError(f"a {kind} literal is text, got {type(text).__name__}")
    return text


def _strip_prefix(kind: str, text: str, prefixes: tuple[str, ...]) -> str:
    match = _PREFIX.match(text)
    if match is None:
        return text
    if match.group(1).upper() not in prefixes:
        allowed = " or ".join(f"{p}#" for p in prefixes)
        raise _bad(kind, text, f"prefix '{match.group(1)}#' does not start a {kind} literal (use {allowed})")
    return text[match.end() :]


def _check_value(kind: str, value: object, high: int, unit: str) -> int:
    # bool is an int to Python but never a duration or a date to the PLC.
    if not isinstance(value, int) or isinstance(value, bool):
        raise TypeError(f"a {kind} value is an int ({unit}), got {type(value).__name__}")
    if not 0 <= value <= high:
        raise ValueError(f"{value} is outside the {kind} range 0 .. {high} ({unit})")
    return value


#: Parsed literals by text. A literal in a body (``T("30ms")`` inside a scan) is
#: parsed once; later calls cost one dict lookup. Bounded, so literals built
#: from changing text cannot grow it without limit.
_SEEN_MAX: Final = 4096
_SEEN_TIME: dict[str, int] = {}
_SEEN_LTIME: dict[str, int] = {}
_SEEN_DATE: dict[str, int] = {}
_SEEN_TOD: dict[str, int] = {}
_SEEN_DT: dict[str, int] = {}


def _remember(seen: dict[str, int], text: str, value: int) -> int:
    if type(text) is str and len(seen) < _SEEN_MAX:
        seen[text] = value
    return value


# --- durations: TIME and LTIME ----------------------------------------------------------


def _parse_duration(spec: _DurationKind, text: str) -> int:
    kind = spec.kind
    body = _strip_prefix(kind, _check_text(kind, text), spec.prefixes)
    if not body:
        raise _bad(kind, text, "empty")
    if body.startswith("-"):
        raise _bad(kind, text, f"negative duration; {kind} is unsigned")
    ranks = {name: rank for rank, (name, _) in enumerate(spec.units)}
    total = 0
    previous: str | None = None
    fraction_seen = False
    pos = 0
    while pos < len(body):
        part = _DURATION_PART.match(body, pos)
        if part is None:
            raise _bad(kind, text, _what_is_wrong(body, pos))
        spelled = part.group("unit")
        unit = spelled.lower()
        if unit not in ranks:
            raise _bad(kind, text, f"unknown unit '{spelled}' ({kind} units: {spec.unit_names})")
        if previous is not None:
            if ranks[unit] == ranks[previous]:
                raise _bad(kind, text, f"unit '{unit}' appears twice")
            if ranks[unit] < ranks[previous]:
                raise _bad(
                    kind, text, f"unit '{unit}' after '{previous}'; units must run in the order {spec.unit_names}"
                )
        if fraction_seen:
            raise _bad(kind, text, f"only the last unit may have a fraction, '{previous}' has one")
        scale = spec.units[ranks[unit]][1]
        total += int(part.group("int").replace("_", "")) * scale
        frac = part.group("frac")
        if frac is not None:
            fraction_seen = True
            digits = frac.replace("_", "")
            numerator, denominator = int(digits) * scale, 10 ** len(digits)
            # A fraction that lands between two ticks would have to be rounded
            # silently; refusing it keeps the literal's meaning exact.
            if numerator % denominator:
                raise _bad(
                    kind, text, f"'{part.group()}' is finer than the {kind} resolution of {spec.resolution}"
                )
            total += numerator // denominator
        previous = unit
        pos = part.end()
    if total > spec.high:
        raise _bad(kind, text, f"out of range ({_format_duration(spec, 0)} .. {_format_duration(spec, spec.high)})")
    return total


def _what_is_wrong(body: str, pos: int) -> str:
    number = _NUMBER.match(body, pos)
    if number is None:
        return f"unexpected {body[pos]!r} at position {pos}"
    after = number.end()
    if after == len(body):
        return f"number '{number.group()}' has no unit"
    return f"unexpected {body[after]!r} after '{number.group()}'"


def _format_duration(spec: _DurationKind, value: int) -> str:
    parts = []
    rest = value
    for name, scale in spec.units:
        count, rest = divmod(rest, scale)
        if count:
            parts.append(f"{count}{name}")
    prefix = spec.prefixes[0]
    return f"{prefix}#{''.join(parts)}" if parts else f"{prefix}#0{spec.units[-1][0]}"


def T(text: str) -> int:
    """TIME literal (ST: ``T#1d2h3m4s5ms``) in milliseconds.

    Units d h m s ms, largest first and each at most once; only the last may
    have a fraction. Range T#0ms .. T#49d17h2m47s295ms.

    >>> T("1d2h3m4s5ms"), T("T#1.5s"), T("time#1_000MS")
    (93784005, 1500, 1000)
    """
    try:
        return _SEEN_TIME[text]
    except (KeyError, TypeError):
        return _remember(_SEEN_TIME, text, _parse_duration(_TIME, text))



def parse_ltime(text: str) -> int:
    """LTIME literal (ST: ``LTIME#1ms500us``) in nanoseconds.

    Units d h m s ms us ns; range LTIME#0ns .. LTIME#213503d23h34m33s709ms551us615ns.

    >>> parse_ltime("LTIME#1ms500us"), parse_ltime("LT#2.5us")
    (1500000, 2500)
    """
    try:
        return _SEEN_LTIME[text]
    except (KeyError, TypeError):
        return _remember(_SEEN_LTIME, text, _parse_duration(_LTIME, text))



def format_time(ms: int) -> str:
    """The canonical TIME literal for ``ms`` milliseconds (zero units left out).

    >>> format_time(93784005), format_time(0)
    ('T#1d2h3m4s5ms', 'T#0ms')
    """
    return _format_duration(_TIME, _check_value("TIME", ms, _U32_MAX, "ms"))


def format_ltime(ns: int) -> str:
    """The canonical LTIME literal for ``ns`` nanoseconds.

    >>> format_ltime(1_500_000), format_ltime(0)
    ('LTIME#1ms500us', 'LTIME#0ns')
    """
    return _format_duration(_LTIME, _check_value("LTIME", ns, _U64_MAX, "ns"))


# --- dates and times of day -----------------------------------------------------------------


def _check_date(kind: str, text: str, year: int, month: int, day: int) -> int:
    """Days since 1970-01-01 of a calendar date inside the 32-bit range."""
    if not 1 <= month <= 12:
        raise _bad(kind, text, f"month out of range ({month}; months run 1..12)")
    length = _MONTH_DAYS[month - 1] + (month == 2 and calendar.isleap(year))
    if not 1 <= day <= length:
        raise _bad(kind, text, f"day out of range ({year:04d}-{month:02d} has {length} days)")
    if not (1970, 1, 1) <= (year, month, day) <= _LAST_DATE:
        last = "DT#2106-02-07-06:28:15" if kind == "DT" else "D#2106-02-07"
        first = "DT#1970-01-01-00:00:00" if kind == "DT" else "D#1970-01-01"
        raise _bad(kind, text, f"out of range ({first} .. {last})")
    return datetime.date(year, month, day).toordinal() - _EPOCH.toordinal()


def _check_time_of_day(kind: str, text: str, hour: int, minute: int, second: int) -> int:
    """Seconds since midnight."""
    if hour > 23:
        raise _bad(kind, text, f"hour out of range ({hour}; hours run 0..23)")
    if minute > 59:
        raise _bad(kind, text, f"minute out of range ({minute}; minutes run 0..59)")
    if second > 59:
        raise _bad(kind, text, f"second out of range ({second}; seconds run 0..59)")
    return (hour * 60 + minute) * 60 + second


def D(text: str) -> int:
    """DATE literal (ST: ``D#2024-01-28``) in seconds since 1970-01-01 (midnight, UTC).

    Range D#1970-01-01 .. D#2106-02-07. ``parse_date`` is the same function.

    >>> D("D#2024-01-28"), D("1970-01-01")
    (1706400000, 0)
    """
    try:
        return _SEEN_DATE[text]
    except (KeyError, TypeError):
        return _remember(_SEEN_DATE, text, _d_text(text))



def _d_text(text: str) -> int:
    kind = "DATE"
    body = _strip_prefix(kind, _check_text(kind, text), ("D", "DATE"))
    if not body:
        raise _bad(kind, text, "empty")
    match = _DATE.fullmatch(body)
    if match is None:
        raise _bad(kind, text, "expected YYYY-MM-DD")
    year, month, day = (int(g) for g in match.groups())
    return _check_date(kind, text, year, month, day) * _S_PER_DAY


parse_date = D


def parse_tod(text: str) -> int:
    """TIME_OF_DAY literal (ST: ``TOD#12:30:00.5``) in milliseconds since midnight.

    Up to three fraction digits; range TOD#00:00:00 .. TOD#23:59:59.999.

    >>> parse_tod("TOD#12:30:00.5"), parse_tod("time_of_day#0:0:0")
    (45000500, 0)
    """
    try:
        return _SEEN_TOD[text]
    except (KeyError, TypeError):
        return _remember(_SEEN_TOD, text, _tod_text(text))



def _tod_text(text: str) -> int:
    kind = "TOD"
    body = _strip_prefix(kind, _check_text(kind, text), ("TOD", "TIME_OF_DAY"))
    if not body:
        raise _bad(kind, text, "empty")
    match = _TIME_OF_DAY.fullmatch(body)
    if match is None:
        raise _bad(kind, text, "expected hh:mm:ss or hh:mm:ss.fff")
    hour, minute, second = (int(g or 0) for g in match.groups()[:3])
    fraction = match.group(4) or ""
    if len(fraction) > 3:
        raise _bad(kind, text, f"fraction '.{fraction}' has more than 3 digits; TOD resolution is 1 ms")
    seconds = _check_time_of_day(kind, text, hour, minute, second)
    return seconds * 1000 + int(fraction.ljust(3, "0"))


def parse_dt(text: str) -> int:
    """DATE_AND_TIME literal (ST: ``DT#2024-01-28-11:05:43``) in seconds since 1970-01-01 UTC.

    Range DT#1970-01-01-00:00:00 .. DT#2106-02-07-06:28:15; DT counts whole
    seconds, so a fraction of a second is refused.

    >>> parse_dt("DT#2024-01-28-11:05:43"), parse_dt("DT#2024-01-28-11:05")
    (1706439943, 1706439900)
    """
    try:
        return _SEEN_DT[text]
    except (KeyError, TypeError):
        return _remember(_SEEN_DT, text, _dt_text(text))



def _dt_text(text: str) -> int:
    kind = "DT"
    body = _strip_prefix(kind, _check_text(kind, text), ("DT", "DATE_AND_TIME"))
    if not body:
        raise _bad(kind, text, "empty")
    match = _DATE_AND_TIME.fullmatch(body)
    if match is None:
        raise _bad(kind, text, "expected YYYY-MM-DD-hh:mm:ss")
    if match.group(7) is not None:
        raise _bad(kind, text, f"fraction '.{match.group(7)}' not allowed; DT resolution is 1 s")
    year, month, day, hour, minute, second = (int(g or 0) for g in match.groups()[:6])
    days = _check_date(kind, text, year, month, day)
    value = days * _S_PER_DAY + _check_time_of_day(kind, text, hour, minute, second)
    if value > _U32_MAX:
        raise _bad(kind, text, "out of range (DT#1970-01-01-00:00:00 .. DT#2106-02-07-06:28:15)")
    return value


def _ymd(days: int) -> str:
    return (_EPOCH + datetime.timedelta(days=days)).isoformat()


def format_date(s: int) -> str:
    """The canonical DATE literal for ``s`` seconds since 1970 (the day that second falls in).

    >>> format_date(1706400000), format_date(0)
    ('D#2024-01-28', 'D#1970-01-01')
    """
    return f"D#{_ymd(_check_value('DATE', s, _U32_MAX, 's') // _S_PER_DAY)}"


def format_tod(ms: int) -> str:
    """The canonical TOD literal for ``ms`` milliseconds since midnight (no trailing zeros).

    >>> format_tod(45000500), format_tod(0), format_tod(86399999)
    ('TOD#12:30:00.5', 'TOD#00:00:00', 'TOD#23:59:59.999')
    """
    seconds, millis = divmod(_check_value("TOD", ms, _TOD_MAX, "ms"), 1000)
    minutes, second = divmod(seconds, 60)
    hour, minute = divmod(minutes, 60)
    fraction = f".{millis:03d}".rstrip("0") if millis else ""
    return f"TOD#{hour:02d}:{minute:02d}:{second:02d}{fraction}"


def format_dt(s: int) -> str:
    """The canonical DT literal for ``s`` seconds since 1970-01-01 UTC.

    >>> format_dt(1706439943), format_dt(2**32 - 1)
    ('DT#2024-01-28-11:05:43', 'DT#2106-02-07-06:28:15')
    """
    days, seconds = divmod(_check_value("DT", s, _U32_MAX, "s"), _S_PER_DAY)
    minutes, second = divmod(seconds, 60)
    hour, minute = divmod(minutes, 60)
    return f"DT#{_ymd(days)}-{hour:02d}:{minute:02d}:{second:02d}"
