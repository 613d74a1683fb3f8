"""Pass 2, expressions: one ``visit_<blark node>`` per expression kind, each giving an ``Ex``."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import blark.transform as tf

from iecoop.exceptions import DefinitionError
from iecoop.st.language import COMPARISONS, INTEGER_LAYOUT, VAR_INFO_MEMBERS
from iecoop.st.read.assignable import comparison_mismatch, store_mismatch
from iecoop.st.read.checks import checked_divisor, checked_indices
from iecoop.st.read.dates import date_arithmetic
from iecoop.st.read.frames import Ex, PRECEDENCE, Scope
from iecoop.st.read.names import python_name
from iecoop.st.read.system import SystemLists
from iecoop.st.read.lookup import unknown_name
from iecoop.st.read.table import BOOL, Callable_, Decl, LREAL, Member, STRING, TypeRef
from iecoop.st.read.trees import has_call, system_list_entry, variables


def _plain(type_: TypeRef | None) -> TypeRef | None:
    """The type an operand is computed in: a REFERENCE TO's target."""
    return type_.deref() if type_ is not None else None


class Expressions(SystemLists):
    """Reads ST expressions into ``Ex`` objects: Python code with its ST type."""

    def arguments(self, params: Sequence[Any], declared: Sequence[Member] | None, scope: Scope, node: Any) -> list[str]:
        """Defined by a later phase of the translator."""
        raise NotImplementedError

    def call(self, node: Any, scope: Scope, level: int | None) -> Ex | None:
        """Defined by a later phase of the translator."""
        raise NotImplementedError

    def enum_ref(self, enum_name: str | None, value: str, node: Any) -> str:
        if enum_name is not None:
            decl = self._enum_through_alias(self.decls.get(enum_name.lower()))
            if decl is None or decl.kind != "enum":
                raise self.fail(f"unknown enumeration {enum_name!r}", node)
            match = next((v for v in decl.values if v.lower() == value.lower()), None)
            if match is None:
                raise self.fail(f"enumeration {decl.st} has no value {value!r}", node)
            return f"{decl.name}.{python_name(match, attribute=True)}"
        if "." in value:  # blark reads a qualified value (E_Mode.AUTO) as one dotted name
            prefix, _, last = value.rpartition(".")
            return self.enum_ref(prefix, last, node)
        found = self.enum_values.get(value.lower())
        if found is None:
            raise self.fail(f"unknown enumeration value {value!r}", node)
        return f"{found[0]}.{found[1]}"

    def _enum_through_alias(self, decl: Decl | None) -> Decl | None:
        """``decl``, or the enumeration an alias of it names (``TYPE T_Order : E_Order``: T_Order.Before)."""
        if decl is not None and decl.kind == "alias":
            target = self.decl_of(TypeRef("user", decl.name))
            if target is not None and target.kind == "enum":
                return target
        return decl

    def _system_alias(self, decl: Decl) -> Ex | None:
        """``TYPE T_Kind : __SYSTEM.TYPE_CLASS``: T_Kind names the system enumeration (T_Kind.TYPE_LREAL); else None."""
        spec = getattr(getattr(decl.node, "init", None), "spec", None)
        if str(spec).strip().upper() == "__SYSTEM.TYPE_CLASS":
            self.need("iecoop", "TYPE_CLASS")
            return Ex("TYPE_CLASS", TypeRef("user", "__SYSTEM.TYPE_CLASS"))
        return None

    def _aggregate(self, type_: TypeRef) -> bool:
        """Whether a value of ``type_`` is an ARRAY, STRUCT or UNION (copied when passed by value)."""
        decl = self.decl_of(type_) if type_.kind == "user" else None
        return type_.kind == "array" or decl is not None and decl.kind in ("struct", "union")

    def _copied(self, type_: TypeRef) -> bool:
        """Whether an assignment of ``type_`` copies a value with members (STRUCT, UNION, ARRAY or block)."""
        decl = self.decl_of(type_) if type_.kind == "user" else None
        return self._aggregate(type_) or decl is not None and decl.kind in ("fb", "stdfb")

    def _local_reference(self, type_: TypeRef | None) -> bool:
        """A REFERENCE TO a STRUCT, UNION or FB: a local of a method or function holds the view of its target."""
        decl = self.decl_of(type_) if type_ is not None and type_.kind == "reference" else None
        return decl is not None and decl.kind in ("struct", "union", "fb", "stdfb")

    def local_of(self, target: Any, scope: Scope) -> Member | None:
        if isinstance(target, tf.SimpleVariable) and not target.dereferenced:
            return scope.locals.get(str(target.name).lower())
        return None

    def subrange(self, type_: TypeRef | None) -> TypeRef | None:
        """The subrange type behind ``type_`` (itself, or the subrange TYPE it names), or None."""
        if type_ is None:
            return None
        if type_.limits is not None:
            return type_
        decl = self.decl_of(type_)
        if decl is not None and decl.kind == "alias" and decl.alias_of is not None and decl.alias_of.limits is not None:
            return decl.alias_of
        return None

    def limit(self, target: TypeRef | None, value: Ex) -> Ex:
        """``value`` stored into a subrange: a constant must lie in it (a compile error on the PLC); another
        value is held to the limits, as TwinCAT's and CODESYS' implicit checks CheckRangeSigned / Unsigned do."""
        subrange = self.subrange(target)
        if subrange is None or subrange.limits is None:
            return value
        low, high = subrange.limits
        if isinstance(value.constant, int):
            if not int(low) <= value.constant <= int(high):
                raise self.fail(f"{value.code} is outside the subrange {subrange.name}({low}..{high})")
            return Ex(value.code, subrange, constant=value.constant)
        self.need("iecoop.functions", "LIMIT")
        return Ex(f"LIMIT({low}, {value.code}, {high})", subrange)

    def _fits(self, value: Ex, target: TypeRef) -> bool:
        if isinstance(value.constant, int):
            bits, signed = INTEGER_LAYOUT[target.name]
            number = value.constant
            low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
            return low <= number <= high
        return value.type is not None and value.type.name == target.name and not value.compound

    def _reference_property(self, node: Any, scope: Scope) -> Ex | None:
        """``x.Prop`` when ``Prop`` is a PROPERTY of type REFERENCE TO a STRUCT, UNION or block, else None."""
        if not (isinstance(node, tf.MultiElementVariable) and isinstance(node.elements[-1], tf.FieldSelector)):
            return None
        rest = tf.MultiElementVariable(node.name, node.dereferenced, node.elements[:-1]) if len(node.elements) > 1 else node.name
        owner = self.decl_of(self.expr(rest, scope).type)
        found = self.find_member(owner, str(node.elements[-1].field)) if owner is not None else None
        if found is None or found[0] != "prop":
            return None
        target = self.expr(node, scope)
        return target if target.type is not None and self._local_reference(target.type) else None

    # --- expressions ---

    def expr(self, node: Any, scope: Scope, *, store: bool = False, expected: TypeRef | None = None) -> Ex:
        handler = None
        if not isinstance(node, tf.Statement) and type(node).__name__ != "Tree":
            handler = getattr(self, f"visit_{type(node).__name__}", None)
        elif type(node).__name__ == "Tree" and str(node.data) == "call_member":
            handler = self.call_member
        if handler is None:
            self.generic_visit(node, "expression")
        result: Ex = handler(node, scope) if not store else handler(node, scope, store=True) if type(node).__name__ in ("SimpleVariable", "MultiElementVariable") else handler(node, scope)
        return result

    def coerce(self, value: Ex, type_: TypeRef | None, into: str | None = None) -> Ex:
        """``value`` as stored in a ``type_`` (``into`` names the variable or input, for the refusal's message)."""
        if type_ is not None and type_.kind == "pointer" and value.this == "THIS":
            # THIS is a POINTER TO the block: stored in a pointer (pSelf := THIS) it is the instance's address
            self.need("iecoop", "adr")
            value = Ex("adr(self)", TypeRef("pointer", "POINTER_TO", of=value.type) if value.type is not None else type_)
        if type_ is not None and type_.is_bool and type(value.constant) is int and value.constant in (0, 1):
            return Ex(str(bool(value.constant)), type_, constant=bool(value.constant))  # BOOL := 0 / 1, as TwinCAT reads it
        self._refuse_mismatch(type_, value, into)
        if type_ is not None and type_.is_real and isinstance(value.constant, int):
            return Ex(f"{value.code}.0", type_, constant=float(value.constant))
        if type_ is not None and type_.kind == "pointer" and type_.of is not None and value.type is not None \
                and value.type.kind == "pointer" and value.type.of is not None and value.type.of.annotation() != type_.of.annotation():
            self._need_type(type_)
            return Ex(f"{value.p()}.typed({type_.of.annotation()})", type_)  # ST converts pointers implicitly: the same address
        return value

    def refuse_conversion(self, type_: TypeRef | None, value: Ex, into: str | None) -> None:
        """A value of a type ST does not convert implicitly into ``type_`` (a STRING into an INT...) is refused where
        a compiler refuses it, not when a cycle stores it (a TypeError there, RTSEXCPT_UNKNOWN)."""
        why = store_mismatch(type_, value.type, self.decl_of) if value.constant is None else None
        if why is not None:
            raise self.fail(f"{into}: {why}" if into else why)

    def _refuse_mismatch(self, type_: TypeRef | None, value: Ex, into: str | None) -> None:
        """``refuse_conversion``, and a number stored in a STRING or BOOL."""
        self.refuse_conversion(type_, value, into)
        target = type_.deref() if type_ is not None else None
        if target is not None and type(value.constant) in (int, float) and (target.is_string or target.is_bool):
            raise self.fail(f"the number {value.code} cannot be stored in a {target.name} "
                            f"({'a string literal or a conversion such as INT_TO_STRING' if target.is_string else 'TRUE or FALSE'})")

    def visit_ParenthesizedExpression(self, node: tf.ParenthesizedExpression, scope: Scope) -> Ex:
        inner = self.expr(node.expr, scope)
        return Ex(inner.code, inner.type, inner.compound, constant=inner.constant, this=inner.this)

    def visit_BracketedExpression(self, node: tf.BracketedExpression, scope: Scope) -> Ex:
        return self.expr(node.expression, scope)

    def visit_UnaryOperation(self, node: tf.UnaryOperation, scope: Scope) -> Ex:
        op = str(node.op).upper()
        inner = self.expr(node.expr, scope)
        if op == "-":
            if inner.constant is not None and inner.constant >= 0:
                return Ex(f"-{inner.code}", inner.type, constant=-inner.constant)
            return Ex(f"-{inner.wrap(PRECEDENCE['unary'])}", inner.type, True, PRECEDENCE["unary"])
        if op == "+":
            return inner
        if op == "NOT":
            if inner.type is not None and inner.type.deref().is_int:
                return Ex(f"~{inner.wrap(PRECEDENCE['unary'])}", inner.type, True, PRECEDENCE["unary"])
            return Ex(f"not {inner.wrap(PRECEDENCE['not'])}", BOOL, True, PRECEDENCE["not"])
        raise self.fail(f"unary operator {op}", node)

    def visit_BinaryOperation(self, node: tf.BinaryOperation, scope: Scope) -> Ex:
        op = str(node.op).upper()
        left = self.expr(node.left, scope)
        right = self.expr(node.right, scope)
        if op in COMPARISONS:
            return self._comparison(COMPARISONS[op], left, right)
        if op in ("AND", "&", "OR", "XOR", "AND_THEN", "OR_ELSE"):
            return self._logical(op, node, left, right, scope)
        right = checked_divisor(self.decls, op, self.wider(_plain(left.type), _plain(right.type)), right, scope)
        return self._arithmetic(op, node, left, right)

    def _comparison(self, py: str, left: Ex, right: Ex) -> Ex:
        if "THIS" in (left.this, right.this):  # a pointer compared with THIS (aSuites[i] = THIS) compares addresses
            left, right = self.coerce(left, right.type), self.coerce(right, left.type)
        for side, other in ((left, right), (right, left)):
            if isinstance(other.constant, int) and other.constant == 0 and side.type is not None and self._is_handle(side.type):
                self.need("iecoop", "NULL")
                return Ex(f"{side.p()} {py} NULL", BOOL, True)
        why = comparison_mismatch(left.type, right.type, self.decl_of)
        if why is not None:
            raise self.fail(why)
        level = PRECEDENCE["compare"]  # both sides wrapped when they compare too: Python would chain them
        return Ex(f"{left.wrap(level + 1)} {py} {right.wrap(level + 1)}", BOOL, True, level)

    def _logical(self, op: str, node: tf.BinaryOperation, left: Ex, right: Ex, scope: Scope) -> Ex:
        """AND, OR, XOR (and AND_THEN, OR_ELSE): Python's ``and`` / ``or`` on BOOL, bit operators on bit strings."""
        lt, rt = _plain(left.type), _plain(right.type)
        logical = (lt is None or lt.is_bool) and (rt is None or rt.is_bool)
        if op in ("AND", "&", "OR") and logical and self._has_effect(node.right, scope):
            # ST evaluates both operands of AND / OR (only AND_THEN / OR_ELSE stop early): a call on
            # the right runs even when the left decides, so the operands are combined with & / |
            symbol = "&" if op != "OR" else "|"
            level = PRECEDENCE[symbol]
            return Ex(f"{self._as_bool(left).wrap(level)} {symbol} {self._as_bool(right).wrap(level + 1)}", BOOL, True, level)
        if op == "XOR" and logical:
            level = PRECEDENCE["compare"]
            return Ex(f"{left.wrap(level + 1)} != {right.wrap(level + 1)}", BOOL, True, level)
        if op in ("AND_THEN", "OR_ELSE") or logical:
            word = {"AND": "and", "&": "and", "AND_THEN": "and", "OR": "or", "OR_ELSE": "or"}[op]
            level = PRECEDENCE[word]
            return Ex(f"{left.wrap(level)} {word} {right.wrap(level + 1)}", BOOL, True, level)
        symbol = {"AND": "&", "&": "&", "OR": "|", "XOR": "^"}[op]
        level = PRECEDENCE[symbol]
        return Ex(f"{left.wrap(level)} {symbol} {right.wrap(level + 1)}", self.wider(lt, rt), True, level)

    def _arithmetic(self, op: str, node: tf.BinaryOperation, left: Ex, right: Ex) -> Ex:
        dated = date_arithmetic(op, left, right)
        if isinstance(dated, str):
            raise self.fail(dated, node)
        if dated is not None:
            return dated
        lt, rt = _plain(left.type), _plain(right.type)
        if op == "/" and not ((lt is not None and lt.is_real) or (rt is not None and rt.is_real)):
            op = "DIV"  # ST's / on integers truncates
        if op in ("+", "-", "*", "/"):
            level = PRECEDENCE[op]
            return Ex(f"{left.wrap(level)} {op} {right.wrap(level + 1)}", self.wider(lt, rt), True, level)
        if op == "MOD" and any(t is not None and t.is_real for t in (lt, rt)):
            raise self.fail("MOD of a REAL: MOD is defined for integers (IEC 61131-3 ANY_INT)", node)
        if op in ("DIV", "MOD"):
            self.need("iecoop.conversions", op)
            return Ex(f"{op}({left.code}, {right.code})", self.wider(lt, rt))
        if op == "**":
            level = PRECEDENCE["**"]
            return Ex(f"{left.wrap(level + 1)} ** {right.wrap(level)}", LREAL, True, level)
        raise self.fail(f"operator {op}", node)

    def _has_effect(self, node: Any, scope: Scope) -> bool:
        """Whether evaluating ``node`` runs code: a call, or a read of a PROPERTY (its Get accessor)."""
        if has_call(node):
            return True
        for variable in variables(node):
            if isinstance(variable, tf.SimpleVariable):
                owner, name = scope.owner, str(variable.name)
                if name.lower() in scope.locals:
                    continue
            elif isinstance(variable.elements[-1], tf.FieldSelector) and not str(variable.elements[-1].field).isdigit():
                rest = tf.MultiElementVariable(variable.name, False, variable.elements[:-1]) if len(variable.elements) > 1 else variable.name
                owner = self.decl_of(self.expr(rest, scope).type)
                field = variable.elements[-1].field
                name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
            else:
                continue
            found = self.find_member(owner, name) if owner is not None else None
            if found is not None and found[0] == "prop":
                return True
        return False

    def _as_bool(self, operand: Ex) -> Ex:
        """``operand`` as a Python bool, for ``&`` / ``|``: a call whose type is not known is wrapped in ``bool()``."""
        if operand.type is not None and operand.type.deref().is_bool:
            return operand
        return Ex(f"bool({operand.code})", BOOL)

    def _is_handle(self, type_: TypeRef) -> bool:
        if type_.kind == "pointer":
            return True
        decl = self.decl_of(type_)
        return decl is not None and decl.kind == "interface"

    def wider(self, left: TypeRef | None, right: TypeRef | None) -> TypeRef | None:
        if left is None:
            return right
        if right is None:
            return left
        if left.is_real or right.is_real:
            return LREAL if "LREAL" in (left.name, right.name) or not (left.is_real and right.is_real) and False else (left if left.is_real else right)
        if left.is_int and right.is_int:
            return left if INTEGER_LAYOUT[left.name][0] >= INTEGER_LAYOUT[right.name][0] else right
        return left

    def visit_SimpleVariable(self, node: tf.SimpleVariable, scope: Scope, store: bool = False) -> Ex:
        base = self.name_ref(str(node.name), scope, node)
        if node.dereferenced:
            return self.deref(base, node)
        return base

    def call_member(self, node: Any, scope: Scope) -> Ex:
        """``F(x)^.y`` (the grammar overlay's ``call_member``): a member of what a call's result points to."""
        call, *selectors = node.children
        current = self.expr(dataclasses.replace(call, dereferenced=False), scope)
        if call.dereferenced:
            current = self.deref(current, call)
        for selector in selectors:
            field = selector.field
            current = self.member_ref(current, str(field.name) if isinstance(field, tf.SimpleVariable) else str(field), call)
            if selector.dereferenced:
                current = self.deref(current, call)
        return current

    def deref(self, base: Ex, node: Any) -> Ex:
        if base.this is not None:  # THIS^ and SUPER^ are the instance
            return base
        target = base.type.of if base.type is not None and base.type.kind == "pointer" else None
        if base.type is not None and base.type.kind != "pointer":
            raise self.fail(f"^ applied to {base.code}, which is not a POINTER", node)
        return Ex.attribute(base.p(), "deref", target)

    def _instance_ref(self, key: str, scope: Scope) -> Ex | None:
        """THIS (``self``) and SUPER (``super()``), typed by the block and its parent; None for any other name."""
        if key == "this":
            return Ex("self", TypeRef("user", scope.owner.name) if scope.owner else None, this="THIS")
        if key == "super":
            base = self.decls.get(scope.owner.bases[0].lower()) if scope.owner and scope.owner.bases else None
            return Ex("super()", TypeRef("user", base.name) if base is not None else None, this="SUPER")
        return None

    def name_ref(self, name: str, scope: Scope, node: Any) -> Ex:
        key = name.lower()
        instance = self._instance_ref(key, scope)
        if instance is not None:
            return instance
        local = scope.locals.get(key)
        if local is not None:
            if local.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                return Ex.attribute(local.name, "deref", local.type)
            return Ex(local.name, local.type, place=local.place)
        if scope.owner is not None and scope.owner.kind in ("fb", "program", "interface", "struct", "union"):
            found = self.find_member(scope.owner, name)
            if found is not None and not (scope.kind == "const" and scope.owner.kind in ("struct", "union")):
                kind, member = found
                if kind == "method":
                    return Ex.attribute("self", member.name, None)
                assert isinstance(member, Member)
                return Ex.attribute("self", member.name, member.type)
        if key in self.globals:
            gvl_name, member = self.globals[key]
            return Ex.attribute(gvl_name, member.name, member.type)
        decl = self._enum_through_alias(self.decls.get(key))
        if decl is not None and decl.kind == "alias":
            system = self._system_alias(decl)
            if system is not None:
                return system
        if decl is not None and decl.kind != "stdfb":
            return Ex(decl.name, TypeRef("user", decl.name) if decl.kind in ("gvl", "enum", "program") else None)
        if key in self.enum_values:
            enum, value = self.enum_values[key]
            return Ex(f"{enum}.{value}", TypeRef("user", enum))
        if key == "__system":
            return Ex("__SYSTEM", TypeRef("user", "__SYSTEM"))
        raise self.fail(f"unknown variable {name!r}", node)

    def member_ref(self, base: Ex, field: str, node: Any, store: bool = False) -> Ex:
        """``base.field``: a system member, an enumeration value, or a member or method of a declared type."""
        system = self._system_member_ref(base, field, node, store)
        if system is not None:
            return system
        decl = self.decl_of(base.type)
        if decl is None:
            if base.type is None:
                raise self.fail(f"cannot tell the type of {base.code} to read its member {field!r}", node)
            raise self.fail(f"{base.type.annotation()} has no member {field!r}", node)
        if decl.kind == "enum":
            match = next((v for v in decl.values if v.lower() == field.lower()), None)
            if match is None:
                raise self.fail(f"enumeration {decl.st} has no value {field!r}", node)
            return Ex(f"{decl.name}.{python_name(match, attribute=True)}", TypeRef("user", decl.name))
        found = self.find_member(decl, field)
        if found is None:
            raise self.fail(f"{decl.name} has no member {field!r}", node)
        kind, member = found
        if base.this == "SUPER":
            return self._super_member_ref(kind, member, store)
        if kind == "method":
            return Ex.attribute(base.p(), member.name, None)
        assert isinstance(member, Member)
        return Ex.attribute(base.p(), member.name, member.type)

    def _system_member_ref(self, base: Ex, field: str, node: Any, store: bool) -> Ex | None:
        """``__SYSTEM.ExceptionCode``, its values, and the members of a ``__SYSTEM.VAR_INFO``; None for any other base."""
        if base.type is not None and base.type.name == "__SYSTEM":
            if field.lower() == "exceptioncode":
                self.need("iecoop", "ExceptionCode")
                return Ex("ExceptionCode", TypeRef("user", "__SYSTEM.EXCEPTIONCODE"))
        if base.type is not None and base.type.name == "__SYSTEM" and field.lower() == "type_class":
            self.need("iecoop", "TYPE_CLASS")
            return Ex("TYPE_CLASS", TypeRef("user", "__SYSTEM.TYPE_CLASS"))
        if base.type is not None and base.type.name == "__SYSTEM.TYPE_CLASS":
            from iecoop.memory.operators import TYPE_CLASS

            if field.upper() not in TYPE_CLASS.__members__:
                raise self.fail(f"__SYSTEM.TYPE_CLASS has no value {field!r}", node)
            return Ex(f"TYPE_CLASS.{field.upper()}", TypeRef("elem", "DINT"))
        if base.code == "ExceptionCode":
            return Ex(f"ExceptionCode.{field.upper()}", TypeRef("user", "ExceptionCode"))
        if base.type is not None and base.type.kind == "varinfo":
            info = next((m for m in VAR_INFO_MEMBERS if m.lower() == field.lower()), None)
            if info is None or store:
                raise self.fail(f"__SYSTEM.VAR_INFO {'member ' + field + ' is read-only' if info else 'has no member ' + repr(field)}", node)
            return Ex(f"{base.p()}.{info}", STRING if info in ("Symbol", "TypeName") else TypeRef("elem", VAR_INFO_MEMBERS[info]))
        return None

    def _super_member_ref(self, kind: str, member: Any, store: bool) -> Ex:
        """``SUPER^.name``: the parent's method or property; a variable is the instance's own."""
        if kind == "method":
            return Ex.attribute("super()", member.name, None)
        if kind == "member":
            assert isinstance(member, Member)
            return Ex.attribute("self", member.name, member.type)  # a variable is not virtual: SUPER^.x is THIS^.x
        assert isinstance(member, Member)
        if store:
            self.need("iecoop", "super_set")
            return Ex.attribute("super()", member.name, member.type, super_property=True)  # written as super_set(super(), ...)
        return Ex.attribute("super()", member.name, member.type)

    def visit_MultiElementVariable(self, node: tf.MultiElementVariable, scope: Scope, store: bool = False) -> Ex:
        system = system_list_entry(node)  # TwinCAT_SystemInfoVarList's _TaskInfo and _AppInfo
        if system is not None:
            return self.task_info(system[1], node, scope, store) if system[0] == "_taskinfo" else self.app_info(system[1], node, store)
        first = node.elements[0] if node.elements else None
        current = self._head(node, first, scope)
        elements = list(node.elements)
        for index, element in enumerate(elements):
            if isinstance(element, tf.SubscriptList):
                current = self._subscripted(current, element, scope, node)
                continue
            field = element.field
            field_name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
            if field_name.isdigit():
                if store and index == len(elements) - 1:
                    raise self.fail("bit assignment in this position", node)
                self.need("iecoop.functions", "get_bit")
                current = Ex(f"get_bit({current.code}, {field_name})", BOOL)
                continue
            if element.dereferenced:
                # blark marks the ^ of ``p^.x[i]`` on the field selector that follows it: dereference first.
                current = self.deref(current, node)
            current = self.member_ref(current, field_name, node, store=store and index == len(elements) - 1)
            if isinstance(field, tf.SimpleVariable) and field.dereferenced:
                current = self.deref(current, node)
        return current

    def _subscripted(self, current: Ex, element: tf.SubscriptList, scope: Scope, node: Any) -> Ex:
        """``a[i, j]`` of an ARRAY (or of a pointer: ``_pointer_element``), dereferenced when ``^`` follows."""
        indices = [self.expr(s, scope).code for s in element.subscripts]
        if current.type is not None and current.type.kind == "pointer":
            current = self._pointer_element(current, indices, node)
        else:
            array = current.type.deref() if current.type is not None and current.type.deref().kind == "array" else None
            indices = checked_indices(self.decls, array, indices, scope)  # the project's CheckBounds, if any
            current = Ex(f"{current.p()}[{', '.join(indices)}]", array.of if array is not None else None)
        return self.deref(current, node) if element.dereferenced else current

    def _pointer_element(self, pointer: Ex, indices: list[str], node: Any) -> Ex:
        """``p[i]`` of a ``POINTER TO T``: the i-th T from where p points, ``(p + i * SIZEOF(T))^``; of a POINTER TO
        STRING its i-th byte (TwinCAT, CODESYS: index access through a pointer)."""
        target = pointer.type.of if pointer.type is not None else None
        if len(indices) != 1 or target is None:
            raise self.fail(f"{pointer.code}[...]: a pointer is indexed with one index, through a POINTER TO a type", node)
        if target.kind == "string":
            self.need("iecoop", "BYTE")
            return Ex.attribute(f"({pointer.p()}.typed(BYTE) + ({indices[0]}))", "deref", TypeRef("elem", "BYTE"))
        if target.kind not in ("elem", "user", "pointer"):
            raise self.fail(f"indexing a POINTER TO {target.annotation()} is not supported (index the variable it points to)", node)
        self.need("iecoop", "sizeof")
        self._need_type(target)
        return Ex.attribute(f"({pointer.p()} + ({indices[0]}) * sizeof({target.annotation()}))", "deref", target)

    def _head(self, node: tf.MultiElementVariable, first: Any, scope: Scope) -> Ex:
        """The variable ``a`` of ``a.b.c``; ``Tc2_Utilities.NoSuch(x)`` is refused naming the library and the name."""
        try:
            return self.visit_SimpleVariable(node.name, scope)
        except DefinitionError:
            if isinstance(first, tf.FieldSelector) and str(node.name.name).lower() in self.decls.namespaces:
                raise self.fail(unknown_name("name", f"{node.name.name}.{first.field}", self.decls), node) from None
            raise

    def bit_target(self, target: Any, scope: Scope) -> tuple[str, str] | None:
        if not isinstance(target, tf.MultiElementVariable) or not target.elements:
            return None
        last = target.elements[-1]
        if not isinstance(last, tf.FieldSelector):
            return None
        field = last.field
        name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
        if not name.isdigit():
            return None
        holder = tf.MultiElementVariable(target.name, False, target.elements[:-1]) if len(target.elements) > 1 else target.name
        return self.expr(holder, scope).code, name

    def holder_field(self, node: Any, scope: Scope) -> tuple[str, str]:
        """``(holder code, field name)`` of a variable that is a field of something."""
        if isinstance(node, tf.SimpleVariable):
            ex = self.name_ref(str(node.name), scope, node)
        elif isinstance(node, tf.MultiElementVariable) and isinstance(node.elements[-1], tf.FieldSelector):
            ex = self.expr(node, scope)
        else:
            raise self.fail("this variable has no holder to take its address from", node)
        if ex.place is None:
            what = "a local variable" if isinstance(node, tf.SimpleVariable) and str(node.name).lower() in scope.locals else "no variable"
            raise self.fail(f"{ex.code} is {what}; ADR / REF= need a variable of a block, struct or GVL", node)
        return ex.place

    def address_of(self, node: Any, scope: Scope) -> str:
        prop = self._reference_property(node, scope)
        if prop is not None:
            return prop.code  # REF= x.Prop: a REFERENCE TO property's Get gives the variable itself
        if isinstance(node, (tf.FunctionCall, tf.ChainedFunctionCall)):
            # REF= F(): a FUNCTION or METHOD that returns REFERENCE TO a STRUCT or block gives the variable itself
            ex = self.expr(node, scope)
            if ex.type is None or not self._local_reference(ex.type):
                raise self.fail(f"the address of a call's result ({ex.code}): only a call that returns REFERENCE TO a STRUCT, UNION or FUNCTION_BLOCK can be bound", node)
            return ex.code
        if isinstance(node, tf.SimpleVariable) and node.dereferenced and str(node.name).lower() != "this":
            return self.name_ref(str(node.name), scope, node).code  # ADR(p^) is p
        if isinstance(node, tf.MultiElementVariable) and getattr(node.elements[-1], "dereferenced", False):
            # ADR(a[i]^), ADR(s.p^): the pointer itself
            last = dataclasses.replace(node.elements[-1], dereferenced=False)
            return self.expr(tf.MultiElementVariable(node.name, node.dereferenced, [*node.elements[:-1], last]), scope).code
        return self._adr(node, scope)

    def _adr(self, node: Any, scope: Scope) -> str:
        """``adr(...)`` of a variable: an element of an ARRAY, the instance, a local STRUCT or block, or a field."""
        self.need("iecoop", "adr")
        if isinstance(node, tf.MultiElementVariable) and isinstance(node.elements[-1], tf.SubscriptList) and len(node.elements[-1].subscripts) == 1:
            rest = tf.MultiElementVariable(node.name, False, node.elements[:-1]) if len(node.elements) > 1 else node.name
            holder, field = self.holder_field(rest, scope)
            index = self.expr(node.elements[-1].subscripts[0], scope).code
            return f'adr({holder}, "{field}", {index})'
        if isinstance(node, tf.SimpleVariable) and str(node.name).lower() == "this" and node.dereferenced:
            return "adr(self)"
        if isinstance(node, tf.SimpleVariable) and str(node.name).lower() in scope.locals:
            local = scope.locals[str(node.name).lower()]
            if local.section in ("VAR_OUTPUT", "VAR_IN_OUT"):
                return local.name  # ADR(nHigh) of an output / in-out: the pointer the call got
            decl = self.decl_of(local.type)
            if decl is not None and decl.kind in ("struct", "union", "fb"):
                return f"adr({local.name})"
        holder, field = self.holder_field(node, scope)
        return f'adr({holder}, "{field}")'

    def visit_FunctionCall(self, node: tf.FunctionCall, scope: Scope) -> Ex:
        result = self.call(node, scope, level=None)
        assert result is not None
        return result

    def visit_ChainedFunctionCall(self, node: tf.ChainedFunctionCall, scope: Scope) -> Ex:
        current: Ex | None = None
        for invocation in node.invocations:
            if current is None:
                current = self.call(invocation, scope, level=None)
            else:
                method = self.member_ref(current, str(invocation.name.name), invocation)
                owner = self.decl_of(current.type)
                found = self.find_member(owner, str(invocation.name.name)) if owner is not None else None
                info = found[1] if found is not None and isinstance(found[1], Callable_) else None
                args = self.arguments(invocation.parameters, info.params if info else None, scope, invocation)
                current = Ex(f"{method.code}({', '.join(args)})", info.returns if info else None)
        assert current is not None
        return current
