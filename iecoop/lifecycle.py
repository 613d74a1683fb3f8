"""FB_init, FB_reinit, FB_exit and dynamic instances (``__NEW`` / ``__DELETE``).

Call order (see the semantics reference, section 1):

- FB_init: nested members first, in declaration order, each completely
  (its FB_init, then the inputs set at its declaration, then its
  call_after_init methods); then the block's own FB_init, base first, then
  derived. Extra FB_init inputs are the constructor's keywords.
- FB_exit: the block's own FB_exit, derived first, then base; then its
  members in reverse declaration order.
- FB_reinit: only the most derived one runs (call ``super().fb_reinit()`` to
  chain), after an online change has copied the data.

>>> from iecoop import BOOL, INT, FunctionBlock, VAR, new, delete
>>> class Motor(FunctionBlock):
...     axis: INT = VAR(0)
...     def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, axis_id: INT = 1) -> BOOL:
...         self.axis = axis_id
...         return True
...     def fb_exit(self, in_copy_code: BOOL) -> BOOL:
...         print(f"FB_exit of axis {self.axis}")
...         return True
>>> p = new(Motor, axis_id=3)
>>> p.deref.axis
3
>>> delete(p)
FB_exit of axis 3
>>> bool(p)
False
"""

from __future__ import annotations

import ctypes
import dataclasses
import inspect
import itertools
import sys
import typing
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

from iecoop.exceptions import AccessError, ExceptionCode, PlcException
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo
from iecoop.memory._infos import StringInfo
from iecoop.memory._handles import allocation_for_handle, free, poison, register, release_held, resolve, table_lock
from iecoop.memory._resolve import class_info
from iecoop.memory.pointers import Pointer
from iecoop.memory.layout import BlockArgument, ClassLayout, FieldRecord
from iecoop.members import caller_description
from iecoop.metadata import Kind, iec_class, kind_of, layout_of, st_name

__all__ = ["Child", "delete", "fb_children", "finalise", "heap_blocks", "initialise", "new", "project_of", "reinitialise"]

_T = TypeVar("_T")

_EMPTY: dict[str, Any] = {}


@dataclasses.dataclass(frozen=True)
class Child:
    """The function block instances one member holds: itself, an ARRAY's elements, or those inside a STRUCT."""

    record: FieldRecord
    #: The instances, in declaration (and element) order.
    members: Callable[[Any], list[Any]]
    #: What each instance's path adds to its holder's: ``.fbAxis``, ``.aAxes[2]``, ``.stCell.fbTimer``.
    labels: tuple[str, ...]
    #: True for a member of the block itself, whose declaration may give inputs and FB_init values.
    direct: bool
    #: The block types the instances are of.
    classes: tuple[type, ...]


def fb_children(layout: ClassLayout) -> Iterator[Child]:
    """Nested function block members (and ARRAYs of them, and those inside STRUCT members), in declaration order."""
    for record in layout.fields:
        info = record.info
        get = record.raw.__get__
        if isinstance(info, ArrayInfo):
            raw_get, count = info.ctype.__mro__[1].__getitem__, info.count
            ranges = [range(low, high + 1) for low, high in info.bounds]
            labels = tuple(f".{record.st_name}[{', '.join(map(str, index))}]" for index in itertools.product(*ranges))
            element = info.elem
            if isinstance(element, AggregateInfo) and kind_of(element.cls) is Kind.FUNCTION_BLOCK:
                yield Child(record, _elements(get, raw_get, count), labels, True, (element.cls,))
            elif isinstance(element, AggregateInfo) and (inside := _inside(element.cls)):
                # element by element, as declared: aBays[1].stStation.fbPart, aBays[1].aSpares[1], ... aBays[2]...
                yield Child(record, _through(_elements(get, raw_get, count), _all(inside)),
                            tuple(outer + label for outer in labels for inner in inside for label in inner.labels),
                            False, tuple({cls: None for inner in inside for cls in inner.classes}))
        elif isinstance(info, AggregateInfo) and kind_of(info.cls) is Kind.FUNCTION_BLOCK:
            yield Child(record, _single(get), (f".{record.st_name}",), True, (info.cls,))
        elif isinstance(info, AggregateInfo):
            for inner in _inside(info.cls):
                yield Child(record, _through(_single(get), inner.members),
                            tuple(f".{record.st_name}{label}" for label in inner.labels), False, inner.classes)


