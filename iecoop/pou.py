"""FUNCTION_BLOCK and PROGRAM: declared once, checked at definition, fast when run.

A function block is a class with annotated VAR sections, a ``body()`` (its
implementation part), METHODs and PROPERTYs. Class creation lays the instance
out in memory (base fields first, as EXTENDS does), checks the OOP rules of
IEC 61131-3 and raises ``DefinitionError`` naming the class, the member and
the rule, then generates the call (``fb(IN=..., PT=...)``) in one piece of
code. Reading a variable runs no Python code.

ST::

    FUNCTION_BLOCK FB_Counter
    VAR_INPUT  enable : BOOL; END_VAR
    VAR_OUTPUT count  : INT;  END_VAR
    IF enable THEN count := count + 1; END_IF

Python:

>>> from iecoop import BOOL, INT, FunctionBlock, VAR_INPUT, VAR_OUTPUT
>>> class Counter(FunctionBlock):
...     enable: BOOL = VAR_INPUT(False)
...     count: INT = VAR_OUTPUT(0)
...     def body(self) -> None:
...         if self.enable:
...             self.count += 1
>>> counter = Counter()
>>> for _ in range(3):
...     counter(enable=True)
>>> counter.count
3
"""

from __future__ import annotations

import ctypes
import dataclasses
import inspect
import weakref
import sys
import types
import typing
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, ClassVar

from iecoop import _config
from iecoop._codegen import compile_source
from iecoop._inline import compile_own_loops, compile_own_writes, inline_call
from iecoop._loop_locals import loop_types
from iecoop.exceptions import AccessError, DefinitionError
from iecoop.gvl import find_global
from iecoop.interfaces import Interface, interface_members
from iecoop.parameters import wrap_parameters
from iecoop.lifecycle import fb_children, initialise
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo, new_class_tag
from iecoop.memory._infos import TypeInfo
from iecoop.memory._views import CheckedMemberField, VIEW_PREFIX, _MemberProperty, set_state_without_views
from iecoop.memory.interface_references import InterfaceInfo
from iecoop.memory.pointers import PointerInfo
from iecoop.memory.open_arrays import OpenArrayInfo, OpenArrayReferenceInfo
from iecoop.memory.references import ReferenceInfo
from iecoop.memory.layout import (
    MISSING,
    ClassLayout,
    DefinitionScope,
    FieldRecord,
    FieldSpec,
    LayoutBuilder,
    build_layout,
    check_unannotated,
    class_st_name,
    hand_over,
    init_op,
    install_st_aliases,
    read_annotations,
    register_builder,
    st_aliases,
    take_over,
)
from iecoop.members import (
    Access,
    Member,
    caller_description,
    format_signature,
    own_code,
    guard_namespace,
    members_of_namespace,
    narrower,
    register_code,
    rewrap,
    same_signature,
    visibility,
)
from iecoop.metadata import IecClass, iec_class, kind_of
from iecoop.sections import SECTION_RULES, AtCall, Kind, Section, Storage, sections_of
from iecoop.writes import (
    FastWrite, accepted_type, check_write, counter_ranges, fast_writes, known_reads, pou_setattr, raw_elementary,
    write_rules,
)

register_builder(__file__)

__all__ = ["FunctionBlock", "Program", "check_write", "fb_children", "pou_members", "static_blocks"]

#: The VAR_STAT block of every class that declares one (one per class, like the PLC's static data).
_static_blocks: weakref.WeakKeyDictionary[type, Any] = weakref.WeakKeyDictionary()


def static_blocks() -> list[tuple[type, Any]]:
    """Every live class with VAR_STAT variables, with its static block."""
    return list(_static_blocks.items())

#: Sections a FUNCTION_BLOCK or PROGRAM may declare.
_POU_SECTIONS = sections_of(Kind.FUNCTION_BLOCK)
_POU_KINDS = (Kind.FUNCTION_BLOCK, Kind.PROGRAM)
_LIFECYCLE = frozenset({"body", "fb_init", "fb_reinit", "fb_exit"})

if TYPE_CHECKING:
    _PouBase = object
    _PouMetaBase = type
else:
    _PouBase = ctypes.Structure
    _PouMetaBase = type(ctypes.Structure)


class _Static:
    """A VAR_STAT or VAR_EXTERNAL variable: one storage outside the instance block."""

    __slots__ = ("raw", "block", "where", "validate")

    def __init__(self, raw: Any, block: Any, where: str, validate: Callable[[Any, str], None] | None) -> None:
        self.raw, self.block, self.where, self.validate = raw, block, where, validate

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.raw.__get__(self.block)

    def __set__(self, obj: Any, value: Any) -> None:
        if self.validate is not None:
            self.validate(value, self.where)
        self.raw.__set__(self.block, value)


