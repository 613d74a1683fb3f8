"""How a class's declared fields become a memory layout (built once per class).

The builder reads each annotated field and its specifier, resolves the IEC
type, lets ctypes lay the block out (base-class fields first, as EXTENDS
does), installs a descriptor only for the types that need one, and records an
immutable ``FieldRecord`` per field. Initial values are checked here, at class
definition, and applied by a precomputed list of operations at instantiation.
Nothing of this runs on a variable read.
"""

from __future__ import annotations

import copy
import ctypes
import dataclasses
import os
import sys
import typing
import weakref
from collections.abc import Callable, Collection, Mapping, Sequence
from typing import Any, Final

from iecoop import _config
from iecoop.exceptions import DefinitionError
from iecoop.metadata import IecClass, kind_of
from iecoop.sections import MISSING, FieldSpec, Kind, Section, check_st_name, sections_of
from iecoop.writes import data_setattr
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo
from iecoop.memory._handles import _HANDLE_MASK, check_block_size, handle_of, target_root
from iecoop.memory._infos import ElementaryInfo, EnumInfo, StringInfo, TypeInfo
from iecoop.memory._resolve import resolve_type
from iecoop.memory.interface_references import InterfaceInfo
from iecoop.memory.pointers import Pointer, PointerInfo
from iecoop.memory.references import ReferenceInfo
from iecoop.memory.open_arrays import OpenArrayInfo, OpenArrayReferenceInfo

__all__ = [
    "MISSING",
    "ClassLayout",
    "DataClassBuilder",
    "FieldRecord",
    "FieldSpec",
    "BlockArgument",
    "LateInitial",
    "LayoutBuilder",
    "build_layout",
]


@dataclasses.dataclass(frozen=True, eq=False)
class FieldRecord:
    """One declared field, fixed at class creation."""

    name: str
    info: TypeInfo
    spec: FieldSpec
    owner: str
    offset: int
    raw: Any

    @property
    def section(self) -> Section:
        return self.spec.section

    @property
    def size(self) -> int:
        return self.info.size

    @property
    def st_name(self) -> str:
        """The ST name (``st_name=`` of the specifier), else the Python name."""
        return self.spec.st_name or self.name

    @property
    def where(self) -> str:
        """``Owner.name`` in ST names, for messages and ``var_info``'s symbol."""
        return f"{self.owner}.{self.st_name}"


@dataclasses.dataclass(frozen=True, eq=False)
class ClassLayout:
    """Every field of a class (base fields first) and how to initialise them."""

    fields: tuple[FieldRecord, ...]
    own: tuple[FieldRecord, ...]
    by_name: Mapping[str, FieldRecord]
    init_ops: tuple[Callable[[Any], None], ...]

    def implicit_init(self, obj: Any) -> None:
        """Write the declared initial values into ``obj`` (its memory is zero)."""
        for op in self.init_ops:
            op(obj)


#: Source files of the class builders: their frames are skipped when looking for the class statement.
BUILDER_FILES: set[str] = {os.path.abspath(__file__)}


def register_builder(path: str) -> None:
    """Declare a module whose functions build classes (its frames are not the user's)."""
    BUILDER_FILES.add(os.path.abspath(path))


