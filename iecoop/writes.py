"""Who may write a variable: the write rules of checked mode, all in one place.

A rule is decided once per field, when the class is built, from its row of
the section table (``iecoop.sections``) and its qualifiers, and kept as a
``WriteRule``. The class builders install the ``__setattr__`` made here in
checked mode (the default); fast mode (``IECOOP_CHECKS=0``) installs none, and
a write is ctypes' C-level store.

- A FUNCTION_BLOCK or PROGRAM (``pou_setattr``): a CONSTANT is never
  written; a section written only by the block's own code (an output, a
  local, a VAR_TEMP, a VAR_STAT, an in-out) refuses a write from any other
  code, and a VAR_INST is written by its METHOD only (CODESYS C0576). Which
  code is running is asked of the caller's frame (``iecoop.members``).
- A STRUCT, UNION or GVL (``data_setattr``): any code writes a member; a
  CONSTANT is never written.
- In both, the value must fit the type, and a name that is no variable is
  refused. A view of a STRUCT or ARRAY variable read by code that may not
  write the variable refuses writes through it too (``read_only_rule``).

ST::

    fbAxis.bDone := TRUE;   (* C0037: VAR_OUTPUT bDone is not an input of FB_Axis *)

>>> from iecoop import BOOL, FunctionBlock, VAR_OUTPUT
>>> from iecoop.metadata import field_record
>>> from iecoop.writes import write_rule
>>> class Axis(FunctionBlock):
...     done: BOOL = VAR_OUTPUT(False)
>>> rule = write_rule(field_record(Axis, "done"))
>>> rule.section, rule.inside_only, rule.constant
(<Section.VAR_OUTPUT: 'VAR_OUTPUT'>, True, False)
"""

from __future__ import annotations

import sys
import typing
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, NamedTuple

from iecoop.exceptions import AccessError
from iecoop.members import FORWARDING_CODES, caller_description, code_of
from iecoop.metadata import layout_of, st_name
from iecoop.memory._aggregates import AggregateInfo, ArrayInfo
from iecoop.memory._infos import ElementaryInfo, TypeInfo
from iecoop.memory._views import CheckedMemberField
from iecoop.sections import SECTION_RULES, Section

if TYPE_CHECKING:
    from iecoop.memory.layout import ClassLayout, FieldRecord

__all__ = [
    "FastWrite", "WriteRule", "accepted_type", "check_write", "counter_ranges", "data_setattr", "fast_writes", "known_reads",
    "pou_setattr", "raw_elementary",
    "read_only_rule", "write_rule", "write_rules",
]


class WriteRule(NamedTuple):
    """One field's write rule in a FUNCTION_BLOCK or PROGRAM, decided when the class is built."""

    #: The value check of an elementary or STRING variable (None: the field's descriptor checks, or none is needed).
    validate: Callable[[Any, str], None] | None
    #: ``Class.field``, for the messages.
    where: str
    section: Section
    #: The METHOD a VAR_INST belongs to.
    method: str | None
    constant: bool
    #: Written only by the block's own code (the section table's "written by").
    inside_only: bool

    @property
    def guarded(self) -> bool:
        """A write must ask who is writing (a CONSTANT, or a section written only from inside)."""
        return self.constant or self.inside_only


def _validator(record: FieldRecord) -> Callable[[Any, str], None] | None:
    info = record.info
    return info.validate if info.direct and not isinstance(info, (AggregateInfo, ArrayInfo)) else None


def write_rule(record: FieldRecord) -> WriteRule:
    """The rule for the variable ``record`` of a block's layout."""
    spec = record.spec
    inside_only = SECTION_RULES[spec.section].inside_only
    return WriteRule(_validator(record), record.where, spec.section, spec.method, spec.constant, inside_only)


def write_rules(cls: Any, layout: ClassLayout) -> dict[str, WriteRule]:
    """Every variable's rule of a block class (its layout and its VAR_STAT), by name."""
    rules = {record.name: write_rule(record) for record in layout.fields}
    inside_only = SECTION_RULES[Section.VAR_STAT].inside_only
    for record in cls.__iec__.static_fields:
        # A VAR_STAT is a VAR of its class's static block; the block's descriptor checks the value.
        where = record.where
        rules.setdefault(record.name, WriteRule(None, where, Section.VAR_STAT, None, record.spec.constant, inside_only))
    return rules


