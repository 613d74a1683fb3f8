"""Global variable lists (GVL) and VAR_EXTERNAL.

``@gvl`` turns a class of declared variables into its one instance, the
global variable list: ``GVL_Plant.alarm_count`` reads and writes the global,
and a POU field ``alarm_count: INT = VAR_EXTERNAL()`` refers to it by name.

ST::

    VAR_GLOBAL
        alarm_count : INT;
        line_speed  : REAL := 0.5;
    END_VAR

Python:

>>> from iecoop import INT, REAL, GlobalVariables, gvl
>>> @gvl
... class GVL_Doc(GlobalVariables):
...     doc_alarms: INT = 0
...     doc_speed: REAL = 0.5
>>> GVL_Doc.doc_alarms += 1
>>> GVL_Doc.doc_alarms, GVL_Doc.doc_speed
(1, 0.5)
"""

from __future__ import annotations

import ctypes
import typing
import weakref
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

from iecoop.exceptions import DefinitionError
from iecoop.lifecycle import fb_children, initialise
from iecoop.memory.layout import ClassLayout, DataClassBuilder, FieldRecord, register_builder
from iecoop.metadata import IecClass
from iecoop.sections import Kind

register_builder(__file__)

__all__ = ["GlobalVariables", "find_global", "gvl", "global_lists", "register_global_list"]

_G = TypeVar("_G")

if TYPE_CHECKING:
    _Base = object
    _MetaBase = type
else:
    _Base = ctypes.Structure
    _MetaBase = type(ctypes.Structure)

#: Every live GVL instance by name, in definition order. Weak: a list defined in a function
#: (a test, a notebook cell) goes when nothing holds it; a POU's VAR_EXTERNAL holds its list.
_lists: weakref.WeakValueDictionary[str, Any] = weakref.WeakValueDictionary()


_BUILDER = DataClassBuilder("GVL", Kind.GVL)


class _GvlMeta(_MetaBase):
    def __new__(
        mcls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], st_name: str | None = None, **kwargs: Any
    ) -> Any:
        return super().__new__(mcls, name, bases, _BUILDER.new(name, bases, namespace, st_name), **kwargs)

    def __init__(cls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(name, bases, namespace)
        _BUILDER.init(cls)


class GlobalVariables(_Base, metaclass=_GvlMeta):
    """Base of a global variable list; decorate the subclass with ``@gvl``."""

    _iec_base_class_: ClassVar[bool] = True
    __iec__: ClassVar[IecClass] = IecClass(Kind.GVL, root=True)
    _iec_layout_: ClassVar[ClassLayout | None] = None

    def __repr__(self) -> str:
        layout = type(self)._iec_layout_
        fields = layout.fields if layout is not None else ()
        return f"{type(self).__name__}({', '.join(f'{f.name}={getattr(self, f.name)!r}' for f in fields)})"


def gvl(cls: type[_G]) -> _G:
    """Create the one instance of a global variable list and register its variables."""
    layout: ClassLayout | None = getattr(cls, "_iec_layout_", None)
    if layout is None:
        raise DefinitionError(f"@gvl needs a GlobalVariables subclass with variables, got {cls.__name__}")
    for record in layout.fields:
        for other_name, other in list(_lists.items()):
            if other_name != cls.__name__ and record.name in type(other)._iec_layout_.by_name:
                raise DefinitionError(
                    f"GVL {cls.__name__}: global {record.name!r} is already declared in GVL {other_name}"
                )
    instance: Any = typing.cast(Any, cls).__new__(cls)
    # Function block instances in a GVL get their FB_init, as global instances do on the PLC.
    cls_any: Any = cls
    cls_any._iec_children_ = tuple(fb_children(layout))
    cls_any._iec_call_after_init_ = ()
    initialise(instance, init_retains=True, in_copy_code=False)
    _lists[cls.__name__] = instance
    return typing.cast(_G, instance)


def global_lists() -> dict[str, Any]:
    """Every global variable list by name."""
    return dict(_lists.items())


def register_global_list(instance: GlobalVariables) -> None:
    """Make ``instance`` the list its class name stands for, the one a VAR_EXTERNAL binds to.

    ``@gvl`` does this when it creates the list; a tool that swaps lists of the
    same name (loading an exported project back, say) gives the original its
    place again with this.
    """
    _lists[type(instance).__name__] = instance


def find_global(name: str, where: str) -> tuple[Any, FieldRecord]:
    """The GVL instance and variable a VAR_EXTERNAL named ``name`` refers to."""
    for instance in list(_lists.values()):
        record = type(instance)._iec_layout_.by_name.get(name)
        if record is not None:
            return instance, record
    raise DefinitionError(f"{where}: VAR_EXTERNAL {name!r} has no global variable of that name in any @gvl list")
