"""The symbol table's records: types (``TypeRef``), variables (``Member``), METHODs (``Callable_``) and declarations (``Decl``).

Pass 1 (``symbols``) fills them; ``freeze`` then makes them read-only, so pass 2 reads the table and never
changes it (a write raises ``FrozenTableError``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from typing import Any, NoReturn, TypeVar

from iecoop.st.language import INTEGER_LAYOUT, REAL_TYPES
from iecoop.st.read.parse import Unit

# --- the table, frozen after pass 1 ---------------------------------------------------------------

_K = TypeVar("_K")
_V = TypeVar("_V")
_T = TypeVar("_T")


class FrozenTableError(TypeError):
    """A phase after pass 1 tried to change the symbol table: pass 1 must collect what that phase needs."""


def _refuse(what: object) -> NoReturn:
    raise FrozenTableError(f"the symbol table is read-only after pass 1: {what} cannot be changed; "
                           "collect it in pass 1 (iecoop.st.read.symbols)")


class _ReadOnly:
    """What the frozen containers share: each writing method refuses."""

    def _refuse_call(self, *args: Any, **kwargs: Any) -> NoReturn:
        _refuse(f"the {type(self).__name__.removeprefix('Frozen').lower()}")


class FrozenDict(_ReadOnly, dict[_K, _V]):
    """A mapping of the frozen table: read as any dict, and a write raises ``FrozenTableError``."""

    def __setitem__(self, key: Any, value: Any) -> NoReturn:
        _refuse(f"the entry {key!r}")

    def __delitem__(self, key: Any) -> NoReturn:
        _refuse(f"the entry {key!r}")

    def __ior__(self, other: Any) -> NoReturn:  # type: ignore[misc]  # never returns: refused
        _refuse("the dict")

    update = setdefault = pop = popitem = clear = _ReadOnly._refuse_call


class FrozenSet(_ReadOnly, set[_T]):
    """A set of the frozen table: read as any set, and a write raises ``FrozenTableError``."""

    add = discard = remove = pop = clear = update = _ReadOnly._refuse_call
    __ior__ = __iand__ = __isub__ = __ixor__ = _ReadOnly._refuse_call
    difference_update = intersection_update = symmetric_difference_update = _ReadOnly._refuse_call


class FrozenList(_ReadOnly, list[_T]):
    """A list of the frozen table: read as any list, and a write raises ``FrozenTableError``."""

    __setitem__ = __delitem__ = __iadd__ = __imul__ = _ReadOnly._refuse_call
    append = extend = insert = remove = pop = clear = sort = reverse = _ReadOnly._refuse_call


# --- types --------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class TypeRef:
    """A resolved ST type: elementary, STRING(n), ARRAY, POINTER TO, REFERENCE TO or a user type."""

    kind: str  # elem | string | array | pointer | reference | user | interface_null
    name: str
    of: TypeRef | None = None
    length: str | None = None
    bounds: list[tuple[str, str]] | None = None
    #: the ST names (lower case) an ARRAY's bounds read: ``ARRAY[1..GVL_Param.cMax]`` reads ``gvl_param``
    bound_names: frozenset[str] = dataclasses.field(default=frozenset(), compare=False)
    #: a subrange ``INT(0..100)``: its lower and upper limits (Python text)
    limits: tuple[str, str] | None = None
    #: an ``ARRAY[*, *]`` (``bounds`` None): how many dimensions it leaves open
    open_dims: int = 0

    def annotation(self) -> str:
        if self.kind == "array":
            assert self.of is not None
            return f"ARRAY[{self.of.annotation()}]"
        if self.kind == "pointer":
            assert self.of is not None
            return f"POINTER_TO[{self.of.annotation()}]"
        if self.kind == "reference":
            assert self.of is not None
            return f"REFERENCE_TO[{self.of.annotation()}]"
        return self.name

    @property
    def is_int(self) -> bool:
        return self.kind == "elem" and self.name in INTEGER_LAYOUT

    @property
    def is_real(self) -> bool:
        return self.kind == "elem" and self.name in REAL_TYPES

    @property
    def is_bool(self) -> bool:
        return self.kind == "elem" and self.name == "BOOL"

    @property
    def is_string(self) -> bool:
        return self.kind == "string"

    def deref(self) -> TypeRef:
        return self.of if self.kind == "reference" and self.of is not None else self


BOOL = TypeRef("elem", "BOOL")
LINT = TypeRef("elem", "LINT")
LREAL = TypeRef("elem", "LREAL")
STRING = TypeRef("string", "STRING", length="80")


@dataclasses.dataclass(frozen=True)
class Member:
    """A variable: ``name`` is its Python code (``python_name`` of the ST name, or how it is reached), ``st`` its ST name."""

    name: str
    type: TypeRef | None
    section: str
    st: str = ""
    #: ``(holder code, field name)`` when ``name`` is the field of something (a local kept in ``_var``, a VAR_STAT)
    place: tuple[str, str] | None = dataclasses.field(default=None, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "st", self.st or self.name)

    @classmethod
    def field_of(cls, holder: str, field: str, type_: TypeRef | None, section: str, st: str = "") -> Member:
        """A variable reached as ``holder.field``."""
        return cls(f"{holder}.{field}", type_, section, st=st, place=(holder, field))


class ReferenceLocal(Member):
    """An elementary ``REFERENCE TO`` local of a METHOD or FUNCTION: a pointer, read and written as an in-out."""


@dataclasses.dataclass(frozen=True)
class Callable_:
    name: str
    returns: TypeRef | None
    params: list[Member]
    st: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "st", self.st or self.name)


@dataclasses.dataclass
class Decl:
    """Everything the second pass needs to know about one declared name."""

    kind: str  # fb program function interface struct union enum alias gvl stdfb
    #: the Python name (``python_name`` of the ST name); ``st`` is the ST name
    name: str
    node: Any = None
    unit: Unit | None = None
    bases: list[str] = dataclasses.field(default_factory=list)
    members: dict[str, Member] = dataclasses.field(default_factory=dict)
    methods: dict[str, Callable_] = dataclasses.field(default_factory=dict)
    props: dict[str, Member] = dataclasses.field(default_factory=dict)
    method_nodes: list[Any] = dataclasses.field(default_factory=list)
    action_nodes: list[Any] = dataclasses.field(default_factory=list)
    prop_nodes: list[Any] = dataclasses.field(default_factory=list)
    values: list[str] = dataclasses.field(default_factory=list)
    alias_of: TypeRef | None = None
    implements: list[str] = dataclasses.field(default_factory=list)
    #: the top-level item of the source it comes from (its lines hold its comments)
    item: Any = None
    #: for a GVL gathered from several sources: the unit of each VAR_GLOBAL block
    units: dict[int, Unit] = dataclasses.field(default_factory=dict)
    st: str = ""
    #: ST name (lower case) -> where it is declared ("file:line"), for the duplicate check
    declared: dict[str, tuple[str, str]] = dataclasses.field(default_factory=dict)
    #: (METHOD's Python name, ST name), lower case -> the field of a VAR_INST whose name another METHOD declares too
    method_inst: dict[tuple[str, str], Member] = dataclasses.field(default_factory=dict)
    #: a bound library's declaration: the module the generated code imports it from, and the import
    #: (``TON``, or ``FB_Log as TCU_FB_Log`` when the name is taken); never emitted
    library: str = ""
    import_spec: str = ""
    #: set by ``freeze`` at the end of pass 1: from then on every field and mapping is read-only
    frozen: bool = dataclasses.field(default=False, compare=False, repr=False)

    def __post_init__(self) -> None:
        self.st = self.st or self.name

    def __setattr__(self, name: str, value: Any) -> None:
        if getattr(self, "frozen", False):
            _refuse(f"{self.kind} {self.st}.{name}")
        super().__setattr__(name, value)

    def freeze(self) -> None:
        """Make the declaration read-only: pass 1 is done with it."""
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if isinstance(value, dict) and not isinstance(value, FrozenDict):
                super().__setattr__(field.name, FrozenDict(value))
            elif isinstance(value, list) and not isinstance(value, FrozenList):
                super().__setattr__(field.name, FrozenList(value))
        super().__setattr__("frozen", True)


#: ``__SYSTEM.IQueryInterface``, the interface TwinCAT and CODESYS give ``__QUERYINTERFACE``: iecoop's
#: IQueryInterface, a type wherever a type may stand (its Python name is the key)
IQUERYINTERFACE = Decl("interface", "IQueryInterface")
IQUERYINTERFACE.freeze()
SYSTEM_DECLS: dict[str, Decl] = FrozenDict({IQUERYINTERFACE.name.lower(): IQUERYINTERFACE})


#: The generic type families a FUNCTION's or METHOD's VAR_INPUT may have (IEC 61131-3; iecoop.generics).
GENERIC_FAMILIES = ("ANY", "ANY_ELEMENTARY", "ANY_NUM", "ANY_INT", "ANY_REAL", "ANY_BIT", "ANY_STRING", "ANY_DATE")
#: ``__SYSTEM.AnyType``, what a generic input is in the body: its members, as ``x.TypeClass`` reads them.
ANYTYPE = Decl("struct", "AnyType", members={
    "typeclass": Member("TypeClass", TypeRef("elem", "DINT"), "VAR", st="TypeClass"),
    "pvalue": Member("pValue", TypeRef("pointer", "POINTER_TO", of=TypeRef("elem", "BYTE")), "VAR", st="pValue"),
    "disize": Member("diSize", TypeRef("elem", "DINT"), "VAR", st="diSize"),
})


def own_method_fields(found: list[tuple[str, Member]], taken: Iterable[str] = ()) -> list[tuple[str, Member, Member]]:
    """(METHOD, VAR_INST, its field) for each METHOD's VAR_INST: the variable itself, or, for a name two METHODs
    declare or the block's own variables (``taken``, lower case) hold, a field named after its METHOD
    (``Up_nCount``): TwinCAT keeps each METHOD's VAR_INST apart, as TcUnit suites' test methods keep their
    blocks under test, and the METHOD's own name hides the block's variable in its code."""
    methods_of: dict[str, set[str]] = {}
    for method, member in found:
        methods_of.setdefault(member.st.lower(), set()).add(method.lower())
    clash = set(taken)
    return [(method, member, member if len(methods_of[member.st.lower()]) == 1 and member.st.lower() not in clash else
             dataclasses.replace(member, name=f"{method}_{member.name}", st=f"{method}_{member.st}")) for method, member in found]
