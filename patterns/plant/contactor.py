"""A direct-on-line motor's contactor, simulated: ``FUNCTION_BLOCK FB_ContactorSim``."""

from __future__ import annotations

from iecoop import BOOL, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, T
from iecoop.stdlib import TON

__all__ = ["ContactorSim"]


class ContactorSim(FunctionBlock):
    """The wiring's side: ``FUNCTION_BLOCK FB_ContactorSim``.

    The auxiliary contact closes 20 ms after the coil is energised (pull-in).
    ``overload`` opens the overload relay's contact, which is in series with
    the coil; ``aux_wire_broken`` simulates a broken feedback wire.
    """

    coil: BOOL = VAR_INPUT(False)
    overload: BOOL = VAR_INPUT(False)
    aux_wire_broken: BOOL = VAR_INPUT(False)
    aux: BOOL = VAR_OUTPUT(False)
    overload_ok: BOOL = VAR_OUTPUT(True)
    pull_in: TON = VAR()

    def body(self) -> None:
        self.overload_ok = not self.overload
        self.pull_in(IN=self.coil and self.overload_ok, PT=T("20ms"))
        self.aux = self.pull_in.Q and not self.aux_wire_broken