class DefinitionScope:
    """The names visible where a ``class`` statement runs: its frame's live globals and locals.

    Annotation strings (``from __future__ import annotations``) refer to those
    names, also for classes defined inside a function or a doctest. Pointer
    targets are resolved later, when first used, so ``POINTER_TO["Node"]``
    inside ``Node`` works.
    """

    def __init__(self, class_namespace: Mapping[str, Any]) -> None:
        frame: Any = sys._getframe(1)
        while frame is not None and os.path.abspath(frame.f_code.co_filename) in BUILDER_FILES:
            frame = frame.f_back
        if frame is not None:
            self.globals: dict[str, Any] = frame.f_globals
            self.locals: dict[str, Any] = dict(frame.f_locals) if frame.f_locals is not frame.f_globals else {}
        else:
            module = str(class_namespace.get("__module__", ""))
            self.globals = vars(sys.modules[module]) if module in sys.modules else {}
            self.locals = {}
        self.own_name = ""
        self.own: type | None = None

    def eval(self, text: str, extra: Mapping[str, Any] | None = None) -> Any:
        local = dict(self.locals)
        if extra:
            local.update(extra)
        if self.own is not None:
            local[self.own_name] = self.own
        return eval(text, self.globals, local)  # noqa: S307 - annotation text of the user's own class

    def resolver(self) -> Callable[[Any], Any]:
        def resolve(ref: Any) -> Any:
            text = ref.__forward_arg__ if isinstance(ref, typing.ForwardRef) else ref
            try:
                return self.eval(text)
            except NameError as exc:
                if text == self.own_name:
                    raise DefinitionError(
                        f"{self.own_name}: a type cannot contain itself inline; use POINTER_TO[{self.own_name}]"
                    ) from None
                raise DefinitionError(f"{self.own_name}: type name {text!r} is not defined ({exc})") from None

        return resolve


def read_annotations(name: str, namespace: Mapping[str, Any], scope: DefinitionScope) -> dict[str, Any]:
    """The class's own annotations, with string annotations evaluated once."""
    raw: dict[str, Any] = dict(namespace.get("__annotations__", {}))
    localns = {k: v for k, v in namespace.items() if not k.startswith("__")}
    localns[name] = typing.ForwardRef(name)
    result: dict[str, Any] = {}
    for field, annotation in raw.items():
        if isinstance(annotation, str):
            try:
                annotation = scope.eval(annotation, localns)
            except NameError as exc:
                raise DefinitionError(f"{name}.{field}: cannot resolve the annotation {annotation!r} ({exc})") from None
            except Exception as exc:
                raise DefinitionError(f"{name}.{field}: invalid annotation {annotation!r} ({exc})") from None
        result[field] = annotation
    return result


def _is_classvar(annotation: Any) -> bool:
    return annotation is typing.ClassVar or typing.get_origin(annotation) is typing.ClassVar


_TYPE_FOR_VALUE: Final = ((bool, "BOOL"), (int, "INT"), (float, "LREAL"), (str, "STRING"))


def _suggested_type(initial: Any) -> str:
    """An IEC type that fits an initial value, for the message about a missing annotation."""
    if isinstance(initial, (list, tuple)):
        return f"ARRAY[{_suggested_type(initial[0]) if initial else '<type>'}]"
    for py_type, iec in _TYPE_FOR_VALUE:
        if isinstance(initial, py_type):
            return iec
    return "<type>"