def _check_rule(holder: Any, rule: WriteRule, frame: Any) -> None:
    if rule.constant:
        raise AccessError(f"{rule.where} is CONSTANT and cannot be written")
    if rule.inside_only:
        section = rule.section
        if not code_of(frame.f_code, holder):
            raise AccessError(
                f"{section} {rule.where} cannot be written from {caller_description(frame)}: "
                f"only {st_name(type(holder))}'s own code writes its {section} variables"
            )
        if rule.method is not None and frame.f_code.co_name != rule.method:
            raise AccessError(f"VAR_INST {rule.where} belongs to METHOD {rule.method} (C0576)")


def check_write(holder: Any, field: str, frame: Any) -> None:
    """Checked mode's write rule: raise AccessError if the code running in ``frame`` may not write it.

    CONSTANT variables are never written; outputs, locals, in-outs, temps,
    statics and VAR_INST only by the block's own code (VAR_INST only by its
    method). Helpers that write on a caller's behalf (ExST ``S=`` / ``R=``)
    call this with the caller's frame.
    """
    rule = getattr(type(holder), "_iec_write_rules_", {}).get(field)
    if rule is not None:
        _check_rule(holder, rule, frame)


def read_only_rule(rule: WriteRule) -> Callable[[Any, Any], str | None] | None:
    """Who may write through a view of a STRUCT / ARRAY variable: the same code that may write the variable."""
    if not rule.guarded:
        return None

    def refusal(holder: Any, frame: Any) -> str | None:
        if frame.f_code in FORWARDING_CODES:
            frame = frame.f_back
        try:
            _check_rule(holder, rule, frame)
        except AccessError as exc:
            return str(exc)
        return None

    return refusal


def accepted_type(info: TypeInfo) -> type | None:
    """The one type a write of ``info`` accepts without calling its validator (None: always validate).

    Like attrs' per-field validators: an exact ``bool`` for BOOL, ``float`` for
    REAL / LREAL, ``int`` for the other elementary types passes at once; any
    other value goes to ``info.validate``, which accepts it or words the refusal.
    """
    if type(info) is not ElementaryInfo:
        return None
    kind = info.record.kind
    return bool if kind == "bool" else float if kind == "real" else int


#: Per field: (the value's accepted class, written from inside only, validator, "Class.field", store).
FastWrite = tuple[type | None, bool, Callable[[Any, str], None], str, Callable[[Any, Any], None]]


def fast_writes(layout: ClassLayout, rules: dict[str, WriteRule]) -> dict[str, FastWrite]:
    """Per field, as attrs generates validators: an elementary variable that is neither CONSTANT nor
    VAR_INST takes a value of its exact Python type without a validator call, and an inside-only
    one is written by the block's own code without the rule check. The rest takes the general path.

    The checked ``__setattr__`` reads this table, and so does a call whose body is compiled in
    (``iecoop._inline``): the body's own ``self.x = v`` does the same work in place.
    """
    fast: dict[str, FastWrite] = {}
    for record in layout.fields:
        rule = rules[record.name]
        if rule.validate is not None and not rule.constant and rule.method is None:
            fast[record.name] = (accepted_type(record.info), rule.inside_only, rule.validate, rule.where, record.raw.__set__)
    return fast


def known_reads(cls: Any, layout: ClassLayout) -> dict[str, type]:
    """Per variable read by a block's own code, ``"x"`` for ``self.x`` and ``"timer.Q"`` for a member's
    ``self.timer.Q``: the exact class the read gives (its ctypes field's value: ``bool``, ``int``, ``float``).

    A written-out store of a value of that class leaves out the class check it would pass.
    """
    known = _field_reads(cls, layout)
    for record in layout.fields:
        inner = record.info.cls if isinstance(record.info, AggregateInfo) else None
        inner_layout = layout_of(inner)
        if inner_layout is not None:  # a member's view is of exactly its declared class
            known.update({f"{record.name}.{name}": kind for name, kind in _field_reads(inner, inner_layout).items()})
    return known


def raw_elementary(cls: Any, layout: ClassLayout) -> list[FieldRecord]:
    """The elementary variables of a block that its ctypes fields read and write themselves (no code runs)."""
    found = []
    classes = [k.__dict__ for k in cls.__mro__]
    for record in layout.fields:
        if type(record.info) is not ElementaryInfo:
            continue
        name = record.name
        attribute = next((d[name] for d in classes if name in d), None)
        if attribute is record.raw:
            found.append(record)
    return found


def counter_ranges(records: list[FieldRecord]) -> dict[str, tuple[int, int]]:
    """Per integer variable of ``raw_elementary`` (SINT .. ULINT, BYTE .. LWORD), the values its type holds:
    the variables a FOR of the block's own code may count with."""
    found: dict[str, tuple[int, int]] = {}
    for record in records:
        info = typing.cast(ElementaryInfo, record.info)
        low, high = info.record.low, info.record.high
        if info.record.kind in ("signed", "unsigned") and isinstance(low, int) and isinstance(high, int):
            found[record.name] = (low, high)
    return found


