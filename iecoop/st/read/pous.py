"""Pass 2, POUs: FUNCTION_BLOCKs, PROGRAMs, METHODs, PROPERTYs, ACTIONs, INTERFACEs, GVLs and FUNCTIONs as Python classes."""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator, Sequence
from typing import Any

import blark.transform as tf

from iecoop.st.language import ACCESS_SPECIFIERS, LIFECYCLE
from iecoop.st.read.locals import Locals
from iecoop.st.read.frames import Scope
from iecoop.st.read.names import field_name, python_name, st_keyword
from iecoop.st.read.symbols import _SECTION_OF
from iecoop.st.read.table import BOOL, Decl, Member, ReferenceLocal, TypeRef
from iecoop.st.read.trees import (
    accessor_access, address_taken, by_reference_arguments, flag_keywords, located_section, location, nodes_below, signature,
    statements_of, variables,
)

#: The qualifiers of a VAR or VAR_GLOBAL block, as blark's flags and iecoop's specifier keywords name them.
_QUALIFIERS = ("constant", "retain", "persistent")
#: The pragmas of a POU and its STRING that give the STRING the instance's path (``VAR(instance_path=True)``).
_REFLECTION = re.compile(r"\{\s*attribute\s+'reflection'\s*\}", re.IGNORECASE)
_INSTANCE_PATH = re.compile(r"\{\s*attribute\s+'instance-path'\s*\}", re.IGNORECASE)


def _parameter_inits(blocks: Sequence[Any]) -> dict[str, Any]:
    """ST name (lower case) -> the declaration of each VAR_INPUT and VAR_OUTPUT (its initial value)."""
    inits: dict[str, Any] = {}
    for block in blocks:
        if isinstance(block, (tf.InputDeclarations, tf.OutputDeclarations)):
            for item in block.items:
                for var in getattr(item, "variables", []):
                    name = str(var.variable.name if hasattr(var, "variable") else var)
                    inits[name.lower()] = getattr(item, "init", None)
    return inits


