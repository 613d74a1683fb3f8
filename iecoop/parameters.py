"""VAR_OUTPUT and VAR_IN_OUT of METHODs and FUNCTIONs.

A METHOD or FUNCTION declares them as parameters whose default is the
section's specifier, typed ``POINTER_TO[T]``, because inside the method
Python reaches them through ``.deref`` (ST names them directly):

ST::

    METHOD Split : BOOL
    VAR_INPUT nValue : UINT; END_VAR
    VAR_OUTPUT nHigh : BYTE; nLow : BYTE; END_VAR
    VAR_IN_OUT nCalls : DINT; END_VAR
    nHigh := nValue / 256; nLow := nValue MOD 256; nCalls := nCalls + 1; Split := TRUE;

    bOk := fbWord.Split(nValue := 1000, nHigh => nHi, nCalls := nCount);   (* nLow left out *)

Python::

    @method
    def split(self, value: UINT, high: POINTER_TO[BYTE] = VAR_OUTPUT(), low: POINTER_TO[BYTE] = VAR_OUTPUT(),
              calls: POINTER_TO[DINT] = VAR_IN_OUT()) -> BOOL:
        high.deref = value // 256
        low.deref = value % 256
        calls.deref += 1
        return True

    ok = word.split(1000, high=adr(self, "hi"), calls=adr(self, "count"))

At the call, an output and an in-out are both given as ``adr(...)`` of the
caller's variable, as a function block's VAR_IN_OUT is
(``fb(buf=adr(self, "data"))``). They differ as on the PLC:

- VAR_OUTPUT: the method works on its own output variable, which starts at
  the type's zero at every call (method data are temporary); when the method
  returns, its value is written to the caller's variable. An output left out
  of the call is computed and dropped. A method that raises writes no output.
- VAR_IN_OUT: the method works on the caller's variable itself (call by
  reference); it must be given at every call.

Only a method or function with such parameters gets a wrapper (generated at
definition, one keyword per parameter); every other method runs as written.

Sources: CODESYS Online Help "Variable: VAR_OUTPUT" (outputs in functions and
methods, ``fun(iIn1 := 1, iOut1 => iLoc1)``) and "Variable: VAR_IN_OUT"
(FUNCTION, FUNCTION_BLOCK, METHOD, PRG); Beckhoff Infosys TwinCAT 3 "Object
Method" (method data are temporary, re-initialised at every call; methods
have additional inputs and outputs like functions) and "Input/Output
Variables - VAR_IN_OUT".
"""

from __future__ import annotations

import inspect
import sys
import types
import typing
from collections.abc import Callable
from typing import Any, TypeVar

from iecoop._codegen import compile_source
from iecoop.exceptions import DefinitionError
from iecoop.generics import with_generics
from iecoop.memory._aggregates import AggregateInfo
from iecoop.memory._handles import access_violation, handle_of
from iecoop.memory._infos import TypeInfo
from iecoop.memory._resolve import resolve_type
from iecoop.memory.pointers import Pointer, PointerInfo
from iecoop.memory.layout import MISSING, FieldSpec

__all__ = ["function", "parameter_sections", "with_parameters", "wrap_parameters"]

_F = TypeVar("_F", bound=Callable[..., Any])

#: The sections a METHOD / FUNCTION parameter may name through its default.
_PARAMETER_SECTIONS = ("VAR_OUTPUT", "VAR_IN_OUT")

_NOT_GIVEN: Any = type("_NotGiven", (), {"__repr__": lambda self: "<not given>", "__slots__": ()})()


def parameter_sections(func: Callable[..., Any]) -> dict[str, FieldSpec]:
    """The VAR_OUTPUT / VAR_IN_OUT parameters of ``func`` (or of the function it wraps), by name."""
    original = inspect.unwrap(func)
    found: dict[str, FieldSpec] = {}
    try:
        params = inspect.signature(original).parameters.values()
    except (TypeError, ValueError):
        return found
    for param in params:
        default = param.default
        if isinstance(default, FieldSpec) and default.section in _PARAMETER_SECTIONS:
            found[param.name] = default
    return found


def function(func: _F) -> _F:
    """``FUNCTION``: a module-level function with VAR_OUTPUT / VAR_IN_OUT parameters.

    A function without them needs no decorator (and gets no wrapper from it).

    >>> from iecoop import INT, POINTER_TO, VAR_IN_OUT, VAR_OUTPUT, Struct, adr
    >>> @function
    ... def divide(a: INT, b: INT, rest: POINTER_TO[INT] = VAR_OUTPUT(), calls: POINTER_TO[INT] = VAR_IN_OUT()) -> INT:
    ...     rest.deref = a % b                 # rest := a MOD b;
    ...     calls.deref += 1                   # calls := calls + 1;
    ...     return a // b
    >>> class Results(Struct):
    ...     rest: INT = 0
    ...     calls: INT = 0
    >>> r = Results()
    >>> divide(17, 5, rest=adr(r, "rest"), calls=adr(r, "calls")), r.rest, r.calls   # divide(17, 5, rest => r.rest, calls := r.calls)
    (3, 2, 1)
    """
    frame = sys._getframe(1)
    # Annotation strings name what is visible where the function is defined (a doctest, a function body too).
    names = dict(frame.f_locals) if frame.f_locals is not frame.f_globals else {}
    globals_ = func.__globals__

    def resolve(text: str) -> Any:
        return eval(text, globals_, names)  # noqa: S307 - the annotation text of the user's own function

    return with_parameters(func, f"FUNCTION {func.__name__}", resolve)


