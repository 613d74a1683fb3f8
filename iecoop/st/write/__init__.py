"""The write wing of the ST bridge: declared Python classes to Structured Text.

One room per phase, each handing the next its data:

* :mod:`.model` reads what a class exports as (its variables, members, names);
* :mod:`.infer`, :mod:`.expressions` and :mod:`.statements` translate the Python bodies of its POUs,
  METHODs and PROPERTYs: the types of expressions, then expressions, then statements, each by one
  handler per syntax node, ``visit_<ast class name>``;
* :mod:`.units` builds each object's declaration and implementation (a ``Unit``) and the flat text;
* :mod:`.files` writes the units as TwinCAT XML or PLCopen XML.

The words of ST (keywords, types, operators and their precedence, standard functions) come from
:mod:`iecoop.st.language`.

:mod:`iecoop.st.export` is the public face (``dump``, ``export``, ``StExportError``).
"""

from __future__ import annotations

from iecoop.st.write.files import plcopen_project, twincat_file
from iecoop.st.write.model import StExportError, collect, ident, with_dependencies
from iecoop.st.write.units import Unit, flat_text, units

__all__ = ["StExportError", "Unit", "collect", "flat_text", "ident", "plcopen_project", "twincat_file", "units", "with_dependencies"]