class LayoutBuilder:
    """Builds one class's memory layout in the phases ctypes allows (attrs' ``_ClassBuilder`` habit).

    1. ``collect`` -- before the class exists, from its namespace only: read
       the annotations and specifiers, resolve the IEC types, check the
       initial values, and take the field values out of the namespace.
    2. ``lay_out`` -- once the ctypes metaclass has initialised the class:
       assign ``_fields_``. The ctypes documentation allows assigning
       ``_fields_`` after the class statement, before the type is first used;
       it says nothing about when a metaclass may see it, and CPython 3.13
       processes it later than 3.12 did.
    3. ``install`` -- replace the fields that need one with a descriptor,
       record a ``FieldRecord`` per field and set ``_iec_layout_``.
    """

    def __init__(
        self,
        name: str,
        bases: tuple[type, ...],
        namespace: dict[str, Any],
        *,
        kind: str,
        allowed_sections: Collection[Section],
        default_section: Section = Section.VAR,
        adjust: Callable[[TypeInfo, FieldSpec, str], TypeInfo] | None = None,
        annotations: dict[str, Any] | None = None,
        scope: DefinitionScope | None = None,
        st_name: str | None = None,
    ) -> None:
        self.name = name
        #: The class as messages name it: its ST name.
        self.label = st_name or name
        self.bases = bases
        self.namespace = namespace
        self.kind = kind
        self.allowed_sections = allowed_sections
        self.default_section = default_section
        self.adjust = adjust
        if scope is None:
            scope = DefinitionScope(namespace)
            scope.own_name = name
        self.scope = scope
        self.annotations = read_annotations(name, namespace, scope) if annotations is None else annotations
        self.pending: list[tuple[str, TypeInfo, FieldSpec]] = []
        self.inherited: list[FieldRecord] = []
        self.cls: Any = None

    def collect(self) -> None:
        """Phase 1: every field's section, type and initial value, checked; the namespace keeps no field value."""
        name, namespace = self.name, self.namespace
        check_unannotated(f"{self.kind} {name}", namespace, self.annotations)
        for base in self.bases:
            layout = getattr(base, "_iec_layout_", None)
            if layout is not None:
                self.inherited.extend(layout.fields)
        taken = {f.name: f.owner for f in self.inherited}
        resolver = self.scope.resolver()
        for field, annotation in self.annotations.items():
            if _is_classvar(annotation):
                continue
            value = namespace.pop(field, MISSING)
            spec = value if isinstance(value, FieldSpec) else FieldSpec(self.default_section, value)
            if spec.st_name is not None:
                check_st_name(spec.st_name, f"{self.kind} {self.label}.{field}")
            where = f"{self.label}.{spec.st_name or field}"
            if field.startswith("_iec") or field.startswith("__"):
                raise DefinitionError(f"{where}: names starting with '_iec' or '__' are reserved")
            if field in taken:
                raise DefinitionError(
                    f"{where}: {field} is already declared in {taken[field]}; a derived type cannot declare it again"
                )
            if spec.section not in self.allowed_sections:
                allowed = ", ".join(self.allowed_sections)
                raise DefinitionError(f"{where}: {spec.section} is not allowed in a {self.kind} (allowed: {allowed})")
            info = resolve_type(annotation, where, length=spec.length, bounds=spec.bounds, resolver=resolver)
            if self.adjust is not None:
                info = self.adjust(info, spec, where)
            if isinstance(info, ReferenceInfo) and isinstance(info.target, OpenArrayInfo) and not isinstance(info, OpenArrayReferenceInfo):
                raise DefinitionError(f"{where}: REFERENCE TO {info.target.name} is not allowed; a VAR_IN_OUT takes an ARRAY[*]")
            if isinstance(info, OpenArrayInfo):
                raise DefinitionError(
                    f"{where}: {info.name} (bounds='*') is the type of a block's VAR_IN_OUT only; "
                    f"a {spec.section} of a {self.kind} needs its bounds, e.g. bounds=(1, 10)"
                )
            if spec.instance_path and not (isinstance(info, StringInfo) and spec.section is Section.VAR
                                           and self.kind in ("FUNCTION_BLOCK", "PROGRAM")):
                raise DefinitionError(f"{where}: instance_path= is for a STRING or WSTRING VAR of a FUNCTION_BLOCK or "
                                      f"PROGRAM (ST: {{attribute 'instance-path'}} above a local STRING), not {spec.section} {info.name}")
            if self.kind in ("STRUCT", "UNION") and (isinstance(spec.initial, (dict, list, tuple)) or spec.fb_init) \
                    and _holds_blocks(info):
                raise DefinitionError(
                    f"{where}: a FUNCTION_BLOCK member of a {self.kind} takes no inputs or fb_init= at its declaration "
                    f"(iecoop applies neither to a block inside a STRUCT: they would be lost): set them in code, or make "
                    f"{self.label} a FUNCTION_BLOCK"
                )
            if spec.instance_path and spec.initial is not MISSING:
                raise DefinitionError(f"{where}: an instance_path= STRING takes no initial value (the path is its value; ST: {{attribute 'noinit'}})")
            spec = _with_alias_initial(spec, info)
            if isinstance(info, PointerInfo) and isinstance(spec.initial, Pointer) and spec.initial:
                spec = copy.copy(spec)
                spec.initial = GlobalAddress(spec.initial, info, where)
            check_initial(info, spec.initial, where)
            self.pending.append((field, info, spec))
            taken[field] = name

    def lay_out(self, cls: Any) -> None:
        """Phase 2: hand the fields to ctypes, which computes offsets and alignment (base fields first)."""
        self.cls = cls
        self.scope.own = cls
        cls._fields_ = [(field, info.ctype) for field, info, _spec in self.pending]
        check_block_size(ctypes.sizeof(cls), self.name)

    def install(self) -> ClassLayout:
        """Phase 3: descriptors where a type needs one, the field records and the layout."""
        cls = self.cls
        own: list[FieldRecord] = []
        for field, info, spec in self.pending:
            raw = cls.__dict__[field]
            descriptor = info.descriptor(raw, field, self.label)
            if descriptor is not None:
                if spec.st_name is not None and hasattr(descriptor, "where"):
                    descriptor.where = f"{self.label}.{spec.st_name}"  # messages name the ST variable
                setattr(cls, field, descriptor)
                alias = getattr(descriptor, "alias", None)
                if alias is not None:
                    setattr(cls, alias, descriptor.cached)
            own.append(FieldRecord(field, info, spec, self.label, int(raw.offset), raw))
        all_fields = tuple(self.inherited) + tuple(own)
        layout = ClassLayout(all_fields, tuple(own), {f.name: f for f in all_fields}, ())
        for record in own:
            if isinstance(record.spec.initial, LateInitial):
                record.spec.initial.check(record, layout)
        for record in own:
            for arguments in fb_init_entries(record.spec.fb_init):
                for argument in arguments.values():
                    if isinstance(argument, BlockArgument):
                        argument.check_argument(record, layout)
        # the addresses of siblings last: after every value, as a vendor's init code sets them
        last = [record for record in all_fields if isinstance(record.spec.initial, LateInitial)]
        first = [record for record in all_fields if not isinstance(record.spec.initial, LateInitial)]
        ops = tuple(op for record in first + last if (op := init_op(record)) is not None)
        layout = ClassLayout(all_fields, tuple(own), layout.by_name, ops)
        cls._iec_layout_ = layout
        return layout