def with_parameters(func: _F, label: str, resolve: Callable[[str], Any] | None = None) -> _F:
    """``func`` itself when it has no VAR_OUTPUT / VAR_IN_OUT or generic parameter, else its wrapper."""
    func = with_generics(func, label, resolve)
    sections = parameter_sections(func)
    if not sections:
        return func
    signature = inspect.signature(func)
    params = list(signature.parameters.values())
    for param in params:
        if param.kind in (param.VAR_POSITIONAL, param.VAR_KEYWORD):
            raise DefinitionError(f"{label}: *{param.name} cannot stand beside VAR_OUTPUT / VAR_IN_OUT parameters; declare each input")
    for name, spec in sections.items():
        if spec.section == "VAR_IN_OUT" and spec.constant:
            raise DefinitionError(f"{label}: VAR_IN_OUT CONSTANT {name!r} is not supported for a METHOD or FUNCTION; use a VAR_INPUT")
        annotation = signature.parameters[name].annotation
        if isinstance(annotation, str) and resolve is None:
            continue  # resolved at the first call, when the names it uses exist
        _check_annotation(annotation, f"{label}: {spec.section} {name!r}", resolve)
    return typing.cast(_F, _generate(func, label, params, sections, resolve))


def wrap_parameters(title: str, namespace: dict[str, Any], resolve: Callable[[str], Any]) -> None:
    """Replace each METHOD of a class body that has VAR_OUTPUT / VAR_IN_OUT parameters with its wrapper."""
    for name, value in list(namespace.items()):
        if isinstance(value, types.FunctionType) and not (name.startswith("__") and name.endswith("__")):
            namespace[name] = with_parameters(value, f"METHOD {title.split()[-1]}.{name}", resolve)


def _check_annotation(annotation: Any, where: str, resolve: Callable[[str], Any] | None) -> Any:
    if isinstance(annotation, str):
        if resolve is None:
            raise DefinitionError(f"{where}: cannot resolve the annotation {annotation!r}")
        try:
            annotation = resolve(annotation)
        except NameError:
            return None  # a name defined later (the class itself): checked at the first call
    if annotation is inspect.Parameter.empty or typing.get_origin(annotation) is not Pointer:
        shown = "no annotation" if annotation is inspect.Parameter.empty else _type_name(annotation)
        raise DefinitionError(
            f"{where}: the method reaches the variable through a pointer, so annotate it POINTER_TO[<type>] "
            f"(got {shown})"
        )
    return annotation


def _type_name(annotation: Any) -> str:
    from iecoop.types import elementary_type

    record = elementary_type(annotation)
    if record is not None:
        return record.name
    return str(getattr(annotation, "__name__", annotation))


class _Cell:
    """Makes the temporary variable a VAR_OUTPUT lives in during one call."""

    __slots__ = ("annotation", "spec", "where", "resolve", "info")

    def __init__(self, annotation: Any, spec: FieldSpec, where: str, resolve: Callable[[str], Any] | None) -> None:
        self.annotation, self.spec, self.where, self.resolve = annotation, spec, where, resolve
        self.info: TypeInfo | None = None

    def target_info(self) -> TypeInfo:
        annotation = self.annotation
        if isinstance(annotation, str):
            resolve = self.resolve
            if resolve is None:
                raise DefinitionError(f"{self.where}: cannot resolve the annotation {annotation!r}")
            annotation = resolve(annotation)
        _check_annotation(annotation, self.where, None)
        spec = self.spec
        pointer = resolve_type(annotation, self.where, length=spec.length, bounds=spec.bounds, resolver=self.resolve)
        assert isinstance(pointer, PointerInfo)
        target = pointer.target
        if target is None:
            raise DefinitionError(f"{self.where}: a VAR_OUTPUT needs a type: POINTER_TO[<type>], not a PVOID")
        return target

    def __call__(self) -> Pointer[Any]:
        info = self.info
        if info is None:
            info = self.info = self.target_info()
        # A fresh variable at every call: method data are temporary on the PLC.
        holder = info.cls() if isinstance(info, AggregateInfo) else info.ctype()
        initial = self.spec.initial
        if initial is not MISSING:
            info.store(holder, 0, initial, self.where)
        return _OutputVariable(holder, info, self.where)


