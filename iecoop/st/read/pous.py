"""Pass 2, POUs: FUNCTION_BLOCKs, PROGRAMs, METHODs, PROPERTYs, ACTIONs, INTERFACEs, GVLs and FUNCTIONs as Python classes."""

from __future__ import annotations

import re
import struct
from collections.abc import Sequence
from typing import Any

import blark.transform as tf

from iecoop.st.language import ACCESS_SPECIFIERS, LIFECYCLE
from iecoop.st.read.declarations import Declarations
from iecoop.st.read.frames import Scope
from iecoop.st.read.names import python_name, st_keyword
from iecoop.st.read.symbols import BOOL, Decl, Member, ReferenceLocal, TypeRef, _SECTION_OF
from iecoop.st.read.trees import accessor_access, by_reference_arguments, flag_keywords, signature, statements_of, variables

#: The qualifiers of a VAR or VAR_GLOBAL block, as blark's flags and iecoop's specifier keywords name them.
_QUALIFIERS = ("constant", "retain", "persistent")


class Pous(Declarations):
    """Writes POUs and their members as Python classes."""

    def _emit_fb(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        bases = list(decl.bases)
        if not bases:
            self.need("iecoop", "FunctionBlock")
            bases.append("FunctionBlock")
        else:
            base_decl = self.decls.get(bases[0].lower())
            if base_decl is None or base_decl.kind not in ("fb", "stdfb"):
                raise self.fail(f"FUNCTION_BLOCK {decl.name} EXTENDS unknown block {bases[0]!r}", node)
            bases[0] = base_decl.name
            if base_decl.kind == "stdfb":
                self.need("iecoop.stdlib", base_decl.name)
        for itf in node.implements.interfaces if node.implements else []:
            itf_decl = self.decls.get(str(itf).lower())
            if itf_decl is None or itf_decl.kind != "interface":
                raise self.fail(f"FUNCTION_BLOCK {decl.name} IMPLEMENTS unknown interface {itf!r}", node)
            bases.append(itf_decl.name)
        self.comments(node, 0)
        self.emit(f"class {decl.name}({', '.join(bases)}{self._class_kwargs(node.access)}{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""FUNCTION_BLOCK {decl.name}."""', 1)
        self._emit_pou(decl, "FUNCTION_BLOCK")

    def _emit_program(self, decl: Decl) -> None:
        self.need("iecoop", "Program")
        self.comments(decl.node, 0)
        self.emit(f"class {decl.name}(Program{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""PROGRAM {decl.name}."""', 1)
        self._emit_pou(decl, "PROGRAM")

    def _emit_pou(self, decl: Decl, kind: str) -> None:
        node = decl.node
        scope = Scope(decl, "body")
        self.pending_references = []
        self._emit_fields(decl, node.declarations, scope, 1)
        self._emit_reference_inits(decl, scope)
        for method in decl.method_nodes:
            self._emit_method(decl, method)
        self._emit_actions(decl)
        self._emit_properties(decl)
        statements = statements_of(node.body)
        if statements or (kind == "FUNCTION_BLOCK" and decl.bases and node.body is not None):
            self.emit("", 0)
            self.emit("def body(self) -> None:", 1)
            self._emit_statements(statements, scope, 2)
        if len(self.out) and self.out[-1].strip().startswith('"""') and self.out[-1].strip().endswith('"""'):
            self.emit("pass", 1)

    def _emit_fields(self, decl: Decl, blocks: Sequence[Any], scope: Scope, level: int, method: str | None = None) -> None:
        for block in blocks:
            self.comments(block, level)
            section = _SECTION_OF.get(type(block))
            extra = flag_keywords(getattr(block, "attrs", None), tf.VariableAttributes, _QUALIFIERS)
            if method is not None and section == "VAR_INST":
                extra.append(f'method="{method}"')
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                trailing = self.comments(item, level, inline=True)
                index = len(self.out)
                if section == "VAR_EXTERNAL":
                    for name, type_ in self._item_types(item):
                        self._need_type(type_)
                        self.need("iecoop", "VAR_EXTERNAL")
                        self.emit(f"{python_name(name, attribute=True)}: {type_.annotation() if type_ else 'object'} = VAR_EXTERNAL({st_keyword(name, python_name(name, attribute=True), '')})", level)
                    self.trail(index, trailing)
                    continue
                for name, type_ in self._item_types(item):
                    init = item if isinstance(item, (tf.FunctionBlockNameDeclaration, tf.FunctionBlockInvocationDeclaration)) else getattr(item, "init", None)
                    member = Member(python_name(name, attribute=True), type_, self.located_section(item, section or "VAR"), st=name)
                    self.emit(self.field_line(member, init, scope, extra=", ".join(extra)), level)
                self.trail(index, ": ".join(filter(None, (self.location(item), trailing))))

    def _emit_reference_inits(self, decl: Decl, scope: Scope) -> None:
        """``ref : REFERENCE TO T := x;`` binds after initialisation, as the PLC binds it: REF= in a call_after_init."""
        if not self.pending_references:
            return
        self.pending_references = []
        self.need("iecoop", "call_after_init", "ref_assign")
        self.emit("", 0)
        self.emit("@call_after_init", 1)
        self.emit(f"def _bind_references_{decl.name}(self) -> None:", 1)
        self.emit('"""The REFERENCE TO variables initialised at their declaration (ref : REFERENCE TO T := x)."""', 2)
        for block in decl.node.declarations:
            for item in block.items:
                init = getattr(item, "init", None)
                target = getattr(init, "value", None)
                if target is None or self.init_type(init, item).kind != "reference":
                    continue
                if isinstance(target, tf.ArrayInitialization) and not target.brackets and len(target.elements) == 1:
                    target = target.elements[0].element  # blark reads `ref : REFERENCE TO ARRAY.. := a` as an array value
                for var in item.variables:
                    self.emit(f'ref_assign(self, "{python_name(str(var.variable.name), attribute=True)}", {self.address_of(target, scope)})', 2)

    def _params(self, params: Sequence[Member], blocks: Sequence[Any], scope: Scope) -> str:
        inits: dict[str, Any] = {}
        for block in blocks:
            if isinstance(block, (tf.InputDeclarations, tf.OutputDeclarations)):
                for item in block.items:
                    for var in getattr(item, "variables", []):
                        name = str(var.variable.name if hasattr(var, "variable") else var)
                        inits[name.lower()] = getattr(item, "init", None)
        parts = []
        last_reference = max((i for i, p in enumerate(params) if p.type is not None and p.type.kind == "reference"), default=-1)
        for index, param in enumerate(params):
            assert param.type is not None
            self._need_type(param.type)
            if param.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                if index < last_reference:
                    raise self.fail(f"{param.section} {param.st} comes before a REFERENCE TO input; declare the REFERENCE TO inputs first")
                parts.append(self._by_reference_param(param, inits.get(param.st.lower()), scope))
                continue
            if index <= last_reference:
                # a REFERENCE TO input has no default (ST requires it), nor can an input before it in Python:
                # that one is required too, as in a Python signature (a STRUCT by value needs its default)
                if param.type.kind != "reference" and self._aggregate(param.type):
                    raise self.fail(f"input {param.st} comes before a REFERENCE TO input; declare the REFERENCE TO inputs first")
                parts.append(f"{param.name}: {param.type.annotation()}")
                scope.locals[param.st.lower()] = param
                continue
            if self._aggregate(param.type):
                if not scope.pou:
                    raise self.fail(f"input {param.st} of type {param.type.annotation()} passed by value is supported in a METHOD or FUNCTION")
                # passed by value: the callee works on a copy, made as it starts (_local_blocks); None is "not given"
                scope.by_value.append((param, inits.get(param.st.lower())))
                parts.append(f"{param.name}: {param.type.annotation()} | None = None")
                scope.locals[param.st.lower()] = param
                continue
            default = self.initial_value(param.type, inits.get(param.st.lower()), scope) or self.zero(param.type)
            if scope.owner is not None and scope.owner.kind == "interface" and self.decl_of(param.type) is scope.owner:
                # a prototype's input of its own interface type: the class does not exist yet to make its null()
                self.need("iecoop", "NULL")
                default = "NULL"
            parts.append(f"{param.name}: {param.type.annotation()} = {default}")
            scope.locals[param.st.lower()] = param
        return "".join(f", {p}" for p in parts)

    def _by_reference_param(self, param: Member, init: Any, scope: Scope) -> str:
        """``nHigh : BYTE`` of VAR_OUTPUT / VAR_IN_OUT: ``nHigh: POINTER_TO[BYTE] = VAR_OUTPUT()``, reached as ``nHigh.deref``."""
        assert param.type is not None
        if param.type.kind == "reference":
            raise self.fail(f"{param.section} {param.st} of a REFERENCE TO type is not supported")
        length = f"length={param.type.length}" if param.type.kind == "string" and param.type.length not in (None, "80") else ""
        line = self.field_line(Member(param.name, TypeRef("pointer", "POINTER", of=param.type), param.section, st=param.st), None, scope, extra=length)
        if init is not None:
            if param.section == "VAR_IN_OUT":
                raise self.fail(f"an initial value for VAR_IN_OUT {param.st}")
            # outputs start at their initial value at every call: the first statement of the body sets it
            value = self.initial_value(param.type, init, scope)
            if value is not None:
                scope.output_inits.append(f"{param.name}.deref = {value}")
        scope.locals[param.st.lower()] = param
        return line

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
        decl = self.decl_of(type_)
        if decl is not None and decl.kind == "enum":
            return f"{decl.name}.{python_name(decl.values[0], attribute=True)}"
        if decl is not None and decl.kind == "interface":
            self.need("iecoop", "null")
            return f"null({decl.name})"
        if decl is not None and decl.kind == "alias" and decl.alias_of is not None:
            return self.zero(decl.alias_of)
        if decl is not None and decl.kind in ("struct", "union", "fb"):
            return f"{decl.name}()"
        raise self.fail(f"a local or input of type {type_.annotation()} has no zero value here")

    def _access_decorator(self, access: Any, extra: Sequence[str] = (), st: str = "", python: str = "") -> str:
        flags = list(extra)
        if access is not None:
            for spec in tf.AccessSpecifier:
                if access & spec and spec.name.upper() in ACCESS_SPECIFIERS and spec.name.upper() != "PUBLIC":
                    flags.append(spec.name.upper())
        for flag in flags:
            self.need("iecoop", flag)
        self.need("iecoop", "method")
        named = st_keyword(st, python, ", " if flags else "")
        return f"@method({' | '.join(flags)}{named})" if flags or named else "@method"

    def _local_blocks(self, blocks: Sequence[Any], scope: Scope, level: int) -> None:
        arrays: list[tuple[Member, Any]] = []
        statics: list[tuple[Any, str, TypeRef | None]] = []
        self._locals_of_blocks(blocks, scope, level, arrays, statics)
        if statics:
            self._statics(scope, statics)
        held = scope.by_value + arrays
        if held:
            # ARRAY and structured locals, and the copies of such inputs passed by value, live in a STRUCT
            # made at each call: initialised as declared, and the caller's variables never written
            addressed = " and the locals passed by address" if any(m.section == "ADDRESSED" for m, _ in held) else ""
            holder = self._holder(scope, "_VAR", held, f"The ARRAY and structured inputs and locals of {scope.pou}{addressed}: new at every call.")
            self.emit(f"_var = {holder}()", level)
            for member, _ in scope.by_value:
                self.emit(f"if {member.name} is not None:", level)
                self.emit(f"_var.{member.name} = {member.name}  # passed by value: a copy", level + 1)
            for member, _ in held:
                assert member.type is not None
                self._need_type(member.type)
                if member.section == "ADDRESSED":
                    continue  # read and written as _var.name
                annotation = f": {member.type.annotation()}" if member.section != "VAR_INPUT" else ""
                self.emit(f"{member.name}{annotation} = _var.{member.name}", level)

    def _statics(self, scope: Scope, statics: Sequence[tuple[Any, str, TypeRef | None]]) -> None:
        """VAR_STAT of a METHOD or FUNCTION: one variable for every instance and every call (TwinCAT, CODESYS)."""
        owner = scope.owner
        if owner is not None:
            method = scope.pou.split(".", 1)[1]
            for item, name, type_ in statics:  # a VAR_STAT of the block, named after the method
                self.need("iecoop", "VAR_STAT")
                field = Member(f"{method}_{python_name(name)}", type_, "VAR_STAT")
                if self.find_member(owner, field.name) is not None:
                    raise self.fail(f"VAR_STAT {name} of METHOD {scope.pou} clashes with the member {field.name}", item)
                self.out.insert(self._field_insert_point(), "    " + self.field_line(field, getattr(item, "init", None), Scope(None, "const")))
                scope.locals[name.lower()] = Member(f"self.{field.name}", type_, "STAT")
            return
        holder = self._holder(scope, "_VAR_STAT", [(Member(python_name(name, attribute=True), type_, "VAR", st=name), getattr(item, "init", None)) for item, name, type_ in statics],
                              f"VAR_STAT of FUNCTION {scope.pou}: one for every call.")
        instance = f"_{scope.pou}_static"
        self.preamble.extend(["", "", f"{instance} = {holder}()"])
        for _, name, type_ in statics:
            scope.locals[name.lower()] = Member(f"{instance}.{python_name(name, attribute=True)}", type_, "STAT", st=name)

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
                    scope.locals[name.lower()] = Member(f"{found[0]}.{found[1].name}", found[1].type, "STAT", st=name)
            return True
        return False

    def _held_local(self, item: Any, name: str, type_: TypeRef, scope: Scope, arrays: list[tuple[Member, Any]],
                    constant: Any) -> bool:
        """A local the POU's holder makes (an addressed scalar, an ARRAY, an initialised STRUCT); True if it is one."""
        py = python_name(name)
        enum = getattr(self.decl_of(type_), "kind", None) == "enum"
        if name.lower() in scope.addressed and scope.pou and (type_.kind in ("elem", "string", "pointer") or enum) and not constant:
            # an output or in-out argument needs the variable's address: a field of the holder has one
            arrays.append((Member(py, type_, "ADDRESSED", st=name), getattr(item, "init", None)))
            scope.locals[name.lower()] = Member(f"_var.{py}", type_, "STAT", st=name)
            return True
        initialised = self._aggregate(type_) and self.initial_value(type_, getattr(item, "init", None), scope) is not None
        if type_.kind == "array" or initialised:  # a STRUCT with its own initial values too: made by the holder
            if not scope.pou:
                raise self.fail(f"{'ARRAY' if type_.kind == 'array' else 'initialised STRUCT'} local {name} in a {scope.kind} is not supported (declare it in the block)", item)
            arrays.append((Member(py, type_, "LOCAL", st=name), getattr(item, "init", None)))
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            return True
        return False

    def _declare_local(self, item: Any, name: str, type_: TypeRef, scope: Scope, level: int, constant: Any) -> None:
        """Emit the Python local of one ST variable of a method or function body."""
        py = python_name(name)
        self._need_type(type_)
        init = getattr(item, "init", None)
        if self._local_reference(type_) and getattr(init, "value", None) is None:
            # bound by REF= to a view of its target, which is what a REFERENCE TO reads and writes through
            assert type_.of is not None
            scope.locals[name.lower()] = Member(py, type_, "LOCAL", st=name)
            self.emit(f"{py}: {type_.of.annotation()}", level)
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
        value = self.initial_value(type_, init, scope) or self.zero(type_)
        scope.locals[name.lower()] = Member(py, type_, "CONSTANT" if constant else "LOCAL", st=name)
        self.emit(f"{py}: {self.local_annotation(type_)} = {value}", level)

    def local_annotation(self, type_: TypeRef) -> str:
        return type_.annotation()

    def _emit_method(self, decl: Decl, node: Any) -> None:
        self.line = node.meta.line if node.meta else None
        self.enter(node)
        name = str(node.name)
        info = decl.methods[name.lower()]
        lifecycle = LIFECYCLE.get(name.upper())
        scope = Scope(decl, "method", return_name=python_name(name) if info.returns is not None else None)
        scope.return_st = name
        scope.pou = f"{decl.name}.{info.name}"
        self.emit("", 0)
        self.comments(node, 1)
        decorators = []
        for pragma in self.pragmas(node):
            if re.fullmatch(r"\{\s*attribute\s+'call_after_init'\s*\}", pragma, re.IGNORECASE):
                self.need("iecoop", "call_after_init")
                decorators.append("@call_after_init")
        # the method's VAR_INST live in the instance
        for block in node.declarations:
            if isinstance(block, tf.MethodInstanceVariableDeclarations):
                for item in block.items:
                    self.line = item.meta.line if item.meta else self.line
                    for var_name, type_ in self._item_types(item):
                        assert type_ is not None
                        self._need_type(type_)
                        member = Member(python_name(var_name, attribute=True), type_, "VAR_INST", st=var_name)
                        self._add_member(decl, member)  # a field of the instance, beside the block's own
                        self.need("iecoop", "VAR_INST")
                        self.out.insert(self._field_insert_point(), "    " + self.field_line(
                            member, getattr(item, "init", None), scope, extra=f'method="{lifecycle or info.name}"'))
        returns = info.returns
        ret_text = returns.annotation() if returns is not None else "None"
        self._need_type(returns)
        if lifecycle is not None:
            if lifecycle == "fb_init":
                inputs = info.params
                if len(inputs) < 2:
                    raise self.fail(f"METHOD FB_init of {decl.name} needs the inputs bInitRetains and bInCopyCode", node)
                # iecoop names the two implicit inputs in PEP 8; the ST names still resolve to them
                first = ", init_retains: BOOL, in_copy_code: BOOL"
                self.need("iecoop", "BOOL")
                for p, py_name in zip(inputs[:2], ("init_retains", "in_copy_code")):
                    scope.locals[p.st.lower()] = Member(py_name, p.type, "VAR_INPUT", st=p.st)
                params = first + self._params(inputs[2:], node.declarations, scope)
            elif lifecycle == "fb_exit":
                if info.params:
                    scope.locals[info.params[0].st.lower()] = Member("in_copy_code", BOOL, "VAR_INPUT", st=info.params[0].st)
                params = ", in_copy_code: BOOL" + self._params(info.params[1:], node.declarations, scope)
            else:
                params = ""
            self.emit_def(f"def {lifecycle}(self{params}) -> BOOL:", 1)
            self.need("iecoop", "BOOL")
            scope.return_name = python_name(name)
            returns = TypeRef("elem", "BOOL")
        else:
            decorators.insert(0, self._access_decorator(node.access, st=name, python=info.name))
            params = self._params(info.params, node.declarations, scope)
            for decorator in decorators:
                self.emit(decorator, 1)
            self.emit_def(f"def {info.name}(self{params}) -> {ret_text}:", 1)
        if node.access is not None and node.access & tf.AccessSpecifier.abstract or decl.kind == "interface":
            self.prototype(returns, 2)
            return
        self._emit_callable_body(node, scope, returns, 2)

    def _emit_actions(self, decl: Decl) -> None:
        """ACTIONs: code of the block that works on its variables; a method without inputs (``fbX.Reset()``)."""
        for node in decl.action_nodes:
            self.line = node.meta.line if node.meta else None
            self.enter(node)
            name = str(node.name).rsplit(".", 1)[-1]
            self.emit("", 0)
            self.comments(node, 1)
            self.emit(self._access_decorator(None, st=name, python=python_name(name, attribute=True)), 1)
            self.emit(f"def {python_name(name, attribute=True)}(self) -> None:", 1)
            self.emit(f'"""ACTION {name}."""', 2)
            self._emit_statements(statements_of(node.body), Scope(decl, "body"), 2)

    def prototype(self, returns: TypeRef | None, level: int) -> None:
        """The body of an interface or ABSTRACT member: no code, and nothing a type checker reads as a return."""
        self.emit("..." if returns is None else "raise NotImplementedError", level)

    def _field_insert_point(self) -> int:
        """Just after the last field line of the class being written."""
        index = len(self.out)
        for i, line in enumerate(self.out):
            if line.startswith("    ") and not line.startswith("        ") and re.match(r"    \w+: .+ = ", line):
                index = i + 1
            if line.startswith("    def ") or line.startswith("    @"):
                break
        return index

    def _emit_callable_body(self, node: Any, scope: Scope, returns: TypeRef | None, level: int) -> None:
        if returns is not None and scope.return_name is not None:
            key = (scope.return_st or scope.return_name).lower()
            scope.locals[key] = Member(scope.return_name, returns, "RETURN", st=scope.return_st or scope.return_name)
            if self._local_reference(returns):
                # REFERENCE TO a STRUCT or block: ``F REF= x`` names the variable itself, which is what Python returns
                assert returns.of is not None
                self.emit(f"{scope.return_name}: {returns.of.annotation()}", level)
            else:
                self.emit(f"{scope.return_name}: {returns.annotation()} = {self.zero(returns)}", level)
        in_out = {c.st.lower() for d in self.decls.values() for c in d.methods.values() if any(p.section == "VAR_IN_OUT" for p in c.params)}
        scope.addressed = set(by_reference_arguments(node.body, in_out))
        self._local_blocks(node.declarations, scope, level)
        for line in scope.output_inits:
            self.emit(line, level)
        statements = statements_of(node.body)
        self._emit_statements(statements, scope, level)
        if returns is not None and scope.return_name is not None:
            self.at(node)  # the declaration's line: the return is no statement of the body
            self.emit(f"return {scope.return_name}", level)
        elif not statements and not scope.output_inits and not any(isinstance(b, (tf.VariableDeclarations, tf.FunctionVariableDeclarations, tf.TemporaryVariableDeclarations)) for b in node.declarations):
            self.emit("pass", level)

    def _emit_properties(self, decl: Decl) -> None:
        accessors: dict[str, dict[str, Any]] = {}
        for node in decl.prop_nodes:
            parts = str(node.name).split(".")
            kind = parts[1].lower() if len(parts) > 1 else self.marked_accessors.get(id(node), "get")
            if kind not in ("get", "set"):
                raise self.fail(f"PROPERTY {node.name}: the accessor after the dot must be Get or Set", node)
            found = accessors.setdefault(parts[0].lower(), {})
            if kind in found:
                raise self.fail(
                    f"PROPERTY {parts[0]} has two {kind.capitalize()} accessors "
                    "(name them {0}.Get and {0}.Set, or mark them // Get and // Set)".format(parts[0]), node,
                )
            found[kind] = node
        for key, found in accessors.items():
            prop = decl.props[key]
            assert prop.type is not None
            self._need_type(prop.type)
            self.need("iecoop", "prop")
            getter = found.get("get")
            setter = found.get("set")
            annotation = prop.type.annotation()
            if getter is None:
                raise self.fail(f"PROPERTY {prop.st} has a Set accessor but no Get (iecoop needs the Get)", setter)
            self.emit("", 0)
            self.enter(getter)
            self.comments(getter, 1)
            self.emit("@prop", 1)
            access = accessor_access(getter)
            flags = self._access_decorator(access, st=prop.st, python=prop.name)
            if flags != "@method":
                self.emit(flags, 1)
            self.emit(f"def {prop.name}(self) -> {annotation}:", 1)
            if decl.kind == "interface" or access is not None and access & tf.AccessSpecifier.abstract:
                self.prototype(prop.type, 2)
            else:
                scope = Scope(decl, "getter", return_name=python_name(prop.st))
                scope.return_st = prop.st
                self._emit_callable_body(getter, scope, prop.type, 2)
            if setter is not None:
                self.emit("", 0)
                self.enter(setter)
                self.comments(setter, 1)
                self.emit(f"@{prop.name}.setter", 1)
                access = accessor_access(setter)
                flags = self._access_decorator(access)
                if flags != "@method":
                    self.emit(flags, 1)
                self.emit(f"def {prop.name}(self, {python_name(prop.st)}: {annotation}) -> None:", 1)
                if decl.kind == "interface" or access is not None and access & tf.AccessSpecifier.abstract:
                    self.emit("...", 2)
                else:
                    scope = Scope(decl, "setter")
                    scope.locals[prop.st.lower()] = Member(python_name(prop.st), prop.type, "VAR_INPUT", st=prop.st)
                    self._emit_callable_body(setter, scope, None, 2)

    def _emit_interface(self, decl: Decl) -> None:
        node = decl.node
        bases = []
        for base in decl.bases:
            if base.upper() == "__SYSTEM.IQUERYINTERFACE":
                self.need("iecoop", "IQueryInterface")
                bases.append("IQueryInterface")
                continue
            base_decl = self.decls.get(base.lower())
            if base_decl is None or base_decl.kind != "interface":
                raise self.fail(f"INTERFACE {decl.name} EXTENDS unknown interface {base!r}", node)
            bases.append(base_decl.name)
        if not bases:
            self.need("iecoop", "Interface")
            bases.append("Interface")
        if node.declarations:
            raise self.fail(f"INTERFACE {decl.name} declares variables; interfaces hold no state", node)
        self.comments(node, 0)
        self.emit(f"class {decl.name}({', '.join(bases)}{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""INTERFACE {decl.name}."""', 1)
        for method in decl.method_nodes:
            self._emit_method(decl, method)
        self._emit_properties(decl)
        if not decl.method_nodes and not decl.prop_nodes:
            self.emit("pass", 1)

    def _emit_gvl(self, decl: Decl) -> None:
        self.need("iecoop", "GlobalVariables", "gvl")
        self.emit("@gvl", 0)
        self.emit(f"class {decl.name}(GlobalVariables{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""VAR_GLOBAL list {decl.name}."""', 1)
        scope = Scope(decl, "const")
        for block in decl.node:
            self.unit = decl.units.get(id(block), self.unit)
            self.enter(block)
            self.comments(block, 1)
            extra = flag_keywords(block.attrs, tf.GlobalVariableAttributes, _QUALIFIERS)
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                trailing = self.comments(item, 1, inline=True)
                index = len(self.out)
                init = item.init
                for name, type_ in self._item_types(item):
                    member = Member(python_name(name, attribute=True), type_, "VAR", st=name)
                    self.emit(self.field_line(member, init, scope, extra=", ".join(extra)), 1)
                self.trail(index, ": ".join(filter(None, (self.location(item), trailing))))

    def _emit_function(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        info = decl.methods["()"]
        scope = Scope(None, "function", return_name=decl.name if info.returns is not None else None)
        scope.return_st = decl.st
        scope.pou = decl.name
        self.comments(node, 0)
        params = self._params(info.params, node.declarations, scope)[2:]
        self._need_type(info.returns)
        ret_text = info.returns.annotation() if info.returns is not None else "None"
        statements = statements_of(node.body)
        is_external = decl.st.lower() in self.externals or not statements or any(
            re.fullmatch(r"\{\s*external\s*\}", p, re.IGNORECASE) for p in self.pragmas(node))
        if is_external:
            self.need("iecoop.st", "external")
            self.emit(f'@external("{decl.st}")', 0)
            self.emit_def(f"def {decl.name}({params}) -> {ret_text}:", 0)
            self.emit(f'"""FUNCTION {decl.st}: bound to a Python callable at load time."""', 1)
            self.emit(f'raise NotImplementedError("FUNCTION {decl.st} has no body: pass externals={{\'{decl.st}\': ...}}")', 1)
            return
        if any(p.section in ("VAR_OUTPUT", "VAR_IN_OUT") for p in info.params):
            self.need("iecoop", "function")
            self.emit("@function", 0)
        self.emit_def(f"def {decl.name}({params}) -> {ret_text}:", 0)
        self.emit(f'"""FUNCTION {decl.st}."""', 1)
        self._emit_callable_body(node, scope, info.returns, 1)