def _with_alias_initial(spec: FieldSpec, info: TypeInfo) -> FieldSpec:
    """The declaration, with the initial value of its alias type (or ARRAY OF it) where it gives none."""
    initial: Any = spec.initial
    if isinstance(info, ElementaryInfo) and info.initial is not None and initial is MISSING:
        initial = info.initial
    elif isinstance(info, ArrayInfo) and isinstance(info.elem, ElementaryInfo) and info.elem.initial is not None:
        # the elements the list does not give start with the alias's value, as ST's do
        given = [] if initial is MISSING else list(initial) if isinstance(initial, (list, tuple)) else None
        if given is None or len(given) >= info.count:
            return spec
        initial = given + [info.elem.initial] * (info.count - len(given))
    else:
        return spec
    spec = copy.copy(spec)  # the VAR(...) object is the caller's
    spec.initial = initial
    return spec


def class_st_name(st_name: str | None, title: str) -> str:
    """The class keyword ``st_name=`` checked ("" when not given): ``class Gate_(FunctionBlock, st_name="Gate")``."""
    return "" if st_name is None else check_st_name(st_name, title)


def check_unannotated(title: str, namespace: Mapping[str, Any], annotations: Mapping[str, Any]) -> None:
    """Reject ``x = VAR_INPUT(0)`` without a type: it would be a plain class attribute, not a variable."""
    for field, value in namespace.items():
        if isinstance(value, FieldSpec) and field not in annotations:
            written = value.as_python()
            raise DefinitionError(
                f"{title}: {field} = {written} has no type, so it declares no variable; "
                f"annotate it: {field}: {_suggested_type(value.initial)} = {written}"
            )


def _holds_blocks(info: TypeInfo) -> bool:
    """A function block, or an ARRAY of them."""
    element = info.elem if isinstance(info, ArrayInfo) else info
    return isinstance(element, AggregateInfo) and kind_of(element.cls) is Kind.FUNCTION_BLOCK


