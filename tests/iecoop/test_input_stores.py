"""An input given to a call is stored only when it differs from the value held, with the same results.

A scan passes most inputs again and again with the value they already hold
(``fbValve(bOpen := bSensor)``); the call compares the value of the
accepted class with the field and stores only a changed one. Each block is
driven over several calls and checked against the value the store would have
left, zero's sign, REAL rounding, NaN and INT wrap-around included, and a
value changed behind the call's back (through a pointer) is stored again.
"""

from __future__ import annotations

import ctypes
import math

import pytest

from iecoop import BOOL, INT, LREAL, REAL, TIME, VAR_INPUT, VAR_OUTPUT, FunctionBlock, _config, adr


class Inputs(FunctionBlock):
    """Copies each input to an output, so each call shows what the input held."""

    flag: BOOL = VAR_INPUT()
    count: INT = VAR_INPUT()
    level: LREAL = VAR_INPUT()
    ratio: REAL = VAR_INPUT()
    delay: TIME = VAR_INPUT()
    seen_flag: BOOL = VAR_OUTPUT()
    seen_count: INT = VAR_OUTPUT()
    seen_level: LREAL = VAR_OUTPUT()
    seen_ratio: REAL = VAR_OUTPUT()
    seen_delay: TIME = VAR_OUTPUT()

    def body(self) -> None:
        self.seen_flag = self.flag
        self.seen_count = self.count
        self.seen_level = self.level
        self.seen_ratio = self.ratio
        self.seen_delay = self.delay


def _float32(value: float) -> float:
    return float(ctypes.c_float(value).value)


def test_the_same_values_given_again_are_held_and_changed_ones_stored() -> None:
    fb = Inputs()
    for flag, count, level, ratio, delay in [
        (True, 5, 1.5, 0.1, 200), (True, 5, 1.5, 0.1, 200), (False, 5, 1.5, 0.1, 200),
        (False, -7, 2.25, 0.1, 300), (True, 32767, 2.25, 0.2, 300), (True, 32767, 2.25, 0.2, 300),
    ]:
        fb(flag=flag, count=count, level=level, ratio=ratio, delay=delay)
        assert (fb.seen_flag, fb.seen_count, fb.seen_level, fb.seen_delay) == (flag, count, level, delay)
        assert fb.seen_ratio == _float32(ratio)  # REAL holds the nearest single-precision value
        assert (fb.flag, fb.count, fb.level, fb.delay) == (flag, count, level, delay)


def test_a_zero_of_the_other_sign_is_stored() -> None:
    fb = Inputs()
    fb(level=0.0, ratio=0.0)
    fb(level=-0.0, ratio=-0.0)
    assert math.copysign(1.0, fb.level) == -1.0 and math.copysign(1.0, fb.seen_level) == -1.0
    assert math.copysign(1.0, fb.ratio) == -1.0
    fb(level=0.0, ratio=0.0)
    assert math.copysign(1.0, fb.seen_level) == 1.0 and math.copysign(1.0, fb.seen_ratio) == 1.0


def test_nan_is_stored_each_time_and_read_back_as_nan() -> None:
    fb = Inputs()
    fb(level=math.nan)
    fb(level=math.nan)
    assert math.isnan(fb.seen_level)
    fb(level=3.0)
    assert fb.seen_level == 3.0


def test_a_value_changed_through_a_pointer_is_stored_again() -> None:
    fb = Inputs()
    fb(flag=True, count=12)
    adr(fb, "flag").deref = False
    adr(fb, "count").deref = 99
    fb(flag=True, count=12)  # the same arguments as before: the held values differ, so they are stored
    assert (fb.seen_flag, fb.seen_count) == (True, 12)


@pytest.mark.skipif(not _config.CHECKS, reason="fast mode lets INT wrap a Python int as ctypes stores it")
def test_checked_mode_refuses_a_value_of_the_wrong_kind_also_when_equal() -> None:
    fb = Inputs()
    fb(count=1, flag=True)
    with pytest.raises(TypeError, match=r"Inputs\.count.*float"):
        fb(count=1.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"Inputs\.flag.*BOOL"):
        fb(flag=1)  # type: ignore[arg-type]
    assert (fb.count, fb.flag) == (1, True)


@pytest.mark.skipif(_config.CHECKS, reason="checked mode refuses the value before any store")
def test_fast_mode_a_value_of_another_class_is_stored_as_ctypes_stores_it() -> None:
    fb = Inputs()
    fb(count=1, flag=True)
    with pytest.raises(TypeError, match="float"):
        fb(count=1.0)  # type: ignore[arg-type]  # equal to the held 1, still refused by the store
    fb(count=70_000)  # wraps as INT, as before
    assert fb.seen_count == 70_000 - 65_536
    fb(count=70_000)  # differs from the held 4464: stored and wrapped again
    assert fb.seen_count == 4464
    fb(flag=2)  # type: ignore[arg-type]  # not the held True itself: stored, and held as TRUE
    assert fb.seen_flag is True
