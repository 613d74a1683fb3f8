"""The objects pass 2 hands between its phases: an expression (``Ex``) and a name scope (``Scope``)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # symbols imports this module
    from iecoop.st.read.table import Decl, Member, TypeRef

@dataclasses.dataclass
class Ex:
    """A translated expression: Python code, its ST type (None when unknown), whether it needs parentheses."""

    code: str
    type: TypeRef | None = None
    compound: bool = False
    #: Python precedence of the outermost operator (see PRECEDENCE); 0 for other compound code
    prec: int = 100
    #: ``super().Prop`` as the target of an assignment: written with super_set
    super_property: bool = False
    #: the value of a numeric literal (``5``, ``-5``, ``2.5``) as the expression visitor read it, else None:
    #: later phases ask this, never the code, whether a value is a constant
    constant: int | float | None = None
    #: "THIS" or "SUPER" for the instance itself (``self``) or its parent's view of it (``super()``)
    this: str | None = None
    #: ``(holder code, field name)`` when the code reads the field of something (``self.count``, ``GVL.x``,
    #: ``p.deref``): ADR, REF= and __VARINFO take the address from it
    place: tuple[str, str] | None = None

    @classmethod
    def attribute(cls, holder: str, field: str, type_: TypeRef | None, **kwargs: Any) -> Ex:
        """``holder.field``: the code, and the place it names."""
        return cls(f"{holder}.{field}", type_, place=(holder, field), **kwargs)

    def __post_init__(self) -> None:
        if self.compound and self.prec == 100:
            self.prec = 0

    def p(self) -> str:
        return f"({self.code})" if self.compound else self.code

    def wrap(self, needed: int) -> str:
        """The code as an operand of an operator of precedence ``needed``: in parentheses only when it binds looser."""
        return f"({self.code})" if self.prec < needed else self.code


#: Python operator precedence, loosest first, for the operators the translation writes.
PRECEDENCE = {"or": 1, "and": 2, "not": 3, "compare": 4, "|": 5, "^": 6, "&": 7, "shift": 8, "+": 9, "-": 9,
              "*": 10, "/": 10, "unary": 11, "**": 12}


class Scope:
    """Name resolution inside one POU body, method, property accessor or function."""

    def __init__(self, owner: Decl | None, kind: str, return_name: str | None = None) -> None:
        self.owner = owner
        self.kind = kind  # body | method | function | getter | setter
        self.locals: dict[str, Member] = {}
        self.return_name = return_name
        #: the ST name of the result variable (the METHOD's, FUNCTION's or PROPERTY's): how the body names it
        self.return_st = return_name
        self.counter = 0
        #: ``x.deref = value`` for each VAR_OUTPUT with an initial value (a METHOD / FUNCTION)
        self.output_inits: list[str] = []
        #: ``FB_X.Method`` or ``F_Name`` for a METHOD or FUNCTION: names its helper classes
        self.pou = ""
        #: what ``__POUNAME()`` gives here, when it is not the owner's ST name: ``FB_X.Method``, ``FB_X.Prop.Get``, ``F_Name``
        self.pou_name = ""
        #: the ARRAY and structured inputs passed by value, with their initialisers: copied at the call
        self.by_value: list[tuple[Member, Any]] = []
        #: whether the top statement list (the only one that may hold labels) is being written
        self.started = False
        #: JMP targets of the body (lower case) and the variable that names the part to run next
        self.labels: set[str] = set()
        self.jump = ""
        #: the FOR, WHILE and REPEAT loops around the statement being written: EXIT and CONTINUE need one
        self.loops = 0
        #: elementary locals given to a call as an output (=>) or in-out: they live in the holder STRUCT, which has addresses
        self.addressed: set[str] = set()
        #: the indentation of the assignment whose right side is being read: a query there is written before it
        self.statement_level: int | None = None
        #: ARRAY / STRUCT locals whose initial value reads locals declared before them: (Python name, type, init),
        #: set once those are (the holder that makes them knows only constants)
        self.local_inits: list[tuple[str, Any, Any]] = []
        #: a PROPERTY's Get with no Set beside it: a REFERENCE TO an elementary result is read through
        self.get_only = False

    def temp(self, stem: str) -> str:
        self.counter += 1
        return f"_{stem}{self.counter}"