def build_layout(
    create: Callable[[dict[str, Any]], type],
    name: str,
    bases: tuple[type, ...],
    namespace: dict[str, Any],
    **options: Any,
) -> type:
    """Build a complete class in one go: ``create`` runs the whole metaclass (its ``__new__`` and ``__init__``).

    ``options`` are LayoutBuilder's; a field in a section not in
    ``allowed_sections`` is rejected naming the kind (``STRUCT``).
    """
    builder = LayoutBuilder(name, bases, namespace, **options)
    builder.collect()
    builder.lay_out(create(namespace))
    builder.install()
    return typing.cast(type, builder.cls)


def _lookup(cls: type, name: str) -> Any:
    """What ``cls.name`` finds in the class dictionaries (descriptors unresolved), or MISSING."""
    return next((klass.__dict__[name] for klass in cls.__mro__ if name in klass.__dict__), MISSING)


def install_st_aliases(cls: type, names: Mapping[str, str]) -> None:
    """Let ``getattr(obj, "in")`` reach the member ``in_``: the ST name is a second class attribute, the same object.

    ``names`` maps the Python names of the class's own members to their ST names. An ST name the
    class already has (``body``, a member's Python name) gets no alias, nor one that Python or
    ctypes would read as their own (``__del__``, ``_pack_``, ``_iec...``). The member's own name keeps
    its descriptor, so nothing changes on the way to ``obj.in_``.
    """
    for python, st in names.items():
        special = st.startswith("_") and st.endswith("_") or st.startswith("_iec")
        if st != python and not special and _lookup(cls, st) is MISSING:
            setattr(cls, st, cls.__dict__[python])


def st_aliases(cls: type, layout: ClassLayout) -> dict[str, str]:
    """ST name -> Python name of each variable of ``cls`` reachable by its ST name (``install_st_aliases``)."""
    return {
        record.st_name: record.name for record in layout.fields
        if record.st_name != record.name and _lookup(cls, record.st_name) is _lookup(cls, record.name)
    }


_BUILDER_KEY: Final = "_iec_builder_"


def hand_over(namespace: dict[str, Any], builder: Any) -> None:
    """Keep ``builder`` with the class from the metaclass ``__new__`` to its ``__init__``."""
    namespace[_BUILDER_KEY] = builder


def take_over(cls: Any) -> Any:
    """The builder ``hand_over`` left on ``cls`` (removed from it), or None for a class built without one."""
    builder = cls.__dict__.get(_BUILDER_KEY)
    if builder is not None:
        delattr(cls, _BUILDER_KEY)
    return builder


class DataClassBuilder:
    """The two halves of a data type's metaclass (STRUCT, UNION, GVL): ``__new__`` and ``__init__``.

    The library's own root class (``_iec_base_class_`` in its body) is created
    empty; every user class gets its layout, implicit init and, in checked
    mode, the validating ``__setattr__``.
    """

    def __init__(self, word: str, kind: Kind) -> None:
        self.kind = word
        self.iec_kind = kind
        self.allowed_sections = sections_of(kind)

    def new(
        self, name: str, bases: tuple[type, ...], namespace: dict[str, Any], st_name: str | None = None
    ) -> dict[str, Any]:
        """Before the class exists: collect and check the fields; return the namespace to create it from."""
        if namespace.get("_iec_base_class_"):
            namespace.setdefault("_fields_", [])
            return namespace
        namespace["__iec__"] = IecClass(self.iec_kind, st_name=class_st_name(st_name, f"{self.kind} {name}"))
        builder = LayoutBuilder(
            name, bases, namespace, kind=self.kind, allowed_sections=self.allowed_sections, st_name=st_name
        )
        builder.collect()
        hand_over(namespace, builder)
        return namespace

    def init(self, cls: Any) -> ClassLayout | None:
        """After the ctypes metaclass's ``__init__``: lay the class out and finish it."""
        builder: LayoutBuilder | None = take_over(cls)
        if builder is None:
            return None
        builder.lay_out(cls)
        layout = builder.install()
        cls.__dict__["__iec__"].complete(layout=layout)
        cls._iec_implicit_init_ = layout.implicit_init
        install_st_aliases(cls, {record.name: record.st_name for record in layout.own})
        if CHECKS:
            cls.__setattr__ = data_setattr(cls.__name__, layout, st_aliases(cls, layout))
        return layout