class _OutputVariable(Pointer[Any]):
    """The pointer a METHOD gets to its own VAR_OUTPUT: reads and writes go straight to the variable.

    The variable gets an address (an entry in the allocation table) only when
    something asks for it: ``adr``-like uses, or passing the output on to another call.
    """

    __slots__ = ("_holder", "_info", "_where", "_address")

    def __init__(self, holder: Any, info: TypeInfo, where: str) -> None:  # noqa: D107 - no Pointer.__init__: no handle yet
        self._holder, self._info, self._where, self._address = holder, info, where, 0
        self._target, self._origin, self._keep = info, None, holder

    @property
    def _handle(self) -> int:
        if not self._address:
            self._address = handle_of(self._holder)
        return self._address

    @_handle.setter
    def _handle(self, value: int) -> None:
        self._address = value

    @property
    def deref(self) -> Any:
        return self._info.load(self._holder, 0)

    @deref.setter
    def deref(self, value: Any) -> None:
        self._info.store(self._holder, 0, value, self._where)


def _generate(
    func: Callable[..., Any], label: str, params: list[inspect.Parameter], sections: dict[str, FieldSpec],
    resolve: Callable[[str], Any] | None,
) -> Callable[..., Any]:
    """One wrapper in one generated script (registered in linecache, so tracebacks show its lines)."""
    globs: dict[str, Any] = {
        "_M": _NOT_GIVEN, "_func": func, "_Pointer": Pointer, "_unbound": _unbound, "_not_a_variable": _not_a_variable,
        "_unknown": _unknown, "_null": _null, "_label": label,
    }
    signature: list[str] = []
    passed: list[str] = []
    entry: list[str] = []
    exit_: list[str] = []
    star_done = False
    positional_only = False
    for i, param in enumerate(params):
        name = param.name
        if param.kind is param.KEYWORD_ONLY and not star_done:
            if positional_only:
                signature.append("/")
                positional_only = False
            signature.append("*")
            star_done = True
        if param.kind is param.POSITIONAL_ONLY:
            positional_only = True
        elif positional_only:
            signature.append("/")
            positional_only = False
        spec = sections.get(name)
        if spec is not None:
            signature.append(f"{name}=_M")
        elif param.default is not param.empty:
            globs[f"_d{i}"] = param.default
            signature.append(f"{name}=_d{i}")
        else:
            signature.append(name)
        if spec is None:
            passed.append(f"{name}={name}" if param.kind is param.KEYWORD_ONLY else name)
            continue
        where = f"{label}: {spec.section} {name!r}"
        if spec.section == "VAR_IN_OUT":
            entry.append(f"    if {name} is _M: _unbound(_label, {name!r})")
            entry.append(f"    if not isinstance({name}, _Pointer): _not_a_variable(_label, 'VAR_IN_OUT', {name!r}, {name})")
            entry.append(f"    if not {name}: _null(_label, {name!r})")
            passed.append(f"{name}={name}" if param.kind is param.KEYWORD_ONLY else name)
            continue
        globs[f"_cell{i}"] = _Cell(param.annotation, spec, where, resolve)
        entry.append(f"    if {name} is not _M and not isinstance({name}, _Pointer): _not_a_variable(_label, 'VAR_OUTPUT', {name!r}, {name})")
        entry.append(f"    _c{i} = _cell{i}()")
        passed.append(f"{name}=_c{i}" if param.kind is param.KEYWORD_ONLY else f"_c{i}")
        # Written at the end of the call, as the PLC copies a method's outputs to the caller's variables.
        exit_.append(f"    if {name} is not _M: {name}.deref = _c{i}.deref")
    if positional_only:
        signature.append("/")
    signature.append("**_extra")
    lines = [f"def {func.__name__}({', '.join(signature)}):", "    if _extra: _unknown(_label, _extra)", *entry]
    lines.append(f"    _r = _func({', '.join(passed)})")
    lines += exit_
    lines.append("    return _r")
    source = "\n".join(lines) + "\n"
    compile_source(source, label, globs)
    wrapper = typing.cast(Callable[..., Any], globs[func.__name__])
    for attribute in ("__module__", "__name__", "__qualname__", "__doc__"):
        setattr(wrapper, attribute, getattr(func, attribute))
    wrapper.__dict__.update(func.__dict__)
    setattr(wrapper, "__wrapped__", func)
    setattr(wrapper, "_iec_parameters_", sections)
    return wrapper


def _unbound(label: str, name: str) -> None:
    raise TypeError(f"{label}: VAR_IN_OUT {name!r} must be assigned at every call ({name}=adr(...))")


def _null(label: str, name: str) -> None:
    raise access_violation(f"{label}: VAR_IN_OUT {name!r} is bound to 0 (NULL); pass adr() of a variable")


def _not_a_variable(label: str, section: str, name: str, value: Any) -> None:
    arrow = "=>" if section == "VAR_OUTPUT" else ":="
    raise TypeError(
        f"{label}: {section} {name!r} is bound to a variable of the caller (ST {name} {arrow} x is "
        f"{name}=adr(holder, \"x\")), got {type(value).__name__} {value!r}"
    )


def _unknown(label: str, extra: dict[str, Any]) -> None:
    names = ", ".join(repr(n) for n in extra)
    raise TypeError(f"{label} has no VAR_INPUT, VAR_OUTPUT or VAR_IN_OUT {names}")
