"""The write wing of the ST bridge: declared Python classes to Structured Text.

One room per phase, each handing the next its data:

* :mod:`.model` reads what a class exports as (its variables, members, names);
* :mod:`.body` translates the Python bodies of its POUs, METHODs and PROPERTYs;
* :mod:`.units` builds each object's declaration and implementation (a ``Unit``);
* :mod:`.files` writes the units as flat text, TwinCAT XML or PLCopen XML.

:mod:`iecoop.st.export` is the public face (``dump``, ``export``, ``StExportError``).
"""

from __future__ import annotations

from iecoop.st.write.files import plcopen_project, twincat_file
from iecoop.st.write.model import StExportError, collect, ident, with_dependencies
from iecoop.st.write.units import Unit, flat_text, units

__all__ = ["StExportError", "Unit", "collect", "flat_text", "ident", "plcopen_project", "twincat_file", "units", "with_dependencies"]