# ---------------------------------------------------------------------------
# Initial values
# ---------------------------------------------------------------------------


def check_initial(info: TypeInfo, initial: Any, where: str) -> None:
    """Reject, at definition, an initial value that does not fit the field's type."""
    if initial is MISSING:
        return
    try:
        if isinstance(info, ArrayInfo):
            if not isinstance(initial, (list, tuple)):
                raise TypeError(f"an ARRAY initial value is a list, got {type(initial).__name__}")
            if len(initial) > info.count:
                raise TypeError(f"{len(initial)} initial values for {info.count} elements")
            for item in initial:
                check_initial(info.elem, item, where)
        elif isinstance(info, AggregateInfo):
            if isinstance(initial, info.cls):
                return
            if not isinstance(initial, Mapping):
                raise TypeError(f"a {info.name} initial value is a dict of member values, got {type(initial).__name__}")
            layout = getattr(info.cls, "_iec_layout_")
            for member, value in initial.items():
                record = layout.by_name.get(member)
                if record is None:
                    raise TypeError(f"{info.name} has no member {member!r}")
                if kind_of(info.cls) is Kind.FUNCTION_BLOCK and record.section is not Section.VAR_INPUT:
                    raise TypeError(f"only inputs may be set in an instance initialiser; {member!r} is {record.section}")
                check_initial(record.info, value, f"{where}.{member}")
        elif isinstance(info, (PointerInfo, ReferenceInfo)) and isinstance(initial, LateInitial):
            return  # checked once the class has all its fields (LateInitial.check)
        elif isinstance(info, (PointerInfo, InterfaceInfo, ReferenceInfo)):
            if initial not in (None, 0):
                or_sibling = "" if isinstance(info, InterfaceInfo) else (
                    ", or as adr_of(member) of a variable beside it" + (
                        ", or as adr(GVL, member) of a global variable" if isinstance(info, PointerInfo) else ""
                    )
                )
                raise TypeError(f"{info.name} starts as 0{or_sibling}; bind it to anything else at run time")
        else:
            info.validate(initial, where)
    except DefinitionError:
        raise
    except (TypeError, ValueError) as exc:
        message = str(exc)
        if message.startswith(where):
            message = message[len(where) :].lstrip(": ")
        raise DefinitionError(f"{where}: initial value of the wrong type: {message}") from None


def assign(obj: Any, record: FieldRecord, value: Any) -> None:
    """Set a member from a Python value: a list fills an ARRAY, a dict a STRUCT, anything else is a plain set."""
    if isinstance(value, (list, tuple, dict)) and isinstance(record.info, (ArrayInfo, AggregateInfo)):
        record.info.store(obj, record.offset, value, record.where)
    else:
        setattr(obj, record.name, value)


def _assign_members(view: Any, values: dict[str, Any]) -> None:
    layout: ClassLayout = type(view)._iec_layout_
    for member, value in values.items():
        record = layout.by_name.get(member)
        if record is None:
            raise TypeError(f"{type(view).__name__} has no member {member!r}")
        assign(view, record, value)


class LateInitial:
    """An initial value that depends on the instance itself, as ``adr_of(member)`` does.

    It is checked once the class has all its fields (``check``) and applied
    after every other initial value (``op``), as a vendor's init code sets
    addresses last.
    """

    __slots__ = ()

    def check(self, record: FieldRecord, layout: ClassLayout) -> None:
        """Refuse, at definition, a value that cannot fit ``record`` in ``layout``."""
        raise NotImplementedError

    def op(self, record: FieldRecord) -> Callable[[Any], None]:
        """The operation that sets ``record`` in a new instance."""
        raise NotImplementedError


