"""How a declared variable's type is described: one ``TypeInfo`` per IEC type, made once per class.

Every ``FieldRecord`` of a class's layout carries the ``TypeInfo`` of its
variable (``record.info``): its name as ST writes it, its size, its ctypes
type and how a value is checked, loaded and stored. Tools that walk
declared classes (diagrams, the OPC UA server, the ST export) tell the kinds
of type apart with these classes.

ST: ``nCount : INT;`` has an ``ElementaryInfo`` named ``INT``;
``aValues : ARRAY[1..3] OF REAL;`` an ``ArrayInfo`` whose ``elem`` is REAL's.

>>> from iecoop import INT, REAL, ARRAY, Struct, VAR
>>> from iecoop.memory.typeinfo import ArrayInfo, ElementaryInfo
>>> class Recipe(Struct):
...     steps: INT = 0
...     values: ARRAY[REAL] = VAR(bounds=(1, 3))
>>> [type(r.info).__name__ for r in Recipe._iec_layout_.fields]
['ElementaryInfo', 'ArrayInfo']
>>> Recipe._iec_layout_.by_name["values"].info.name
'ARRAY[1..3] OF REAL'
"""

# The classes live with the memory machinery they drive; this module is their public name.
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo
from iecoop.memory._infos import ElementaryInfo, EnumInfo, StringInfo, TypeInfo
from iecoop.memory._resolve import class_info, resolve_type
from iecoop.memory.interface_references import InterfaceInfo
from iecoop.memory.open_arrays import OpenArrayInfo, OpenArrayReferenceInfo
from iecoop.memory.pointers import PointerInfo
from iecoop.memory.references import ReferenceInfo

__all__ = [
    "AggregateInfo",
    "ArrayInfo",
    "ElementaryInfo",
    "EnumInfo",
    "InterfaceInfo",
    "OpenArrayInfo",
    "OpenArrayReferenceInfo",
    "PointerInfo",
    "ReferenceInfo",
    "StringInfo",
    "TypeInfo",
    "class_info",
    "resolve_type",
]
