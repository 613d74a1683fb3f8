"""Pass 2, data types and fields: enums, aliases, STRUCTs, UNIONs, and the fields and initial values of any class."""

from __future__ import annotations

import keyword
import re
from collections.abc import Iterator
from typing import Any

import blark.transform as tf

from iecoop.st.read.frames import Scope
from iecoop.st.read.names import field_name, python_name, st_keyword
from iecoop.st.read.statements import Statements
from iecoop.st.read.table import Callable_, Decl, Member, TypeRef
from iecoop.st.read.trees import flag_keywords, lark_token_type, python_string, structure_elements

#: The most values one ARRAY initialiser gives (each is a line of the generated code's list).
MAX_INITIAL_VALUES = 1 << 20


def _declared_value(init: Any) -> Any:
    """The value node a declaration gives its variable (``:= 5``, ``:= (a := 1)``, a block's inputs), or None."""
    if isinstance(init, tf.FunctionBlockInvocationDeclaration):
        return init.defaults
    if isinstance(init, (tf.FunctionBlockNameDeclaration, tf.InitializedStructure)):
        return init.init
    if init is not None and not isinstance(init, tf.FunctionCall):
        return getattr(init, "value", None)
    return None


def _shape_keywords(type_: TypeRef) -> list[str]:
    """``length=`` of a STRING(n), ``bounds=`` (and the element's ``length=``) of an ARRAY or a pointer to one."""
    kwargs = []
    if type_.kind == "string" and type_.length not in (None, "80"):
        kwargs.append(f"length={type_.length}")
    shape = type_.of if type_.kind in ("pointer", "reference") and type_.of is not None and type_.of.kind == "array" else type_
    if shape.kind != "array":
        return kwargs
    levels = []
    if shape is type_ and type_.bounds is None:
        # ARRAY[*] (a block's VAR_IN_OUT): bounds="*", or one "*" per dimension
        stars = ", ".join(['"*"'] * type_.open_dims)
        return [*kwargs, f"bounds={stars}" if type_.open_dims == 1 else f"bounds=({stars})"]
    while shape.kind == "array" and shape.of is not None:
        assert shape.bounds is not None
        pairs = [f"({a}, {b})" for a, b in shape.bounds]
        levels.append(pairs[0] if len(pairs) == 1 else "(" + ", ".join(pairs) + ")")
        shape = shape.of
    # ARRAY OF ARRAY: one bounds entry per level, outermost first
    kwargs.append(f"bounds={levels[0] if len(levels) == 1 else '(' + ', '.join(levels) + ')'}")
    if shape.kind == "string" and shape.length not in (None, "80"):
        kwargs.append(f"length={shape.length}")
    return kwargs