def _inside(cls: type) -> list[Child]:
    """The blocks a STRUCT (or UNION) holds, found once per type: FB_init runs for them as for a block's members."""
    found: list[Child] | None = cls.__dict__.get("_iec_struct_children_")
    if found is None:
        layout = layout_of(cls)
        found = [] if layout is None or kind_of(cls) is not Kind.STRUCT else list(fb_children(layout))
        setattr(cls, "_iec_struct_children_", found)
    return found


def _single(get: Callable[[Any], Any]) -> Callable[[Any], list[Any]]:
    return lambda obj: [get(obj)]


def _elements(get: Callable[[Any], Any], raw_get: Callable[[Any, int], Any], count: int) -> Callable[[Any], list[Any]]:
    return lambda obj: [raw_get(get(obj), i) for i in range(count)]


def _all(children: list[Child]) -> Callable[[Any], list[Any]]:
    return lambda holder: [child for inner in children for child in inner.members(holder)]


def _through(holders: Callable[[Any], list[Any]], members: Callable[[Any], list[Any]]) -> Callable[[Any], list[Any]]:
    return lambda obj: [child for holder in holders(obj) for child in members(holder)]


#: Instances created by new(): kept alive until delete(), as a PLC heap block is.
_heap: dict[int, Any] = {}
#: Instances whose FB_exit is running inside delete(): deleting one again only clears the pointer.
_exiting: set[int] = set()


class _InitPlan:
    """A class's FB_init chain (base first) and the inputs each link takes."""

    __slots__ = ("chain", "exit_chain", "names", "owner", "required")

    def __init__(self, cls: type) -> None:
        self.owner = cls
        self.chain: list[tuple[Callable[..., Any], list[str]]] = []
        self.names: set[str] = set()
        self.required: set[str] = set()
        for klass in reversed(cls.__mro__):
            init = klass.__dict__.get("fb_init")
            if init is None:
                continue
            params = list(inspect.signature(init).parameters.values())[3:]
            self.chain.append((init, [p.name for p in params]))
            for p in params:
                self.names.add(p.name)
                if p.default is inspect.Parameter.empty:
                    self.required.add(p.name)
        self.exit_chain: list[Callable[..., Any]] = [
            klass.__dict__["fb_exit"] for klass in cls.__mro__ if "fb_exit" in klass.__dict__
        ]


def _plan(cls: type) -> _InitPlan:
    # Kept on the class, so it goes with the class; a derived class finds its base's plan
    # by inheritance, and the owner check makes it build its own.
    plan: _InitPlan | None = getattr(cls, "_iec_init_plan_", None)
    if plan is None or plan.owner is not cls:
        plan = _InitPlan(cls)
        setattr(cls, "_iec_init_plan_", plan)
    return plan


def _run_fb_init(obj: Any, init_retains: bool, in_copy_code: bool, args: dict[str, Any]) -> None:
    cls = type(obj)
    plan = _plan(cls)
    unknown = set(args) - plan.names
    if unknown:
        known = ", ".join(sorted(plan.names)) or "none"
        raise TypeError(f"{cls.__name__}: FB_init has no input {sorted(unknown)[0]!r} (its extra inputs: {known})")
    missing = plan.required - set(args)
    if missing:
        raise TypeError(
            f"{cls.__name__}: FB_init input {sorted(missing)[0]!r} has no value; pass it as {cls.__name__}({sorted(missing)[0]}=...)"
        )
    for init, names in plan.chain:
        init(obj, init_retains, in_copy_code, **{n: args[n] for n in names if n in args})