def _field_reads(cls: Any, layout: ClassLayout) -> dict[str, type]:
    found: dict[str, type] = {}
    for record in raw_elementary(cls, layout):  # only a read the ctypes field answers itself
        kind = type(typing.cast(ElementaryInfo, record.info).ctype().value)
        if kind is accepted_type(record.info):
            found[record.name] = kind
    return found


def pou_setattr(cls: Any, layout: ClassLayout, aliases: Mapping[str, str] | None = None) -> Callable[[Any, str, Any], None]:
    """The checked ``__setattr__`` of a FUNCTION_BLOCK or PROGRAM; sets ``cls._iec_write_rules_``.

    A write by an ST name in ``aliases`` (ST name -> Python name) takes the general path with the variable's rule.
    """
    rules = cls._iec_write_rules_ = write_rules(cls, layout)
    rules.update({alias: rules[python] for alias, python in (aliases or {}).items()})
    for record in layout.own:
        field = cls.__dict__.get(record.name)
        if isinstance(field, CheckedMemberField):
            field.rule = read_only_rule(rules[record.name])
    getframe = sys._getframe
    setter = object.__setattr__
    fast = fast_writes(layout, rules)

    def __setattr__(self: Any, field: str, value: Any) -> None:
        spec = fast.get(field)
        if spec is not None:
            accepted, inside, check, where, store = spec
            if not inside or getframe(1).f_code in type(self)._iec_codes_:
                if value.__class__ is not accepted:
                    check(value, where)
                store(self, value)
                return
        rule = rules.get(field)
        if rule is None:
            if field.startswith("_iec") or not hasattr(type(self), field):
                raise AttributeError(f"{type(self).__name__} has no variable {field!r}; declare it in a VAR section")
            setter(self, field, value)
            return
        if rule.constant or rule.inside_only:  # rule.guarded, without a property call on a write
            frame = getframe(1)
            # The usual case, the block's own code writing a plain inside variable, passes here;
            # _check_rule decides everything else (and words the refusal).
            if rule.constant or rule.method is not None or frame.f_code not in type(self)._iec_codes_:
                _check_rule(self, rule, frame)
        if rule.validate is not None:
            rule.validate(value, rule.where)
        setter(self, field, value)

    __setattr__.__qualname__ = f"{cls.__name__}.__setattr__"
    FORWARDING_CODES.add(__setattr__.__code__)
    return __setattr__


def data_setattr(
    cls_name: str, layout: ClassLayout, aliases: Mapping[str, str] | None = None
) -> Callable[[Any, str, Any], None]:
    """The checked ``__setattr__`` of a STRUCT, UNION or GVL: the value's kind, CONSTANT, unknown members.

    ``aliases`` (ST name -> Python name) are checked as the variable they name.
    """
    validators: dict[str, Callable[[Any, str], None]] = {}
    wheres: dict[str, str] = {}
    for record in layout.fields:
        validate = _validator(record)
        if validate is not None:
            validators[record.name] = validate
            wheres[record.name] = record.where
    constants = {record.name: record.where for record in layout.fields if record.spec.constant}
    for alias, python in (aliases or {}).items():
        if python in validators:
            validators[alias], wheres[alias] = validators[python], wheres[python]
        if python in constants:
            constants[alias] = constants[python]
    setter = object.__setattr__
    # Per field: a value of the field's exact Python type is stored without a validator call.
    fast = {
        record.name: (accepted_type(record.info), validators[record.name], record.where, record.raw.__set__)
        for record in layout.fields
        if record.name in validators and record.name not in constants
    }

    def __setattr__(self: Any, name: str, value: Any) -> None:
        refusal = self.__dict__.get("_iec_ro_")
        if refusal is not None:  # a view of another block's local / output, or of a CONSTANT
            raise AccessError(refusal)
        spec = fast.get(name)
        if spec is not None:
            accepted, check, where, store = spec
            if value.__class__ is not accepted:
                check(value, where)
            store(self, value)
            return
        if name in constants:
            raise AccessError(f"{constants[name]} is CONSTANT and cannot be written")
        validate = validators.get(name)
        if validate is not None:
            validate(value, wheres[name])
        elif not hasattr(type(self), name):
            raise AttributeError(f"{type(self).__name__} has no member {name!r}; declare it as a field")
        setter(self, name, value)

    return __setattr__