class Declarations(Statements):
    """Writes data types and the fields of classes."""

    # --- data types ---

    def enum_default(self, decl: Decl) -> str:
        """The value a variable of the enumeration ``decl`` starts with: ``TYPE E : (A, B) := B;`` declares B, else the first."""
        given = getattr(getattr(decl.node, "init", None), "value", None)
        name = str(getattr(given, "name", None) or given or "").rsplit(".", 1)[-1] if given is not None else ""
        match = next((v for v in decl.values if v.lower() == name.lower()), None)
        if given is not None and match is None:
            raise self.fail(f"the default {name!r} of enumeration {decl.st} is none of its values", decl.node)
        return f"{decl.name}.{python_name(match or decl.values[0], attribute=True)}"

    def _emit_enum(self, decl: Decl) -> None:
        node = decl.node
        self.line = node.meta.line if node.meta else None
        base = node.init.spec.type_name
        base_kw = ""
        if base is not None:
            base_type = self.type_named(str(base), node)
            self.need("iecoop", base_type.name)
            base_kw = f", base={base_type.name}"
        self.need("iecoop", "IecEnum")
        self.comments(node, 0)
        renamed = {python_name(v, attribute=True): v for v in decl.values if python_name(v, attribute=True) != v}
        names_kw = ", st_names={" + ", ".join(f'"{p}": "{v}"' for p, v in renamed.items()) + "}" if renamed else ""
        self.emit(f"class {decl.name}(IecEnum{base_kw}{st_keyword(decl.st, decl.name)}{names_kw}):", 0)
        self.emit(f'"""TYPE {decl.name} (enumeration)."""', 1)
        value = -1
        scope = Scope(None, "const")
        for item in node.init.spec.values or []:
            if item.value is not None:
                text = self.expr(item.value, scope).code
                try:
                    value = int(eval(text, {}))  # a literal or a constant expression of literals
                except Exception:
                    raise self.fail(f"enumeration value {decl.name}.{item.name} := {text} is not a constant", node) from None
            else:
                value += 1
            self.emit(f"{python_name(str(item.name), attribute=True)} = {value}", 1)
        if node.init.value is not None:
            self.enum_default(decl)  # a name among the values; the variables of the type start with it

    def _emit_alias(self, decl: Decl) -> None:
        assert decl.alias_of is not None
        target = decl.alias_of
        shaped = target.kind in ("string", "array") and (target.length not in (None, "80") or target.bounds)
        self.need("typing", "Annotated")
        self.need("iecoop", "Alias")
        self._need_type(target)
        self.comments(decl.node, 0)
        init = getattr(getattr(decl.node, "init", None), "value", None)
        initial = ""
        if init is not None:
            if target.kind != "elem":
                raise self.fail(f"alias {decl.name} of {target.annotation()} with an initial value is not supported", decl.node)
            initial = f", initial={self.init_value(init, target, Scope(None, 'alias'))}"
        elif target.limits is not None:
            initial = f", initial={target.limits[0]}"  # a subrange starts at its lower limit (IEC 61131-3)
        if shaped:
            shape = f"STRING({target.length})" if target.kind == "string" else "its ARRAY bounds"
            self.emit(f"# TYPE {decl.st} is {shape}: the variables declared with it carry that", 0)
        # what the TYPE declares of its STRING, ARRAY or subrange, for writing it back
        if target.kind == "string" and target.length not in (None, "80"):
            initial += f", length={target.length}"
        if target.kind == "array" and target.bounds:
            initial += f", bounds=({''.join(f'({low}, {high}), ' for low, high in target.bounds)})"
        if target.limits is not None:
            initial += f", limits=({target.limits[0]}, {target.limits[1]})"
        self.emit(f'{decl.name} = Annotated[{target.annotation()}, Alias("{decl.name}"{initial})]', 0)

    def _emit_struct(self, decl: Decl) -> None:
        self._emit_datatype(decl, "Struct")

    def _emit_union(self, decl: Decl) -> None:
        self._emit_datatype(decl, "Union")

    def _emit_datatype(self, decl: Decl, base: str) -> None:
        node = decl.node
        keyword = "STRUCT" if base == "Struct" else "UNION"
        bases = decl.bases[0] if decl.bases else base
        if decl.bases:
            base_decl = self.decls.get(bases.lower())
            if base_decl is None or base_decl.kind != decl.kind:
                raise self.fail(f"{keyword} {decl.st} EXTENDS {bases}, which is no declared {keyword}", node)
            bases = base_decl.name
        else:
            self.need("iecoop", base)
        if not node.declarations and not decl.bases:
            raise self.fail(f"{keyword} {decl.st} has no members; declare at least one (an empty STRUCT has no layout)", node)
        self.comments(node, 0)
        self.emit(f"class {decl.name}({bases}{st_keyword(decl.st, decl.name)}):", 0)
        self.emit(f'"""TYPE {decl.name} : {keyword}."""', 1)
        pack = self._pack_mode(node)
        if pack is not None:  # ctypes lays the members out with at most this alignment, as TwinCAT's pack_mode does
            self.emit(f"_pack_ = {pack}", 1)
        scope = Scope(decl, "const")
        for element in node.declarations:
            self.line = element.meta.line if element.meta else self.line
            trailing = self.comments(element, 1, inline=True)
            index = len(self.out)
            members = list(self._element_members(element, decl.kind))
            init = getattr(element, "init", None)
            if isinstance(element, tf.UnionElementDeclaration):
                init = None
            for member in members:
                if init is not None and getattr(self.decl_of(member.type), "kind", None) in ("fb", "stdfb") and _declared_value(init) is not None:
                    # a STRUCT's block member would start from the block's own values, not these: refused, not ignored
                    raise self.fail(f"{keyword} member {member.st} : {member.type.annotation() if member.type else ''} := (...): a "
                                    "FUNCTION_BLOCK member of a STRUCT with an initialiser is not supported (set its inputs in code, "
                                    "or make the STRUCT a FUNCTION_BLOCK)", element)
                self.emit(self.field_line(member, init, scope, plain=True), 1)
            self.trail(index, trailing)
        if not node.declarations:
            self.emit("pass", 1)

    def _pack_mode(self, node: Any) -> int | None:
        """``{attribute 'pack_mode' := 'n'}`` before a STRUCT or UNION: its members' largest alignment (0 is 1)."""
        for pragma in self.pragmas(node):
            found = re.fullmatch(r"\{\s*attribute\s+'pack_mode'\s*:=\s*'([^']*)'\s*\}", pragma, re.IGNORECASE)
            if found is None:
                continue
            if found.group(1).strip() not in ("0", "1", "2", "4", "8"):
                raise self.fail(f"{pragma}: pack_mode is 0, 1, 2, 4 or 8 (the largest alignment of the members)", node)
            return max(int(found.group(1)), 1)
        return None

    # --- field declarations ---

    def field_line(self, member: Member, init: Any, scope: Scope, *, plain: bool = False, extra: str = "") -> str:
        type_ = member.type
        assert type_ is not None
        if type_.kind == "any":
            raise self.fail(f"{member.section} {member.st} : {type_.name}: a generic type is not supported outside a VAR_INPUT of a FUNCTION or METHOD")
        if type_.kind == "array" and type_.bounds is None and member.section != "VAR_IN_OUT":
            raise self.fail(f"{member.section} {member.st} : ARRAY[*] is not supported outside a VAR_IN_OUT (of a block, METHOD or FUNCTION)")
        if type_.kind == "varinfo" and member.section == "VAR_TEMP" and scope.kind == "body":
            # VAR_TEMP is new at every call of the body: a Python local of body(), set by := __VARINFO(x)
            scope.locals[member.st.lower()] = Member(member.name, type_, "LOCAL", st=member.st)
            return f"# {member.st} : __SYSTEM.VAR_INFO (VAR_TEMP) is a local of body()"
        if type_.kind == "varinfo":
            raise self.fail(f"{member.section} {member.st} : __SYSTEM.VAR_INFO (declare it as a local of a METHOD or FUNCTION)")
        self._need_type(type_)
        args: list[str] = []
        value = self._field_initial_value(member.name, type_, init, scope)
        if value is not None:
            args.append(value)
        kwargs = _shape_keywords(type_)
        fb_init = self.fb_init_args(init, scope)
        if fb_init:
            kwargs.append(f"fb_init={fb_init}")
        if extra:
            kwargs.append(extra)
        if member.name != member.st and member.name in (python_name(member.st, attribute=True), field_name(member.st, type_)):
            kwargs.append(st_keyword(member.st, member.name, ""))
        section = member.section if member.section != "VAR_GLOBAL" else "VAR"
        note = f"  # {type_.name}({type_.limits[0]}..{type_.limits[1]})" if type_.limits is not None else ""
        if plain and not kwargs and value is not None:
            return f"{member.name}: {type_.annotation()} = {value}{note}"
        self.need("iecoop", section)
        return f"{member.name}: {type_.annotation()} = {section}({', '.join(args + kwargs)}){note}"

    def _field_initial_value(self, name: str, type_: TypeRef, init: Any, scope: Scope) -> str | None:
        """The initial value of the field ``name``; in a block, a reference or pointer its initialiser binds waits."""
        self.field_path = f"self.{name}" if scope.owner is not None and scope.kind in ("body", "method") else None
        try:
            return self.initial_value(type_, init, scope)
        finally:
            self.field_path = None

    def fb_init_args(self, init: Any, scope: Scope) -> str:
        call: Any = None
        if isinstance(init, tf.FunctionBlockInvocationDeclaration):
            call = init.init
            type_name, parameters = str(call.name.name), call.parameters
        elif isinstance(init, tf.TypeInitialization) and isinstance(init.spec, tf.IndirectSimpleSpecification) and init.spec.init_parameters:
            call = init
            type_name, parameters = str(init.spec.type.type), init.spec.init_parameters
        # ``R_TRIG()``: empty parentheses, an FB_init call without arguments (blark gives a None parameter)
        parameters = [p for p in parameters if p is not None] if call is not None else []
        if parameters:
            decl = self.decls.get(type_name.lower())
            fb_init = self.find_member(decl, "FB_init") if decl is not None else None
            params = fb_init[1].params if fb_init is not None and isinstance(fb_init[1], Callable_) else []
            params = [p for p in params if p.st.lower() not in ("binitretains", "bincopycode")]
            pairs = []
            for index, param in enumerate(parameters):
                if isinstance(param, tf.OutputParameterAssignment):
                    raise self.fail("an output (=>) in an FB_init call of a declaration", init)
                if param.name is not None:
                    name = str(param.name.name)
                    match = next((p.name for p in params if p.st.lower() == name.lower()), python_name(name))
                elif index < len(params):
                    match = params[index].name
                else:
                    raise self.fail(f"FB_init of {type_name} has no input number {index + 1}", init)
                pairs.append(f'"{match}": {self._fb_init_value(param.value, match, type_name, init, scope)}')
            return "{" + ", ".join(pairs) + "}"
        return ""

    def _fb_init_value(self, value: Any, name: str, type_name: str, init: Any, scope: Scope) -> str:
        """The code of one FB_init argument of a declaration: a variable of the same block is ``sibling("x")``,
        its address ``adr_of("x")``, taken from each instance as the member's FB_init runs."""
        if isinstance(value, tf.FunctionCall) and str(value.name).upper() == "ADR" and len(value.parameters) == 1:
            found = self._sibling_target(value.parameters[0].value, scope)
            if found is not None:
                self.need("iecoop", "adr_of")
                return f"adr_of({found})"
        found = self._sibling_target(value, scope)
        if found is not None:
            self.need("iecoop", "sibling")
            return f"sibling({found})"
        code = self.expr(value, scope).code
        if re.search(r"\bself\b", code):
            # an expression of the block's variables has no instance to be computed in before FB_init runs
            raise self.fail(f"FB_init argument {name} of {type_name} computes with variables of the same block "
                            f"({value}): not supported (pass the variable itself, or a GVL variable)", init)
        return code

    def _sibling_target(self, target: Any, scope: Scope) -> str | None:
        """``"x"`` / ``"a", 3`` when ``target`` is a variable ``x`` (or ``a[3]``) of the block being declared."""
        index = ""
        if isinstance(target, tf.MultiElementVariable) and len(target.elements) == 1 and isinstance(target.elements[0], tf.SubscriptList):
            subscripts = target.elements[0].subscripts
            if not all(isinstance(sub, tf.Integer) for sub in subscripts):
                return None
            numbers = [self.expr(sub, scope).code for sub in subscripts]
            index = ", " + (numbers[0] if len(numbers) == 1 else "(" + ", ".join(numbers) + ")")
            target = target.name
        if scope.owner is None or not isinstance(target, tf.SimpleVariable) or target.dereferenced:
            return None
        found = self.find_member(scope.owner, str(target.name))
        if found is None or not isinstance(found[1], Member):
            return None
        return f'"{found[1].name}"{index}'

    def sibling_address(self, type_: TypeRef, init: Any, scope: Scope) -> str | None:
        """``p : POINTER TO T := ADR(x);`` / ``r : REFERENCE TO T := x;`` of a member beside it: ``adr_of("x")``."""
        target = getattr(init, "value", None)
        if type_.kind == "pointer":
            if not (isinstance(target, tf.FunctionCall) and str(target.name).upper() == "ADR" and len(target.parameters) == 1):
                return None
            target = target.parameters[0].value
        elif isinstance(target, tf.ArrayInitialization) and not target.brackets and len(target.elements) == 1:
            target = target.elements[0].element  # blark reads `ref : REFERENCE TO ARRAY.. := a` as an array value
        found = self._sibling_target(target, scope)
        if found is None:
            return None
        self.need("iecoop", "adr_of")
        return f"adr_of({found})"

    def initial_value(self, type_: TypeRef, init: Any, scope: Scope) -> str | None:
        if type_.kind in ("pointer", "reference"):
            sibling = self.sibling_address(type_, init, scope)
            if sibling is not None:
                return sibling
        if type_.kind == "reference" and getattr(init, "value", None) is not None:
            if scope.owner is None or scope.kind != "body":
                raise self.fail("a REFERENCE TO initialised at its declaration is supported in a block's VAR only", init)
            self.pending_references.append(init.value)
            return None
        value = _declared_value(init)
        if value is None:
            return self._implicit_initial_value(type_)
        if self.subrange(type_) is not None:
            return self.limit(type_, self.expr(value, scope)).code
        if isinstance(value, lark_token_type()):
            if type_.kind == "string":
                return python_string(str(value))
            raise self.fail(f"initial value {value}", init)
        return self.init_value(value, type_, scope)

    def _implicit_initial_value(self, type_: TypeRef) -> str | None:
        """Where no value is declared: an enumeration's first value, a subrange's lower limit, else None (zero)."""
        decl = self.decl_of(type_) if type_.kind == "user" else None
        if decl is not None and decl.kind == "enum" and decl.values:
            return self.enum_default(decl)
        if type_.limits is not None:
            return type_.limits[0]  # a subrange starts at its lower limit (IEC 61131-3)
        return None

    def init_value(self, value: Any, type_: TypeRef | None, scope: Scope) -> str:
        if isinstance(value, tf.ArrayInitialization):
            element = type_.of if type_ is not None and type_.kind == "array" else None
            return "[" + ", ".join(self._array_elements(value, element, scope)) + "]"
        elements = structure_elements(value)
        if elements is not None:
            decl = self.decl_of(type_)
            pairs = []
            for element_name, element_value in elements:
                if element_name is None:
                    raise self.fail("a structure initialiser element without a name", value)
                found = self.find_member(decl, element_name) if decl is not None else None
                name = found[1].name if found is not None else python_name(element_name, attribute=True)
                member_type = found[1].type if found is not None and isinstance(found[1], Member) else None
                if member_type is not None and member_type.kind in ("reference", "pointer") and self._bound_later(name, member_type, element_value):
                    continue
                outer, self.field_path = self.field_path, f"{self.field_path}.{name}" if self.field_path else None
                try:
                    pairs.append(f'"{name}": {self.init_value(element_value, member_type, scope)}')
                finally:
                    self.field_path = outer
            return "{" + ", ".join(pairs) + "}"
        if isinstance(value, tf.EnumeratedValue):
            enum_name = str(value.type_name) if value.type_name is not None else None
            return self.enum_ref(enum_name, str(value.name), value)
        return self.coerce(self.expr(value, scope, expected=type_), type_).code

    def _bound_later(self, name: str, type_: TypeRef, value: Any) -> bool:
        """``(ref := x)`` / ``(p := ADR(x))`` in a block's field initialiser: bound after init, as the PLC binds it.

        A constant (``p := 0``) is an initial value like any other; a variable's address is known only once the
        instance exists, so the binding waits for ``call_after_init`` (see ``_emit_reference_inits``).
        """
        if type_.kind == "pointer" and not isinstance(value, tf.FunctionCall):
            return False
        if self.field_path is None:
            raise self.fail(f"{name} := ...: a REFERENCE TO or POINTER TO bound to a variable in an initialiser is not supported outside a block's VAR (bind it in code, REF= or := ADR(...))", value)
        self.pending_member_references.append((self.field_path, name, type_, value))
        return True

    def _array_elements(self, value: Any, element: TypeRef | None, scope: Scope) -> Iterator[str]:
        produced = 0
        for item in value.elements:
            count = 1
            if item.count is not None:
                count = int(eval(self.expr(item.count, scope).code, {}))
            if isinstance(item.element, tf.ArrayInitialization) and not item.element.brackets:
                values = list(self._array_elements(item.element, element, scope))
            else:
                values = [self.init_value(item.element, element, scope)]
            produced += count * len(values)
            if produced > MAX_INITIAL_VALUES:  # counted before they are made: [1000000000(0)] would take hours
                raise self.fail(f"an ARRAY initialiser of more than {MAX_INITIAL_VALUES} values (n(x) is n values) is not "
                                "supported: set the elements in a FOR loop or FB_init", value)
            for _ in range(count):
                yield from values

    # --- POUs ---

    def _class_kwargs(self, access: Any) -> str:
        kwargs = flag_keywords(access, tf.AccessSpecifier, ("abstract", "final", "internal"))
        return "".join(f", {k}" for k in kwargs)
