"""CTU / CTD / CTUD in vendor (RESET, LOAD, WORD) and IEC (R, LD, INT ...) form, as docs/reference/stdlib.md describes them."""

from __future__ import annotations

import dataclasses
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import adr, sizeof, use_profile
from iecoop.profiles import CODESYS, TWINCAT
from iecoop.stdlib import CTD, CTD_INT, CTU, CTU_DINT, CTU_INT, CTU_UDINT, CTUD, CTUD_INT

TYPE_MAX = dataclasses.replace(TWINCAT, ctu_limit="type_max")
CODESYS_TYPE_MAX = dataclasses.replace(CODESYS, ctu_limit="type_max")


@dataclasses.dataclass(frozen=True)
class Up:
    cls: type[Any]
    reset: str
    low: int
    high: int


@dataclasses.dataclass(frozen=True)
class Down:
    cls: type[Any]
    load: str
    low: int
    high: int


@dataclasses.dataclass(frozen=True)
class UpDown:
    cls: type[Any]
    reset: str
    load: str
    low: int
    high: int


UPS = [
    Up(CTU, "RESET", 0, 0xFFFF),
    Up(CTU_INT, "R", -0x8000, 0x7FFF),
    Up(CTU_DINT, "R", -0x8000_0000, 0x7FFF_FFFF),
    Up(CTU_UDINT, "R", 0, 0xFFFF_FFFF),
]
DOWNS = [Down(CTD, "LOAD", 0, 0xFFFF), Down(CTD_INT, "LD", -0x8000, 0x7FFF)]
UPDOWNS = [UpDown(CTUD, "RESET", "LOAD", 0, 0xFFFF), UpDown(CTUD_INT, "R", "LD", -0x8000, 0x7FFF)]


def ids(spec: Any) -> str:
    return str(spec.cls.__name__)


def preset(counter: Any, cv: int) -> None:
    """Put CV at ``cv`` through its address, as a test fixture (CV is an output)."""
    adr(counter, "CV").deref = cv


def pulse(counter: Any, pin: str, times: int = 1, **inputs: Any) -> None:
    for _ in range(times):
        counter(**{pin: True}, **inputs)
        counter(**{pin: False}, **inputs)


# ---------------------------------------------------------------------------
# Interfaces: pin names and types
# ---------------------------------------------------------------------------


def test_vendor_forms_use_reset_load_and_word() -> None:
    ctu, ctd, ctud = CTU(), CTD(), CTUD()
    assert {"CU", "RESET", "PV", "Q", "CV"} <= set(dir(ctu)) and not hasattr(ctu, "R")
    assert {"CD", "LOAD", "PV", "Q", "CV"} <= set(dir(ctd)) and not hasattr(ctd, "LD")
    assert {"CU", "CD", "RESET", "LOAD", "PV", "QU", "QD", "CV"} <= set(dir(ctud))
    assert sizeof(ctu, "CV") == sizeof(ctu, "PV") == 2
    ctu(PV=-1)  # WORD wraps on store
    assert ctu.PV == 0xFFFF


def test_iec_forms_use_r_ld_and_signed_types() -> None:
    assert not hasattr(CTU_INT(), "RESET") and not hasattr(CTD_INT(), "LOAD")
    ctu = CTU_INT()
    ctu(PV=-1)
    assert ctu.PV == -1 and sizeof(ctu, "CV") == 2
    assert sizeof(CTU_DINT(), "CV") == 4 and sizeof(CTU_UDINT(), "CV") == 4
    wide = CTU_UDINT()
    wide(PV=-1)
    assert wide.PV == 0xFFFF_FFFF


def test_wrong_pin_name_is_rejected() -> None:
    with pytest.raises(TypeError):
        CTU()(R=True)  # type: ignore[call-arg]
    with pytest.raises(TypeError):
        CTU_INT()(RESET=True)  # type: ignore[call-arg]


