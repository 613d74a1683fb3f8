"""Tc3_Module: Beckhoff's TcCOM module library, which every TwinCAT 3 project template references.

Its names (``TcBaseModuleRegistered``, ``FW_ObjMgr_CreateInstance``,
``ITComObject``...) talk to TwinCAT's TcCOM object server, which iecoop's
virtual PLC does not have: this module declares none of them. It is here so a
project that references Tc3_Module without calling it (the template's
reference, as most projects keep it) loads and runs; a project that uses one
of its names is refused at load, naming that name.

>>> from iecoop.libraries import known
>>> known("Tc3_Module").module, __all__
('iecoop.libraries.tc3_module', [])
"""

from __future__ import annotations

__all__: list[str] = []
