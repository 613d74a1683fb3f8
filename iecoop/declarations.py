"""VAR sections: the specifiers that declare a field's section, initial value and qualifiers.

Each specifier returns the initial value's type to a type checker (``VAR(0)``
is an ``int`` to mypy, as ``Field()`` is in pydantic), while at class creation
the builder reads the section from it. A field with a plain default and no
specifier is a ``VAR``. A specifier needs the annotation: ``x = VAR_INPUT(0)``
would declare no variable, so the class statement rejects it and names the
line to write (``x: INT = VAR_INPUT(0)``).

=======================  ===============================================  =========================
ST                       Python                                           notes
=======================  ===============================================  =========================
``VAR x : INT := 5;``    ``x: INT = VAR(5)`` or ``x: INT = 5``            local, kept between calls
``VAR_INPUT``            ``speed: REAL = VAR_INPUT(1.0)``                 set by the caller
``VAR_OUTPUT``           ``done: BOOL = VAR_OUTPUT()``                    read by the caller
``VAR_IN_OUT``           ``buf: ARRAY[INT] = VAR_IN_OUT(bounds=(1, 8))``  bound at every call
``VAR_IN_OUT CONSTANT``  ``VAR_IN_OUT(constant=True)``                    read-only inside
``VAR_STAT``             ``VAR_STAT(0)``                                  one per class
``VAR_TEMP``             ``VAR_TEMP(0)``                                  re-initialised each call
``VAR_INST``             ``VAR_INST(0, method="start")``                  kept, seen by one method
``VAR_EXTERNAL``         ``VAR_EXTERNAL()``                               the global of that name
``VAR RETAIN``           ``VAR(0, retain=True)``                          survives a warm restart
``VAR PERSISTENT``       ``VAR(0, persistent=True)``                      survives a download
``VAR CONSTANT``         ``VAR(10, constant=True)``                       cannot be written
``VAR in : INT;``        ``in_: INT = VAR(st_name="in")``                 an ST name Python cannot spell
=======================  ===============================================  =========================
"""

from __future__ import annotations

from typing import Any, TypeVar, overload

from iecoop.memory.layout import MISSING, FieldSpec
from iecoop.sections import SECTIONS, Section

__all__ = [
    "SECTIONS",
    "VAR",
    "VAR_EXTERNAL",
    "VAR_INPUT",
    "VAR_INST",
    "VAR_IN_OUT",
    "VAR_OUTPUT",
    "VAR_STAT",
    "VAR_TEMP",
    "FieldSpec",
]

_T = TypeVar("_T")


def _spec(st_name: str | None, section: Section, initial: Any, **options: Any) -> Any:
    return FieldSpec(section, initial, st_name=st_name, **options)


@overload
def VAR(
    *, length: int | None = None, bounds: object = None, retain: bool = False,
    persistent: bool = False, constant: bool = False, fb_init: dict[str, Any] | list[dict[str, Any]] | None = None,
    st_name: str | None = None, instance_path: bool = False,
) -> Any: ...
@overload
def VAR(
    initial: list[Any] | dict[str, Any], *, length: int | None = None, bounds: object = None, retain: bool = False,
    persistent: bool = False, constant: bool = False, fb_init: dict[str, Any] | list[dict[str, Any]] | None = None,
    st_name: str | None = None, instance_path: bool = False,
) -> Any: ...
@overload
def VAR(
    initial: _T, *, length: int | None = None, bounds: object = None, retain: bool = False,
    persistent: bool = False, constant: bool = False, fb_init: dict[str, Any] | list[dict[str, Any]] | None = None,
    st_name: str | None = None, instance_path: bool = False,
) -> _T: ...
def VAR(
    initial: Any = MISSING, *, length: int | None = None, bounds: object = None, retain: bool = False,
    persistent: bool = False, constant: bool = False, fb_init: dict[str, Any] | list[dict[str, Any]] | None = None,
    st_name: str | None = None, instance_path: bool = False,
) -> Any:
    """``VAR``: a local variable of the POU (or a member of a STRUCT).

    Every specifier takes ``st_name=``: the variable's ST name when Python
    cannot spell it (ST ``in : INT;`` is ``in_: INT = VAR(st_name="in")``);
    messages, ``var_info``, OPC UA and export show that name.

    For a function block member, ``fb_init={...}`` passes FB_init arguments
    (ST: ``motor : FB_Motor(axis_id := 3);``) and a dict initial value sets
    inputs at the declaration (ST: ``motor : FB_Motor := (speed := 1.5);``).

    ``instance_path=True`` on a STRING of a function block or program gives
    it the instance's path when the instance is initialised, before FB_init
    (ST: ``{attribute 'instance-path'} {attribute 'noinit'} sPath : STRING;``):
    ``<project>.MAIN.fbLogger``.
    """
    return _spec(
        st_name,
        Section.VAR, initial, length=length, bounds=bounds, retain=retain, persistent=persistent, constant=constant,
        fb_init=fb_init, instance_path=instance_path,
    )