# ---------------------------------------------------------------------------
# CTU
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_counts_rising_edges_not_levels(spec: Up) -> None:
    ctr = spec.cls()
    assert (ctr.CV, ctr.Q, ctr.CU_M) == (0, False, False)
    ctr(CU=True, PV=3)
    assert ctr.CV == 1
    for _ in range(5):
        ctr(CU=True, PV=3)
    assert ctr.CV == 1
    ctr(CU=False)
    pulse(ctr, "CU", 2, PV=3)
    assert (ctr.CV, ctr.Q) == (3, True)


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_q_is_cv_at_least_pv(spec: Up) -> None:
    ctr = spec.cls()
    ctr(PV=0)
    assert ctr.Q  # 0 >= 0
    ctr(PV=2)
    assert not ctr.Q
    pulse(ctr, "CU", 2, PV=2)
    assert ctr.Q
    ctr(PV=5)
    assert not ctr.Q


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_reset_clears_and_has_priority_over_an_edge(spec: Up) -> None:
    ctr = spec.cls()
    pulse(ctr, "CU", 3, PV=10)
    ctr(**{"CU": True, spec.reset: True})
    assert (ctr.CV, ctr.Q) == (0, False)
    ctr(**{"CU": True, spec.reset: False})  # the edge was consumed during the reset
    assert ctr.CV == 0
    ctr(**{"CU": False})
    ctr(**{"CU": True})
    assert ctr.CV == 1


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_stops_at_pv_in_both_vendor_profiles(spec: Up) -> None:
    assert TWINCAT.ctu_limit == CODESYS.ctu_limit == "pv"
    for profile in (TWINCAT, CODESYS):
        ctr = spec.cls()
        with use_profile(profile):
            pulse(ctr, "CU", 7, PV=4)
        assert (ctr.CV, ctr.Q) == (4, True)


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_above_pv_does_not_count_with_the_pv_limit(spec: Up) -> None:
    ctr = spec.cls()
    preset(ctr, 10)
    pulse(ctr, "CU", 3, PV=5)
    assert (ctr.CV, ctr.Q) == (10, True)


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_type_max_profile_counts_past_pv_and_stops_at_the_type_maximum(spec: Up) -> None:
    ctr = spec.cls()
    with use_profile(TYPE_MAX):
        pulse(ctr, "CU", 7, PV=4)
        assert (ctr.CV, ctr.Q) == (7, True)
        preset(ctr, spec.high - 2)
        pulse(ctr, "CU", 5, PV=4)
    assert (ctr.CV, ctr.Q) == (spec.high, True)


@pytest.mark.parametrize("spec", UPS, ids=ids)
def test_ctu_limit_profile_is_read_at_each_call(spec: Up) -> None:
    ctr = spec.cls()
    with use_profile(CODESYS_TYPE_MAX):
        pulse(ctr, "CU", 3, PV=2)
    assert ctr.CV == 3
    pulse(ctr, "CU", 3, PV=2)  # back under the default profile: CV > PV, no count
    assert ctr.CV == 3


def test_ctu_word_counts_the_whole_range_and_never_wraps() -> None:
    ctr = CTU()
    with use_profile(TYPE_MAX):
        pulse(ctr, "CU", 0xFFFF + 3, PV=100)
    assert (ctr.CV, ctr.Q) == (0xFFFF, True)


def test_ctu_int_negative_pv_never_counts() -> None:
    ctr = CTU_INT()
    pulse(ctr, "CU", 3, PV=-5)
    assert (ctr.CV, ctr.Q) == (0, True)


def test_ctu_first_call_with_cu_true_counts() -> None:
    ctr = CTU()
    ctr(CU=True, PV=1)
    assert (ctr.CV, ctr.Q) == (1, True)


# ---------------------------------------------------------------------------
# CTD
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("spec", DOWNS, ids=ids)
def test_ctd_load_then_count_down_to_zero_and_stop(spec: Down) -> None:
    ctr = spec.cls()
    assert (ctr.CV, ctr.Q) == (0, False)
    ctr(**{spec.load: True, "PV": 3})
    assert (ctr.CV, ctr.Q) == (3, False)
    ctr(**{spec.load: False})
    pulse(ctr, "CD", 2)
    assert (ctr.CV, ctr.Q) == (1, False)
    pulse(ctr, "CD", 5)
    assert (ctr.CV, ctr.Q) == (0, True)


