"""The VAR sections and their rules, as one table.

Every rule that depends only on a variable's section is a column of
``SECTION_RULES``: who may write the variable, where it is stored, what a
call does with it, which qualifiers it takes and which kinds of class may
declare it. The class builder, the checked-mode write rules, the generated
call, the diagrams and the OPC UA server read this table, and the VAR-sections
page of the documentation is generated from it.

ST::

    FUNCTION_BLOCK FB_Axis
    VAR_INPUT  speed : REAL; END_VAR     (* written by the caller *)
    VAR_OUTPUT done  : BOOL; END_VAR     (* written by FB_Axis only *)

>>> from iecoop.sections import SECTION_RULES, Kind, Section, Writer
>>> SECTION_RULES[Section.VAR_OUTPUT].written_by is Writer.OWN_CODE
True
>>> [str(s) for s in Section if Kind.STRUCT in SECTION_RULES[s].kinds]
['VAR']
"""

from __future__ import annotations

import dataclasses
import enum
import re
from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any, Final

from iecoop.exceptions import DefinitionError

__all__ = [
    "MISSING",
    "AtCall",
    "FieldSpec",
    "Kind",
    "Qualifier",
    "SECTION_RULES",
    "SECTIONS",
    "Section",
    "SectionRule",
    "Storage",
    "Writer",
    "check_st_name",
    "sections_of",
]


class Section(enum.StrEnum):
    """A VAR section keyword. Each member equals its ST keyword as a string (``Section.VAR == "VAR"``)."""

    VAR_INPUT = "VAR_INPUT"
    VAR_OUTPUT = "VAR_OUTPUT"
    VAR_IN_OUT = "VAR_IN_OUT"
    VAR = "VAR"
    VAR_STAT = "VAR_STAT"
    VAR_TEMP = "VAR_TEMP"
    VAR_INST = "VAR_INST"
    VAR_EXTERNAL = "VAR_EXTERNAL"
    VAR_GLOBAL = "VAR_GLOBAL"


class Qualifier(enum.StrEnum):
    """A section qualifier (``VAR RETAIN``): a keyword argument of the specifier (``VAR(0, retain=True)``)."""

    CONSTANT = "CONSTANT"
    RETAIN = "RETAIN"
    PERSISTENT = "PERSISTENT"

    @property
    def keyword(self) -> str:
        """The specifier's keyword argument: ``retain``."""
        return self.value.lower()


class Kind(enum.StrEnum):
    """The kind of a declared class; the value is the short name the library uses (``Kind.PROGRAM == "program"``)."""

    FUNCTION_BLOCK = "fb"
    PROGRAM = "program"
    STRUCT = "struct"
    UNION = "union"
    GVL = "gvl"
    INTERFACE = "interface"
    ENUM = "enum"

    @property
    def keyword(self) -> str:
        """The ST keyword that declares it (``FUNCTION_BLOCK``); a global variable list is a ``GVL``."""
        return _KEYWORDS[self]

    @property
    def is_pou(self) -> bool:
        """A FUNCTION_BLOCK or a PROGRAM: a class with a body, methods and a generated call."""
        return self in (Kind.FUNCTION_BLOCK, Kind.PROGRAM)


_KEYWORDS: Final = {
    Kind.FUNCTION_BLOCK: "FUNCTION_BLOCK",
    Kind.PROGRAM: "PROGRAM",
    Kind.STRUCT: "STRUCT",
    Kind.UNION: "UNION",
    Kind.GVL: "GVL",
    Kind.INTERFACE: "INTERFACE",
    Kind.ENUM: "TYPE (enum)",
}


class Writer(enum.Enum):
    """Whose code may write a variable of the section (checked mode)."""

    ANYONE = "any code"
    OWN_CODE = "the block's own code"
    OWN_METHOD = "its METHOD only"


class Storage(enum.Enum):
    """Where a variable of the section lives."""

    INSTANCE = "in the instance"
    CALLER = "the caller's variable, bound by reference"
    CLASS = "once per class"
    GLOBAL = "in a global variable list"


class AtCall(enum.Enum):
    """What a call of the block (``fb(...)``) does with a variable of the section."""

    KEPT = "keeps its value"
    SET_IF_GIVEN = "set if given: fb(x=...)"
    BOUND = "bound at every call: fb(x=...)"
    REINITIALISED = "re-initialised"


@dataclasses.dataclass(frozen=True)
class SectionRule:
    """Everything decided by one section: a row of ``SECTION_RULES``."""

    section: Section
    #: Part of the block's interface, the caller's view of it: inputs, outputs and in-outs.
    interface: bool
    written_by: Writer
    storage: Storage
    at_call: AtCall
    qualifiers: frozenset[Qualifier]
    kinds: frozenset[Kind]

    @property
    def inside_only(self) -> bool:
        """Checked mode refuses a write from code that is not the block's own."""
        return self.written_by is not Writer.ANYONE

    @property
    def in_instance(self) -> bool:
        """Stored in the instance's memory block (VAR_STAT and the globals are not)."""
        return self.storage in (Storage.INSTANCE, Storage.CALLER)

    @property
    def remanent(self) -> bool:
        """May be RETAIN or PERSISTENT."""
        return Qualifier.RETAIN in self.qualifiers

    @property
    def call_parameter(self) -> bool:
        """A keyword of the generated call (an input or an in-out)."""
        return self.at_call in (AtCall.SET_IF_GIVEN, AtCall.BOUND)


_POU: Final = frozenset({Kind.FUNCTION_BLOCK, Kind.PROGRAM})
_ALL: Final = frozenset(Qualifier)
_REMANENT: Final = frozenset({Qualifier.RETAIN, Qualifier.PERSISTENT})
_CONSTANT: Final = frozenset({Qualifier.CONSTANT})