def _init_tree(
    obj: Any, init_retains: bool, in_copy_code: bool, args: dict[str, Any], declared: dict[str, Any] | None
) -> None:
    cls = type(obj)
    for found in cls._iec_children_:
        # a block inside a STRUCT takes no declared inputs or FB_init values (refused at the STRUCT's definition)
        spec = found.record.spec if found.direct else None
        initial = spec.initial if spec is not None else None
        for index, child in enumerate(found.members(obj)):
            # ARRAY OF FB: one initialiser per element, (in := x) applied after its FB_init like a single member's.
            if isinstance(initial, (list, tuple)):
                item = initial[index] if index < len(initial) else None
                member_inputs = item if isinstance(item, dict) else None
            else:
                member_inputs = initial if isinstance(initial, dict) else None
            fb_init = spec.fb_init if spec is not None else None
            if isinstance(fb_init, list):  # one entry per ARRAY element (ST: aAxes : ARRAY[1..2] OF FB_Axis[(n := 1), (n := 2)])
                fb_init = fb_init[index] if index < len(fb_init) else None
            if fb_init and any(isinstance(value, BlockArgument) for value in fb_init.values()):
                # ST: fbUser : FB_User(fbCounter): the variable beside the member, of this instance
                fb_init = {k: v.resolve(obj) if isinstance(v, BlockArgument) else v for k, v in fb_init.items()}
            _init_tree(child, init_retains, in_copy_code, fb_init or _EMPTY, member_inputs)
    _run_fb_init(obj, init_retains, in_copy_code, args)
    if declared:
        for name, value in declared.items():
            setattr(obj, name, value)
    for name in cls._iec_call_after_init_:
        getattr(obj, name)()


def initialise(
    obj: Any, *, init_retains: bool, in_copy_code: bool, args: dict[str, Any] | None = None, zero: bool = False
) -> None:
    """Implicit initialisation (initial values) then the FB_init tree of a block instance.

    ``zero=True`` first clears the memory, as a reset does before re-initialising.
    """
    if zero:
        ctypes.memset(ctypes.addressof(obj), 0, ctypes.sizeof(obj))
        release_held(obj)
    type(obj)._iec_implicit_init_(obj)
    paths = _path_plan(type(obj))
    if paths.members or paths.own:
        root = _root_path(type(obj))
        if root is not None:
            paths.fill(obj, root)
    _init_tree(obj, init_retains, in_copy_code, args or _EMPTY, None)


class _PathPlan:
    """Where a class's instance tree holds ``instance_path=`` STRINGs: its own, and the members that hold some."""

    __slots__ = ("members", "owner", "own")

    def __init__(self, cls: type) -> None:
        self.owner = cls
        layout = layout_of(cls)
        self.own = tuple(record for record in layout.fields if record.spec.instance_path) if layout is not None else ()
        #: the member instances of an object, what each adds to the path
        self.members: list[tuple[Callable[[Any], list[Any]], tuple[str, ...]]] = []
        for found in getattr(cls, "_iec_children_", ()):
            if any(plan.own or plan.members for plan in map(_path_plan, found.classes)):
                self.members.append((found.members, found.labels))

    def fill(self, obj: Any, path: str) -> None:
        for record in self.own:
            # into memory, as initialisation writes (the block's own write rules are for code); a STRING(n)
            # keeps the path's first n characters, as any store does
            typing.cast(StringInfo, record.info).store(obj, record.offset, path, record.where)
        for members, labels in self.members:
            for child, label in zip(members(obj), labels):
                _path_plan(type(child)).fill(child, path + label)


def _path_plan(cls: type) -> _PathPlan:
    plan: _PathPlan | None = cls.__dict__.get("_iec_path_plan_")
    if plan is None:
        plan = _PathPlan(cls)
        setattr(cls, "_iec_path_plan_", plan)
    return plan


def _root_path(cls: type) -> str | None:
    """``<project>.MAIN`` of a PROGRAM or GVL, the start of its members' instance paths; None for any other instance."""
    if kind_of(cls) not in (Kind.PROGRAM, Kind.GVL):
        return None
    project, name = project_of(cls.__module__), st_name(cls)
    return f"{project}.{name}" if project else name


def project_of(module: str) -> str:
    """The project the code of ``module`` belongs to, as TwinCAT's ``_AppInfo.ProjectName`` and instance paths name it:
    the ``.plcproj``'s (folder's, file's) name of code loaded from ST, else the module's top package; "" for
    ST given as text and for ``__main__``."""
    found = sys.modules.get(module)
    if hasattr(found, "__st_project__"):
        return str(getattr(found, "__st_project__") or "")
    top = module.split(".")[0]
    return "" if top == "__main__" else top


def finalise(obj: Any, *, in_copy_code: bool, static_type: type | None = None) -> None:
    """The FB_exit tree: the block's FB_exit (derived first, then base), then its members in reverse.

    ``static_type`` is the type the block is deleted through: ``__DELETE``
    through a base pointer runs only the base's FB_exit, as on the PLC.
    """
    cls = static_type or type(obj)
    for fb_exit in _plan(cls).exit_chain:
        fb_exit(obj, in_copy_code)
    for found in reversed(type(obj)._iec_children_):
        for child in reversed(found.members(obj)):
            finalise(child, in_copy_code=in_copy_code)


