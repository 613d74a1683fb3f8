"""A streamed trace keeps its columns aligned when a later enumeration name is longer than the first."""

from __future__ import annotations

import enum
import io

from iecoop.cli.trace import RowWriter, widest


class Mode(enum.IntEnum):
    IDLE = 1
    UNSUSPENDING = 2


def test_an_enumeration_column_is_as_wide_as_its_longest_name_from_the_first_row() -> None:
    out = io.StringIO()
    writer = RowWriter(["state", "packs"], out, last_time=10, last_cycle=2, widths=[widest(Mode.IDLE), 0])
    writer.row((0, 1, ["IDLE", "0"]))
    writer.row((10, 2, ["UNSUSPENDING", "3"]))
    lines = out.getvalue().splitlines()
    assert len({len(line) for line in lines}) == 1, lines  # every row ends in the same column
    assert widest(True) == 5 and widest(3) == 0
