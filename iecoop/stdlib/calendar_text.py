"""``STRING_TO_DATE``, ``STRING_TO_TOD``, ``STRING_TO_DT``: a date or time of day read from the literal a STRING
starts with, as TwinCAT and CODESYS read it (blanks before it skipped, characters after it ignored).

The text must be a literal of the target type, its prefix included (``'DT#2019-9-9-1:1:1'``,
``'TOD#12:30:00.5'``, ``'D#2024-02-29'``); a DT's fraction of a second is dropped, a TOD's beyond the
millisecond too. Text that is no such literal, or a date that does not exist, gives 0 (``D#1970-01-01``).

>>> string_to_calendar("DT#2019-9-9-1:1:1.9", "DT") == string_to_calendar("DT#2019-09-09-01:01:01", "DT")
True
>>> string_to_calendar("  TOD#12:30:00.5 (shift 2)", "TOD"), string_to_calendar("12:30", "TOD")
(45000500, 0)
"""

from __future__ import annotations

import re

from iecoop.literals import D, parse_dt, parse_tod

__all__ = ["string_to_calendar"]

_DIGITS_DATE = r"\d{4}-\d{1,2}-\d{1,2}"
_DIGITS_TIME = r"\d{1,2}:\d{1,2}(?::\d{1,2})?"
#: The literal a STRING_TO_<target> reads from the start of its text: prefix, body, and the fraction left out.
_LITERALS = {
    "DATE": re.compile(rf"((?:D|DATE)#{_DIGITS_DATE})", re.IGNORECASE),
    "TOD": re.compile(rf"((?:TOD|TIME_OF_DAY)#{_DIGITS_TIME}(?:\.\d{{1,3}})?)\d*", re.IGNORECASE),
    "DT": re.compile(rf"((?:DT|DATE_AND_TIME)#{_DIGITS_DATE}-{_DIGITS_TIME})(?:\.\d*)?", re.IGNORECASE),
}
_READERS = {"DATE": D, "TOD": parse_tod, "DT": parse_dt}


def string_to_calendar(text: str, target: str) -> int:
    """``STRING_TO_<target>(text)`` for DATE, TOD (ms since midnight) and DT (s since 1970): see the module."""
    found = _LITERALS[target].match(text.lstrip())
    if found is None:
        return 0
    try:
        return _READERS[target](found.group(1))
    except ValueError:  # a month 13, a 25th hour: no value of the type
        return 0