@overload
def VAR_INPUT(*, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> Any: ...
@overload
def VAR_INPUT(initial: list[Any] | dict[str, Any], *, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> Any: ...
@overload
def VAR_INPUT(initial: _T, *, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> _T: ...
def VAR_INPUT(initial: Any = MISSING, *, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> Any:
    """``VAR_INPUT``: set by the caller (``fb(IN=True)``), read-only inside by convention."""
    return _spec(st_name, Section.VAR_INPUT, initial, length=length, bounds=bounds, retain=retain, persistent=persistent)


@overload
def VAR_OUTPUT(*, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> Any: ...
@overload
def VAR_OUTPUT(initial: list[Any] | dict[str, Any], *, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> Any: ...
@overload
def VAR_OUTPUT(initial: _T, *, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> _T: ...
def VAR_OUTPUT(initial: Any = MISSING, *, length: int | None = None, bounds: object = None, retain: bool = False, persistent: bool = False, st_name: str | None = None) -> Any:
    """``VAR_OUTPUT``: written by the POU, read by the caller after the call."""
    return _spec(st_name, Section.VAR_OUTPUT, initial, length=length, bounds=bounds, retain=retain, persistent=persistent)


def VAR_IN_OUT(*, length: int | None = None, bounds: object = None, constant: bool = False, st_name: str | None = None) -> Any:
    """``VAR_IN_OUT`` (``constant=True``: ``VAR_IN_OUT CONSTANT``): passed by reference at every call."""
    return _spec(st_name, Section.VAR_IN_OUT, MISSING, length=length, bounds=bounds, constant=constant)


@overload
def VAR_STAT(*, length: int | None = None, bounds: object = None, constant: bool = False, st_name: str | None = None) -> Any: ...
@overload
def VAR_STAT(initial: list[Any] | dict[str, Any], *, length: int | None = None, bounds: object = None, constant: bool = False, st_name: str | None = None) -> Any: ...
@overload
def VAR_STAT(initial: _T, *, length: int | None = None, bounds: object = None, constant: bool = False, st_name: str | None = None) -> _T: ...
def VAR_STAT(initial: Any = MISSING, *, length: int | None = None, bounds: object = None, constant: bool = False, st_name: str | None = None) -> Any:
    """``VAR_STAT``: one variable shared by every instance of the class."""
    return _spec(st_name, Section.VAR_STAT, initial, length=length, bounds=bounds, constant=constant)


@overload
def VAR_TEMP(*, length: int | None = None, bounds: object = None, st_name: str | None = None) -> Any: ...
@overload
def VAR_TEMP(initial: list[Any] | dict[str, Any], *, length: int | None = None, bounds: object = None, st_name: str | None = None) -> Any: ...
@overload
def VAR_TEMP(initial: _T, *, length: int | None = None, bounds: object = None, st_name: str | None = None) -> _T: ...
def VAR_TEMP(initial: Any = MISSING, *, length: int | None = None, bounds: object = None, st_name: str | None = None) -> Any:
    """``VAR_TEMP``: re-initialised at every call of the body."""
    return _spec(st_name, Section.VAR_TEMP, initial, length=length, bounds=bounds)


@overload
def VAR_INST(*, method: str, length: int | None = None, bounds: object = None, st_name: str | None = None) -> Any: ...
@overload
def VAR_INST(initial: list[Any] | dict[str, Any], *, method: str, length: int | None = None, bounds: object = None, st_name: str | None = None) -> Any: ...
@overload
def VAR_INST(initial: _T, *, method: str, length: int | None = None, bounds: object = None, st_name: str | None = None) -> _T: ...
def VAR_INST(initial: Any = MISSING, *, method: str, length: int | None = None, bounds: object = None, st_name: str | None = None) -> Any:
    """``VAR_INST`` inside METHOD ``method``: kept in the instance, visible to that method only."""
    return _spec(st_name, Section.VAR_INST, initial, length=length, bounds=bounds, method=method)


def VAR_EXTERNAL(*, length: int | None = None, bounds: object = None, constant: bool = False, st_name: str | None = None) -> Any:
    """``VAR_EXTERNAL``: refers to the global variable of the same name in a GVL."""
    return _spec(st_name, Section.VAR_EXTERNAL, MISSING, length=length, bounds=bounds, constant=constant)