def reinitialise(obj: Any) -> None:
    """FB_reinit after an online-change copy: members first, then the most derived FB_reinit."""
    for found in type(obj)._iec_children_:
        for child in found.members(obj):
            reinitialise(child)
    reinit = getattr(type(obj), "fb_reinit", None)
    if reinit is not None:
        reinit(obj)


def new(cls: type[_T], **fb_init_args: Any) -> Pointer[_T]:
    """``__NEW(T)``: create an instance on the heap; FB_init runs with the keyword inputs.

    The instance lives until ``delete(p)``; ownership is the caller's.
    """
    info = class_info(cls)
    record = iec_class(cls)
    if info is None or record is None or record.kind not in (Kind.FUNCTION_BLOCK, Kind.STRUCT, Kind.UNION):
        raise TypeError(f"__NEW needs a function block or struct type, got {getattr(cls, '__name__', cls)!r}")
    if record.abstract:
        raise TypeError(f"__NEW: ABSTRACT {cls.__name__} cannot be instantiated")
    if record.internal:
        frame = sys._getframe(1)
        here = str(frame.f_globals.get("__name__", "")).split(".", 1)[0]
        if here != cls.__module__.split(".", 1)[0]:
            raise AccessError(f"INTERNAL {cls.__name__} cannot be created from {caller_description(frame)}")
    if record.kind is Kind.FUNCTION_BLOCK:
        obj: Any = typing.cast(Any, cls).__new__(cls)
        alloc = register(obj)
        _heap[alloc.id] = obj
        try:
            initialise(obj, init_retains=True, in_copy_code=False, args=fb_init_args)
        except BaseException:
            _heap.pop(alloc.id, None)
            free(alloc)
            raise
    else:
        obj = cls(**fb_init_args)
        alloc = register(obj)
        _heap[alloc.id] = obj
    return Pointer(alloc.id << 32, info)


def heap_blocks() -> list[Any]:
    """Every block ``new()`` created that is not yet deleted (an online change adjusts the addresses they hold)."""
    return list(_heap.values())


def delete(pointer: Pointer[Any]) -> None:
    """``__DELETE(p)``: FB_exit, free the memory, set ``p`` to 0.

    Every other pointer, reference or interface variable still aimed at the
    instance raises RTSEXCPT_ACCESS_VIOLATION when used, and so does Python
    code still holding the instance itself. ``delete`` of an instance whose
    FB_exit is running (an FB_exit deleting its own instance) only sets ``p`` to 0.
    """
    if not isinstance(pointer, Pointer):
        raise TypeError(f"__DELETE needs a pointer from new(), got {type(pointer).__name__}")
    handle = pointer.handle
    if handle == 0:
        return
    alloc = allocation_for_handle(handle)
    if alloc is not None and alloc.id in _exiting:
        pointer._clear()
        return
    if alloc is None or alloc.id not in _heap:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "__DELETE of memory that new() did not create (or already deleted)")
    if handle & 0xFFFFFFFF:
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "__DELETE needs the pointer new() returned, not one inside the block")
    resolve(handle, 0, "__DELETE")
    target = pointer._target
    static_type = getattr(target, "cls", None)
    real = type(_heap.get(alloc.id))
    if static_type is not None and not issubclass(real, static_type):
        # FB_exit of an unrelated type must never run on this memory.
        raise PlcException(
            ExceptionCode.RTSEXCPT_ACCESS_VIOLATION,
            f"__DELETE through POINTER TO {static_type.__name__} of a {real.__name__} instance; "
            f"delete it through a POINTER TO {real.__name__} (or one of its bases)",
        )
    obj = _heap.pop(alloc.id, None)
    if obj is None:  # another thread deleted it first
        raise PlcException(ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, "__DELETE of memory that new() did not create (or already deleted)")
    _exiting.add(alloc.id)
    try:
        if kind_of(type(obj)) is Kind.FUNCTION_BLOCK:
            finalise(obj, in_copy_code=False, static_type=static_type)
    except BaseException:
        _heap[alloc.id] = obj
        raise
    finally:
        _exiting.discard(alloc.id)
    with table_lock:
        ctypes.memset(ctypes.addressof(obj), 0, ctypes.sizeof(obj))
        free(alloc)
    poison(obj)
    pointer._clear()