class BlockArgument:
    """An FB_init argument of a member that depends on the instance declaring it, as ``sibling(member)`` does.

    It is checked once the class has all its fields (``check_argument``) and
    taken from each new instance as the member's FB_init runs (``resolve``).
    """

    __slots__ = ()

    def check_argument(self, record: FieldRecord, layout: ClassLayout) -> None:
        """Refuse, at definition, an argument the block declaring ``record`` cannot give."""
        raise NotImplementedError

    def resolve(self, obj: Any) -> Any:
        """The value passed, taken from ``obj``, the instance whose member's FB_init runs."""
        raise NotImplementedError


def fb_init_entries(fb_init: dict[str, Any] | list[dict[str, Any]] | None) -> list[dict[str, Any]]:
    """The FB_init argument dicts of a declaration: one, one per ARRAY element, or none."""
    return [] if not fb_init else [fb_init] if isinstance(fb_init, dict) else list(fb_init)


class GlobalAddress(LateInitial):
    """The initial value ``ADR(globalVar)`` of a POINTER: ``VAR(adr(GVL_Plant, "counter"))``.

    ST: ``pCounter : POINTER TO DINT := ADR(counter);`` with ``counter`` in a
    VAR_GLOBAL list. Every (re-)initialisation aims the pointer at the global
    again; the declaration does not keep the list alive, and once the list is
    gone the pointer starts dangling (using it is RTSEXCPT_ACCESS_VIOLATION).
    """

    __slots__ = ("handle", "offset", "gvl", "member", "text")

    def __init__(self, pointer: Pointer[Any], info: PointerInfo, where: str) -> None:
        root = target_root(pointer.handle)
        if root is None or kind_of(type(root)) is not Kind.GVL:
            what = "deleted memory" if root is None else f"a {type(root).__name__} instance"
            raise DefinitionError(
                f"{where}: {info.name} starts as 0, or as adr_of(member) of a variable beside it, or as "
                f"adr(GVL, member) of a global variable; this address is into {what}: bind it at run time"
            )
        target = pointer._target
        if info.target is not None and target is not None and target.signature != info.target.signature:
            raise DefinitionError(
                f"{where}: {info.name} cannot be initialised with the address of a {target.name}: the types must match"
            )
        self.handle = pointer.handle
        self.offset = pointer.handle & _HANDLE_MASK
        self.gvl = weakref.ref(root)
        fields = getattr(type(root), "_iec_layout_").fields
        #: the global variable designated (None for an address inside one, an array element say)
        self.member: str | None = next((f.name for f in fields if f.offset == self.offset and (
            target is None or f.info.signature == target.signature)), None)
        name = type(root).__name__
        self.text = f"adr({name}, {self.member!r})" if self.member else f"adr({name}) + {self.offset}"

    def __repr__(self) -> str:
        return self.text

    def check(self, record: FieldRecord, layout: ClassLayout) -> None:
        """Checked when made: nothing depends on the rest of the class."""

    def op(self, record: FieldRecord) -> Callable[[Any], None]:
        store, offset, where, target = record.info.store, record.offset, record.where, record.info
        assert isinstance(target, PointerInfo)

        def aim(obj: Any) -> None:
            gvl = self.gvl()
            if gvl is None:
                # The list is gone: keep its old address, which faults when used instead of aiming anywhere.
                store(obj, offset, Pointer(self.handle, target.target), where)
            else:
                store(obj, offset, Pointer(handle_of(gvl, self.offset), target.target, keep=gvl), where)

        return aim


def init_op(record: FieldRecord) -> Callable[[Any], None] | None:
    """The operation that writes ``record``'s initial value into a zeroed instance, or None."""
    info, initial, raw = record.info, record.spec.initial, record.raw
    if isinstance(initial, LateInitial):
        return initial.op(record)
    if isinstance(info, (ElementaryInfo, EnumInfo)):
        if initial is MISSING or not initial:
            return None
        value = int(initial) if isinstance(info, EnumInfo) else initial
        setter = raw.__set__
        return lambda obj: setter(obj, value)
    if isinstance(info, StringInfo):
        if initial is MISSING or initial == "":
            return None
        data = info._encode(initial, record.where)
        offset, size = record.offset, info.size

        def op_string(obj: Any) -> None:
            ctypes.memmove(ctypes.addressof(obj) + offset, data, size)

        return op_string
    if isinstance(info, AggregateInfo):
        return _aggregate_op(info, raw.__get__, initial)
    if isinstance(info, ArrayInfo):
        return _array_op(info, raw.__get__, initial)
    return None