class _PouMeta(_PouMetaBase):
    """Builds FUNCTION_BLOCK / PROGRAM classes (derived from ctypes' own metaclass).

    ``__new__`` runs the phases that need only the class body (the OOP checks
    and the field declarations), ``__init__`` those that need the class
    (its ctypes layout, descriptors, members, generated call); see _PouBuilder.
    """

    def __new__(
        mcls,
        name: str,
        bases: tuple[type, ...],
        namespace: dict[str, Any],
        *,
        abstract: bool = False,
        final: bool = False,
        internal: bool = False,
        st_name: str | None = None,
        **kwargs: Any,
    ) -> Any:
        if not namespace.get("_iec_base_class_"):
            builder = _PouBuilder(name, bases, namespace, abstract, final, internal, st_name)
            builder.declare()
            hand_over(namespace, builder)
        return super().__new__(mcls, name, bases, namespace, **kwargs)

    def __init__(cls, name: str, bases: tuple[type, ...], namespace: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(name, bases, namespace)
        builder: _PouBuilder | None = take_over(cls)
        if builder is not None:
            builder.build(cls)

    def __setattr__(cls, name: str, value: Any) -> None:
        super().__setattr__(name, value)
        if name == "__call__":
            _follow_call(cls)

    def __delattr__(cls, name: str) -> None:
        super().__delattr__(name)
        if name == "__call__":
            _follow_call(cls)


def _follow_call(cls: Any) -> None:
    """``Class.__call__`` rebound or deleted: the compiled calls of its holders call it as Python's call would."""
    cell = cls.__dict__.get("_iec_call_cell_")
    if cell is None:
        return
    built = cls.__dict__["_iec_built_call_"]
    same = cls.__dict__.get("__call__") is built
    cell.cell_contents = built if same else _call_as_python_does
    positional = cls.__dict__.get("_iec_positional_")
    if positional is not None:
        by_position, _order, call, by_name = positional
        by_position.cell_contents = call if same else by_name


def _call_as_python_does(view: Any, /, *args: Any, **inputs: Any) -> None:
    """A member call once its class's ``__call__`` is no longer the one built: Python's call protocol."""
    view(*args, **inputs)


def _kind_word(cls_or_kind: Any) -> str:
    kind = cls_or_kind if isinstance(cls_or_kind, Kind) else kind_of(cls_or_kind)
    return Kind.PROGRAM.keyword if kind is Kind.PROGRAM else Kind.FUNCTION_BLOCK.keyword


#: Names the block itself defines: a method may not take them, whatever their case.
_RESERVED_SPELLING = {n.lower(): n for n in (*_LIFECYCLE, "__call__")}


class _PouBuilder:
    """One FUNCTION_BLOCK or PROGRAM, built in named phases.

    Before the class exists (metaclass ``__new__``), from the class body:
    ``declare`` checks the bases (one EXTENDS, FINAL, INTERNAL), the slips
    that would silently do nothing, the METHODs and PROPERTYs against the
    inherited ones and FB_init / FB_exit, then collects the fields.
    Once ctypes has initialised the class (metaclass ``__init__``): ``build``
    lays it out, installs the members, checks the interfaces, creates the
    VAR_STAT block and generates the call.
    """

    def __init__(
        self, name: str, bases: tuple[type, ...], namespace: dict[str, Any], abstract: bool, final: bool, internal: bool,
        st_name: str | None = None,
    ) -> None:
        self.name = name
        self.bases = bases
        self.namespace = namespace
        self.abstract, self.final, self.internal = abstract, final, internal
        self.kind = Kind.PROGRAM if any(kind_of(b) is Kind.PROGRAM for b in bases) else Kind.FUNCTION_BLOCK
        self.word = _kind_word(self.kind)
        self.st_name = class_st_name(st_name, f"{self.word} {name}")
        #: The block as messages name it: ``FUNCTION_BLOCK`` and its ST name.
        self.title = f"{self.word} {self.st_name or name}"
        self.parent: type | None = None
        self.scope = DefinitionScope(namespace)
        self.scope.own_name = name
        self.own: dict[str, Member] = {}
        self.inherited: dict[str, Member] = {}
        self.outside: dict[str, Any] = {}
        self.outside_specs: dict[str, FieldSpec] = {}
        self.owner_ref: list[type] = []
        self.original_namespace: dict[str, Any] = {}
        self.layout_builder: LayoutBuilder | None = None

    # -- phases before the class exists ------------------------------------------------

    def declare(self) -> None:
        self.check_bases()
        self.check_slips()
        annotations = read_annotations(self.name, self.namespace, self.scope)
        check_unannotated(self.title, self.namespace, annotations)
        self.check_declarations(annotations)
        self.collect_fields(annotations)

    def check_bases(self) -> None:
        name, title, bases = self.name, self.title, self.bases
        if self.abstract and self.final:
            raise DefinitionError(f"{title}: a block cannot be both ABSTRACT and FINAL")
        pou_bases = [b for b in bases if kind_of(b) in _POU_KINDS]
        iface_bases = [b for b in bases if kind_of(b) is Kind.INTERFACE]
        if Interface in bases and pou_bases:
            # `class IFoo(Interface, SomeFB)` declares an interface, not a block implementing the root Interface.
            raise DefinitionError(
                f"INTERFACE {name}: an interface can only EXTEND interfaces, not {_kind_word(pou_bases[0])} {pou_bases[0].__name__}"
            )
        others = [b for b in bases if b not in pou_bases and b not in iface_bases]
        if others:
            raise DefinitionError(
                f"{title}: {others[0].__name__} is neither a function block nor an interface; "
                "EXTENDS takes one function block and IMPLEMENTS takes interfaces"
            )
        user_bases = [b for b in pou_bases if not _record(b).root]
        if len(user_bases) > 1:
            names = ", ".join(b.__name__ for b in user_bases)
            raise DefinitionError(f"{title}: EXTENDS allows one function block, got {names}")
        parent = self.parent = user_bases[0] if user_bases else None
        if parent is not None:
            if _record(parent).final:
                raise DefinitionError(f"{title} cannot EXTEND {parent.__name__}: {parent.__name__} is FINAL")
            module = self.namespace.get("__module__", "")
            if _record(parent).internal and _package(module) != _package(parent.__module__):
                raise DefinitionError(
                    f"{title} cannot EXTEND INTERNAL {parent.__name__} outside the package {_package(parent.__module__)!r}"
                )

    def check_slips(self) -> None:
        """Definitions Python accepts but that would silently never run."""
        title = self.title
        if "__call__" in self.namespace:
            raise DefinitionError(
                f"{title}: __call__ cannot be overridden; the call sets the inputs and runs body(), "
                "so write the block's code in def body(self) -> None"
            )
        for member, value in self.namespace.items():
            meant = _RESERVED_SPELLING.get(member.lower())
            if meant is not None and member != meant and (callable(value) or isinstance(value, property)):
                raise DefinitionError(
                    f"{title}: {member} is not {meant} (IEC names ignore case, Python's do not): "
                    f"rename it to {meant}, or {member} never runs as the block's {meant}"
                )

    def check_declarations(self, annotations: dict[str, Any]) -> None:
        name, title, namespace, parent = self.name, self.title, self.namespace, self.parent
        for field in annotations:
            value = namespace.get(field, MISSING)
            if isinstance(value, (types.FunctionType, property)):
                raise DefinitionError(f"{title}: {field} is declared both as a variable and as a METHOD / PROPERTY")
        # Members: what this block declares and what it inherits.
        placeholder = type(name, (), {"__module__": namespace.get("__module__", "")})
        self.own = members_of_namespace(placeholder, namespace, self.scope.eval, _LIFECYCLE)
        self.inherited = dict(_record(parent).members) if parent is not None else {}
        _check_name_clashes(title, parent, annotations, self.own, self.inherited)
        _check_members(title, name, self.own, self.inherited, self.abstract)
        _check_lifecycle(title, namespace, parent, self.scope)

    def collect_fields(self, annotations: dict[str, Any]) -> None:
        namespace = self.namespace
        # VAR_STAT and VAR_EXTERNAL live outside the instance block.
        self.outside = {
            f: a for f, a in annotations.items()
            if isinstance(namespace.get(f), FieldSpec) and not SECTION_RULES[namespace[f].section].in_instance
        }
        self.outside_specs = {f: namespace.pop(f) for f in self.outside}
        inside = {f: a for f, a in annotations.items() if f not in self.outside}
        wrap_parameters(self.title, namespace, self.scope.eval)
        self.original_namespace = dict(namespace)
        guard_namespace(self.owner_ref, self.st_name or self.name, namespace)
        namespace["__iec__"] = IecClass(self.kind, self.abstract, self.final, self.internal, st_name=self.st_name)
        self.layout_builder = LayoutBuilder(
            self.name, self.bases, namespace, kind=self.word, allowed_sections=_POU_SECTIONS, adjust=self.adjust,
            annotations=inside, scope=self.scope, st_name=self.st_name,
        )
        self.layout_builder.collect()

    def adjust(self, info: TypeInfo, spec: FieldSpec, where: str) -> TypeInfo:
        """The POU rules for one field's type and section."""
        if isinstance(info, AggregateInfo) and (record := iec_class(info.cls)) is not None and record.abstract:
            raise DefinitionError(
                f"{where}: ABSTRACT {info.name} cannot be instantiated; use REFERENCE_TO, POINTER_TO or an interface"
            )
        if spec.section is Section.VAR_IN_OUT:
            if isinstance(info, (ReferenceInfo, InterfaceInfo)):
                raise DefinitionError(f"{where}: VAR_IN_OUT of {info.name} is not allowed")
            return OpenArrayReferenceInfo(info) if isinstance(info, OpenArrayInfo) else ReferenceInfo(info)
        if spec.section is Section.VAR_INST and not spec.method:
            raise DefinitionError(f"{where}: VAR_INST needs the method it belongs to: VAR_INST(..., method='name')")
        if spec.section is Section.VAR_INST and spec.method not in self.own:
            raise DefinitionError(f"{where}: VAR_INST belongs to METHOD {spec.method!r}, which {self.name} does not declare")
        if spec.fb_init:
            element = info.elem if isinstance(info, ArrayInfo) else info
            if not (isinstance(element, AggregateInfo) and kind_of(element.cls) is Kind.FUNCTION_BLOCK):
                raise DefinitionError(f"{where}: fb_init= applies to function block members (or ARRAYs of them) only")
            if isinstance(spec.fb_init, list):
                if not isinstance(info, ArrayInfo):
                    raise DefinitionError(f"{where}: a list of fb_init= inputs is for an ARRAY OF function blocks")
                if len(spec.fb_init) > info.count:
                    raise DefinitionError(f"{where}: {len(spec.fb_init)} fb_init= entries for {info.count} elements")
        if (spec.retain or spec.persistent) and isinstance(info, (PointerInfo, ReferenceInfo, InterfaceInfo)):
            raise DefinitionError(f"{where}: {info.name} cannot be RETAIN or PERSISTENT (an address is not kept)")
        return info

    # -- phases once the class exists ---------------------------------------------------

    def build(self, cls: Any) -> None:
        assert self.layout_builder is not None
        self.layout_builder.lay_out(cls)
        layout = self.layout_builder.install()
        members = self.install_members(cls)
        statics = _install_outside(cls, self.st_name or self.name, self.outside, self.outside_specs, self.scope)
        cls.__dict__["__iec__"].complete(layout=layout, members=members, static_fields=statics)
        # Variables only, and never a name the block looks up as its own (fb_init): a METHOD or
        # PROPERTY is reached by its Python name (member_named gives it), so none runs twice or as a hook.
        install_st_aliases(
            cls, {record.name: record.st_name for record in (*layout.own, *statics) if record.st_name not in _LIFECYCLE}
        )
        self.install_runtime(cls, layout)

    def install_members(self, cls: Any) -> dict[str, Member]:
        self.owner_ref.append(cls)
        register_code(cls, self.original_namespace)
        own_members = {m.name: _rebind(m, cls, self.inherited.get(m.name)) for m in self.own.values()}
        members = {**self.inherited, **own_members}
        _check_interfaces(self.title, cls, members, self.abstract)
        return members

    def install_runtime(self, cls: Any, layout: ClassLayout) -> None:
        """What an instance and a call need: type tag, implicit init, children, temps, the call."""
        tag = new_class_tag(cls)
        cls._iec_tag_value_ = tag
        set_tag = FunctionBlock.__dict__["_iec_tag_"].__set__
        fields_init = layout.implicit_init

        def implicit_init(obj: Any) -> None:
            set_tag(obj, tag)
            fields_init(obj)

        cls._iec_implicit_init_ = implicit_init
        cls._iec_children_ = tuple(fb_children(layout))
        cls._iec_call_after_init_ = tuple(
            n for n in dir(cls) if getattr(getattr(cls, n, None), "_iec_call_after_init_", False)
        )
        temps = [r for r in layout.fields if SECTION_RULES[r.section].at_call is AtCall.REINITIALISED]
        cls._iec_temp_reset_ = _temp_reset(temps) if temps else None
        cls._iec_view_keys_ = tuple(
            (d.alias, sys.intern(VIEW_PREFIX + r.name)) for r in layout.fields
            if isinstance(d := getattr(cls, r.name, None), _MemberProperty)
        )
        cls.__call__ = cls._iec_built_call_ = _make_call(cls, layout)
        # A task may call an instance with no argument when no VAR_IN_OUT must be bound.
        cls._iec_task_call_ = not any(SECTION_RULES[r.section].at_call is AtCall.BOUND for r in layout.fields)
        # What a holder's compiled call calls for `self.member(...)` of this class (see _follow_call).
        cls._iec_call_cell_ = types.CellType(cls.__call__)
        if _config.CHECKS:
            cls.__setattr__ = pou_setattr(cls, layout, st_aliases(cls, layout))
        _compile_methods(cls, layout, self.original_namespace)


def _compile_methods(cls: Any, layout: ClassLayout, namespace: dict[str, Any]) -> None:
    """Each METHOD compiled as the call compiles the body: in checked mode its own writes written out
    (``compile_own_writes``), in fast mode its loops that call nothing keeping the variables in locals
    (``compile_own_loops``)."""
    if _config.CHECKS:
        stores = fast_writes(layout, cls._iec_write_rules_)
        known = known_reads(cls, layout)
        if not stores:
            return
    else:
        loops = loop_types(raw_elementary(cls, layout))
        if not loops:
            return
    for name, func in namespace.items():
        if not isinstance(func, types.FunctionType) or name == "body" or (name.startswith("__") and name.endswith("__")):
            continue
        compiled = compile_own_writes(func, cls, stores, known) if _config.CHECKS else compile_own_loops(func, cls, loops)
        if compiled is None:
            continue
        installed = cls.__dict__.get(name)
        if installed is func:
            setattr(cls, name, compiled)
        else:  # PRIVATE, PROTECTED or INTERNAL: the guard calls the compiled method
            rewrap(installed, func, compiled)


def _record(cls: type) -> IecClass:
    record = iec_class(cls)
    assert record is not None, cls
    return record


def _package(module: str) -> str:
    return module.split(".", 1)[0]


def _rebind(member: Member, cls: type, base: Member | None) -> Member:
    # An override keeps the ST name of the member it overrides unless it gives its own.
    return dataclasses.replace(member, owner=cls, st_name=member.st_name or (base.st_name if base else ""))


def _check_members(title: str, name: str, own: dict[str, Member], inherited: dict[str, Member], abstract: bool) -> None:
    for member in own.values():
        label = f"{title}: {member.kind.upper() if member.kind == 'method' else 'PROPERTY'} {member.st_name or member.name}"
        flags = member.flags
        if flags & Access.ABSTRACT:
            if visibility(flags) == Access.PRIVATE:
                raise DefinitionError(f"{label}: ABSTRACT cannot be combined with PRIVATE")
            if flags & Access.FINAL:
                raise DefinitionError(f"{label}: ABSTRACT cannot be combined with FINAL")
            if not abstract:
                raise DefinitionError(
                    f"{label} is ABSTRACT, so {name} must be declared abstract: class {name}(..., abstract=True)"
                )
        if member.kind == "property" and member.has_set and member.set_flags & Access.ABSTRACT and not abstract:
            raise DefinitionError(f"{label} has an ABSTRACT Set accessor, so {name} must be declared abstract")
        base = inherited.get(member.name)
        if base is None:
            continue
        if base.visibility == Access.PRIVATE:
            raise DefinitionError(f"{title}: {base.describe()} is PRIVATE and cannot be overridden")
        if base.final:
            raise DefinitionError(f"{title}: FINAL {base.describe()} cannot be overridden")
        if base.kind != member.kind:
            raise DefinitionError(f"{title}: {member.name} overrides a {base.kind.upper()} with a {member.kind.upper()}")
        if not same_signature(base.signature, member.signature):
            raise DefinitionError(
                f"{title}: interface of overridden {base.kind} '{member.name}' of base '{base.owner.__name__}' "
                f"doesn't match declaration (C0094): base {format_signature(base.signature)}, "
                f"here {format_signature(member.signature)}"
            )
        if narrower(member.flags, base.flags):
            raise DefinitionError(
                f"{title}: {member.name} narrows the access of {base.describe()} to {visibility(member.flags).name}"
            )
        if base.kind == "property" and base.has_set and not member.has_set:
            raise DefinitionError(f"{title}: PROPERTY {member.name} drops the Set accessor its base declares")
    if not abstract:
        merged = {**inherited, **own}
        for member in merged.values():
            if member.abstract:
                raise DefinitionError(
                    f"{title} must be ABSTRACT or implement {member.describe()}: an ABSTRACT member is left unimplemented"
                )


def _check_name_clashes(
    title: str, parent: type | None, annotations: dict[str, Any], own: dict[str, Member], inherited: dict[str, Member]
) -> None:
    """A name is one identifier in the whole EXTENDS chain: a variable and a METHOD / PROPERTY cannot share it."""
    layout: ClassLayout | None = getattr(parent, "_iec_layout_", None)
    inherited_fields = {r.name: r.owner for r in layout.fields} if layout is not None else {}
    for member in own.values():
        owner = inherited_fields.get(member.name)
        if owner is not None:
            what = "METHOD" if member.kind == "method" else "PROPERTY"
            raise DefinitionError(
                f"{title}: {what} {member.name} reuses the name of the variable {owner}.{member.name}"
            )
    for field in annotations:
        base = inherited.get(field)
        if base is not None:
            raise DefinitionError(f"{title}: variable {field} reuses the name of {base.describe()}")


def _params(func: Any) -> list[str]:
    return list(inspect.signature(func).parameters)[1:]


def _check_lifecycle(title: str, namespace: dict[str, Any], parent: type | None, scope: DefinitionScope) -> None:
    init = namespace.get("fb_init")
    if init is not None:
        params = _params(init)
        if params[:2] != ["init_retains", "in_copy_code"]:
            raise DefinitionError(
                f"{title}: fb_init must start with the inputs (init_retains, in_copy_code) (C0119), got {params[:2]}"
            )
        base_params = _base_fb_init_params(parent)
        if params[: len(base_params)] != base_params:
            raise DefinitionError(
                f"{title}: fb_init must declare the base's FB_init inputs {base_params} first and in the same order"
            )
    exit_ = namespace.get("fb_exit")
    if exit_ is not None and _params(exit_) != ["in_copy_code"]:
        raise DefinitionError(f"{title}: fb_exit takes exactly one input, in_copy_code, got {_params(exit_)}")
    reinit = namespace.get("fb_reinit")
    if reinit is not None and _params(reinit):
        raise DefinitionError(f"{title}: fb_reinit takes no inputs, got {_params(reinit)}")


def _base_fb_init_params(parent: type | None) -> list[str]:
    if parent is None:
        return ["init_retains", "in_copy_code"]
    for klass in parent.__mro__:
        init = klass.__dict__.get("fb_init")
        if init is not None:
            return _params(init)
    return ["init_retains", "in_copy_code"]


def _check_interfaces(title: str, cls: type, members: dict[str, Member], abstract: bool) -> None:
    for iface in cls.__mro__:
        if kind_of(iface) is not Kind.INTERFACE or iface is Interface:
            continue
        for proto in interface_members(iface).values():
            impl = members.get(proto.name)
            if impl is None or (impl.abstract and not abstract):
                if abstract and impl is not None:
                    continue
                if abstract and impl is None:
                    continue
                what = "method" if proto.kind == "method" else "property"
                raise DefinitionError(
                    f"{title}: there is no implementation for {what} '{proto.name}' defined in interface "
                    f"'{iface.__name__}' (C0087)"
                )
            if impl.kind != proto.kind:
                raise DefinitionError(f"{title}: {proto.name} of interface {iface.__name__} is a {proto.kind.upper()}")
            if not same_signature(impl.signature, proto.signature):
                raise DefinitionError(
                    f"{title}: {proto.name} does not match interface {iface.__name__}: "
                    f"interface {format_signature(proto.signature)}, here {format_signature(impl.signature)}"
                )
            if impl.visibility != Access.PUBLIC:
                raise DefinitionError(f"{title}: {proto.name} implements interface {iface.__name__} and must be PUBLIC")
            if proto.kind == "property" and proto.has_set and not impl.has_set:
                raise DefinitionError(f"{title}: PROPERTY {proto.name} of interface {iface.__name__} needs a Set accessor")


def _install_outside(
    cls: Any, name: str, outside: dict[str, Any], specs: dict[str, FieldSpec], scope: DefinitionScope
) -> tuple[FieldRecord, ...]:
    """VAR_STAT: one block per declaring class. VAR_EXTERNAL: the GVL variable of that name. Returns the VAR_STATs."""
    static_fields: tuple[FieldRecord, ...] = ()
    statics = {f: a for f, a in outside.items() if SECTION_RULES[specs[f].section].storage is Storage.CLASS}
    if statics:
        ns: dict[str, Any] = {"__module__": cls.__module__, "__annotations__": statics}
        for field in statics:
            spec = specs[field]
            ns[field] = FieldSpec(
                Section.VAR, spec.initial, length=spec.length, bounds=spec.bounds, constant=spec.constant, st_name=spec.st_name
            )

        def create(n: dict[str, Any]) -> type:
            meta: Any = type(ctypes.Structure)
            return typing.cast(type, meta(f"{name}.VAR_STAT", (ctypes.Structure,), n))

        block_cls: Any = build_layout(create, name, (), ns, kind="VAR_STAT", allowed_sections=(Section.VAR,), annotations=statics)
        block_cls._iec_children_ = tuple(fb_children(block_cls._iec_layout_))
        block_cls._iec_call_after_init_ = ()
        block_cls._iec_implicit_init_ = block_cls._iec_layout_.implicit_init
        block = block_cls()
        initialise(block, init_retains=True, in_copy_code=False)
        cls._iec_static_block_ = block
        _static_blocks[cls] = block
        for record in block_cls._iec_layout_.fields:
            descriptor = getattr(block_cls, record.name)
            raw = descriptor if record.info.direct else _BlockField(descriptor)
            validate = record.info.validate if _config.CHECKS else None
            setattr(cls, record.name, _Static(raw, block, record.where, validate))
        static_fields = block_cls._iec_layout_.fields
    externals = [f for f in outside if SECTION_RULES[specs[f].section].storage is Storage.GLOBAL]
    for field in externals:
        block, record = find_global(field, f"{name}.{field}", cls.__module__)
        raw = getattr(type(block), field)
        raw = raw if record.info.direct else _BlockField(raw)
        validate = record.info.validate if _config.CHECKS else None
        setattr(cls, field, _Static(raw, block, f"{name}.{specs[field].st_name or field}", validate))
    return static_fields


class _BlockField:
    """Adapts a Python descriptor to the raw-field interface used by _Static."""

    __slots__ = ("descriptor",)

    def __init__(self, descriptor: Any) -> None:
        self.descriptor = descriptor

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        return self.descriptor.__get__(obj, type(obj))

    def __set__(self, obj: Any, value: Any) -> None:
        self.descriptor.__set__(obj, value)


def _temp_reset(temps: list[FieldRecord]) -> Callable[[Any], None]:
    spans = [(r.offset, r.size) for r in temps]
    ops = [op for r in temps if (op := init_op(r)) is not None]
    memset = ctypes.memset
    addressof = ctypes.addressof

    def reset(obj: Any) -> None:
        base = addressof(obj)
        for offset, size in spans:
            memset(base + offset, 0, size)
        for op in ops:
            op(obj)

    return reset


# ---------------------------------------------------------------------------
# The generated call: fb(IN=..., PT=...)
# ---------------------------------------------------------------------------

#: An input not given: the call's default. Ellipsis, no IEC value, is a constant the compiled call loads
#: itself, where a sentinel object of its own would be a closure cell every call copies and reads.
_NOT_GIVEN: Any = ...
#: The same in the generated call's text.
_M = "..."


def _make_call(cls: Any, layout: ClassLayout, positional: bool = False) -> Callable[..., None]:
    """Generate ``__call__`` with one keyword per input, as attrs generates ``__init__``.

    ``positional``: the same call taking every input and in-out by position,
    in declaration order, ``...`` for one not given (see ``_positional_call``).
    """
    inputs = [r for r in layout.fields if SECTION_RULES[r.section].at_call is AtCall.SET_IF_GIVEN]
    in_outs = [r for r in layout.fields if SECTION_RULES[r.section].at_call is AtCall.BOUND]
    name = cls.__name__
    globs: dict[str, Any] = {"_call_error": _call_error}
    params: list[str] = []
    lines: list[str] = []
    # The variables a read of `self.x` takes from the ctypes field itself, with no code run.
    plain = raw_elementary(cls, layout)
    raw = {r.name for r in plain}
    for i, record in enumerate(inputs):
        params.append(f"{record.name}={_M}")
        info = record.info
        if isinstance(info, ReferenceInfo):
            globs[f"_bind{i}"] = info.bind_handle
            globs[f"_raw{i}"] = record.raw.__set__
            lines.append(f"    if {record.name} is not {_M}: _raw{i}(self, _bind{i}({record.name}, {record.where!r}))")
        elif isinstance(info, (ArrayInfo, AggregateInfo)):
            # an ARRAY / STRUCT input also takes a list / dict (fb(points := [1, 2, 3]))
            globs[f"_store{i}"] = info.store
            lines.append(f"    if {record.name} is not {_M}: _store{i}(self, {record.offset}, {record.name}, {record.where!r})")
        elif info.direct:
            accepted = globs[f"_type{i}"] = accepted_type(info)
            # A value equal to the one its field holds stores nothing new (see _changed); only a field
            # read with no code run is compared.
            compared = accepted is not None and record.name in raw
            if not _config.CHECKS:
                # fast mode: a plain attribute store reaches the ctypes field in C
                test = f" and ({_changed(record.name, accepted, f'_type{i}')})" if compared else ""
                lines.append(f"    if {record.name} is not {_M}{test}: self.{record.name} = {record.name}")
                continue
            globs[f"_check{i}"] = info.validate
            globs[f"_set{i}"] = record.raw.__set__
            lines.append(f"    if {record.name} is not {_M}:")
            lines.append(f"        if {record.name}.__class__ is not _type{i}:")
            lines.append(f"            _check{i}({record.name}, {record.where!r})")
            if compared:
                lines.append(f"            _set{i}(self, {record.name})")
                lines.append(f"        elif {_changed(record.name, accepted)}: _set{i}(self, {record.name})")
            else:
                lines.append(f"        _set{i}(self, {record.name})")
        else:
            globs[f"_desc{i}"] = getattr(cls, record.name).__set__
            lines.append(f"    if {record.name} is not {_M}: _desc{i}(self, {record.name})")
    for j, record in enumerate(in_outs):
        params.append(f"{record.name}={_M}")
        reference = typing.cast(ReferenceInfo, record.info)
        globs[f"_rawio{j}"] = record.raw.__set__
        lines.append(f"    if {record.name} is {_M}: _call_error({name!r}, {record.name!r})")
        if record.spec.constant:
            globs[f"_bindio{j}"] = reference.bind_constant
            lines.append(f"    _rawio{j}(self, _bindio{j}(self, {record.name}, {record.where!r}))")
        else:
            globs[f"_bindio{j}"] = reference.bind_handle
            lines.append(f"    _rawio{j}(self, _bindio{j}({record.name}, {record.where!r}))")
    if cls._iec_temp_reset_ is not None:
        globs["_temp_reset"] = cls._iec_temp_reset_
        lines.append("    _temp_reset(self)")
    body = next((k.__dict__["body"] for k in cls.__mro__ if "body" in k.__dict__), None)
    if isinstance(body, types.FunctionType):
        # One frame per call: the body's statements compiled after the input lines, when provably the same code.
        given = dict.fromkeys((r.name for r in (*inputs, *in_outs)), _NOT_GIVEN)
        # Checked mode: the body's own `self.x = value` takes the checked __setattr__'s path for x written out
        # in place (the class check, the validator only for another class, the store): the same work, no call.
        rules = write_rules(cls, layout) if _config.CHECKS else {}
        stores: dict[str, FastWrite] = fast_writes(layout, rules) if _config.CHECKS else {}
        # A value the code alone shows to be of the variable's class skips the class check it would pass.
        known = known_reads(cls, layout) if _config.CHECKS else {}
        # A block member's read `self.timer` is its property's getter, attrgetter(alias), which keeps the view;
        # the call reads the same view under a key with no class attribute (see VIEW_PREFIX).
        # A member declared as one block is a view of exactly that class (its memory holds that type).
        members = {
            r.name: (sys.intern(VIEW_PREFIX + r.name), r.info.cls if isinstance(r.info, AggregateInfo) else None)
            for r in layout.fields if isinstance(getattr(cls, r.name, None), _MemberProperty)
        }
        # Checked mode: the body's own read of its STRUCT / ARRAY variable is one its rule always allows
        # (neither CONSTANT nor a METHOD's VAR_INST), so it needs no look at the reading frame.
        # The call reads such a view under a key as a member's (keep_member_views fills it with own_read).
        own_views = {
            r.name: (sys.intern(VIEW_PREFIX + r.name), field.own_read) for r in layout.fields
            if isinstance(field := getattr(cls, r.name, None), CheckedMemberField)
            and not rules[r.name].constant and rules[r.name].method is None
        }
        cls._iec_own_views_ = tuple(own_views.values())
        views = {name: key for name, (key, _read) in own_views.items()}
        # A one-dimensional ARRAY OF a block: the body's own `self.stations[i]` reads the kept element in place.
        arrays = {
            r.name: (r.info.elem.cls, *r.info.bounds[0]) for r in layout.fields
            if isinstance(r.info, ArrayInfo) and len(r.info.bounds) == 1 and isinstance(r.info.elem, AggregateInfo)
            and getattr(r.info.elem.cls, "_iec_tagged_", False)
        }
        bools = {r.name for r in plain if accepted_type(r.info) is bool} & {r.name for r in inputs}
        inlined = inline_call(
            name, body, params, lines, globs, given, cls, stores, members, positional=positional,
            direct=_positional_call, views=views, known=known, arrays=arrays,
            plain=raw, counters=counter_ranges(plain), bools=bools,
            loops=None if _config.CHECKS else loop_types(plain),
        )
        if inlined is not None:
            inlined.__doc__ = f"Call {name}: set the named inputs, bind the in-outs, run body()."
            return inlined
        # The class's body as found now: this call is this class's own (a subclass generates its own).
        globs["_body"] = body
        lines.append("    _body(self)")
    else:
        lines.append("    self.body()")
    if positional:
        signature = ", ".join(["self", *(p.removesuffix(f"={_M}") for p in params)])
    else:
        signature = ", ".join(["self", "*", *params]) if params else "self"
    source = f"def __call__({signature}) -> None:\n" + "\n".join(lines) + "\n"
    compile_source(source, f"{name}.__call__", globs)
    call = typing.cast(Callable[..., None], globs["__call__"])
    call.__qualname__ = f"{name}.__call__"
    call.__doc__ = f"Call {name}: set the named inputs, bind the in-outs, run body()."
    own_code(call.__code__, cls)
    return call


def _changed(name: str, accepted: type | None, unchecked: str | None = None) -> str:
    """The test that a given input differs from the value its field holds, for a value of class ``accepted``;
    ``unchecked``: the name of that class, when the value's class is not known yet (fast mode).

    An input a scan passes again and again (``fb(enable := bSensor)``) mostly
    holds it already, and a read of the field costs less than a store. The test
    is exact: a BOOL field holds ``True`` or ``False``, so identity decides
    whatever the value; an integer equal to the held one stores that same
    value; a REAL equal to the held one is the same number except for a zero's
    sign, so zero is always stored. A value of another class is always stored.
    """
    if accepted is bool:
        return f"{name} is not self.{name}"
    test = f"{name} != self.{name} or not {name}" if accepted is float else f"{name} != self.{name}"
    return test if unchecked is None else f"{name}.__class__ is not {unchecked} or {test}"


def _positional_call(cls: Any) -> tuple[types.CellType, tuple[str, ...]]:
    """The cell a holder's compiled call calls ``cls`` through with the inputs by position, and their order.

    ``self.timer(IN=x, PT=t)`` passes its keywords as names the callee matches
    one by one (CPython 3.13 does not specialise such a call); with the inputs
    by position, ``...`` for one not given, the callee starts from its
    arguments as they come. The positional call is built at the first holder
    that needs it; the cell holds it while ``cls.__call__`` is the built call,
    and a function making Python's ordinary call with the given inputs by
    name once it is not (``_follow_call``).
    """
    entry = cls.__dict__.get("_iec_positional_")
    if entry is None:
        layout = cls._iec_layout_
        # _make_call lists the inputs, then the in-outs, each in declaration order.
        order = (
            *(r.name for r in layout.fields if SECTION_RULES[r.section].at_call is AtCall.SET_IF_GIVEN),
            *(r.name for r in layout.fields if SECTION_RULES[r.section].at_call is AtCall.BOUND),
        )
        call = _make_call(cls, layout, positional=True)
        fallback = _by_name(order)
        built = cls.__dict__.get("__call__") is cls.__dict__["_iec_built_call_"]
        entry = (types.CellType(call if built else fallback), order, call, fallback)
        cls._iec_positional_ = entry
    return entry[0], entry[1]


def _by_name(order: tuple[str, ...]) -> Callable[..., None]:
    def call_by_name(view: Any, /, *values: Any) -> None:
        """A positional member call once its class's ``__call__`` is rebound: Python's call, given inputs by name."""
        view(**{name: value for name, value in zip(order, values) if value is not _NOT_GIVEN})

    return call_by_name


def _call_error(name: str, field: str) -> None:
    raise TypeError(f"{name}: VAR_IN_OUT {field!r} must be assigned at every call ({name}({field}=...))")


# ---------------------------------------------------------------------------
# The base classes
# ---------------------------------------------------------------------------


class _PouMixin:
    """What FunctionBlock and Program share: construction, body, comparison."""

    _iec_layout_: ClassVar[ClassLayout | None] = None
    __iec__: ClassVar[IecClass]
    #: The code this class's body defined, and with its bases' (see members.own_code).
    _iec_own_codes_: ClassVar[frozenset[types.CodeType] | set[types.CodeType]] = frozenset()
    _iec_codes_: ClassVar[frozenset[types.CodeType] | set[types.CodeType]] = frozenset()
    #: (alias, key) of each block member: where keep_member_views puts the view the compiled call reads.
    _iec_view_keys_: ClassVar[tuple[tuple[str, str], ...]] = ()
    #: Instances start with a type tag, so a pointer, reference or interface to a
    #: base block dereferences to the derived block it designates (virtual calls).
    _iec_tagged_: ClassVar[bool] = True

    def __init__(self, **fb_init_args: Any) -> None:
        cls = type(self)
        if cls._iec_layout_ is None:
            raise DefinitionError(f"{cls.__name__} is a base class; declare a subclass")
        record = cls.__iec__
        if record.abstract:
            raise DefinitionError(
                f"ABSTRACT {_kind_word(cls)} {cls.__name__} cannot be instantiated; instantiate a derived block"
            )
        if record.internal:
            frame = sys._getframe(1)
            here = _package(str(frame.f_globals.get("__name__", "")))
            if here != _package(cls.__module__):
                raise AccessError(
                    f"INTERNAL {_kind_word(cls)} {cls.__name__} cannot be instantiated from {caller_description(frame)} "
                    f"(outside the package {_package(cls.__module__)!r})"
                )
        if fb_init_args:
            # Kept for the runtime: a reset re-runs FB_init with the declaration's inputs.
            self.__dict__["_iec_init_args_"] = dict(fb_init_args)
        initialise(self, init_retains=True, in_copy_code=False, args=fb_init_args)

    def body(self) -> None:
        """The implementation part, run by every call (ST: the FB's code body)."""

    if TYPE_CHECKING:

        def __call__(self, **inputs: Any) -> None: ...

    #: A copy (copy.copy) takes the memory, not the views of members kept for the original.
    __setstate__ = set_state_without_views

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, _PouMixin):
            return NotImplemented
        return ctypes.addressof(typing.cast(Any, self)) == ctypes.addressof(typing.cast(Any, other))

    def __hash__(self) -> int:
        return hash(ctypes.addressof(typing.cast(Any, self)))

    def __repr__(self) -> str:
        layout = type(self)._iec_layout_
        shown = []
        if layout is not None:
            for record in layout.fields:
                if record.section in (Section.VAR_INPUT, Section.VAR_OUTPUT):
                    try:
                        shown.append(f"{record.name}={getattr(self, record.name)!r}")
                    except Exception as exc:  # a dangling reference must not break repr
                        shown.append(f"{record.name}=<{type(exc).__name__}>")
        return f"<{type(self).__name__} {' '.join(shown)}>".replace(" >", ">")


class FunctionBlock(_PouMixin, _PouBase, metaclass=_PouMeta):
    """``FUNCTION_BLOCK``: subclass it; class keywords ``abstract``, ``final``, ``internal``."""

    _iec_base_class_: ClassVar[bool] = True
    __iec__ = IecClass(Kind.FUNCTION_BLOCK, root=True)
    if not TYPE_CHECKING:
        _fields_ = [("_iec_tag_", ctypes.c_uint64)]


class Program(_PouMixin, _PouBase, metaclass=_PouMeta):
    """``PROGRAM``: like a function block, one instance per task entry."""

    _iec_base_class_: ClassVar[bool] = True
    __iec__ = IecClass(Kind.PROGRAM, root=True)
    if not TYPE_CHECKING:
        _fields_ = [("_iec_tag_", ctypes.c_uint64)]


def pou_members(cls: type) -> dict[str, Member]:
    """Every METHOD and PROPERTY of a block, inherited ones included."""
    record = iec_class(cls)
    return dict(record.members) if record is not None else {}
