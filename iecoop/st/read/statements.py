"""Pass 2, statements: one ``visit_<blark node>`` per statement kind, each writing Python lines."""

from __future__ import annotations

import keyword
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import blark.transform as tf

from iecoop.st.read.calls import Calls
from iecoop.st.read.frames import Ex, PRECEDENCE, Scope
from iecoop.st.read.table import Member, ReferenceLocal, TypeRef
from iecoop.st.read.trees import assigned, exact_real, has_call, is_zero, jumps_in_loop, variables, walk


class Statements(Calls):
    """Writes ST statements as Python statements."""

    # --- statements ---

    def _emit_statements(self, statements: Sequence[Any], scope: Scope, level: int) -> None:
        top, scope.started = not scope.started, True
        if top and any(isinstance(s, tf.LabeledStatement) for s in statements):
            self._emit_jumps(statements, scope, level)
            return
        if not statements:
            self.emit("pass", level)
            return
        start = self.code_lines
        for statement in statements:
            self.line = statement.meta.line if statement.meta else self.line
            trailing = self.comments(statement, level, inline=True)
            index = len(self.out)
            self.statement(statement, scope, level)
            self.trail(index, trailing)
        if self.code_lines == start:  # only comments: a Python block needs a statement
            self.emit("pass", level)

    def statement(self, node: Any, scope: Scope, level: int) -> None:
        """Write one statement through its ``visit_<blark node>`` (a ``__TRY`` of the grammar overlay is a Tree)."""
        handler: Callable[[Any, Scope, int], None] | None = None
        if isinstance(node, tf.Statement) or type(node).__name__ == "Tree":
            handler = getattr(self, f"visit_{type(node).__name__}", None)
        if handler is None:
            self.generic_visit(node, "statement")
        else:
            handler(node, scope, level)

    def visit_NoOpStatement(self, node: tf.NoOpStatement, scope: Scope, level: int) -> None:
        self.emit(self.expr(node.variable, scope).code, level)

    def visit_AssignmentStatement(self, node: tf.AssignmentStatement, scope: Scope, level: int) -> None:
        scope.statement_level = level  # __QUERYINTERFACE on the right side writes its query first, at this level
        if isinstance(node.expression, tf.ArrayInitialization):
            scope.statement_level = None
            self._assign_array_literal(node, scope, level)
            return
        try:
            value = self.expr(node.expression, scope)
        finally:
            scope.statement_level = None
        targets = list(node.variables)
        if len(targets) > 1:
            temp = scope.temp("value")
            self.emit(f"{temp} = {value.code}", level)
            value = Ex(temp, value.type)
        for target in targets:
            self.assign(target, value, scope, level)

    def _array_elements(self, value: Any, element: TypeRef | None, scope: Scope) -> Iterator[str]:
        """Defined by a later phase of the translator."""
        raise NotImplementedError

    def _assign_array_literal(self, node: Any, scope: Scope, level: int) -> None:
        """``aPoints := [(x := 1), (x := 2)];``: the elements from the first index on, each stored as an element is."""
        if len(node.variables) != 1:
            raise self.fail("an array literal assigned to several variables at once is not supported", node)
        lhs = self.expr(node.variables[0], scope, store=True)
        array = lhs.type.deref() if lhs.type is not None else None
        if array is None or array.kind != "array" or array.of is None or not array.bounds or len(array.bounds) != 1:
            raise self.fail(f"an array literal assigned to {lhs.code}, which is no one-dimensional ARRAY, is not supported", node)
        if "." not in lhs.code:
            raise self.fail(f"an array literal assigned to the local ARRAY {lhs.code} is not supported (assign its elements)", node)
        decl = self.decl_of(array.of)
        items = list(self._array_elements(node.expression, array.of, scope))
        if decl is not None and decl.kind in ("struct", "union"):
            items = [f"{decl.name}(**{item})" if item.startswith("{") else item for item in items]
        low, high = array.bounds[0]
        if low.lstrip("-").isdigit() and high.lstrip("-").isdigit() and len(items) > int(high) - int(low) + 1:
            raise self.fail(f"{len(items)} values for {lhs.code}, an ARRAY[{low}..{high}]", node)
        loop = scope.temp("item")
        self.emit(f"for {loop}, {loop}_value in enumerate([{', '.join(items)}]):", level)
        self.emit(f"{lhs.code}[{low} + {loop}] = {loop}_value", level + 1)

    def assign(self, target: Any, value: Ex, scope: Scope, level: int) -> None:
        bit = self.bit_target(target, scope)
        if bit is not None:
            holder, index = bit
            self.need("iecoop.functions", "set_bit")
            self.emit(f"{holder} = set_bit({holder}, {index}, {value.code})", level)
            return
        lhs = self.expr(target, scope, store=True)
        if lhs.super_property:  # SUPER^.Prop := value: Python's super() refuses attribute writes
            assert lhs.place is not None  # made by Ex.attribute("super()", name)
            name = lhs.place[1]
            self.emit(f'super_set(super(), "{name}", {self.store_value(lhs.type, value, False, str(target))})', level)
            return
        local = self.local_of(target, scope)
        if local is not None and local.section == "CONSTANT":
            raise self.fail(f"assignment to CONSTANT {local.st or local.name}", target)
        if local is not None and local.section == "LOCAL" and self._local_reference(local.type):
            raise self.fail(f"assignment to the whole REFERENCE TO local {local.name} (bind it with REF=, write its members)", target)
        by_reference = local is not None and local.section in ("VAR_OUTPUT", "VAR_IN_OUT")
        if local is not None and not by_reference and "." not in local.name and lhs.type is not None and lhs.type.kind != "reference" and self._copied(lhs.type):
            # a Python local names a view: ST's assignment of a STRUCT, ARRAY or block copies the value
            self.need("copy", "copy")
            value = Ex(f"copy({value.code})", value.type)
        is_local = local is not None and not by_reference and local.section != "STAT"
        self.emit(f"{lhs.code} = {self.store_value(lhs.type, value, is_local, str(target))}", level)

    def store_value(self, target: TypeRef | None, value: Ex, is_local: bool, into: str | None = None) -> str:
        """What to store: converted where ST converts implicitly, wrapped where a Python local would not."""
        if target is None:
            return value.code
        target = target.deref()
        self.refuse_conversion(target, value, f"{into} := ..." if into else None)
        value = self.coerce(value, target) if target.is_bool or target.is_string else value  # b := 1; s := 5 is refused
        limited = self.limit(target, value)
        if limited is not value:
            return limited.code
        if target.kind == "pointer":
            return self.coerce(value, target).code
        function = self._implicit_conversion(target, value, is_local)
        if function is None:
            return value.code
        if function.startswith("TO_"):
            self.need("iecoop.conversions", function)
        return f"{function}({value.code})"

    def _implicit_conversion(self, target: TypeRef, value: Ex, is_local: bool) -> str | None:
        """The function a stored value goes through: ST's implicit conversion, or the width a Python local lacks."""
        source = value.type
        if target.is_bool and source is not None and source.is_int:
            return "bool"
        if target.is_int and source is not None and source.is_real:
            return f"TO_{target.name}"
        if not is_local:
            return None
        if target.is_int and not self._fits(value, target):
            return f"TO_{target.name}"
        if target.name == "REAL" and not exact_real(value.code) and not (source is not None and source.name == "REAL" and not value.compound):
            return "TO_REAL"
        if target.is_real and source is not None and source.is_int:
            return "float"
        return None

    def visit_SetStatement(self, node: tf.SetStatement, scope: Scope, level: int) -> None:
        self._set_reset("S", True, node, scope, level)

    def visit_ResetStatement(self, node: tf.ResetStatement, scope: Scope, level: int) -> None:
        self._set_reset("R", False, node, scope, level)

    def _set_reset(self, operator: str, value: bool, node: Any, scope: Scope, level: int) -> None:
        """``x S= c`` is ``S(self, "x", c)`` (iecoop.stdlib); a method's local is set with an IF."""
        condition = self.expr(node.expression, scope).code
        if self.local_of(node.variable, scope) is not None:
            self.emit(f"if {condition}:", level)
            self.emit(f"{self.expr(node.variable, scope).code} = {value}", level + 1)
            return
        holder, field = self.holder_field(node.variable, scope)
        self.need("iecoop.stdlib", operator)
        self.emit(f'{operator}({holder}, "{field}", {condition})', level)

    def visit_ReferenceAssignmentStatement(self, node: tf.ReferenceAssignmentStatement, scope: Scope, level: int) -> None:
        local = self.local_of(node.variable, scope)
        if is_zero(node.expression):
            self._unbind(node, local, scope, level)
            return
        if local is not None and self._local_reference(local.type):
            assert local.type is not None
            bound = self.expr(node.expression, scope)
            if self.decl_of(bound.type) is not self.decl_of(local.type):
                raise self.fail(f"REF= of {local.name} needs a {local.type.deref().name} variable, got {bound.code}", node)
            self.emit(f"{local.name} = {bound.code}", level)
            return
        if isinstance(local, ReferenceLocal):
            self.emit(f"{local.name} = {self.address_of(node.expression, scope)}", level)
            return
        prop = self._reference_property(node.variable, scope)
        if prop is not None:
            # fbSample.MyProp REF= stSet: the Set accessor of a REFERENCE TO property gets stSet itself.
            bound = self.expr(node.expression, scope)
            if self.decl_of(bound.type) is not self.decl_of(prop.type):
                raise self.fail(f"REF= of {prop.code} needs a {prop.type.deref().name if prop.type else '?'} variable, got {bound.code}", node)
            self.emit(f"{prop.code} = {bound.code}", level)
            return
        holder, field = self.holder_field(node.variable, scope)
        self.need("iecoop", "ref_assign")
        target = self.address_of(node.expression, scope)
        self.emit(f'ref_assign({holder}, "{field}", {target})', level)

    def _unbind(self, node: Any, local: Member | None, scope: Scope, level: int) -> None:
        """``r REF= 0``: the reference points nowhere again (``__ISVALIDREF`` is FALSE, reading it faults)."""
        if isinstance(local, ReferenceLocal):
            assert local.type is not None
            self.need("iecoop", "Pointer")
            self.emit(f"{local.name} = Pointer(0, None).typed({local.type.annotation()})", level)
            return
        if local is not None:
            raise self.fail(f"REF= 0 of {local.name}: a local REFERENCE TO a STRUCT, UNION or FB cannot be unbound "
                            "(make it a variable of the block)", node)
        holder, field = self.holder_field(node.variable, scope)
        self.need("iecoop", "ref_assign")
        self.emit(f'ref_assign({holder}, "{field}", None)', level)

    def visit_IfStatement(self, node: tf.IfStatement, scope: Scope, level: int) -> None:
        self.emit(f"if {self.condition(node.if_expression, scope)}:", level)
        self._emit_statements(node.statements.statements if node.statements else [], scope, level + 1)
        for clause in node.else_ifs:
            self.at(clause)
            self.emit(f"elif {self.condition(clause.if_expression, scope)}:", level)
            self._emit_statements(clause.statements.statements if clause.statements else [], scope, level + 1)
        if node.else_clause is not None:
            self.emit("else:", level)
            self._emit_statements(node.else_clause.statements.statements if node.else_clause.statements else [], scope, level + 1)

    def condition(self, node: Any, scope: Scope) -> str:
        return self.expr(node, scope).code

    def visit_CaseStatement(self, node: tf.CaseStatement, scope: Scope, level: int) -> None:
        selector = self.expr(node.expression, scope)
        subject = selector.code
        if selector.compound or "(" in subject:
            subject = scope.temp("case")
            self.emit(f"{subject} = {selector.code}", level)
        keyword = "if"
        for case in node.cases:
            self.at(case)
            tests = []
            for match in case.matches:
                if isinstance(match, tf.Subrange):
                    low = self.expr(match.start, scope).code
                    high = self.expr(match.stop, scope).code
                    tests.append(f"{low} <= {subject} <= {high}")
                else:
                    tests.append(f"{subject} == {self.case_label(match, selector.type, scope)}")
            self.emit(f"{keyword} {' or '.join(tests)}:", level)
            self._emit_statements(case.statements.statements if case.statements else [], scope, level + 1)
            keyword = "elif"
        if node.else_clause is not None:
            if keyword == "if":
                self._emit_statements(node.else_clause.statements.statements if node.else_clause.statements else [], scope, level)
                return
            self.emit("else:", level)
            self._emit_statements(node.else_clause.statements.statements if node.else_clause.statements else [], scope, level + 1)

    def case_label(self, match: Any, selector: TypeRef | None, scope: Scope) -> str:
        if isinstance(match, tf.EnumeratedValue):
            prefix, _, last = str(match.name).rpartition(".")
            decl = self.decls.get(prefix.lower())
            if match.type_name is None and prefix and (decl is None or decl.kind != "enum"):
                # a qualified constant (GVL_Const.cMax) or an enumeration value of a GVL's type
                ex = self.name_ref(prefix.split(".")[0], scope, match)
                for field in [*prefix.split(".")[1:], last]:
                    ex = self.member_ref(ex, field, match)
                return ex.code
            if match.type_name is None and not prefix and str(match.name).lower() not in self.enum_values:
                return self.name_ref(str(match.name), scope, match).code  # a constant of the POU or a GVL (cStart:)
            return self.enum_ref(str(match.type_name) if match.type_name else None, str(match.name), match)
        return self.expr(match, scope).code

    def visit_ForStatement(self, node: tf.ForStatement, scope: Scope, level: int) -> None:
        control = self.expr(node.control, scope, store=True)
        name = str(node.control.name).lower() if isinstance(node.control, tf.SimpleVariable) else None
        if any(isinstance(t, tf.SimpleVariable) and str(t.name).lower() == name for t in assigned(node.statements)):
            # IEC 61131-3: the repeated statements shall not alter the control variable (a Python for would undo it)
            raise self.fail(f"the FOR loop writes its control variable {node.control.name}", node)
        start = self.expr(node.from_, scope)
        stop = self.expr(node.to, scope)
        step = self.expr(node.step, scope) if node.step is not None else None
        self._integer_counts(node, start, stop, step)
        if self._for_end_moves(node):
            self._for_checked_each_pass(node, control, start, step, scope, level)
            return
        header = self._for_range(node, start, stop, step)
        # A loop that ends by its test leaves the variable at the first value that failed it (ST:
        # FOR i := 1 TO 10 leaves 11); after EXIT it keeps the value it had. Python's for ... else.
        literal = [ex.constant if isinstance(ex.constant, int) else None for ex in (start, stop, step or Ex("1", constant=1))]
        if None not in literal:
            first, last, by = (n for n in literal if n is not None)
            past = first + by * len(range(first, last + (1 if by > 0 else -1), by))
            after = Ex(str(past), start.type, constant=past)
        else:
            loop = scope.temp("for")
            self.emit(f"{loop} = {header}", level)
            header = loop
            after = Ex(f"{loop}.start + {loop}.step * len({loop})", start.type or stop.type, True, PRECEDENCE["+"])
        self.emit(f"for {control.code} in {header}:", level)
        self._emit_loop_body(node.statements.statements, scope, level + 1)
        self.at(node)
        self.emit("else:  # the first value past the end, as ST leaves it", level)
        self.assign(node.control, after, scope, level + 1)

    def _integer_counts(self, node: tf.ForStatement, start: Ex, stop: Ex, step: Ex | None) -> None:
        """A FOR counts in integers (IEC 61131-3): a REAL start, end or step is refused here, not by a cycle's TypeError."""
        for part, value in (("start", start), ("end", stop), ("step", step)):
            if value is not None and (isinstance(value.constant, float) or value.type is not None and value.type.deref().is_real):
                raise self.fail(f"FOR {node.control.name}: its {part} is a REAL; a FOR counts in integers", node)

    @staticmethod
    def _for_end_moves(node: tf.ForStatement) -> bool:
        """Whether a FOR's end or step calls something, or its end changes in the loop: then it is checked each pass."""
        ends = {str(v.name).lower() for v in variables(node.to) if isinstance(v, tf.SimpleVariable)}
        return has_call(node.to) or (node.step is not None and has_call(node.step)) or any(
            isinstance(t, tf.SimpleVariable) and str(t.name).lower() in ends for t in assigned(node.statements))

    def _for_range(self, node: Any, start: Ex, stop: Ex, step: Ex | None) -> str:
        """The ``range(...)`` of a FOR whose bounds are evaluated once: its end included, in the step's direction."""
        if step is None:
            return f"range({start.code}, {stop.p()} + 1)"
        if isinstance(step.constant, int):
            if step.constant == 0:
                raise self.fail("FOR ... BY 0 never ends", node)
            sign = "+ 1" if step.constant > 0 else "- 1"
            return f"range({start.code}, {stop.p()} {sign}, {step.code})"
        return f"range({start.code}, {stop.p()} + (1 if {step.p()} > 0 else -1), {step.code})"

    def _for_checked_each_pass(self, node: Any, control: Ex, start: Ex, step: Ex | None, scope: Scope, level: int) -> None:
        """A FOR whose end calls something or changes in the loop: the start and the step are evaluated once, at
        entry; the end before every pass, where TwinCAT and CODESYS check the counter against it."""
        flag = scope.temp("for")
        by = step
        if step is not None and step.constant is None:
            by = Ex(f"{flag}_by", step.type)
            self.emit(f"{by.code} = {step.code}", level)
        self.assign(node.control, start, scope, level)
        self.emit(f"{flag} = False  # True once a pass has run: each later pass starts by stepping the counter", level)
        self.emit("while True:", level)
        self.emit(f"if {flag}:", level + 1)
        counter = self.expr(node.control, scope)
        increment = Ex(f"{counter.code} + {by.p() if by is not None else '1'}", counter.type, True, PRECEDENCE["+"])
        self.assign(node.control, increment, scope, level + 2)
        self.emit(f"{flag} = True", level + 1)
        end = self.expr(node.to, scope)
        if by is None or isinstance(by.constant, int):
            if by is not None and by.constant == 0:
                raise self.fail("FOR ... BY 0 never ends", node)
            test = f"{counter.code} {'<=' if by is None or (by.constant or 0) > 0 else '>='} {end.p()}"
        else:
            test = f"({counter.code} <= {end.p()} if {by.code} > 0 else {counter.code} >= {end.p()})"
        self.emit(f"if not {test}:", level + 1)
        self.emit("break  # the counter is the first value past the end, as ST leaves it", level + 2)
        self._emit_loop_body(node.statements.statements, scope, level + 1)

    def visit_WhileStatement(self, node: tf.WhileStatement, scope: Scope, level: int) -> None:
        self.emit(f"while {self.condition(node.expression, scope)}:", level)
        self._emit_loop_body(node.statements.statements, scope, level + 1)

    def visit_RepeatStatement(self, node: tf.RepeatStatement, scope: Scope, level: int) -> None:
        loops = (tf.ForStatement, tf.WhileStatement, tf.RepeatStatement)
        if any(isinstance(n, tf.ContinueStatement) for n in walk(node.statements.statements, lambda n: isinstance(n, loops))):
            # CONTINUE goes on at UNTIL (IEC 61131-3: after the loop's last statement), so the test heads the loop
            again = scope.temp("again")
            self.emit(f"{again} = False  # True once a pass has run: UNTIL is tested before each later one", level)
            self.at(node)
            self.emit(f"while not {again} or not ({self.condition(node.expression, scope)}):", level)
            self.emit(f"{again} = True", level + 1)
            self._emit_loop_body(node.statements.statements, scope, level + 1)
            return
        self.emit("while True:", level)
        self._emit_loop_body(node.statements.statements, scope, level + 1)
        self.at(node)  # UNTIL: the REPEAT's line, not the last statement's
        self.emit(f"if {self.condition(node.expression, scope)}:", level + 1)
        self.emit("break", level + 2)

    def _emit_loop_body(self, statements: Sequence[Any], scope: Scope, level: int) -> None:
        scope.loops += 1
        try:
            self._emit_statements(statements, scope, level)
        finally:
            scope.loops -= 1

    def visit_ExitStatement(self, node: tf.ExitStatement, scope: Scope, level: int) -> None:
        self._in_loop("EXIT", node, scope)
        self.emit("break", level)

    def visit_ContinueStatement(self, node: tf.ContinueStatement, scope: Scope, level: int) -> None:
        self._in_loop("CONTINUE", node, scope)
        self.emit("continue", level)

    def _in_loop(self, statement: str, node: Any, scope: Scope) -> None:
        """EXIT and CONTINUE stand in a FOR, WHILE or REPEAT (else Python's break would end a JMP's loop, or not compile)."""
        if not scope.loops:
            raise self.fail(f"{statement} outside a FOR, WHILE or REPEAT loop", node)

    def visit_ReturnStatement(self, node: tf.ReturnStatement, scope: Scope, level: int) -> None:
        self.emit(f"return {scope.return_name}" if scope.return_name else "return", level)

    def visit_FunctionCallStatement(self, node: tf.FunctionCallStatement, scope: Scope, level: int) -> None:
        call = self.call(node, scope, level=level)
        if call is not None and call.code:
            self.emit(call.code, level)

    def visit_ChainedFunctionCallStatement(self, node: tf.ChainedFunctionCallStatement, scope: Scope, level: int) -> None:
        self.emit(self.expr(tf.ChainedFunctionCall(node.invocations), scope).code, level)

    def visit_Tree(self, node: Any, scope: Scope, level: int) -> None:
        """A statement of the grammar overlay: ``__TRY ... __CATCH(exc) ... __FINALLY ... __ENDTRY``."""
        if str(node.data) != "try_statement":
            raise self.fail(f"statement {node.data} is not supported", node)
        body, catch, final = (list(node.children) + [None, None, None])[:3]
        self.need("iecoop", "try_catch", "ExceptionCode")
        block = scope.temp("try")
        inner = level
        if final is not None:
            self.emit("try:", level)
            inner = level + 1
        self.emit(f"with try_catch() as {block}:  # __TRY", inner)
        self._emit_statements(body.statements if body is not None else [], scope, inner + 1)
        if catch is not None:
            variable, handler = (list(catch.children) + [None])[:2]
            self.emit(f"if {block}.code != ExceptionCode.RTSEXCPT_NOEXCEPTION:  # __CATCH", inner)
            self.assign(variable, Ex(f"{block}.code", TypeRef("elem", "UDINT")), scope, inner + 1)
            if handler is not None:
                self._emit_statements(handler.statements, scope, inner + 1)
        if final is not None:
            self.emit("finally:  # __FINALLY", level)
            handler = final.children[0] if final.children else None
            self._emit_statements(handler.statements if handler is not None else [], scope, level + 1)

    def _emit_jumps(self, statements: Sequence[Any], scope: Scope, level: int) -> None:
        """A body with labels: its parts, from one label to the next, in a loop that a JMP restarts at a label."""
        parts: list[tuple[str, list[Any]]] = [("", [])]
        for statement in statements:
            if isinstance(statement, tf.LabeledStatement):
                label = str(statement.label)
                if label.lower() in scope.labels:
                    raise self.fail(f"label {label} is declared twice", statement)
                scope.labels.add(label.lower())
                parts.append((label, [statement.statement] if statement.statement is not None else []))
            else:
                parts[-1][1].append(statement)
            if jumps_in_loop(statement):
                raise self.fail("JMP inside a FOR, WHILE or REPEAT loop is not supported (labels and JMPs outside loops)", statement)
        scope.jump = scope.temp("jump")
        # A body that opens with a label starts at that label's part (the part before it is empty and left out).
        first = parts[0][0] if parts[0][1] else parts[1][0].lower()
        self.emit(f'{scope.jump} = "{first}"  # JMP: the label the code runs from next', level)
        self.emit("while True:", level)
        for index, (label, body) in enumerate(parts):
            if index == 0 and not body:
                continue
            self.emit(f'if {scope.jump} == "{label.lower()}":' + (f"  # {label}:" if label else ""), level + 1)
            self._emit_statements(body, scope, level + 2)
            if index + 1 < len(parts) and not (body and isinstance(body[-1], (tf.ReturnStatement, tf.JumpStatement))):
                self.emit(f'{scope.jump} = "{parts[index + 1][0].lower()}"', level + 2)  # on to the next label
        self.emit("break", level + 1)

    def visit_JumpStatement(self, node: tf.JumpStatement, scope: Scope, level: int) -> None:
        label = str(node.label)
        if label.lower() not in scope.labels:
            raise self.fail(f"JMP {label}: no label {label} at the top of this body (labels inside IF, CASE or loops are not supported)", node)
        self.emit(f'{scope.jump} = "{label.lower()}"  # JMP {label}', level)
        self.emit("continue", level)

    def visit_LabeledStatement(self, node: tf.LabeledStatement, scope: Scope, level: int) -> None:
        raise self.fail(f"label {node.label} inside IF, CASE or a loop is not supported (labels at the top of a body)", node)
