"""Libraries: namespaces of POUs, types and GVLs that a project references by name.

A TwinCAT or CODESYS project references libraries (``Tc2_Standard``,
``Tc2_MC2``, ``TcUnit``...) and calls what they declare, plain (``TON``) or
qualified by the library's namespace (``Tc2_Standard.TON``). In iecoop a
library is a Python module of iecoop classes: FUNCTION_BLOCKs, STRUCTs,
enumerations, aliases, INTERFACEs, FUNCTIONs and GVL instances, each under its
ST name and listed in the module's ``__all__``. iecoop ships the vendor
libraries real projects use as such modules (see the "Libraries" page for
what each simulates); a folder or ``.plcproj`` of ST becomes one through
``st.load``.

``KNOWN`` is the table of the libraries iecoop ships; ``known(name)`` finds
one by its title or namespace, case-insensitively, as TwinCAT does:

>>> known("tc2_standard").module
'iecoop.libraries.tc2_standard'
>>> known("Tc2_NoSuchLibrary") is None
True
"""

from __future__ import annotations

import dataclasses
import importlib
import types

__all__ = ["KNOWN", "Library", "known", "module_of"]


@dataclasses.dataclass(frozen=True)
class Library:
    """A library iecoop ships: its title as a project references it, and the module that implements it.

    ``namespace`` is the default namespace qualified names use (``Tc2_MC2.MC_Power``);
    ``company`` and ``version`` are those of the vendor library the module follows;
    ``docs`` is the vendor's documentation page the behaviour is written from.
    """

    name: str
    module: str
    company: str
    version: str
    docs: str
    namespace: str = ""

    def __post_init__(self) -> None:
        if not self.namespace:
            object.__setattr__(self, "namespace", self.name)


_BECKHOFF = "Beckhoff Automation GmbH"
_CODESYS = "3S - Smart Software Solutions GmbH"
_INFOSYS = "https://infosys.beckhoff.com/english.php?content=../content/1033/"

#: The libraries iecoop ships, by the title a ``.plcproj`` references.
KNOWN: tuple[Library, ...] = (
    Library("Tc2_Standard", "iecoop.libraries.tc2_standard", _BECKHOFF, "3.3.3.0", _INFOSYS + "tcplclib_tc2_standard/index.html"),
    Library("Tc2_System", "iecoop.libraries.tc2_system", _BECKHOFF, "3.4.26.0", _INFOSYS + "tcplclib_tc2_system/index.html"),
    Library("Tc2_Utilities", "iecoop.libraries.tc2_utilities", _BECKHOFF, "3.3.59.0", _INFOSYS + "tcplclib_tc2_utilities/index.html"),
    Library("Tc2_MC2", "iecoop.libraries.tc2_mc2", _BECKHOFF, "3.3.52.0", _INFOSYS + "tcplclib_tc2_mc2/index.html"),
    Library("Tc3_Module", "iecoop.libraries.tc3_module", _BECKHOFF, "3.4.5.0", _INFOSYS + "tcplclib_tc3_module/index.html"),
    Library("Standard", "iecoop.libraries.codesys_standard", _CODESYS, "3.5.17.0", "https://content.helpme-codesys.com/en/libs/Standard/Current/index.html"),
    Library("Util", "iecoop.libraries.codesys_util", _CODESYS, "3.5.17.0", "https://content.helpme-codesys.com/en/libs/Util/Current/index.html"),
    Library("TcUnit", "iecoop.libraries.tcunit", "www.tcunit.org", "1.3.1.0", "https://tcunit.org/#/api"),
    Library("CfUnit", "iecoop.libraries.tcunit", "www.cfunit.org", "1.3.1.0", "https://tcunit.org/#/api"),
)


def known(name: str) -> Library | None:
    """The shipped library whose title or namespace is ``name`` (case-insensitive), or None."""
    lowered = name.lower()
    for library in KNOWN:
        if lowered in (library.name.lower(), library.namespace.lower()):
            return library
    return None


def module_of(library: Library) -> types.ModuleType:
    """Import the module that implements ``library``; an ImportError names the library when it is not there."""
    try:
        return importlib.import_module(library.module)
    except ModuleNotFoundError as exc:
        if exc.name != library.module:
            raise
        raise ImportError(f"iecoop does not ship the library {library.name} ({library.module} is missing)") from None
