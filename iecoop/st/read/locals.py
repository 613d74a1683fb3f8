"""Pass 2, the locals of a METHOD, FUNCTION or PROPERTY accessor: Python locals, or fields of a holder STRUCT.

ARRAY and structured locals, the copies of such inputs passed by value and the locals passed by address
live in a STRUCT made at each call; a METHOD's VAR_STAT is a field of the block, a FUNCTION's a module-level
STRUCT; a VAR_EXTERNAL is the global itself.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import blark.transform as tf

from iecoop.st.read.declarations import Declarations
from iecoop.st.read.frames import Scope
from iecoop.st.read.names import python_name
from iecoop.st.read.symbols import _SECTION_OF
from iecoop.st.read.table import Member, ReferenceLocal, TypeRef
from iecoop.st.read.trees import names_read


class Locals(Declarations):
    """Writes the locals of a METHOD, FUNCTION or PROPERTY accessor as the call starts."""

    def _holder(self, scope: Scope, suffix: str, fields: Sequence[tuple[Member, Any]], doc: str) -> str:
        """A module-level STRUCT that holds ``fields`` of the METHOD or FUNCTION ``scope``, written before its POU."""
        name = "_" + scope.pou.replace(".", "_") + suffix
        self.need("iecoop", "Struct")
        lines = ["", "", f"class {name}(Struct):", f'    """{doc}"""']
        const = Scope(None, "const")
        for member, init in fields:
            lines.append("    " + self.field_line(Member(member.name, member.type, "VAR", st=member.st), init, const))
        self.preamble.extend(lines)
        return name

    def zero(self, type_: TypeRef) -> str:
        if type_.is_bool:
            return "False"
        if type_.is_real:
            return "0.0"
        if type_.is_int:
            return "0"
        if type_.kind == "string":
            return '""'
        if type_.kind == "pointer":
            self.need("iecoop", "Pointer")
            return "Pointer(0, None)"
        if type_.kind == "varinfo":  # a VAR_INFO input not given: all of it zero, as the PLC's memory starts
            self.need("iecoop", "VarInfo", "TYPE_CLASS")
            return 'VarInfo("", 0, 0, 0, 0, 0, TYPE_CLASS.TYPE_BOOL, "", 0, 0, TYPE_CLASS.TYPE_BOOL)'
        decl = self.decl_of(type_)
        if decl is not None and decl.kind == "enum":
            return self.enum_default(decl)
        if decl is not None and decl.kind == "interface":
            self.need("iecoop", "null")
            return f"null({decl.name})"
        if decl is not None and decl.kind == "alias" and decl.alias_of is not None:
            return self.zero(decl.alias_of)
        if decl is not None and decl.kind in ("struct", "union", "fb", "stdfb"):
            if decl.kind == "stdfb":  # a standard block as a local of a FUNCTION: a new instance at every call
                self.need("iecoop.stdlib", decl.name)
            return f"{decl.name}()"
        raise self.fail(f"a local or input of type {type_.annotation()} has no zero value here")

    def _local_blocks(self, blocks: Sequence[Any], scope: Scope, level: int, inputs_addressed: frozenset[str] = frozenset()) -> None:
        arrays: list[tuple[Member, Any]] = []
        statics: list[tuple[Any, str, TypeRef | None]] = []
        inputs = self._addressed_inputs(inputs_addressed, scope, arrays)
        start = len(self.out)
        self._locals_of_blocks(blocks, scope, level, arrays, statics)
        if statics:
            self._statics(scope, statics)
        held = scope.by_value + arrays
        if held:
            # ARRAY and structured locals, and the copies of such inputs passed by value, live in a STRUCT
            # made at each call: initialised as declared, and the caller's variables never written
            addressed = " and the locals passed by address" if any(m.section == "ADDRESSED" for m, _ in held) else ""
            holder = self._holder(scope, "_VAR", held, f"The ARRAY and structured inputs and locals of {scope.pou}{addressed}: new at every call.")
            mark = len(self.out)
            self.emit(f"_var = {holder}()", level)
            for member, _ in scope.by_value:
                self.emit(f"if {member.name} is not None:", level)
                self.emit(f"_var.{member.name} = {member.name}  # passed by value: a copy", level + 1)
            for name in inputs:
                self.emit(f"_var.{name} = {name}  # an input whose address is taken", level)
            for member, _ in held:
                assert member.type is not None
                self._need_type(member.type)
                if member.section == "ADDRESSED":
                    continue  # read and written as _var.name
                annotation = f": {member.type.annotation()}" if member.section != "VAR_INPUT" else ""
                self.emit(f"{member.name}{annotation} = _var.{member.name}", level)
            # the holder comes before the plain locals: their initial values may take an address in it
            moved = self.out[mark:]
            del self.out[mark:]
            self.out[start:start] = moved
            for py, type_, init in scope.local_inits:  # [nFirst, nSecond]: once the locals it reads have their values
                # made by a holder of its own, so the field takes a value of its exact class (checked or not)
                self.emit(f"_var.{py} = {holder}({py}={self.initial_value(type_, init, scope)}).{py}", level)
        scope.local_inits.clear()

    @staticmethod
    def _reads_locals(init: Any, scope: Scope) -> bool:
        """Whether the initial value ``init`` reads a (non-constant) local declared before it."""
        return any(getattr(scope.locals.get(name), "section", "CONSTANT") != "CONSTANT" for name in names_read(init))

    def _addressed_inputs(self, inputs_addressed: frozenset[str], scope: Scope, arrays: list[tuple[Member, Any]]) -> list[str]:
        """The inputs whose address is taken (ADR of an input): copied where they have one, read and written there."""
        inputs = []
        for key in sorted(inputs_addressed):
            param = scope.locals.get(key)
            if param is not None and param.section == "VAR_INPUT" and param.type is not None and scope.pou and (
                    param.type.kind in ("elem", "string", "pointer") or getattr(self.decl_of(param.type), "kind", None) == "enum"):
                arrays.append((Member(param.name, param.type, "ADDRESSED", st=param.st), None))
                scope.locals[key] = Member.field_of("_var", param.name, param.type, "STAT", st=param.st)
                inputs.append(param.name)
        return inputs

    def _statics(self, scope: Scope, statics: Sequence[tuple[Any, str, TypeRef | None]]) -> None:
        """VAR_STAT of a METHOD or FUNCTION: one variable for every instance and every call (TwinCAT, CODESYS)."""
        owner = scope.owner
        if owner is not None:
            method = scope.pou.split(".", 1)[1]
            for _, name, type_ in statics:  # a VAR_STAT of the block, named after the method (its field is written with the block's)
                scope.locals[name.lower()] = Member.field_of("self", f"{method}_{python_name(name)}", type_, "STAT")
            return
        holder = self._holder(scope, "_VAR_STAT", [(Member(python_name(name, attribute=True), type_, "VAR", st=name), getattr(item, "init", None)) for item, name, type_ in statics],
                              f"VAR_STAT of FUNCTION {scope.pou}: one for every call.")
        instance = f"_{scope.pou}_static"
        self.preamble.extend(["", "", f"{instance} = {holder}()"])
        for _, name, type_ in statics:
            scope.locals[name.lower()] = Member.field_of(instance, python_name(name, attribute=True), type_, "STAT", st=name)

    def _locals_of_blocks(self, blocks: Sequence[Any], scope: Scope, level: int, arrays: list[tuple[Member, Any]],
                          statics: list[tuple[Any, str, TypeRef | None]]) -> None:
        for block in blocks:
            if self._non_local_block(block, scope, statics):
                continue
            constant = getattr(block, "attrs", None) is not None and block.attrs & tf.VariableAttributes.constant
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                trailing = self.comments(item, level, inline=True)
                index = len(self.out)
                for name, type_ in self._item_types(item):
                    assert type_ is not None
                    if not self._held_local(item, name, type_, scope, arrays, constant):
                        self._declare_local(item, name, type_, scope, level, constant)
                self.trail(index, trailing)

    def _non_local_block(self, block: Any, scope: Scope, statics: list[tuple[Any, str, TypeRef | None]]) -> bool:
        """Handle a VAR section that declares no plain local (parameters, VAR_STAT, VAR_EXTERNAL); True if handled."""
        section = _SECTION_OF.get(type(block))
        if section == "VAR_INST" and scope.owner is not None and scope.owner.method_inst:
            method = scope.pou.split(".", 1)[1].lower()
            for item in block.items:  # a name another METHOD declares too: this METHOD's own field
                for name, _ in self._item_types(item):
                    own = scope.owner.method_inst.get((method, name.lower()))
                    if own is not None:
                        scope.locals[name.lower()] = Member.field_of("self", own.name, own.type, "STAT", st=name)
            return True
        if section in ("VAR_INPUT", "VAR_INST"):
            return True
        if section in ("VAR_OUTPUT", "VAR_IN_OUT"):
            if scope.kind in ("method", "function"):
                return True  # parameters (see _by_reference_param)
            raise self.fail(f"{section} in a {scope.kind} is not supported", block)
        if section == "VAR_STAT":
            if not scope.pou:
                raise self.fail(f"VAR_STAT in a {scope.kind} is not supported", block)
            statics.extend((item, name, type_) for item in block.items for name, type_ in self._item_types(item))
            return True
        if section == "VAR_EXTERNAL":  # the global itself, read and written in place (never a local copy)
            for item in block.items:
                for name, _ in self._item_types(item):
                    found = self.globals.get(name.lower())
                    if found is None:
                        raise self.fail(f"VAR_EXTERNAL {name} of {scope.pou or scope.kind} names no VAR_GLOBAL", item)
                    scope.locals[name.lower()] = Member.field_of(found[0], found[1].name, found[1].type, "STAT", st=name)
            return True
        return False

    def _held_local(self, item: Any, name: str, type_: TypeRef, scope: Scope, arrays: list[tuple[Member, Any]],
                    constant: Any) -> bool:
        """A local the POU's holder makes (an addressed scalar, an ARRAY, an initialised STRUCT); True if it is one."""
        py = python_name(name)
        enum = getattr(self.decl_of(type_), "kind", None) == "enum"
        if name.lower() in scope.addressed and scope.pou and (type_.kind in ("elem", "string", "pointer") or enum):
            # an output or in-out argument needs the variable's address: a field of the holder has one (a
            # CONSTANT's too: ADR of a constant is how numeric code reads a bit pattern as another type)
            arrays.append((Member(py, type_, "ADDRESSED", st=name), getattr(item, "init", None)))
            scope.locals[name.lower()] = Member.field_of("_var", py, type_, "CONSTANT" if constant else "STAT", st=name)
            return True
        initialised = self._aggregate(type_) and self.initial_value(type_, getattr(item, "init", None), scope) is not None
        if type_.kind == "array" or initialised:  # a STRUCT with its own initial values too: made by the holder
            if not scope.pou:
                raise self.fail(f"{'ARRAY' if type_.kind == 'array' else 'initialised STRUCT'} local {name} in a {scope.kind} is not supported (declare it in the block)", item)
            init = getattr(item, "init", None)
            if init is not None and self._reads_locals(init, scope):
                scope.local_inits.append((py, type_, init))
                init = None
            arrays.append((Member(py, type_, "LOCAL", st=name), init))
            if type_.kind == "array" and name.lower() in scope.addressed:
                # passed as an in-out or output: read and written as the holder's field, which has an address
                scope.locals[name.lower()] = Member.field_of("_var", py, type_, "STAT", st=name)
            else:
                scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            return True
        return False

    def _declare_local(self, item: Any, name: str, type_: TypeRef, scope: Scope, level: int, constant: Any) -> None:
        """Emit the Python local of one ST variable of a method or function body."""
        if type_.kind == "any":  # __SYSTEM.AnyType as a local: only a generic input receives one
            raise self.fail(f"VAR {name} : {type_.name}: a generic type is not supported outside a VAR_INPUT of a FUNCTION or METHOD", item)
        py = python_name(name)
        self._need_type(type_)
        init = getattr(item, "init", None)
        if self._local_reference(type_) and getattr(init, "value", None) is None:
            # bound by REF= to a view of its target, which is what a REFERENCE TO reads and writes through
            assert type_.of is not None
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            self.emit(f"{py}: {type_.of.annotation()} | None = None", level)  # None: not bound (__ISVALIDREF FALSE)
            return
        if type_.kind == "varinfo":  # set by := __VARINFO(x) before it is read
            self.need("iecoop", "VarInfo")
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            self.emit(f"{py}: VarInfo", level)
            return
        if type_.kind == "reference" and type_.of is not None and type_.of.kind in ("elem", "string") and getattr(init, "value", None) is None:
            # a pointer that REF= binds; reached through .deref, as an in-out is
            self.need("iecoop", "POINTER_TO", "Pointer")
            scope.locals[name.lower()] = ReferenceLocal(py, type_.of, "VAR_IN_OUT", st=name)
            self.emit(f"{py}: POINTER_TO[{type_.of.annotation()}] = Pointer(0, None).typed({type_.of.annotation()})", level)
            return
        value = self.initial_value(type_, init, scope)
        if value is not None and getattr(self.decl_of(type_), "kind", None) == "fb":
            raise self.fail(f"{name} : {type_.annotation()} := (...): a FUNCTION_BLOCK local of a {scope.kind} with an initialiser is "
                            "not supported (declare it in the block's VAR or the METHOD's VAR_INST)", item)
        value = value or self.zero(type_)
        scope.locals[name.lower()] = Member(py, type_, "CONSTANT" if constant else "LOCAL", st=name)
        self.emit(f"{py}: {self.local_annotation(type_)} = {value}", level)

    def local_annotation(self, type_: TypeRef) -> str:
        return type_.annotation()