@pytest.mark.parametrize("spec", DOWNS, ids=ids)
def test_ctd_counts_edges_not_levels(spec: Down) -> None:
    ctr = spec.cls()
    ctr(**{spec.load: True, "PV": 5})
    for _ in range(4):
        ctr(**{spec.load: False, "CD": True})
    assert ctr.CV == 4


@pytest.mark.parametrize("spec", DOWNS, ids=ids)
def test_ctd_load_wins_over_an_edge_and_consumes_it(spec: Down) -> None:
    ctr = spec.cls()
    ctr(**{spec.load: True, "PV": 5, "CD": True})
    assert ctr.CV == 5
    ctr(**{spec.load: False, "CD": True})
    assert ctr.CV == 5


@pytest.mark.parametrize("spec", DOWNS, ids=ids)
def test_ctd_at_zero_q_and_the_first_call(spec: Down) -> None:
    ctr = spec.cls()
    ctr(CD=True)  # an edge, but CV is already 0
    assert (ctr.CV, ctr.Q) == (0, True)


@pytest.mark.parametrize("spec", DOWNS, ids=ids)
def test_ctd_reload_with_a_new_pv(spec: Down) -> None:
    ctr = spec.cls()
    ctr(**{spec.load: True, "PV": 2})
    ctr(**{spec.load: False})
    pulse(ctr, "CD", 2)
    ctr(**{spec.load: True, "PV": 9})
    assert (ctr.CV, ctr.Q) == (9, False)


def test_ctd_int_loads_a_negative_pv_and_does_not_count_below_it() -> None:
    ctr = CTD_INT()
    ctr(LD=True, PV=-3)
    ctr(LD=False)
    pulse(ctr, "CD", 2)
    assert (ctr.CV, ctr.Q) == (-3, True)


def test_ctd_word_never_wraps_below_zero() -> None:
    ctr = CTD()
    pulse(ctr, "CD", 3)
    assert ctr.CV == 0


# ---------------------------------------------------------------------------
# CTUD
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_counts_up_and_down(spec: UpDown) -> None:
    ctr = spec.cls()
    pulse(ctr, "CU", 3, PV=5)
    assert (ctr.CV, ctr.QU, ctr.QD) == (3, False, False)
    pulse(ctr, "CD", 1, PV=5)
    assert ctr.CV == 2
    pulse(ctr, "CU", 3, PV=5)
    assert (ctr.CV, ctr.QU, ctr.QD) == (5, True, False)


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_reset_has_priority_over_load(spec: UpDown) -> None:
    ctr = spec.cls()
    ctr(**{spec.reset: True, spec.load: True, "PV": 7})
    assert (ctr.CV, ctr.QU, ctr.QD) == (0, False, True)
    ctr(**{spec.reset: False, spec.load: True})
    assert (ctr.CV, ctr.QU, ctr.QD) == (7, True, False)


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_simultaneous_edges_do_not_count_and_are_consumed(spec: UpDown) -> None:
    ctr = spec.cls()
    ctr(**{spec.load: True, "PV": 3})
    ctr(**{spec.load: False, "CU": True, "CD": True})
    assert ctr.CV == 3
    ctr(CU=True, CD=False)  # CU is still high: no new edge
    assert ctr.CV == 3
    ctr(CU=False)
    ctr(CU=True)
    assert ctr.CV == 3  # PV reached (CV < PV is needed)
    ctr(CD=True)
    assert ctr.CV == 2


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_one_edge_while_the_other_input_is_held(spec: UpDown) -> None:
    ctr = spec.cls()
    ctr(**{spec.load: True, "PV": 5})
    ctr(**{spec.load: False, "CD": True})
    assert ctr.CV == 4
    ctr(CU=True)  # CD held TRUE: only CU has an edge
    assert ctr.CV == 5


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_edges_during_reset_or_load_are_consumed(spec: UpDown) -> None:
    ctr = spec.cls()
    ctr(**{spec.load: True, "PV": 5, "CU": True})
    ctr(**{spec.load: False})
    assert ctr.CV == 5
    ctr(**{spec.reset: True, "CD": True})
    ctr(**{spec.reset: False})
    assert ctr.CV == 0


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_down_stops_at_zero(spec: UpDown) -> None:
    ctr = spec.cls()
    pulse(ctr, "CD", 3, PV=2)
    assert (ctr.CV, ctr.QU, ctr.QD) == (0, False, True)


