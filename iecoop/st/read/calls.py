"""Pass 2, calls: FB, METHOD and FUNCTION calls, their arguments, and the standard and system functions."""

from __future__ import annotations

import re
import struct
from collections.abc import Callable, Sequence
from typing import Any

import blark.transform as tf

from iecoop.exceptions import DefinitionError

from iecoop.st.language import INTEGER_LAYOUT, MATH_FUNCTIONS, STRING_FUNCTIONS, SYSTEM_FUNCTIONS, TYPE_SYNONYMS
from iecoop.st.read.operators import Operators
from iecoop.st.read.frames import Ex, Scope
from iecoop.st.read.names import python_name
from iecoop.st.read.table import BOOL, Callable_, Decl, LREAL, Member, STRING, TypeRef
from iecoop.st.read.trees import assigned, variables



#: The unit each date and time type counts in: a conversion between two of them keeps the number only when it
#: is the same (DATE into DT, TOD into TIME).
_CALENDAR_UNITS = {"TIME": "ms", "TOD": "ms", "LTIME": "ns", "DATE": "s", "DT": "s"}

class Calls(Operators):
    """Reads calls: the callee, its arguments by name, and the standard functions."""

    def assign(self, target: Any, value: Ex, scope: Scope, level: int) -> None:
        """Defined by a later phase of the translator."""
        raise NotImplementedError

    def arguments(self, params: Sequence[Any], declared: Sequence[Member] | None, scope: Scope, node: Any) -> list[str]:
        """The Python arguments of a METHOD or FUNCTION call; ``declared``: its parameters, None when unknown."""
        self.check_argument_order(params, node, declared)
        args = []
        named = False
        for index, param in enumerate(params):
            if isinstance(param, tf.OutputParameterAssignment):
                args.extend(self._output_argument(param, declared, scope, node))
            elif param.name is not None:
                args.append(self._named_argument(param, declared, scope, node))
                named = True
            else:
                match = declared[index] if declared is not None and index < len(declared) else None
                code = self._positional_argument(param, match, scope)
                args.append(f"{match.name}={code}" if named and match is not None else code)
        return args

    def _positional_argument(self, param: Any, match: Member | None, scope: Scope) -> str:
        """A value by position: an in-out bound to the caller's variable, a generic input's AnyType, or a value."""
        if match is not None and match.section == "VAR_IN_OUT":
            return self.in_out_argument(param.value, match, scope)
        if match is not None and match.type is not None and match.type.kind == "any":
            return self.generic_argument(param.value, match, scope)
        expected = match.type if match is not None else None
        into = f"input {match.st}" if match is not None else None
        return self.limit(expected, self.coerce(self.expr(param.value, scope), expected, into)).code

    def check_argument_order(self, params: Sequence[Any], node: Any, declared: Sequence[Member] | None) -> None:
        """A positional argument after a named one takes the parameter of its place, as TwinCAT binds it (TcUnit's
        examples write ``AssertEquals(Expected := e, Actual := a, 'message')``); refused where the parameters are
        not known here, past the last one, or on a parameter a named argument sets too."""
        first = next((p for p in params if p.name is not None), None)
        if first is None:
            return
        names = {str(p.name.name).lower() for p in params if p.name is not None}
        for index in range(params.index(first), len(params)):
            if params[index].name is not None:
                continue
            if declared is None or index >= len(declared):
                raise self.fail(
                    f"a positional argument follows the named argument {first.name.name} and has no parameter at its "
                    f"place ({index + 1}): name it", node)
            if declared[index].st.lower() in names:
                raise self.fail(f"argument {index + 1} is {declared[index].st} by its place, which a named argument "
                                "sets too", node)

    def in_out_argument(self, value: Any, param: Member, scope: Scope) -> str:
        """The caller's variable a VAR_IN_OUT gets: its address, or for an ``ARRAY[*]`` the array itself (a view of it)."""
        if param.type is not None and param.type.kind == "array" and param.type.bounds is None:
            ex = self.expr(value, scope)
            if not isinstance(value, (tf.SimpleVariable, tf.MultiElementVariable)):
                raise self.fail(f"VAR_IN_OUT {param.st} : ARRAY[*] takes an ARRAY variable, not {ex.code}", value)
            self.check_open_array(value, ex, param)
            return ex.code
        return self.by_reference_argument(value, scope, ":=")

    def check_open_array(self, value: Any, ex: Ex, param: Member) -> None:
        """An ``ARRAY[*] OF T`` in-out takes an ARRAY of T with as many dimensions, as the PLC's compiler checks."""
        assert param.type is not None
        if ex.type is None or ex.type.deref().kind != "array":
            raise self.fail(f"VAR_IN_OUT {param.st} : ARRAY[*] takes an ARRAY variable, not {value}", value)
        given, wanted = ex.type.deref(), param.type
        dims = len(given.bounds) if given.bounds is not None else given.open_dims
        same_element = given.of is None or wanted.of is None or given.of.annotation() == wanted.of.annotation()
        if same_element and (not wanted.open_dims or dims == wanted.open_dims):
            return
        stars = ", ".join("*" * (wanted.open_dims or 1))
        element = wanted.of.name if wanted.of is not None else "?"
        raise self.fail(f"VAR_IN_OUT {param.st} : ARRAY[{stars}] OF {element} takes an ARRAY of {element} with "
                        f"{wanted.open_dims or 1} dimension(s), not {value} (of {given.of.name if given.of else '?'}, "
                        f"{dims} dimension(s))", value)

    def generic_argument(self, value: Any, param: Member, scope: Scope) -> str:
        """The ``AnyType`` a generic input (``x : ANY_NUM``) gets: the caller's variable where it has an address,
        else a copy of the value; a type outside the family is refused here, as the compilers refuse it."""
        from iecoop.generics import FAMILIES

        assert param.type is not None
        family = FAMILIES[param.type.name]
        ex = self.expr(value, scope)
        if ex.type is not None and ex.type.kind == "any":
            return ex.code  # a generic input handed on: its AnyType as it is
        type_class = self.type_class_of(ex.type)
        if type_class is not None and not family.admits(type_class):
            shown = ex.type.annotation() if ex.type is not None else "?"
            raise DefinitionError(f"{self.unit.where(self.line) if self.unit else '<st>'}: VAR_INPUT {param.st} : {family.name} "
                                  f"takes {family.takes}, not {shown} ({ex.code})")
        self.need("iecoop", "AnyType")
        if isinstance(value, (tf.SimpleVariable, tf.MultiElementVariable)) and not value.dereferenced:
            root = value.name if isinstance(value, tf.MultiElementVariable) else value
            local = scope.locals.get(str(getattr(root, "name", root)).lower())
            bit = isinstance(value, tf.MultiElementVariable) and isinstance(value.elements[-1], tf.FieldSelector) \
                and not isinstance(value.elements[-1].field, tf.SimpleVariable)
            if not bit and (local is None or local.section in ("STAT", "VAR_OUTPUT", "VAR_IN_OUT")):
                return f"AnyType.at({self.address_of(value, scope)})"
        if ex.type is not None and ex.type.kind in ("elem", "string"):
            self._need_type(ex.type)
            return f"AnyType.of({ex.code}, {ex.type.name})"
        return f"AnyType.of({ex.code})"

    def type_class_of(self, type_: TypeRef | None) -> Any:
        """The ``TYPE_CLASS`` of a value of ``type_`` (None when the type is not known here)."""
        from iecoop.memory.operators import TYPE_CLASS

        if type_ is None:
            return None
        type_ = type_.deref()
        if type_.kind in ("elem", "string"):
            name = {"DT": "DATEANDTIME", "TOD": "TIMEOFDAY"}.get(type_.name, type_.name)
            return TYPE_CLASS.__members__.get(f"TYPE_{name}")
        if type_.kind in ("pointer", "array"):
            return TYPE_CLASS.TYPE_POINTER if type_.kind == "pointer" else TYPE_CLASS.TYPE_ARRAY
        decl = self.decl_of(type_)
        if decl is None:
            return None
        if decl.kind == "alias" and decl.alias_of is not None:
            return self.type_class_of(decl.alias_of)
        return {"enum": TYPE_CLASS.TYPE_ENUM, "interface": TYPE_CLASS.TYPE_INTERFACE}.get(decl.kind, TYPE_CLASS.TYPE_USERDEF)

    def _output_argument(self, param: Any, declared: Sequence[Member] | None, scope: Scope, node: Any) -> list[str]:
        """``nLow => x``: the output bound to the caller's variable (none for ``nLow =>``, which drops it)."""
        name = str(param.name.name)
        match = next((p for p in declared or [] if p.st.lower() == name.lower()), None)
        if match is None or match.section != "VAR_OUTPUT":
            raise self.fail(f"call has no output {name!r}", node)
        if param.inverted:
            raise self.fail("an inverted output (=> NOT) is not supported", node)
        if param.value is None:
            return []
        return [f"{match.name}={self.by_reference_argument(param.value, scope, '=>')}"]

    def _named_argument(self, param: Any, declared: Sequence[Member] | None, scope: Scope, node: Any) -> str:
        """``name := value``: an input by value, or an in-out bound to the caller's variable."""
        name = str(param.name.name)
        match = next((p for p in declared or [] if p.st.lower() == name.lower()), None)
        if declared is not None and match is None:
            raise self.fail(f"call has no input {name!r}", node)
        if match is not None and match.section == "VAR_OUTPUT":
            raise self.fail(f"output {name!r} is assigned with =>, not :=", node)
        if match is not None and match.section == "VAR_IN_OUT":
            return f"{match.name}={self.in_out_argument(param.value, match, scope)}"
        if match is not None and match.type is not None and match.type.kind == "any":
            return f"{match.name}={self.generic_argument(param.value, match, scope)}"
        value = self.expr(param.value, scope)
        expected = match.type if match is not None else None
        # A subrange input is held to its limits at the call, as a store into it is (CheckRange).
        stored = self.coerce(value, expected, f"input {name}")
        return f"{match.name if match else python_name(name)}={self.limit(expected, stored).code}"

    def by_reference_argument(self, value: Any, scope: Scope, arrow: str) -> str:
        """The caller's variable an output (``=>``) or an in-out (``:=``) of a METHOD / FUNCTION is bound to."""
        if isinstance(value, tf.SimpleVariable) and not value.dereferenced:
            local = scope.locals.get(str(value.name).lower())
            if local is not None and local.section not in ("VAR_OUTPUT", "VAR_IN_OUT", "STAT") and self.decl_of(local.type) is None:
                raise self.fail(
                    f"{arrow} {value.name}: a local variable of a {'METHOD or FUNCTION' if scope.pou else 'PROPERTY accessor'} has no address here; "
                    "declare it in the block, or pass it through the block's own variable", value)
        return self.address_of(value, scope)

    def _named_call(self, node: Any, scope: Scope, level: int | None) -> Ex | None:
        """A call of a bare name: a standard function, SUPER, a FUNCTION; None for any other callee."""
        target = node.name
        if not isinstance(target, tf.SimpleVariable):
            return None
        key = str(target.name).lower()
        if key == "super":
            return Ex("super().body()", None)
        if target.dereferenced:
            return None
        standard = self.standard_call(str(target.name), node, scope, level)
        if standard is not None:
            return standard
        decl = self.decls.get(key)
        # a FUNCTION's name in its own body is its result, except where it is called: F := n * F(n - 1)
        if decl is not None and decl.kind == "function" and (key not in scope.locals or scope.locals[key].section == "RETURN"):
            info = decl.methods["()"]
            args = self.arguments(node.parameters, info.params, scope, node)
            return Ex(f"{decl.name}({', '.join(args)})", info.returns)
        return None

    def call(self, node: Any, scope: Scope, level: int | None) -> Ex | None:
        target = node.name
        named = self._named_call(node, scope, level)
        if named is not None:
            return named
        callee = self.expr(target, scope)
        if node.dereferenced:
            callee = self.deref(callee, node)
        if callee.this == "SUPER":
            return Ex("super().body()", None)
        decl = self.decl_of(callee.type)
        if decl is not None and decl.kind in ("fb", "stdfb") and callee.type is not None and callee.type.kind in ("user", "reference"):
            return self.fb_call(callee, decl, node, scope, level)
        # a method: find its declaration through the owner to type the result
        method = self.method_info(target, scope)
        args = self.arguments(node.parameters, method.params if method else None, scope, node)
        return Ex(f"{callee.code}({', '.join(args)})", method.returns if method else None)

    def method_info(self, target: Any, scope: Scope) -> Callable_ | None:
        if isinstance(target, tf.SimpleVariable):
            owner, name = scope.owner, str(target.name)
        elif isinstance(target, tf.MultiElementVariable) and isinstance(target.elements[-1], tf.FieldSelector):
            rest = tf.MultiElementVariable(target.name, False, target.elements[:-1]) if len(target.elements) > 1 else target.name
            owner_ex = self.expr(rest, scope)
            owner = self.decl_of(owner_ex.type)
            field = target.elements[-1].field
            name = str(field.name) if isinstance(field, tf.SimpleVariable) else str(field)
        else:
            return None
        if owner is None:
            return None
        found = self.find_member(owner, name)
        if found is not None and found[0] == "method":
            assert isinstance(found[1], Callable_)
            return found[1]
        return None

    def _block_argument(self, member: Member, value: Any, scope: Scope) -> str:
        """What a block's call passes for ``member := value``: an in-out's or a REFERENCE TO input's variable, else the value."""
        if member.section == "VAR_IN_OUT":
            if member.type is not None and member.type.kind == "array" and member.type.bounds is None:
                self.check_open_array(value, self.expr(value, scope), member)
            return self.address_of(value, scope)
        if member.type is not None and member.type.kind == "reference":
            # a REFERENCE TO input given a variable at the call is bound to it (REF= at the call)
            return self.address_of(value, scope)
        return self.limit(member.type, self.coerce(self.expr(value, scope), member.type, f"input {member.st}")).code

    def fb_call(self, callee: Ex, decl: Decl, node: Any, scope: Scope, level: int | None) -> Ex | None:
        inputs, outputs = [], []
        # IEC 61131-3's non-formal call: fb(1, 2) sets the inputs (and in-outs) in the order the block declares them
        positional = [m for d in reversed(list(self.lineage(decl))) for m in d.members.values() if m.section in ("VAR_INPUT", "VAR_IN_OUT")]
        self.check_argument_order(node.parameters, node, positional)
        for index, param in enumerate(node.parameters):
            if param.name is None:
                if index >= len(positional):
                    raise self.fail(f"{decl.st} takes {len(positional)} inputs by position, the call gives {len(node.parameters)}", node)
                member = positional[index]
            else:
                found = self.find_member(decl, str(param.name.name))
                if found is None or not isinstance(found[1], Member):
                    raise self.fail(f"{decl.name} has no input or output {param.name.name!r}", node)
                member = found[1]
            if isinstance(param, tf.OutputParameterAssignment):
                if param.inverted:
                    raise self.fail("an inverted output (=> NOT) is not supported", node)
                outputs.append((member, param.value))
                continue
            inputs.append(f"{member.name}={self._block_argument(member, param.value, scope)}")
        code = f"{callee.code}({', '.join(inputs)})"
        if outputs:
            if level is None:
                raise self.fail(f"outputs (=>) of {callee.code} in an expression", node)
            self.emit(code, level)
            for member, target in outputs:
                self.assign(target, Ex(f"{callee.code}.{member.name}", member.type), scope, level)
            return None
        return Ex(code, None)

    def _user_named(self, name: str, scope: Scope) -> bool:
        """Whether ``name`` is a local, a member or a user declaration: then it is no standard function."""
        key = name.lower()
        if key in scope.locals or (scope.owner is not None and self.find_member(scope.owner, name) is not None):
            return True
        return key in self.decls and self.decls[key].kind != "stdfb"

    def standard_call(self, name: str, node: Any, scope: Scope, level: int | None) -> Ex | None:
        upper = name.upper()
        if self._user_named(name, scope):
            return None
        if upper == "__POUNAME":
            return self._pou_name(node, scope)
        if upper in ("ADR", "__QUERYPOINTER", "__QUERYINTERFACE", "__ISVALIDREF", "TEST_AND_SET", "TESTANDSET",
                     "SIZEOF", "__NEW", "__DELETE", "__VARINFO"):
            return self.operator_call(upper, node, scope, level)  # operands that are types, not values
        if upper in SYSTEM_FUNCTIONS:
            return self.system_call(upper, node, scope)
        args = [self.expr(p.value, scope) for p in node.parameters if isinstance(p, tf.InputParameterAssignment)]
        numeric = self._numeric_call(upper, args, node)
        if numeric is not None:
            return numeric
        conversion = re.fullmatch(r"(?:(\w+?)_)?TO_(\w+)", upper)
        if conversion is not None:
            enum_text = self.enum_to_string(conversion.group(1), conversion.group(2), args)
            if enum_text is not None:
                return enum_text
            return self.conversion(conversion.group(1), conversion.group(2), args, node)
        strings = self.string_call(upper, args, node)
        if strings is not None:
            return strings
        if upper in ("AND", "OR", "XOR", "NOT"):
            raise self.fail(f"{upper} in function form is not supported (use the operator)", node)
        return None

    def _pou_name(self, node: Any, scope: Scope) -> Ex:
        """``__POUNAME()``: the name of the POU the code stands in (a METHOD's qualified with its block's), a STRING."""
        if node.parameters:
            raise self.fail("__POUNAME() takes no operands", node)
        name = scope.pou_name or (scope.owner.st if scope.owner is not None else "")
        return Ex(repr(name), STRING)

    def _numeric_call(self, upper: str, args: list[Ex], node: Any) -> Ex | None:
        """ABS, the math functions, MIN / MAX / LIMIT / SEL / MUX, MOVE, the shifts and rotations, TRUNC; else None."""
        codes = [a.code for a in args]
        first = args[0].type.deref() if args and args[0].type is not None else None
        if upper == "ABS":
            return self.function_call(upper, codes, first)
        if upper in MATH_FUNCTIONS or upper == "EXPT":
            return self.function_call(upper, codes, LREAL)
        if upper in ("MIN", "MAX"):
            return self.function_call(upper, codes, self.wider(first, args[1].type if len(args) > 1 else None))
        if upper in ("LIMIT", "SEL", "MUX"):
            return self.function_call(upper, codes, args[1].type)
        if upper == "MOVE":
            return args[0]
        if upper in ("SHL", "SHR", "ROL", "ROR"):
            if first is None or not first.is_int:
                raise self.fail(f"{upper} of an operand without a bit width (an untyped literal) is not supported: "
                                "give it a type (DWORD#32) or pass a BYTE, WORD, DWORD, LWORD ... variable", node)
            self._need_type(first)
            return self.function_call(upper, [*codes, first.name], first)
        if upper in ("LOWER_BOUND", "UPPER_BOUND"):
            # of an ARRAY[*] in-out (or any ARRAY): its bounds, which the array carries (dimension 1 first)
            if len(args) != 2 or args[0].type is None or args[0].type.deref().kind != "array":
                raise self.fail(f"{upper}(array, dimension) needs an ARRAY and a dimension", node)
            return Ex(f"{args[0].p()}.bounds[{args[1].code} - 1][{0 if upper == 'LOWER_BOUND' else 1}]", TypeRef("elem", "DINT"))
        if upper == "TRUNC":
            self.need("iecoop.conversions", "TRUNC")
            return Ex(f"TRUNC({codes[0]})", TypeRef("elem", "DINT"))
        return None

    def enum_to_string(self, source: str | None, target: str, args: list[Ex]) -> Ex | None:
        """``TO_STRING(eMode)``, ``E_Mode_TO_STRING(eMode)``: the component's name when the enumeration has
        ``{attribute 'to_string'}`` (TwinCAT 3.1.4024, CODESYS), else the number's text; None if not an enumeration."""
        if target not in ("STRING", "WSTRING") or not args:
            return None
        name = source if source is not None else args[0].type.name if args[0].type is not None and args[0].type.kind == "user" else None
        decl = self.decls.get(name.lower()) if name is not None else None
        if decl is None or decl.kind != "enum":
            return None
        result = self._elem_or_none(target)
        value = args[0]
        if not any(re.fullmatch(r"\{\s*attribute\s+'to_string'\s*\}", p, re.IGNORECASE) for p in self._decl_pragmas(decl)):
            return Ex(f"str(int({value.code}))", result)
        # a value that names no component (an integer stored in the variable) gives its number's text
        return Ex(f'str(getattr({value.code}, "name", int({value.code})))', result)

    def _decl_pragmas(self, decl: Decl) -> list[str]:
        """The pragmas written before the declaration ``decl``, which may be another item than the current one."""
        saved = self.unit, self.window
        try:
            self.unit = decl.unit
            self.enter(decl.item)
            return self.pragmas(decl.node)
        finally:
            self.unit, self.window = saved

    def system_call(self, upper: str, node: Any, scope: Scope) -> Ex:
        """TwinCAT's system functions: ``TIME()`` (the task clock in ms, as TON reads it), MEMCPY, MEMSET, MEMCMP."""
        if upper == "TIME":
            if node.parameters:
                raise self.fail("TIME() takes no input", node)
            self.need("iecoop.runtime", "now_ms")
            return Ex("now_ms()", TypeRef("elem", "TIME"))
        codes = [self.expr(p.value, scope).code for p in node.parameters]
        self.need("iecoop", upper.lower())
        return Ex(f"{upper.lower()}({', '.join(codes)})", TypeRef("elem", SYSTEM_FUNCTIONS[upper]))

    def conversion(self, source: str | None, target: str, args: list[Ex], node: Any) -> Ex:
        from iecoop import conversions

        source = TYPE_SYNONYMS.get(source, source) if source else None
        target = TYPE_SYNONYMS.get(target, target)
        value = args[0]
        if source is None and value.type is not None and value.type.deref().kind == "string":
            source = value.type.deref().name  # TO_REAL(sText) reads the text as STRING_TO_REAL does
        result_type = self._elem_or_none(target)
        if result_type is None:  # DEG_TO_RAD, DWORD_TO_HEXSTR: a library's function, not a conversion
            called = f"{source}_TO_{target}" if source else f"TO_{target}"
            raise self.fail(f"unknown function {called} (not a conversion: {target} is not an elementary type)", node)
        if target in ("STRING", "WSTRING"):
            return self._to_string(source, target, value, result_type, node)
        if source in ("STRING", "WSTRING"):
            # the literal the text starts with, stored in the target type (TwinCAT, CODESYS: '34abc' is 34, 'abc' 0)
            if target in ("DATE", "TOD", "DT"):  # the date or time of day literal the text starts with
                self.need("iecoop.stdlib.calendar_text", "string_to_calendar")
                return Ex(f'string_to_calendar({value.code}, "{target}")', result_type)
            if result_type.kind != "elem":
                raise self.fail(f"{source}_TO_{target} is not supported", node)
            self.need("iecoop.conversions", "STRING_TO_NUMBER", f"TO_{target}")
            return Ex(f'TO_{target}(STRING_TO_NUMBER({value.code}, "{target}"))', result_type)
        name = f"{source}_TO_{target}" if source else f"TO_{target}"
        name = self._calendar_conversion(name, source, target, value, node)
        if source is not None and name not in conversions.__all__:
            if source == "BOOL":
                name = f"TO_{target}"
            elif source in INTEGER_LAYOUT and target in INTEGER_LAYOUT:
                # reinterpret through the source width, then store in the target width
                self.need("iecoop.conversions", f"TO_{source}", f"TO_{target}")
                return Ex(f"TO_{target}(TO_{source}({value.code}))", result_type)
            else:
                name = f"TO_{target}"
        if name not in conversions.__all__:
            raise self.fail(f"conversion {name} is not supported", node)
        self.need("iecoop.conversions", name)
        return Ex(f"{name}({value.code})", result_type)

    def _calendar_conversion(self, name: str, source: str | None, target: str, value: Ex, node: Any) -> str:
        """A conversion into DATE, TOD or DT by what its argument holds: a DT's day or time of day is DT_TO_DATE /
        DT_TO_TOD; between units that do not match (a TOD's milliseconds into a DT's seconds) it is refused."""
        if target not in ("DATE", "TOD", "DT"):
            return name
        held = source or (value.type.name if value.type is not None and value.type.kind == "elem" else None)
        held = TYPE_SYNONYMS.get(held, held) if held else None
        if held == "DT" and target in ("DATE", "TOD"):
            return f"DT_TO_{target}"
        if held in _CALENDAR_UNITS and _CALENDAR_UNITS[held] != _CALENDAR_UNITS[target]:
            raise self.fail(f"{name} of a {held} is not supported (write DT_TO_TOD or DT_TO_DATE to split a DT, "
                            "or convert the number it holds)", node)
        return name

    def _to_string(self, source: str | None, target: str, value: Ex, result_type: TypeRef, node: Any) -> Ex:
        """``*_TO_STRING``: iecoop's write the vendor text (T#1s500ms, 1.5, TRUE).

        TO_STRING goes by the argument's declared type, which the Python function cannot see, so it gets the
        source-named form (an enumeration's TO_STRING is enum_to_string's, before this).
        """
        from iecoop import conversions

        named = source or (value.type.name if value.type is not None and value.type.kind == "elem" else None)
        named = TYPE_SYNONYMS.get(named, named) if named else None
        form = f"{named}_TO_STRING" if named else ""
        if form not in conversions.__all__:
            if value.type is None or not value.type.is_int:
                raise self.fail(f"{source or 'ANY'}_TO_{target} is not supported", node)
            form = "TO_STRING"
        self.need("iecoop.conversions", form)
        return Ex(f"{form}({value.code})", result_type)

    def string_call(self, upper: str, args: list[Ex], node: Any) -> Ex | None:
        """LEN, CONCAT ... and their WSTRING forms WLEN, WCONCAT ... (Tc2_Standard): the same functions on
        characters, which a Python str holds either way; the W forms give a WSTRING."""
        wide = upper not in STRING_FUNCTIONS and upper.startswith("W") and upper[1:] in STRING_FUNCTIONS
        name = upper[1:] if wide else upper
        if name not in STRING_FUNCTIONS:
            return None
        result = TypeRef("elem", "INT") if name in ("LEN", "FIND") else TypeRef("string", "WSTRING", length="80") if wide else STRING
        return self.function_call(name, [a.code for a in args], result)

    def function_call(self, name: str, codes: Sequence[str], type_: TypeRef | None) -> Ex:
        """A call of the standard function ``name`` of ``iecoop.functions``: the form the Rosetta teaches."""
        self.need("iecoop.functions", name)
        return Ex(f"{name}({', '.join(codes)})", type_)

    def operator_call(self, upper: str, node: Any, scope: Scope, level: int | None) -> Ex:
        """ADR, SIZEOF, __NEW, __DELETE, __ISVALIDREF, TEST_AND_SET, __QUERYINTERFACE, __QUERYPOINTER: operands that are variables or types."""
        handler = _OPERATORS.get(upper)
        if handler is None:
            raise self.fail(f"{upper} is not supported", node)
        return handler(self, upper, [p.value for p in node.parameters], node, scope, level)

    def _op_adr(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        return Ex(self.address_of(params[0], scope), TypeRef("pointer", "POINTER_TO", of=self.expr(params[0], scope).type))

    def _op_varinfo(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "var_info")
        holder, field = self.holder_field(params[0], scope)
        return Ex(f'var_info({holder}, "{field}")', TypeRef("varinfo", "VarInfo"))

    def _op_sizeof(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "sizeof")
        target = params[0]
        if isinstance(target, tf.SimpleVariable) and not target.dereferenced:
            of_type = self._sizeof_type(str(target.name))
            if of_type is not None:
                return of_type
        ex = self.expr(target, scope)
        decl = self.decl_of(ex.type)
        if decl is not None and decl.kind in ("struct", "union", "fb", "stdfb"):
            return Ex(f"sizeof({ex.code})", TypeRef("elem", "UDINT"))
        static = self._static_size(ex.type) if ex.place is None and ex.type is not None else None
        if static is not None:  # a local, an input or an ARRAY element: its size is its type's
            return Ex(static, TypeRef("elem", "UDINT"))
        holder, field = self.holder_field(target, scope)
        return Ex(f'sizeof({holder}, "{field}")', TypeRef("elem", "UDINT"))

    def _static_size(self, type_: TypeRef) -> str | None:
        """SIZEOF of a value of ``type_`` as Python code, or None when only its holder can tell."""
        if type_.kind == "elem":
            self._need_type(type_)
            return f"sizeof({type_.name})"
        if type_.kind == "string" and type_.length is not None:  # the characters and the terminating 0
            return f"(({type_.length}) + 1)" if type_.name == "STRING" else f"(2 * (({type_.length}) + 1))"
        if type_.kind == "array" and type_.bounds and type_.of is not None:
            each = self._static_size(type_.of)
            counts = " * ".join(f"(({high}) - ({low}) + 1)" for low, high in type_.bounds)
            return None if each is None else f"({counts} * {each})"
        decl = self.decl_of(type_)
        return f"sizeof({decl.name})" if decl is not None and decl.kind in ("struct", "union", "fb") else None

    def _sizeof_type(self, name: str) -> Ex | None:
        """``SIZEOF(T)`` of a type name, or None when ``name`` is not one."""
        elem = self._elem_or_none(name)
        if elem is not None:
            self._need_type(elem)
            return Ex(f"sizeof({elem.name})", TypeRef("elem", "UDINT"))
        decl = self.decls.get(name.lower())
        if decl is not None and decl.kind in ("struct", "union", "fb", "stdfb", "alias", "enum"):
            if decl.kind == "stdfb":
                self.need("iecoop.stdlib", decl.name)
            return Ex(f"sizeof({decl.name})", TypeRef("elem", "UDINT"))
        return None


#: The operators whose operands are variables or types, not values: ST name -> Calls method.
_OPERATORS: dict[str, Callable[[Calls, str, list[Any], Any, Scope, int | None], Ex]] = {
    "ADR": Calls._op_adr,
    "SIZEOF": Calls._op_sizeof,
    "__VARINFO": Calls._op_varinfo,
    "__NEW": Calls._op_new,
    "__DELETE": Calls._op_delete,
    "__ISVALIDREF": Calls._op_isvalidref,
    "TEST_AND_SET": Calls._op_test_and_set,
    "TESTANDSET": Calls._op_test_and_set,
    "__QUERYINTERFACE": Calls._op_query,
    "__QUERYPOINTER": Calls._op_query,
}