class Pous(Locals):
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
        named: list[Decl] = []
        for itf in node.implements.interfaces if node.implements else []:
            itf_decl = self.decls.get(str(itf).lower())
            if itf_decl is None or itf_decl.kind != "interface":
                raise self.fail(f"FUNCTION_BLOCK {decl.name} IMPLEMENTS unknown interface {str(itf)!r}", node)
            named.append(itf_decl)
        # IMPLEMENTS I_A, I_B with I_B EXTENDS I_A is legal ST; a Python class cannot list a base after its subclass.
        bases += [d.name for d in named if not any(d is not o and any(d is a for a in self._interface_ancestors(o)) for o in named)]
        self.comments(node, 0)
        self.emit(f"class {decl.name}({', '.join(bases)}{self._class_kwargs(node.access)}{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""FUNCTION_BLOCK {decl.name}."""', 1)
        self._emit_pou(decl, "FUNCTION_BLOCK")

    def _interface_ancestors(self, decl: Decl) -> list[Decl]:
        """The interfaces ``decl`` EXTENDS, directly or through others (a cycle stops the walk)."""
        found: list[Decl] = []
        pending = list(decl.bases)
        while pending:
            base = self.decls.get(pending.pop().lower())
            if base is not None and base.kind == "interface" and not any(base is f for f in found):
                found.append(base)
                pending += base.bases
        return found

    def _emit_program(self, decl: Decl) -> None:
        self.need("iecoop", "Program")
        self.comments(decl.node, 0)
        if decl.name in self.named_programs:
            self.emit("@_program_instance", 0)  # other POUs read it by name: the class name is its one instance
        self.emit(f"class {decl.name}(Program{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""PROGRAM {decl.name}."""', 1)
        self._emit_pou(decl, "PROGRAM")

    def _emit_pou(self, decl: Decl, kind: str) -> None:
        node = decl.node
        scope = Scope(decl, "body")
        written = self.code_lines  # the class line and its docstring
        self.pending_references = []
        self._emit_fields(decl, node.declarations, scope, 1)
        self._emit_method_instance_fields(decl)
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
        if self.code_lines == written:
            self.emit("pass", 1)

    def _emit_fields(self, decl: Decl, blocks: Sequence[Any], scope: Scope, level: int, method: str | None = None) -> None:
        # an initial value is made with the class: a VAR CONSTANT it names is that constant's value, not self.x
        with self._constants_in(scope, self.block_owner.get(id(next((i for b in blocks for i in b.items), None)))):
            self._emit_field_blocks(decl, blocks, scope, level, method)

    @contextlib.contextmanager
    def _constants_in(self, scope: Scope, owner: Any) -> Iterator[None]:
        """``scope`` reads the VAR CONSTANTs of ``owner`` (a POU or METHOD node) as their values while it is open."""
        constants = {key: member for key, member in self.owner_constants(owner).items() if key not in scope.locals}
        scope.locals.update(constants)
        try:
            yield
        finally:
            for key, member in constants.items():
                if scope.locals.get(key) is member:
                    del scope.locals[key]

    def _emit_field_blocks(self, decl: Decl, blocks: Sequence[Any], scope: Scope, level: int, method: str | None) -> None:
        # {attribute 'instance-path'} takes effect in a POU marked {attribute 'reflection'}, as the PLC's compiler does
        reflection = method is None and any(_REFLECTION.fullmatch(p) for p in self.pragmas(decl.node))
        for block in blocks:
            self.comments(block, level)
            section = _SECTION_OF.get(type(block))
            extra = flag_keywords(getattr(block, "attrs", None), tf.VariableAttributes, _QUALIFIERS)
            if method is not None and section == "VAR_INST":
                extra.append(f'method="{method}"')
            previous = block.meta.line if block.meta else None
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                pragmas = self.pragmas(item, previous) if reflection and section == "VAR" else []
                previous = getattr(item.meta, "end_line", None) or self.line
                path = ["instance_path=True"] if any(_INSTANCE_PATH.fullmatch(p) for p in pragmas) else []
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
                    member = Member(field_name(name, type_), type_, located_section(item, section or "VAR"), st=name)
                    self.emit(self.field_line(member, init, scope, extra=", ".join(extra + path)), level)
                self.trail(index, ": ".join(filter(None, (location(item), trailing))))

    def _emit_method_instance_fields(self, decl: Decl) -> None:
        """The VAR_INST of each METHOD: fields of the instance, after the block's own (pass 1 declared them)."""
        for node in decl.method_nodes:
            method = decl.methods[str(node.name).lower()]
            scope = Scope(decl, "method")
            scope.pou = f"{decl.name}.{method.name}"
            scope.pou_name = f"{decl.st}.{node.name}"
            for block in node.declarations:
                if not isinstance(block, tf.MethodInstanceVariableDeclarations):
                    continue
                for item in block.items:
                    self.line = item.meta.line if item.meta else self.line
                    for var_name, _ in self._item_types(item):
                        member = decl.method_inst.get((method.name.lower(), var_name.lower())) or decl.members[var_name.lower()]
                        self._need_type(member.type)
                        self.need("iecoop", "VAR_INST")
                        extra = f'method="{LIFECYCLE.get(method.st.upper()) or method.name}"'
                        self.emit(self.field_line(member, getattr(item, "init", None), scope, extra=extra), 1)
            if not (decl.kind == "interface" or node.access is not None and node.access & tf.AccessSpecifier.abstract):
                self._emit_method_statics(decl, node, method.name)  # a prototype has no body, so no VAR_STAT

    def _emit_method_statics(self, decl: Decl, node: Any, method: str) -> None:
        """VAR_STAT of a METHOD: a VAR_STAT of the block named after the method, one for every instance and call."""
        for block in node.declarations:
            if not isinstance(block, tf.StaticDeclarations):
                continue
            for item in block.items:
                self.line = item.meta.line if item.meta else self.line
                for name, type_ in self._item_types(item):
                    self.need("iecoop", "VAR_STAT")
                    field = Member(f"{method}_{python_name(name)}", type_, "VAR_STAT")
                    if self.find_member(decl, field.name) is not None:
                        raise self.fail(f"VAR_STAT {name} of METHOD {decl.name}.{method} clashes with the member {field.name}", item)
                    self.emit(self.field_line(field, getattr(item, "init", None), Scope(None, "const")), 1)

    def _emit_reference_inits(self, decl: Decl, scope: Scope) -> None:
        """``ref : REFERENCE TO T := x;`` binds after initialisation, as the PLC binds it: REF= in a call_after_init."""
        if not self.pending_references and not self.pending_member_references:
            return
        self.pending_references = []
        members, self.pending_member_references = self.pending_member_references, []
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
        for path, name, type_, value in members:  # fb : FB_X := (ref := x, p := ADR(y))
            if type_.kind == "reference":
                self.emit(f'ref_assign({path}, "{name}", {self.address_of(value, scope)})', 2)
            else:
                self.emit(f"{path}.{name} = {self.expr(value, scope, expected=type_).code}", 2)

    def _params(self, params: Sequence[Member], blocks: Sequence[Any], scope: Scope) -> list[str]:
        """The Python parameters of a METHOD or FUNCTION, in order; each becomes a name of ``scope``."""
        inits = _parameter_inits(blocks)
        parts = []
        last_reference = max((i for i, p in enumerate(params) if p.type is not None and p.type.kind == "reference"), default=-1)
        for index, param in enumerate(params):
            assert param.type is not None
            self._need_type(param.type)
            init = inits.get(param.st.lower())
            if param.section == "VAR_IN_OUT" and param.type.kind == "array" and param.type.bounds is None:
                # ARRAY[*]: the caller's array itself (a view of its memory), with the bounds it was declared with
                parts.append(f"{param.name}: {param.type.annotation()} | None = None")
                scope.locals[param.st.lower()] = Member(param.name, param.type, "VAR_INPUT", st=param.st)
                scope.output_inits.append(
                    f'if {param.name} is None: raise TypeError("{scope.pou}: VAR_IN_OUT {param.st} must be given at every call")')
                continue
            if param.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                if index < last_reference:
                    raise self.fail(f"{param.section} {param.st} comes before a REFERENCE TO input; declare the REFERENCE TO inputs first")
                parts.append(self._by_reference_param(param, init, scope))
            else:
                parts.append(self._input_param(param, init, index <= last_reference, scope))
                scope.locals[param.st.lower()] = param
        return parts

    def _input_param(self, param: Member, init: Any, required: bool, scope: Scope) -> str:
        """A VAR_INPUT: required (before a REFERENCE TO input), a copy when passed by value, or with its default."""
        assert param.type is not None
        if required:
            # a REFERENCE TO input has no default (ST requires it), nor can an input before it in Python:
            # that one is required too, as in a Python signature (a STRUCT by value needs its default)
            if param.type.kind != "reference" and self._aggregate(param.type):
                raise self.fail(f"input {param.st} comes before a REFERENCE TO input; declare the REFERENCE TO inputs first")
            return f"{param.name}: {param.type.annotation()}"
        if param.type.kind == "any":  # a generic input: the body gets its AnyType, the call always passes it
            return f"{param.name}: {param.type.annotation()} = None"
        if self._aggregate(param.type):
            if not scope.pou:
                raise self.fail(f"input {param.st} of type {param.type.annotation()} passed by value is supported in a METHOD or FUNCTION")
            # passed by value: the callee works on a copy, made as it starts (_local_blocks); None is "not given"
            scope.by_value.append((param, init))
            return f"{param.name}: {param.type.annotation()} | None = None"
        owner = scope.owner.node if scope.owner is not None and scope.owner.kind in ("fb", "program") else None
        with self._constants_in(scope, owner):  # a default is made with the function: the block's constants as values
            default = self.initial_value(param.type, init, scope) or self.zero(param.type)
        if scope.owner is not None and scope.owner.kind == "interface" and self.decl_of(param.type) is scope.owner:
            # a prototype's input of its own interface type: the class does not exist yet to make its null()
            self.need("iecoop", "NULL")
            default = "NULL"
        return f"{param.name}: {param.type.annotation()} = {default}"

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

    def _emit_method(self, decl: Decl, node: Any) -> None:
        self.line = node.meta.line if node.meta else None
        self.enter(node)
        name = str(node.name)
        info = decl.methods[name.lower()]
        lifecycle = LIFECYCLE.get(name.upper())
        scope = Scope(decl, "method", return_name=python_name(name) if info.returns is not None else None)
        scope.return_st = name
        scope.pou = f"{decl.name}.{info.name}"
        scope.pou_name = f"{decl.st}.{name}"
        self.emit("", 0)
        self.comments(node, 1)
        decorators = []
        for pragma in self.pragmas(node):
            if re.fullmatch(r"\{\s*attribute\s+'call_after_init'\s*\}", pragma, re.IGNORECASE):
                self.need("iecoop", "call_after_init")
                decorators.append("@call_after_init")
        returns = info.returns
        ret_text = returns.annotation() if returns is not None else "None"
        self._need_type(returns)
        if lifecycle is not None:
            if lifecycle == "fb_init":
                inputs = info.params
                if len(inputs) < 2:
                    raise self.fail(f"METHOD FB_init of {decl.name} needs the inputs bInitRetains and bInCopyCode", node)
                # iecoop names the two implicit inputs in PEP 8; the ST names still resolve to them
                first = ["self", "init_retains: BOOL", "in_copy_code: BOOL"]
                self.need("iecoop", "BOOL")
                for p, py_name in zip(inputs[:2], ("init_retains", "in_copy_code")):
                    scope.locals[p.st.lower()] = Member(py_name, p.type, "VAR_INPUT", st=p.st)
                params = first + self._params(inputs[2:], node.declarations, scope)
            elif lifecycle == "fb_exit":
                if info.params:
                    scope.locals[info.params[0].st.lower()] = Member("in_copy_code", BOOL, "VAR_INPUT", st=info.params[0].st)
                params = ["self", "in_copy_code: BOOL", *self._params(info.params[1:], node.declarations, scope)]
            else:
                params = ["self"]
            self.emit_def(lifecycle, params, "BOOL", 1)
            self.need("iecoop", "BOOL")
            scope.return_name = python_name(name)
            returns = TypeRef("elem", "BOOL")
        else:
            decorators.insert(0, self._access_decorator(node.access, st=name, python=info.name))
            params = ["self", *self._params(info.params, node.declarations, scope)]
            for decorator in decorators:
                self.emit(decorator, 1)
            self.emit_def(info.name, params, ret_text, 1)
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
            scope = Scope(decl, "body")
            scope.pou_name = f"{decl.st}.{name}"
            self._emit_statements(statements_of(node.body), scope, 2)

    def prototype(self, returns: TypeRef | None, level: int) -> None:
        """The body of an interface or ABSTRACT member: no code, and nothing a type checker reads as a return."""
        self.emit("..." if returns is None else "raise NotImplementedError", level)

    def _emit_result(self, scope: Scope, returns: TypeRef, level: int) -> None:
        """The result variable of a METHOD, FUNCTION or PROPERTY accessor, a local named as the POU."""
        assert scope.return_name is not None
        key = (scope.return_st or scope.return_name).lower()
        scope.locals[key] = Member(scope.return_name, returns, "RETURN", st=scope.return_st or scope.return_name)
        if self._local_reference(returns):
            # REFERENCE TO a STRUCT or block: ``F REF= x`` names the variable itself, which is what Python returns
            assert returns.of is not None
            self.emit(f"{scope.return_name}: {returns.of.annotation()}", level)
        elif returns.kind == "reference" and returns.of is not None and scope.get_only and returns.of.kind in ("elem", "string"):
            # PROPERTY P : REFERENCE TO REAL with a Get only: ``P REF= x`` aims a pointer at x, read when the Get returns
            self.need("iecoop", "POINTER_TO", "Pointer")
            of = returns.of.annotation()
            scope.locals[key] = ReferenceLocal(scope.return_name, returns.of, "VAR_IN_OUT", st=scope.return_st or scope.return_name)
            self.emit(f"{scope.return_name}: POINTER_TO[{of}] = Pointer(0, None).typed({of})", level)
        elif returns.kind == "reference" and returns.of is not None:
            raise self.fail(f"a result of type REFERENCE TO {returns.of.annotation()} is not supported (REFERENCE TO a "
                            f"STRUCT or block is): return a POINTER TO {returns.of.annotation()}, the ADR of the variable")
        else:
            self.emit(f"{scope.return_name}: {returns.annotation()} = {self.zero(returns)}", level)

    def _emit_callable_body(self, node: Any, scope: Scope, returns: TypeRef | None, level: int) -> None:
        if returns is not None and scope.return_name is not None:
            self._emit_result(scope, returns, level)
        in_out = {c.st.lower() for d in self.decls.values() for c in d.methods.values()
                  if any(p.section == "VAR_IN_OUT" or p.type is not None and p.type.kind == "any" for p in c.params)}
        scope.addressed = set(by_reference_arguments(node.body, in_out)) | set(by_reference_arguments(node.declarations, in_out))
        self._local_blocks(node.declarations, scope, level, frozenset(address_taken([node.body, node.declarations])))
        for line in scope.output_inits:
            self.emit(line, level)
        statements = statements_of(node.body)
        self._emit_statements(statements, scope, level)
        if returns is not None and scope.return_name is not None:
            self.at(node)  # the declaration's line: the return is no statement of the body
            through = isinstance(scope.locals.get((scope.return_st or scope.return_name).lower()), ReferenceLocal)
            self.emit(f"return {scope.return_name}{'.deref' if through else ''}", level)
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
            self.emit("", 0)
            self.enter(getter or setter)
            self.comments(getter, 1)
            self.emit("@prop", 1)
            access = accessor_access(getter or setter)
            flags = self._access_decorator(access, st=prop.st, python=prop.name)
            if flags != "@method":
                self.emit(flags, 1)
            self.emit(f"def {prop.name}(self) -> {annotation}:", 1)
            if getter is None:  # a PROPERTY with a Set only: written, never read (TwinCAT refuses a read when compiling)
                self.need("iecoop", "AccessError")
                self.emit(f'raise AccessError("PROPERTY {decl.st}.{prop.st} has no Get accessor: it can only be written")', 2)
            elif decl.kind == "interface" or access is not None and access & tf.AccessSpecifier.abstract:
                self.prototype(prop.type, 2)
            else:
                scope = Scope(decl, "getter", return_name=python_name(prop.st))
                scope.return_st = prop.st
                scope.get_only = setter is None
                scope.pou_name = f"{decl.st}.{prop.st}.Get"
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
                    scope.pou_name = f"{decl.st}.{prop.st}.Set"
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
        self._emit_method_instance_fields(decl)
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
                    member = Member(field_name(name, type_), type_, "VAR", st=name)
                    self.emit(self.field_line(member, init, scope, extra=", ".join(extra)), 1)
                self.trail(index, ": ".join(filter(None, (location(item), trailing))))

    def _emit_function(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        info = decl.methods["()"]
        scope = Scope(None, "function", return_name=decl.name if info.returns is not None else None)
        scope.return_st = decl.st
        scope.pou = decl.name
        scope.pou_name = decl.st
        if info.returns is not None and any(isinstance(n, tf.FunctionCall) and str(n.name).lower() == decl.st.lower()
                                            for n in nodes_below(node.body)):
            scope.return_name = scope.temp(decl.name)  # F := F(n - 1) * n: the call names the FUNCTION, not its result
        self.comments(node, 0)
        params = self._params(info.params, node.declarations, scope)
        self._need_type(info.returns)
        ret_text = info.returns.annotation() if info.returns is not None else "None"
        statements = statements_of(node.body)
        is_external = decl.st.lower() in self.externals or not statements or any(
            re.fullmatch(r"\{\s*external\s*\}", p, re.IGNORECASE) for p in self.pragmas(node))
        if is_external:
            self.need("iecoop.st", "external")
            self.emit(f'@external("{decl.st}")', 0)
            self.emit_def(decl.name, params, ret_text, 0)
            self.emit(f'"""FUNCTION {decl.st}: bound to a Python callable at load time."""', 1)
            self.emit(f'raise NotImplementedError("FUNCTION {decl.st} has no body: pass externals={{\'{decl.st}\': ...}}")', 1)
            return
        if any(p.section in ("VAR_OUTPUT", "VAR_IN_OUT") or p.type is not None and p.type.kind == "any" for p in info.params):
            self.need("iecoop", "function")
            self.emit("@function", 0)
        self.emit_def(decl.name, params, ret_text, 0)
        self.emit(f'"""FUNCTION {decl.st}."""', 1)
        self._emit_callable_body(node, scope, info.returns, 1)
