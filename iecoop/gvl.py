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

__all__ = ["GlobalVariables", "all_global_lists", "find_global", "gvl", "global_lists", "namespace_of", "register_global_list"]

_G = TypeVar("_G")

if TYPE_CHECKING:
    _Base = object
    _MetaBase = type
else:
    _Base = ctypes.Structure
    _MetaBase = type(ctypes.Structure)

#: Every live GVL instance by (namespace, name), in definition order. Weak: a list defined in a
#: function (a test, a notebook cell) goes when nothing holds it; a POU's VAR_EXTERNAL holds its list.
#: The namespace is the top-level package of the list's module (a PLC project: its own code, one
#: ``st.load`` of a project, or the Python package it is loaded into), so two projects in one
#: process may each have a ``GVL_IO`` and each its own global ``bStart``.
_lists: weakref.WeakValueDictionary[tuple[str, str], Any] = weakref.WeakValueDictionary()


def namespace_of(module: str) -> str:
    """The namespace a class of ``module`` declares its globals in: the module's top-level package."""
    return module.split(".", 1)[0]


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
    # Two lists may declare one name (TwinCAT: reached as GVL_A.x and GVL_B.x); a VAR_EXTERNAL of it is refused.
    namespace = namespace_of(cls.__module__)
    instance: Any = typing.cast(Any, cls).__new__(cls)
    # Function block instances in a GVL get their FB_init, as global instances do on the PLC.
    cls_any: Any = cls
    cls_any._iec_children_ = tuple(fb_children(layout))
    cls_any._iec_call_after_init_ = ()
    initialise(instance, init_retains=True, in_copy_code=False)
    _lists[namespace, cls.__name__] = instance
    return typing.cast(_G, instance)


def global_lists() -> dict[str, Any]:
    """Every global variable list by name (of two lists of one name, the one registered last)."""
    return {name: instance for (_space, name), instance in list(_lists.items())}


def all_global_lists() -> list[Any]:
    """Every global variable list of every namespace, in definition order."""
    return list(_lists.values())


def register_global_list(instance: GlobalVariables) -> None:
    """Make ``instance`` the list its class name stands for, the one a VAR_EXTERNAL binds to.

    ``@gvl`` does this when it creates the list; a tool that swaps lists of the
    same name (loading an exported project back, say) gives the original its
    place again with this.
    """
    cls = type(instance)
    _lists.pop((namespace_of(cls.__module__), cls.__name__), None)  # re-inserted last: it wins by name
    _lists[namespace_of(cls.__module__), cls.__name__] = instance


def find_global(name: str, where: str, module: str = "") -> tuple[Any, FieldRecord]:
    """The GVL instance and variable a VAR_EXTERNAL named ``name`` in a class of ``module`` refers to.

    The lists of the class's own namespace come first; elsewhere, the name must be declared once.
    """
    namespace = namespace_of(module)
    found = [
        (space, instance, record)
        for (space, _name), instance in list(_lists.items())
        if (record := type(instance)._iec_layout_.by_name.get(name)) is not None
    ]
    own = [(instance, record) for space, instance, record in found if space == namespace]
    if len(own) > 1:
        lists = ", ".join(sorted(type(instance).__name__ for instance, _record in own))
        raise DefinitionError(f"{where}: VAR_EXTERNAL {name!r} is declared by several global lists ({lists}): "
                              "read it through its list (GVL_A.x) instead")
    if own:
        return own[-1]
    if len(found) == 1:
        return found[0][1], found[0][2]
    if found:
        spaces = ", ".join(sorted(f"{type(i).__name__} ({s})" for s, i, _r in found))
        raise DefinitionError(f"{where}: VAR_EXTERNAL {name!r} is declared by several global lists outside its namespace: {spaces}")
    raise DefinitionError(f"{where}: VAR_EXTERNAL {name!r} has no global variable of that name in any @gvl list")