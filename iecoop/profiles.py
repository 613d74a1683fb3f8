"""Vendor profiles: the switches where TwinCAT 3 and CODESYS behave differently.

The TwinCAT 3 profile is the default. A ``Runtime`` activates its profile while
it runs, and ``use_profile`` does the same for code outside a runtime. The
active profile is a context variable: each thread has its own, so two
runtimes in two threads each run under their own vendor's rules.

>>> active_profile().name
'twincat'
>>> with use_profile("codesys"):
...     active_profile().test_and_set
'previous_value'
"""

from __future__ import annotations

import contextvars
import dataclasses
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Literal

__all__ = ["CODESYS", "TWINCAT", "Profile", "active_profile", "get_profile", "use_profile"]


@dataclasses.dataclass(frozen=True)
class Profile:
    """One vendor's choices; ``dataclasses.replace`` makes a variant.

    Fields marked UNCONFIRMED in the semantics reference are settings here so a
    user can match the target they have measured.
    """

    name: str
    #: REAL_TO_<int> on an exact .5: "even" (x64 SSE conversion) or "away" from zero.
    round_tie: Literal["even", "away"]
    #: TEST_AND_SET result: TwinCAT returns TRUE when acquired, CODESYS the previous value.
    test_and_set: Literal["acquired", "previous_value"]
    #: Whether the runtime offers reset warm (CODESYS does, TwinCAT 3 does not).
    has_reset_warm: bool
    #: RETAIN kept on reset cold / download (the course's TwinCAT table keeps it).
    retain_on_reset_cold: bool
    retain_on_download: bool
    #: CTU stops counting at PV ("pv", IEC reference) or at the type maximum ("type_max").
    ctu_limit: Literal["pv", "type_max"]
    #: TP: ET drops to 0 when IN is FALSE after the pulse (IEC reference) or holds until the next pulse.
    tp_et_after_pulse: Literal["reset_when_in_false", "hold_until_next_pulse"]


TWINCAT = Profile(
    name="twincat",
    round_tie="even",
    test_and_set="acquired",
    has_reset_warm=False,
    retain_on_reset_cold=True,
    retain_on_download=True,
    ctu_limit="pv",
    tp_et_after_pulse="reset_when_in_false",
)

CODESYS = Profile(
    name="codesys",
    round_tie="even",
    test_and_set="previous_value",
    has_reset_warm=True,
    retain_on_reset_cold=False,
    retain_on_download=False,
    ctu_limit="pv",
    tp_et_after_pulse="reset_when_in_false",
)

_PROFILES = {"twincat": TWINCAT, "codesys": CODESYS}
_active: contextvars.ContextVar[Profile] = contextvars.ContextVar("iecoop_profile", default=TWINCAT)


def get_profile(profile: str | Profile) -> Profile:
    """The profile named ``"twincat"`` or ``"codesys"``, or ``profile`` itself."""
    if isinstance(profile, Profile):
        return profile
    try:
        return _PROFILES[profile.lower()]
    except KeyError:
        known = ", ".join(sorted(_PROFILES))
        raise ValueError(f"unknown vendor profile {profile!r}; known profiles: {known}") from None


def active_profile() -> Profile:
    """The profile in force now, in the calling thread."""
    return _active.get()


@contextmanager
def use_profile(profile: str | Profile) -> Iterator[Profile]:
    """Make ``profile`` the active one inside the ``with`` block (in the calling thread only)."""
    chosen = get_profile(profile)
    token = _active.set(chosen)
    try:
        yield chosen
    finally:
        _active.reset(token)
