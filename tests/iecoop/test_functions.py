"""The IEC standard functions: vendor examples, algebraic properties and refusals."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop import BOOL, BYTE, DWORD, INT, LWORD, REAL, VAR, VAR_INPUT, VAR_OUTPUT, WORD, FunctionBlock
from iecoop.functions import (
    CONCAT,
    DELETE,
    EXPT,
    FIND,
    INSERT,
    LEFT,
    LEN,
    LIMIT,
    LN,
    MAX,
    MID,
    MIN,
    MUX,
    REPLACE,
    RIGHT,
    ROL,
    ROR,
    SEL,
    SHL,
    SHR,
    SQRT,
    get_bit,
    set_bit,
)

WIDTHS = [(BYTE, 8), (WORD, 16), (DWORD, 32), (LWORD, 64)]


# --- the vendors' documented examples -----------------------------------------------------------


def test_codesys_shift_and_rotate_examples_on_a_byte() -> None:
    # CODESYS "SHL" / "SHR" / "ROL" / "ROR": in_byte = 16#45.
    assert SHL(0x45, 2, BYTE) == 0x14
    assert SHR(0x45, 2, BYTE) == 0x11
    assert ROL(0x45, 2, BYTE) == 0x15
    assert ROR(0x45, 2, BYTE) == 0x51


def test_the_width_decides_what_falls_off() -> None:
    assert SHL(0x45, 2, WORD) == 0x114
    assert ROL(0x8000, 1, WORD) == 1
    assert ROL(0x8000, 1, DWORD) == 0x10000
    # A signed INT operand is shifted as its 16 bits.
    assert SHR(-1, 8, INT) == 0xFF


def test_codesys_string_function_examples() -> None:
    assert LEN("SUSI") == 4
    assert LEFT("SUSI", 3) == "SUS"
    assert RIGHT("SUSI", 3) == "USI"
    assert MID("SUSI", 2, 2) == "US"
    assert CONCAT("SUSI", "WILLI") == "SUSIWILLI"
    assert INSERT("SUSI", "XY", 2) == "SUXYSI"
    assert DELETE("SUXYSI", 2, 3) == "SUSI"
    assert REPLACE("SUXYSI", "K", 2, 2) == "SKYSI"
    assert FIND("abcdef", "de") == 4
    assert FIND("abcdef", "xy") == 0


def test_selection_examples() -> None:
    assert SEL(False, 3, 4) == 3 and SEL(True, 3, 4) == 4
    assert MUX(0, 30, 40, 50) == 30 and MUX(2, 30, 40, 50) == 50
    assert MIN(90, 30) == 30 and MAX(90, 30) == 90 and MIN(5) == 5
    assert LIMIT(30, 90, 80) == 80 and LIMIT(30, 10, 80) == 30 and LIMIT(30, 50, 80) == 50


def test_numeric_edges_follow_the_fpu() -> None:
    assert SQRT(-1.0) != SQRT(-1.0)  # NaN
    assert LN(0.0) == float("-inf")
    assert EXPT(2, 0.5) == pytest.approx(2**0.5)
    assert EXPT(10.0, 400.0) == float("inf")


# --- properties ---------------------------------------------------------------------------------


@given(st.sampled_from(WIDTHS), st.integers(0, 2**64 - 1), st.integers(0, 200))
def test_rol_then_ror_by_the_same_count_gives_the_value_back(width: tuple[object, int], value: int, n: int) -> None:
    type_, bits = width
    value &= (1 << bits) - 1
    assert ROR(ROL(value, n, type_), n, type_) == value
    assert ROL(value, bits, type_) == value


@given(st.sampled_from(WIDTHS), st.integers(0, 2**64 - 1), st.integers(0, 70))
def test_shl_is_multiplication_modulo_the_width(width: tuple[object, int], value: int, n: int) -> None:
    type_, bits = width
    assert SHL(value, n, type_) == (value * 2**n) % 2**bits
    assert SHR(value, n, type_) == (value % 2**bits) // 2**n


@given(st.integers(-(2**63), 2**64 - 1), st.integers(0, 63), st.booleans())
def test_set_bit_then_get_bit(value: int, n: int, flag: bool) -> None:
    changed = set_bit(value, n, flag)
    assert get_bit(changed, n) is flag
    assert changed ^ value in (0, 1 << n)


@given(st.text(max_size=20), st.text(max_size=5), st.integers(0, 25))
def test_insert_then_delete_restores_the_string(text: str, piece: str, pos: int) -> None:
    at = min(pos, len(text))
    assert DELETE(INSERT(text, piece, pos), len(piece), at + 1) == text


@given(st.text(max_size=20), st.text(min_size=1, max_size=3))
def test_find_points_at_the_first_occurrence(text: str, search: str) -> None:
    pos = FIND(text, search)
    if pos == 0:
        assert search not in text
    else:
        assert MID(text, len(search), pos) == search and search not in text[: pos - 1 + len(search) - 1]


@given(st.integers(-1000, 1000), st.integers(-1000, 1000), st.integers(-1000, 1000))
def test_limit_stays_inside_its_bounds(mn: int, value: int, mx: int) -> None:
    if mn <= mx:
        assert mn <= LIMIT(mn, value, mx) <= mx


# --- refusals name the function and the rule ----------------------------------------------------


@given(st.sampled_from(WIDTHS), st.integers(0, 2**64 - 1), st.integers(0, 2**64 - 1))
def test_a_shift_by_the_width_or_more_gives_zero(width: tuple[object, int], value: int, extra: int) -> None:
    """A count of ULINT size answers at once: no shifted integer of that many bits is ever built."""
    type_, bits = width
    assert SHL(value, bits + extra, type_) == 0
    assert SHR(value, bits + extra, type_) == 0


def test_a_shift_needs_an_integer_width() -> None:
    with pytest.raises(TypeError, match="ROL: the width is an integer or bit-string type"):
        ROL(1, 1, REAL)
    with pytest.raises(ValueError, match="SHL: the shift count N is a non-negative integer"):
        SHL(1, -1, WORD)


def test_mux_and_bit_numbers_out_of_range_are_refused() -> None:
    with pytest.raises(ValueError, match=r"MUX: K = 3 selects no input \(K runs 0..2\)"):
        MUX(3, 1, 2, 3)
    with pytest.raises(ValueError, match="bit number 64 is outside 0..63"):
        get_bit(1, 64)


# --- in a block: the store wraps the result to the variable's type ------------------------------


class Packer(FunctionBlock):
    """FB_Packer: packs a status word and rotates a pattern each call."""

    ready: BOOL = VAR_INPUT(False)
    pattern: WORD = VAR(0x0001)
    status: WORD = VAR_OUTPUT(0)
    shifted: BYTE = VAR_OUTPUT(0)

    def body(self) -> None:
        self.status = set_bit(self.status, 3, self.ready)
        self.pattern = ROL(self.pattern, 1, WORD)
        self.shifted = SHL(self.pattern, 1, WORD)  # the BYTE store keeps the low byte


def test_functions_across_cycles_in_a_block() -> None:
    fb = Packer()
    seen = []
    for cycle in range(17):
        fb(ready=cycle % 2 == 0)
        seen.append((fb.pattern, get_bit(fb.status, 3), fb.shifted))
    assert [p for p, _, _ in seen[:3]] == [2, 4, 8]
    assert seen[14][0] == 0x8000 and seen[15][0] == 1  # the top bit comes round
    assert [b for _, b, _ in seen[:4]] == [True, False, True, False]
    assert seen[6][2] == 0 and seen[2][2] == 16  # 0x80 << 1 = 0x100 falls off the BYTE