def _aggregate_op(info: AggregateInfo, get: Callable[[Any], Any], initial: Any) -> Callable[[Any], None] | None:
    cls = info.cls
    implicit = getattr(cls, "_iec_implicit_init_")
    if initial is MISSING:
        return lambda obj: implicit(get(obj))
    if isinstance(initial, cls):
        source = bytes(memoryview(typing.cast(Any, initial)).cast("B"))
        size = len(source)

        def op_copy(obj: Any) -> None:
            ctypes.memmove(ctypes.addressof(get(obj)), source, size)

        return op_copy
    values = dict(initial)
    if kind_of(cls) is Kind.FUNCTION_BLOCK:
        # Declaration-site inputs (fb : FB := (in := x)) are applied after FB_init by the POU layer.
        return lambda obj: implicit(get(obj))

    def op(obj: Any) -> None:
        view = get(obj)
        implicit(view)
        _assign_members(view, values)

    return op


def _array_op(info: ArrayInfo, get: Callable[[Any], Any], initial: Any) -> Callable[[Any], None] | None:
    elem = info.elem
    ctype = info.ctype
    count = info.count
    raw_get = ctype.__mro__[1].__getitem__
    raw_set = ctype.__mro__[1].__setitem__
    if isinstance(elem, AggregateInfo):
        implicit = getattr(elem.cls, "_iec_implicit_init_")
        items = list(initial) if initial is not MISSING else []
        if kind_of(elem.cls) is Kind.FUNCTION_BLOCK:
            # Declaration-site inputs of ARRAY OF FB elements are applied after their FB_init by the POU layer.
            items = [item for item in items if not isinstance(item, dict)]

        def op(obj: Any) -> None:
            array = get(obj)
            for i in range(count):
                view = raw_get(array, i)
                implicit(view)
                if i < len(items):
                    item: Any = items[i]
                    if isinstance(item, elem.cls):
                        ctypes.memmove(ctypes.addressof(view), ctypes.addressof(typing.cast(Any, item)), elem.size)
                    else:
                        _assign_members(view, item)

        return op
    if isinstance(elem, ArrayInfo):
        return _nested_array_op(info, get, initial)
    if initial is MISSING or not initial:
        return None
    values = list(initial)
    if isinstance(elem, StringInfo):
        size = elem.size
        encoded = [elem._encode(v, "ARRAY element") for v in values]

        def op_str(obj: Any) -> None:
            base = ctypes.addressof(get(obj))
            for i, data in enumerate(encoded):
                ctypes.memmove(base + i * size, data, size)

        return op_str
    if isinstance(elem, EnumInfo):
        values = [int(v) for v in values]

    def op_values(obj: Any) -> None:
        array = get(obj)
        for i, value in enumerate(values):
            raw_set(array, i, value)

    return op_values


def _nested_array_op(info: ArrayInfo, get: Callable[[Any], Any], initial: Any) -> Callable[[Any], None] | None:
    """ARRAY OF ARRAY: each element array initialised as a field of its own (its item of ``initial``, a list)."""
    raw_get = info.ctype.__mro__[1].__getitem__
    items = list(initial) if initial is not MISSING else []
    ops: list[Callable[[Any], None]] = []
    for i in range(info.count):

        def element(obj: Any, i: int = i) -> Any:
            return raw_get(get(obj), i)

        op = _array_op(typing.cast(ArrayInfo, info.elem), element, items[i] if i < len(items) else MISSING)
        if op is not None:
            ops.append(op)
    if not ops:
        return None

    def op_all(obj: Any) -> None:
        for op in ops:
            op(obj)

    return op_all



CHECKS = _config.CHECKS