def _rule(
    section: Section, interface: bool, written_by: Writer, storage: Storage, at_call: AtCall,
    qualifiers: frozenset[Qualifier], kinds: frozenset[Kind],
) -> tuple[Section, SectionRule]:
    return section, SectionRule(section, interface, written_by, storage, at_call, qualifiers, kinds)


#: The rule table: one row per section, in the order ST declares them.
SECTION_RULES: Final[Mapping[Section, SectionRule]] = MappingProxyType(dict([
    _rule(Section.VAR_INPUT, True, Writer.ANYONE, Storage.INSTANCE, AtCall.SET_IF_GIVEN, _REMANENT, _POU),
    _rule(Section.VAR_OUTPUT, True, Writer.OWN_CODE, Storage.INSTANCE, AtCall.KEPT, _REMANENT, _POU),
    _rule(Section.VAR_IN_OUT, True, Writer.OWN_CODE, Storage.CALLER, AtCall.BOUND, _CONSTANT, _POU),
    _rule(
        Section.VAR, False, Writer.OWN_CODE, Storage.INSTANCE, AtCall.KEPT, _ALL,
        _POU | {Kind.STRUCT, Kind.UNION, Kind.GVL},  # a STRUCT member; in a GVL, a VAR_GLOBAL
    ),
    _rule(Section.VAR_STAT, False, Writer.OWN_CODE, Storage.CLASS, AtCall.KEPT, _CONSTANT, _POU),
    _rule(Section.VAR_TEMP, False, Writer.OWN_CODE, Storage.INSTANCE, AtCall.REINITIALISED, frozenset(), _POU),
    _rule(Section.VAR_INST, False, Writer.OWN_METHOD, Storage.INSTANCE, AtCall.KEPT, frozenset(), _POU),
    _rule(Section.VAR_EXTERNAL, False, Writer.ANYONE, Storage.GLOBAL, AtCall.KEPT, _CONSTANT, _POU),
    _rule(Section.VAR_GLOBAL, False, Writer.ANYONE, Storage.GLOBAL, AtCall.KEPT, _ALL, frozenset({Kind.GVL})),
]))

#: The VAR sections, in the order ST declares them.
SECTIONS: Final = tuple(SECTION_RULES)


def sections_of(kind: Kind) -> tuple[Section, ...]:
    """The sections a class of ``kind`` may declare, in ST order."""
    return tuple(s for s, rule in SECTION_RULES.items() if kind in rule.kinds)


_ST_IDENTIFIER: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def check_st_name(st_name: object, where: str) -> str:
    """``st_name`` if it is an ST identifier (letters, digits and ``_``, not starting with a digit).

    ``where`` (``FUNCTION_BLOCK FB_Valve.in_``) names the declaration in the
    ``DefinitionError`` that refuses anything else.
    """
    if not isinstance(st_name, str) or _ST_IDENTIFIER.fullmatch(st_name) is None:
        raise DefinitionError(
            f"{where}: st_name={st_name!r} is not an ST identifier (a letter or _, then letters, digits and _)"
        )
    return st_name


# A field's declaration lives beside the sections it names: every module that reads one
# (the builders, the write rules, the member checks) imports it from here without a cycle.
class _Missing:
    def __repr__(self) -> str:
        return "MISSING"

    def __bool__(self) -> bool:
        return False


MISSING: Final[Any] = _Missing()



class FieldSpec:
    """A field's declaration: section, initial value and qualifiers (what ``VAR(...)`` returns)."""

    __slots__ = (
        "section", "initial", "length", "bounds", "retain", "persistent", "constant", "method", "fb_init", "st_name",
        "instance_path",
    )

    def __init__(
        self,
        section: str,
        initial: Any = MISSING,
        *,
        length: int | None = None,
        bounds: object = None,
        retain: bool = False,
        persistent: bool = False,
        constant: bool = False,
        method: str | None = None,
        fb_init: Mapping[str, Any] | Sequence[Mapping[str, Any]] | None = None,
        st_name: str | None = None,
        instance_path: bool = False,
    ) -> None:
        self.section = Section(section)
        self.initial = initial
        self.length = length
        self.bounds = bounds
        self.retain = retain
        self.persistent = persistent
        self.constant = constant
        self.method = method
        #: The variable's ST name when Python could not spell it (``in`` for the field ``in_``); checked by the builder.
        self.st_name = st_name
        #: ``{attribute 'instance-path'}``: the STRING holds the instance's path, set when the instance is initialised.
        self.instance_path = instance_path
        # One dict of FB_init inputs, or one per element of an ARRAY OF FB.
        self.fb_init: dict[str, Any] | list[dict[str, Any]] | None
        if not fb_init:
            self.fb_init = None
        elif isinstance(fb_init, Mapping):
            self.fb_init = dict(fb_init)
        else:
            self.fb_init = [dict(item) for item in fb_init]

    @property
    def qualifiers(self) -> str:
        words = [w for w, on in (("CONSTANT", self.constant), ("RETAIN", self.retain), ("PERSISTENT", self.persistent)) if on]
        return " ".join(words)

    def __repr__(self) -> str:
        init = "" if self.initial is MISSING else repr(self.initial)
        qual = f" {self.qualifiers}" if self.qualifiers else ""
        return f"{self.section}{qual}({init})"

    def as_python(self) -> str:
        """The specifier call as the user writes it: ``VAR(10, constant=True)``."""
        args = [] if self.initial is MISSING else [repr(self.initial)]
        for option in ("length", "bounds", "retain", "persistent", "constant", "method", "fb_init", "st_name", "instance_path"):
            value = getattr(self, option)
            if value:
                args.append(f"{option}={value!r}")
        return f"{self.section}({', '.join(args)})"