@pytest.mark.parametrize("spec", UPDOWNS, ids=ids)
def test_ctud_up_limit_follows_the_profile(spec: UpDown) -> None:
    ctr = spec.cls()
    pulse(ctr, "CU", 5, PV=2)
    assert ctr.CV == 2
    with use_profile(TYPE_MAX):
        pulse(ctr, "CU", 3, PV=2)
        assert ctr.CV == 5
        preset(ctr, spec.high - 1)
        pulse(ctr, "CU", 3, PV=2)
        assert (ctr.CV, ctr.QU) == (spec.high, True)


# ---------------------------------------------------------------------------
# Properties
# ---------------------------------------------------------------------------

PROFILES = st.sampled_from([TWINCAT, CODESYS, TYPE_MAX, CODESYS_TYPE_MAX])


@settings(max_examples=150, deadline=None)
@given(
    spec=st.sampled_from(UPS),
    pv=st.integers(-3, 12),
    inputs=st.lists(st.tuples(st.booleans(), st.sampled_from([False, False, False, True])), max_size=60),
    profile=PROFILES,
)
def test_ctu_cv_is_the_rising_edges_since_the_last_reset_clipped(
    spec: Up, pv: int, inputs: list[tuple[bool, bool]], profile: Any
) -> None:
    pv = max(pv, spec.low)
    limit = pv if profile.ctu_limit == "pv" else spec.high
    ctr = spec.cls()
    previous = False
    edges = 0
    with use_profile(profile):
        for cu, reset in inputs:
            ctr(**{"CU": cu, spec.reset: reset, "PV": pv})
            rising = cu and not previous
            previous = cu
            edges = 0 if reset else edges + rising
            assert ctr.CV == max(0, min(edges, limit))
            assert ctr.Q == (ctr.CV >= pv)


@settings(max_examples=150, deadline=None)
@given(
    spec=st.sampled_from(DOWNS),
    pv=st.integers(-3, 12),
    inputs=st.lists(st.tuples(st.booleans(), st.booleans()), max_size=60),
)
def test_ctd_cv_is_the_loaded_pv_minus_the_edges_since_floored_at_zero(
    spec: Down, pv: int, inputs: list[tuple[bool, bool]]
) -> None:
    pv = pv if spec.low < 0 else abs(pv)
    ctr = spec.cls()
    previous = False
    loaded = 0
    edges = 0
    for cd, load in inputs:
        ctr(**{"CD": cd, spec.load: load, "PV": pv})
        rising = cd and not previous
        previous = cd
        if load:
            loaded, edges = pv, 0
        else:
            edges += rising
        expected = loaded if loaded <= 0 else max(loaded - edges, 0)
        assert ctr.CV == expected
        assert ctr.Q == (expected <= 0)


@settings(max_examples=150, deadline=None)
@given(
    spec=st.sampled_from(UPDOWNS),
    pv=st.integers(0, 6),
    inputs=st.lists(st.tuples(st.booleans(), st.booleans(), st.booleans(), st.booleans()), max_size=60),
    profile=PROFILES,
)
def test_ctud_follows_the_up_down_model(
    spec: UpDown, pv: int, inputs: list[tuple[bool, bool, bool, bool]], profile: Any
) -> None:
    limit = pv if profile.ctu_limit == "pv" else spec.high
    ctr = spec.cls()
    prev_cu = prev_cd = False
    cv = 0
    with use_profile(profile):
        for cu, cd, reset, load in inputs:
            ctr(**{"CU": cu, "CD": cd, spec.reset: reset, spec.load: load, "PV": pv})
            up, down = cu and not prev_cu, cd and not prev_cd
            prev_cu, prev_cd = cu, cd
            if reset:
                cv = 0
            elif load:
                cv = pv
            elif up and not down and cv < limit:
                cv += 1
            elif down and not up and cv > 0:
                cv -= 1
            assert ctr.CV == cv
            assert (ctr.QU, ctr.QD) == (cv >= pv, cv <= 0)
