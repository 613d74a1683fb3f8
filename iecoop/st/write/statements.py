"""Python statements to Structured Text statements: the subset iecoop code is written in.

A POU body, a METHOD or a property accessor is read from its source
(``inspect.getsource`` + ``ast``) and translated statement by statement.
Anything outside the subset raises :class:`StExportError` naming the file,
the line and the construct, or, when the caller asks for it, becomes an ST
comment that says the same.
"""

from __future__ import annotations

import ast
import builtins
import collections
import io
import tokenize
import textwrap
import typing
from collections.abc import Iterator
from typing import Any

from iecoop._codegen import definition, python_source
from iecoop.metadata import kind_of
from iecoop.memory.typeinfo import AggregateInfo, ArrayInfo, ReferenceInfo
from iecoop.st.write.expressions import _ADD, _ATOM, _BINARY_OPERATORS
from iecoop.st.write.infer import _DINT, _Untranslated, _is_integer, _constant_int, _fields_of, _from_iecoop, _is_name
from iecoop.st.write.model import StExportError, annotation_info, type_text
from iecoop.st.write.cases import Branch, CaseForm, Label, case_form
from iecoop.st.write.forms import ReaderForms, TryStatement
from iecoop.st.write.loops import reader_loops, same_variable

__all__ = ["BodyWriter", "StatementWriter"]

class StatementWriter(ReaderForms):
    """Translate one function of a POU into ST lines and the locals they need."""

    def translate(self) -> list[str]:
        """The ST lines of the function: its tree read, the names it binds, its result variable, then its statements."""
        node = self.function_tree()
        self.bound = self.bound_names(node)
        body = _statements(node)
        self.result_local = self.result_variable(body)
        # A final `return x` needs no RETURN after the result assignment.
        self.block(body, 0, top=True)
        self.comments_before(None, 0)
        return self.lines

    def comments_before(self, line: int | None, depth: int) -> None:
        """Write the comments of the source's own lines before ``line`` (all that are left, for None) as ST's ``//``
        comments: what the ST or Python said about its statements stays with them."""
        while self.comments and (line is None or self.comments[0][0] < line):
            _, text = self.comments.pop(0)
            self.lines.append("    " * depth + (f"// {text}" if text else "//"))

    def function_tree(self) -> ast.FunctionDef:
        """The syntax tree of the function, from its source (the Python the reader made, for loaded ST)."""
        try:
            source = textwrap.dedent(python_source(self.func))
        except (OSError, TypeError) as exc:
            raise StExportError(f"{self.where_text()}: the source of {self.func.__qualname__} is not available ({exc})") from None
        node = ast.parse(source).body[0]
        if not isinstance(node, ast.FunctionDef):
            raise StExportError(f"{self.where_text()}: {self.func.__qualname__} is not a plain def")
        self.source_lines = source.splitlines()
        registered = definition(getattr(self.func, "__code__", None))
        if registered is not None:
            # the same def as it was compiled, its statements given the ST lines they were read from
            self.st_lines = {
                fresh.lineno: mapped.lineno for fresh, mapped in zip(ast.walk(node), ast.walk(registered[0]))
                if isinstance(fresh, ast.stmt) and isinstance(mapped, ast.stmt) and type(fresh) is type(mapped)
            }
        self.comments = _line_comments(source)
        self.reads = collections.Counter(n.id for n in ast.walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load))
        return node

    def bound_names(self, node: ast.FunctionDef) -> set[str]:
        """The names the function binds: each is an ST local for the whole body, so it hides a variable of the
        same name even in the statements before its first assignment (those read ``THIS^.name``)."""
        bound = {n.id for n in ast.walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
        if self.func.__name__ != "body":
            return bound
        # The body's locals named like a variable are renamed (see declare()): they hide nothing.
        # ST names ignore case: a local axis is the variable Axis there.
        variables = {f.lower() for f in self.fields}
        for name in sorted(n for n in bound if n.lower() in variables):
            self.temp_name(name)
        return bound - set(self.temp_names)

    def result_variable(self, body: list[ast.stmt]) -> str | None:
        """The result variable as the ST reader writes it: a local named like the member (``Start: BOOL = False``
        ... ``return Start``) is the member's own result, which ST declares by the member itself."""
        if self.result is None or isinstance(self.result, ReferenceInfo):
            return None
        return next(
            (stmt.target.id for stmt in body
             if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name) and stmt.target.id == self.st_name),
            None,
        )

    def block(self, body: list[ast.stmt], depth: int, *, top: bool = False) -> None:
        start = self.statements_written
        self._block(body, depth, top)
        if not top and self.statements_written == start:
            self.write(depth, ";")  # ST needs a statement where Python had only pass / a docstring

    def _block(self, body: list[ast.stmt], depth: int, top: bool) -> None:
        body = self.reader_tries(self.reader_cases(reader_loops(body, self.reads)))
        for i, stmt in enumerate(body):
            last = top and i == len(body) - 1
            if isinstance(getattr(stmt, "lineno", None), int):
                self.comments_before(stmt.lineno, depth)
            mark = len(self.lines)
            saved = (dict(self.locals), set(self.references), dict(self.local_types))
            self.hoisted = {}
            try:
                self.visit(stmt, depth, last)
            except _Untranslated as exc:
                del self.lines[mark:]
                self.locals, self.references, self.local_types, self.prelude = saved[0], saved[1], saved[2], []
                line = self.line_of(exc.node)
                message = f"{self.filename}:{line}: {exc.what} has no Structured Text form (in {self.func.__qualname__})"
                if not self.lenient:
                    raise StExportError(message) from None
                if (line, exc.what) not in self.untranslated:  # once, though an unrolled loop repeats it
                    self.untranslated.append((line, exc.what))
                text = " ".join(
                    part.strip() for part in self.source_lines[stmt.lineno - 1 : (stmt.end_lineno or stmt.lineno)]
                )
                text = text.replace("(*", "( *").replace("*)", "* )")
                self.lines.append("    " * depth + f"(* not translated, {exc.what} (line {line}): {text} *)")

    def write(self, depth: int, text: str) -> None:
        """Write one line at ``depth``, after the statements it needs first (a call's result kept in a temporary)."""
        pending, self.prelude = self.prelude, []
        for line in pending:
            self.lines.append("    " * depth + line)
        self.lines.append("    " * depth + text)
        self.statements_written += 1

    def once(self, node: ast.AST, text: str) -> str:
        """A condition evaluated again and again (WHILE, ELSIF): it cannot use a temporary set before."""
        if self.prelude:
            self.fail(node, "a member of a call's result in a while or elif condition (assign the result to a local first)")
        return text

    # -- one handler per statement: visit_<ast class name>(node, depth, last) ---------------------------

    def visit_Pass(self, node: ast.Pass, depth: int, last: bool) -> None:
        """``pass``: nothing (a block left empty gets ST's empty statement ``;``)."""

    def visit_Expr(self, node: ast.Expr, depth: int, last: bool) -> None:
        """A call as a statement; a docstring or other constant is nothing."""
        if not isinstance(node.value, ast.Constant):
            self.call_statement(node.value, depth)

    def visit_Assign(self, node: ast.Assign, depth: int, last: bool) -> None:
        """``a = b`` / ``a, b = b, a``: ``a := b;`` (``REF=`` where Python binds a name to a variable)."""
        self.assign(node, depth)

    def visit_AnnAssign(self, node: ast.AnnAssign, depth: int, last: bool) -> None:
        """``n: INT = 3``: the local ``n : INT`` in VAR, and ``n := 3;``."""
        if not isinstance(node.target, ast.Name):
            self.fail(node, "an annotated assignment to an attribute")
        if node.target.id == self.result_local:
            # The result starts at its type's zero on every call: only another initial value is written.
            if node.value is not None and not _is_zero(node.value):
                self.write(depth, f"{self.st_name} := {self.expr(node.value)[0]};")
            return
        info = annotation_info(ast.unparse(node.annotation), self.func, f"{self.func.__qualname__}.{node.target.id}", self.scope.cls)
        if info is None:
            self.fail(node, "a local annotated None")
        if isinstance(info, AggregateInfo) and isinstance(node.value, ast.Call) and not node.value.args \
                and not node.value.keywords and self.constant_object(node.value.func) is info.cls:
            self.declare(node.target.id, info, node)  # ``p: FB_P = FB_P()``: the METHOD's local ``p : FB_P;``
            return
        bound_by_call = isinstance(node.value, ast.Call) and isinstance(self.typeof(node.value), ReferenceInfo)
        if not (isinstance(info, AggregateInfo) and node.value is not None and (not isinstance(node.value, ast.Call) or bound_by_call)):
            self.declare(node.target.id, info, node)
        if node.value is not None:
            self.assign_one(node.target, node.value, depth, node)

    def visit_AugAssign(self, node: ast.AugAssign, depth: int, last: bool) -> None:
        """``a += b``: ``a := a + b;``."""
        if type(node.op).__name__ not in _BINARY_OPERATORS:
            self.fail(node, f"the operator {type(node.op).__name__}=")
        target = self.target(node.target)
        value = self.binop(ast.BinOp(node.target, node.op, node.value), node)[0]
        self.write(depth, f"{target} := {value};")

    def visit_While(self, node: ast.While, depth: int, last: bool) -> None:
        """``while c:``: ``WHILE c DO ... END_WHILE``."""
        if node.orelse:
            self.fail(node, "while ... else")
        self.write(depth, f"WHILE {self.once(node, self.condition(node.test))} DO")
        self.block(node.body, depth + 1)
        self.write(depth, "END_WHILE")

    def visit_Break(self, node: ast.Break, depth: int, last: bool) -> None:
        self.write(depth, "EXIT;")

    def visit_Continue(self, node: ast.Continue, depth: int, last: bool) -> None:
        self.write(depth, "CONTINUE;")

    def visit_Return(self, node: ast.Return, depth: int, last: bool) -> None:
        if _is_name(node.value, self.result_local or ""):
            pass  # ``return Start``: the result variable holds it already
        elif node.value is not None and not (isinstance(node.value, ast.Constant) and node.value.value is None and self.result is None):
            if self.result is None:
                self.fail(node, "a return value in a block without a result")
            place = self.is_place(node.value)
            self.return_places.append(place)
            if isinstance(self.result, ReferenceInfo):
                if not place:
                    self.fail(node, f"a return of a value that ends with the call, where the result is {type_text(self.result)} "
                              "(the member's first definition hands out a variable: return a variable of the block, a GVL or an input)")
                self.write(depth, f"{self.st_name} REF= {self.ref_target(node.value)};")
            else:
                self.write(depth, f"{self.st_name} := {self.expr(node.value)[0]};")
        if not last:
            self.write(depth, "RETURN;")

    def visit_If(self, node: ast.If, depth: int, last: bool) -> None:
        """``if`` / ``elif`` / ``else``: IF / ELSIF / ELSE, or CASE where every test compares one integer or
        enumeration variable with distinct constants (see :mod:`.cases`)."""
        form = case_form(node, self.case_value)
        if form is not None and _is_integer(self.typeof(form.subject)):
            self.write_case(form, depth)
            return
        self.write(depth, f"IF {self.condition(node.test)} THEN")
        self.block(node.body, depth + 1)
        orelse = node.orelse
        while len(orelse) == 1 and isinstance(orelse[0], ast.If):
            branch = orelse[0]
            self.write(depth, f"ELSIF {self.once(branch, self.condition(branch.test))} THEN")
            self.block(branch.body, depth + 1)
            orelse = branch.orelse
        if orelse:
            self.write(depth, "ELSE")
            self.block(orelse, depth + 1)
        self.write(depth, "END_IF")

    def visit_For(self, node: ast.For, depth: int, last: bool) -> None:
        if node.orelse:
            self.fail(node, "for ... else")
        it = node.iter
        enumerated = isinstance(it, ast.Call) and _is_name(it.func, "enumerate") and "enumerate" not in self.globals
        sequence = typing.cast(ast.Call, it).args[0] if enumerated and typing.cast(ast.Call, it).args else it
        if isinstance(sequence, (ast.Tuple, ast.List)):
            self.unrolled_loop(node, sequence.elts, depth)
            return
        owner = self.constant_object(sequence)
        if isinstance(owner, type) and kind_of(owner) == "enum":
            # An enumeration's components, in declaration order.
            members = [ast.Attribute(sequence, m.name, ast.Load()) for m in typing.cast(Any, owner)]
            self.unrolled_loop(node, typing.cast(list[ast.expr], members), depth)
            return
        if isinstance(self.typeof(sequence), ArrayInfo):
            self.array_loop(node, depth)
            return
        if not (isinstance(node.target, (ast.Name, ast.Attribute)) and isinstance(it, ast.Call) and _is_name(it.func, "range") and not it.keywords):
            self.fail(node, "a for loop over something other than range(), an ARRAY or a tuple")
        self.range_loop(node, it, depth)

    def loop_targets(self, node: ast.For, width: int) -> tuple[ast.Name | None, list[str]]:
        """(the enumerate() counter or None, the names bound to each element) of a for loop."""
        target = node.target
        enumerated = isinstance(node.iter, ast.Call) and _is_name(node.iter.func, "enumerate")
        counter: ast.Name | None = None
        if enumerated:
            if not (isinstance(target, ast.Tuple) and len(target.elts) == 2 and isinstance(target.elts[0], ast.Name)):
                self.fail(node, "enumerate() without a (counter, element) target")
            counter, target = target.elts[0], target.elts[1]
        names = target.elts if isinstance(target, ast.Tuple) else [target]
        if not all(isinstance(n, ast.Name) for n in names) or width != len(names) and width != 0:
            self.fail(node, "a for loop target that is not one name per element")
        return counter, [typing.cast(ast.Name, n).id for n in names]

    def enumerate_start(self, node: ast.For) -> int:
        it = node.iter
        if not (isinstance(it, ast.Call) and _is_name(it.func, "enumerate")):
            return 0
        if it.keywords or len(it.args) not in (1, 2):
            self.fail(node, "enumerate() with these arguments")
        start = _constant_int(it.args[1]) if len(it.args) == 2 else 0
        if start is None:
            self.fail(node, "an enumerate() start that is not a constant integer")
        return start

    def unrolled_loop(self, node: ast.For, items: list[ast.expr], depth: int) -> None:
        """A loop over a literal tuple: the body once per element, each name standing for its element."""
        rows = [list(e.elts) if isinstance(e, ast.Tuple) else [e] for e in items]
        counter, names = self.loop_targets(node, len(rows[0]) if rows and len(rows[0]) > 1 else 1)
        start = self.enumerate_start(node)
        bound = [*names, *([counter.id] if counter is not None else [])]
        if _escapes(node.body) or any(isinstance(n, ast.Name) and n.id in bound and isinstance(n.ctx, ast.Store) for b in node.body for n in ast.walk(b)):
            self.fail(node, "a loop over a tuple whose body breaks, continues or assigns the loop names (write the statements once per element)")
        saved = dict(self.rename), dict(self.params)
        try:
            for i, row in enumerate(rows):
                if len(row) != len(names):
                    self.fail(node, "a for loop over tuples of different lengths")
                values = [*row, *([ast.Constant(start + i)] if counter is not None else [])]
                for name, value in zip(bound, values):
                    text, prec = self.expr(value)
                    if prec != _ATOM:
                        self.fail(node, "a loop over a tuple of expressions (name each element)")
                    self.rename[name] = text
                    self.params[name] = self.typeof(value)  # type: ignore[assignment]
                self.block(node.body, depth)
        finally:
            self.rename, self.params = saved

    def array_loop(self, node: ast.For, depth: int) -> None:
        """A loop over a one-dimensional ARRAY: FOR over its declared bounds, the name bound to each element."""
        it = node.iter
        array = it.args[0] if isinstance(it, ast.Call) else it
        info = typing.cast(ArrayInfo, self.typeof(array))
        if len(info.bounds) != 1:
            self.fail(node, "a for loop over an ARRAY of several dimensions")
        (low, high), elem = info.bounds[0], info.elem
        counter, (name,) = self.loop_targets(node, 1)
        start = self.enumerate_start(node)
        aggregate = isinstance(elem, AggregateInfo)
        if aggregate and any(isinstance(n, ast.Name) and n.id == name and isinstance(n.ctx, ast.Store) for b in node.body for n in ast.walk(b)):
            self.fail(node, "a loop over an ARRAY of blocks or structs whose body assigns the loop name")
        index = counter.id if counter is not None and start == low else self.fresh_name(f"{name}_index")
        self.declare_once(index, _DINT, node)
        self.write(depth, f"FOR {self.name_text(index)} := {low} TO {high} DO")
        if counter is not None and index != counter.id:
            self.declare_once(counter.id, _DINT, node)
            offset = start - low
            self.write(depth + 1, f"{self.name_text(counter.id)} := {self.name_text(index)} {'+' if offset >= 0 else '-'} {abs(offset)};")
        element = f"{self.expr(array, _ATOM)[0]}[{self.name_text(index)}]"
        if aggregate:
            # Python binds the name to the element itself: in ST that is a reference to it.
            if name not in self.references:
                self.references.add(name)
                self.declare(name, ReferenceInfo(elem), node, seen_as=elem)
            self.write(depth + 1, f"{self.name_text(name)} REF= {element};")
        else:
            self.declare_once(name, elem, node)
            self.write(depth + 1, f"{self.name_text(name)} := {element};")
        self.block(node.body, depth + 1)
        self.write(depth, "END_FOR")

    def range_loop(self, node: ast.For, it: ast.Call, depth: int) -> None:
        args = it.args
        if not 1 <= len(args) <= 3:
            self.fail(node, "range() with no argument")
        start = args[0] if len(args) > 1 else ast.Constant(0)
        stop = args[1] if len(args) > 1 else args[0]
        step = 1
        by = ""
        if len(args) == 3:
            value = _constant_int(args[2])
            if value is None and isinstance(stop, ast.BinOp) and isinstance(stop.op, ast.Add) and isinstance(stop.right, ast.IfExp):
                # the reader's ``b + (1 if c > 0 else -1)`` for FOR ... TO b BY c: the ST end is b
                end, by = self.expr(stop.left)[0], f" BY {self.expr(args[2])[0]}"
            elif value is None or value == 0:
                self.fail(node, "a range() step that is not a constant integer")
            else:
                step = value
        if isinstance(node.target, ast.Name):
            self.declare_once(node.target.id, _DINT, node)
            variable = self.name_text(node.target.id)
        else:  # a variable of the block (``self.n``), as the reader writes an ST FOR
            variable = self.expr(node.target)[0]
        if not by:
            end = self.end_bound(stop, -1 if step > 0 else 1)
            by = f" BY {step}" if step != 1 else ""
        self.write(depth, f"FOR {variable} := {self.expr(start)[0]} TO {end}{by} DO")
        self.block(node.body, depth + 1)
        self.write(depth, "END_FOR")

    def end_bound(self, stop: ast.expr, delta: int) -> str:
        """``stop + delta`` written simply (``n + 1`` with delta -1 is ``n``)."""
        value = _constant_int(stop)
        if value is not None:
            return str(value + delta)
        if isinstance(stop, ast.BinOp) and isinstance(stop.op, (ast.Add, ast.Sub)):
            right = _constant_int(stop.right)
            if right is not None:
                total = (right if isinstance(stop.op, ast.Add) else -right) + delta
                left = self.expr(stop.left, _ADD)[0]
                if total == 0:
                    return left
                return f"{left} {'+' if total > 0 else '-'} {abs(total)}"
        text = self.expr(stop, _ADD)[0]
        return f"{text} {'+' if delta > 0 else '-'} {abs(delta)}"

    def visit_With(self, node: ast.With, depth: int, last: bool) -> None:
        if len(node.items) != 1:
            self.fail(node, "a with statement of several items")
        item = node.items[0]
        call = item.context_expr
        if not (isinstance(call, ast.Call) and self.resolves_to(call.func, "try_catch")):
            self.fail(node, "a with statement other than try_catch()")
        self.write(depth, "__TRY")
        self.block(node.body, depth + 1)
        if isinstance(item.optional_vars, ast.Name):
            name = item.optional_vars.id
            self.catch_vars.add(name)
            self.declare(name, "__SYSTEM.ExceptionCode", node)
            self.write(depth, f"__CATCH({name})")
        else:
            self.write(depth, "__CATCH")
        self.write(depth, "__ENDTRY")

    def visit_Try(self, node: ast.Try, depth: int, last: bool) -> None:
        """``try`` / ``except`` (/ ``finally``) where it means what __TRY / __CATCH (/ __FINALLY) mean."""
        if not node.handlers:
            # The vendors' __TRY ... __FINALLY ... __ENDTRY goes on after __ENDTRY; Python's finally re-raises.
            self.fail(node, "try / finally without except (ST goes on after __FINALLY where Python passes the exception on: "
                      "put the clean-up after the statements, or use with try_catch() and act on exc.code)")
        if len(node.handlers) > 1 or node.orelse:
            self.fail(node, "try with several except clauses or an else (write one except clause)")
        handler = node.handlers[0]
        if not self.catches_all_faults(handler.type, node.body):
            self.fail(handler, "an except clause other than except PlcException, except (PlcException, ZeroDivisionError) "
                      "or except Exception (__CATCH catches every runtime fault, a division by zero too)")
        name = handler.name if handler.name is not None else self.fresh_name("exc")
        self.visit_TryStatement(ast.copy_location(TryStatement(node.body, name, handler.body, node.finalbody), node), depth, last)

    def catches_all_faults(self, node: ast.expr | None, body: list[ast.stmt]) -> bool:
        """Whether an except clause catches what try_catch() (and the PLC's __CATCH) catch: a
        ZeroDivisionError too, unless the statements divide nothing themselves."""
        names = node.elts if isinstance(node, ast.Tuple) else [node] if node is not None else []
        found = {self.constant_object(n) or getattr(builtins, getattr(n, "id", ""), None) for n in names}
        from iecoop.exceptions import PlcException

        divides = any(isinstance(n, (ast.Div, ast.FloorDiv, ast.Mod)) for b in body for n in ast.walk(b))
        return bool({Exception, BaseException} & found) or PlcException in found and (ZeroDivisionError in found or not divides)

    def visit_Match(self, node: ast.Match, depth: int, last: bool) -> None:
        """``match x: case A.B | A.C: ... case _: ...`` as CASE: neither falls through."""
        branches: list[Branch] = []
        orelse: list[ast.stmt] = []
        for case in node.cases:
            if case.guard is not None:
                self.fail(case.guard, "a case with a guard (write an if inside the case)")
            pattern = case.pattern
            if isinstance(pattern, ast.MatchAs) and pattern.pattern is None and pattern.name is None:
                orelse = case.body or [ast.Pass()]
                continue
            options = pattern.patterns if isinstance(pattern, ast.MatchOr) else [pattern]
            if not all(isinstance(o, ast.MatchValue) for o in options):
                self.fail(pattern, "a case pattern other than values, enumeration components and _")
            branches.append(Branch(tuple(Label(typing.cast(ast.MatchValue, o).value) for o in options), case.body))
        self.write_case(CaseForm(node.subject, tuple(branches), orelse), depth)

    def call_statement(self, node: ast.expr, depth: int) -> None:
        if not isinstance(node, ast.Call):
            self.fail(node, "an expression statement that is not a call")
        func = node.func
        if self.resolves_to(func, "ref_assign"):
            holder, field, target = self.operator_args(node, 3)
            self.write(depth, f"{self.member_text(holder, field)} REF= {self.ref_target(target)};")
            return
        chain = self.set_reset_chain(node)
        if chain is not None:
            links, condition = chain
            reads = {_path(n) for n in ast.walk(condition) if isinstance(n, (ast.Attribute, ast.Name))} - {None}
            once = len(links) > 1 and any(isinstance(n, ast.Call) for n in ast.walk(condition))
            if once or len(links) > 1 and any(target in reads for target, _ in links):
                # The condition is evaluated once for the whole chain: ST's a S= b R= c.
                self.write(depth, " ".join(f"{text} {word}" for _, (text, word) in links) + f" {self.expr(condition)[0]};")
            else:
                # One statement per link, the innermost first as Python runs them (blark reads no chain).
                for _, (text, word) in reversed(links):
                    self.write(depth, f"{text} {word} {self.expr(condition)[0]};")
            return
        self.write(depth, f"{self.call(node)[0]};")

    def set_reset_chain(self, node: ast.expr) -> tuple[list[tuple[_Path | None, tuple[str, str]]], ast.expr] | None:
        """``S(self, "a", R(self, "b", c))``: the links ((the target's path, (ST target, S= / R=)), outermost
        first) and the condition ``c`` they all act on (S and R return their condition)."""
        if not isinstance(node, ast.Call):
            return None
        for op, word in (("S", "S="), ("R", "R=")):
            if self.resolves_to(node.func, op) and _from_iecoop(self.globals.get(op)):
                holder, field, condition = self.operator_args(node, 3)
                base = _path(holder)
                target = (*base, (".", str(getattr(field, "value", "")))) if base is not None else None
                link = (target, (self.member_text(holder, field), word))
                inner = self.set_reset_chain(condition)
                return ([link], condition) if inner is None else ([link, *inner[0]], inner[1])
        return None

    def assign(self, node: ast.Assign, depth: int) -> None:
        for target in node.targets:
            if isinstance(target, ast.Tuple):
                if not (isinstance(node.value, ast.Tuple) and len(node.value.elts) == len(target.elts)) or len(node.targets) != 1:
                    self.fail(node, "unpacking a value that is not a tuple of the same length")
                self.tuple_assign(target.elts, node.value.elts, depth, node)
            else:
                self.assign_one(target, node.value, depth, node)

    def tuple_assign(self, targets: list[ast.expr], values: list[ast.expr], depth: int, node: ast.stmt) -> None:
        """``a, b = x, y``: one assignment after another; a value that reads an earlier target is kept
        in a temporary first, since Python evaluates every value before it assigns."""
        paths = [_path(t) for t in targets]
        held: dict[int, str] = {}
        for i, value in enumerate(values):
            reads = [_path(n) for n in ast.walk(value) if isinstance(n, (ast.Name, ast.Attribute, ast.Subscript))]
            # a read of an earlier target, or of a member or element of it
            if not any(p is not None and r is not None and r[: len(p)] == p for p in paths[:i] for r in reads):
                continue
            info = self.typeof(targets[i]) or self.typeof(value)
            if info is None:
                self.fail(node, "a tuple assignment whose later values read an earlier target of unknown type")
            temp = self.temporary(f"{_stem(paths[i])}_new", info, node)
            self.hoisted[id(value)] = temp
            self.write(depth, f"{temp} := {self.expr(value)[0]};")
            held[i] = temp
        for i, (t, v) in enumerate(zip(targets, values)):
            self.assign_one(t, ast.Name(held[i], ast.Load()) if i in held else v, depth, node)

    def assign_one(self, target: ast.expr, value: ast.expr, depth: int, node: ast.stmt) -> None:
        if isinstance(value, ast.BoolOp) and isinstance(value.op, ast.Or) and len(value.values) == 2 and _is_null_call(value.values[1], self):
            # ``b = query_interface(a, IB) or null(IB)``: __QUERYINTERFACE leaves 0 in b where a has no IB
            value = value.values[0]
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "set_bit") and len(value.args) == 3 and same_variable(value.args[0], target):
            # ``x = set_bit(x, 3, flag)`` is ST's bit access ``x.3 := flag;``
            bit = _constant_int(value.args[1])
            if bit is None:
                self.fail(node, "set_bit() with a bit number that is not a constant")
            self.write(depth, f"{self.target(target)}.{bit} := {self.expr(value.args[2])[0]};")
            return
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "query_interface"):
            source, _iface = self.operator_args(value, 2)
            self.maybe_declare(target, value, node)
            self.write(depth, f"__QUERYINTERFACE({self.expr(source)[0]}, {self.target(target)});")
            return
        if isinstance(value, ast.Call) and self.resolves_to(value.func, "query_pointer"):
            (source,) = self.operator_args(value, 1)
            self.maybe_declare(target, value, node)
            self.write(depth, f"__QUERYPOINTER({self.expr(source)[0]}, {self.target(target)});")
            return
        self.maybe_declare(target, value, node)
        if isinstance(target, ast.Name) and target.id in self.references:
            self.write(depth, f"{self.name_text(target.id)} REF= {self.expr(value)[0]};")
            return
        if isinstance(target, ast.Attribute) and self.reads_property(target):
            info = self.typeof(target)
            if isinstance(info, ReferenceInfo) and isinstance(info.target, AggregateInfo):
                # The Set accessor of a REFERENCE TO property is called with REF= (fbSample.MyProp REF= stSet),
                # as Python's setter gets the object itself; := would write through the Get accessor's reference.
                self.write(depth, f"{self.target(target)} REF= {self.expr(value)[0]};")
                return
        text, _prec = self.expr(value)
        self.write(depth, f"{self.target(target)} := {text};")

    def maybe_declare(self, target: ast.expr, value: ast.expr, node: ast.stmt) -> None:
        """Declare the local a first assignment binds, of the type of its value."""
        if not isinstance(target, ast.Name):
            return
        name = target.id
        if name in self.locals or name in self.params or name == self.result_local or self.declare_operator_result(name, value, node):
            return
        info = self.typeof(value)
        if info is None:
            self.fail(node, f"a local {name!r} whose type cannot be inferred (annotate it: {name}: INT = ...)")
        gives_reference = isinstance(value, ast.Call) or self.reads_property(value)
        if isinstance(info, ReferenceInfo) and isinstance(info.target, AggregateInfo) and gives_reference:
            # A METHOD, FUNCTION or PROPERTY that gives REFERENCE TO: Python's name is the variable itself, as ST's REF= binds it.
            self.references.add(name)
            self.declare(name, info, node)
            return
        if isinstance(info, AggregateInfo) and not gives_reference:
            # Python binds a name to the element itself: in ST that is a reference to it (a PROPERTY's
            # Get gives a value, which has no address: that one is a copy).
            self.references.add(name)
            self.declare(name, ReferenceInfo(info), node, seen_as=info)
            return
        self.declare(name, info, node)

    def declare_operator_result(self, name: str, value: ast.expr, node: ast.stmt) -> bool:
        """Declare a local that holds what __QUERYINTERFACE, __QUERYPOINTER or __VARINFO give (True if it is one)."""
        if not isinstance(value, ast.Call):
            return False
        if self.resolves_to(value.func, "query_interface"):
            iface = value.args[1] if len(value.args) > 1 else None
            cls = self.constant_object(iface) if iface is not None else None
            if cls is None:
                self.fail(node, "query_interface() with a target that is not an interface name")
            self.declare(name, cls.__name__, node)
            return True
        declared = next((text for operator, text in _OPERATOR_LOCALS.items() if self.resolves_to(value.func, operator)), None)
        if declared is not None:
            self.declare(name, declared, node)
        return declared is not None

    def is_place(self, node: ast.expr) -> bool:
        """Whether ``node`` names a variable that outlives the call: a variable of the block or of a GVL, an
        element or member of one, an input passed by reference, a pointer's target, a REFERENCE local bound to
        one of those, or the result of a call that returns a REFERENCE TO (ST can bind a reference to it)."""
        if isinstance(node, ast.Name):
            if node.id == "self":
                return "self" not in self.locals and self.scope.cls is not None
            if node.id in self.references:
                return True
            if node.id in self.params:
                return node.id not in self.bound and isinstance(self.params[node.id], AggregateInfo)
            return node.id not in self.locals and kind_of(type(self.globals.get(node.id))) == "gvl"
        if isinstance(node, ast.Attribute):
            if node.attr == "deref":
                return True
            if isinstance(node.value, ast.Name) and node.value.id not in self.locals and node.value.id not in self.params:
                holder = self.globals.get(node.value.id)
                if kind_of(type(holder)) == "gvl":
                    return node.attr in _fields_of(type(holder))
            return self.is_place(node.value) and self.typeof(node) is not None and not self.reads_property(node)
        if isinstance(node, ast.Subscript):
            return self.is_place(node.value)
        if isinstance(node, ast.Call):
            return isinstance(self.typeof(node), ReferenceInfo)
        return False



#: iecoop operators whose result a local holds, and the ST type of that local.
_OPERATOR_LOCALS = {"query_pointer": "PVOID", "var_info": "__SYSTEM.VAR_INFO"}


#: The variable a name, member or element designates, step by step: ``self.a[i]`` is
#: ``(("", "self"), (".", "a"), ("[", <the syntax tree of i>))``.
_Path = tuple[tuple[str, str], ...]


def _path(node: ast.expr) -> _Path | None:
    """The path of the variable ``node`` designates (an index by its syntax tree); None for another expression."""
    if isinstance(node, ast.Name):
        return (("", node.id),)
    if isinstance(node, (ast.Attribute, ast.Subscript)):
        base = _path(node.value)
        step = (".", node.attr) if isinstance(node, ast.Attribute) else ("[", ast.dump(node.slice))
        return None if base is None else (*base, step)
    return None


def _stem(path: _Path | None) -> str:
    """A name for a temporary from an assignment target's path (``self.a[i]`` gives ``a``)."""
    steps = list(path or (("", "value"),))
    if steps[0] == ("", "self") and len(steps) > 1:
        steps = steps[1:]
    names: list[str] = []
    for kind, name in steps:
        if kind == "[":
            break
        names.append(name)
    return "_".join(names)


def _escapes(body: list[ast.stmt]) -> bool:
    """Whether a loop body breaks or continues its own loop (not one nested in it)."""
    for stmt in body:
        if isinstance(stmt, (ast.Break, ast.Continue)):
            return True
        if isinstance(stmt, (ast.For, ast.While)):
            continue
        if _escapes([c for c in ast.iter_child_nodes(stmt) if isinstance(c, ast.stmt)]):
            return True
    return False


def walk_calls(tree: ast.AST) -> Iterator[ast.Call]:
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            yield node



#: The writer of a body (its statements, expressions and types).
BodyWriter = StatementWriter


def _line_comments(source: str) -> list[tuple[int, str]]:
    """(line, text) of each comment that stands on a line of its own in ``source``, in order (the text without
    its ``#``); a comment after a statement on its line stays out (the reader's notes to Python are such)."""
    found: list[tuple[int, str]] = []
    try:
        for token in tokenize.generate_tokens(io.StringIO(source).readline):
            if token.type == tokenize.COMMENT and not token.line[: token.start[1]].strip():
                found.append((token.start[0], token.string[1:].strip()))
    except (tokenize.TokenError, SyntaxError):  # the source parsed: this cannot happen, and comments are no reason to fail
        return []
    return found


def _is_null_call(node: ast.expr, writer: StatementWriter) -> bool:
    """``null(ITF)``: iecoop's null interface reference."""
    return isinstance(node, ast.Call) and writer.resolves_to(node.func, "null") and _from_iecoop(writer.globals.get("null"))


def _is_zero(value: ast.expr) -> bool:
    """A literal zero of any elementary type (``False``, ``0``, ``0.0``, ``""``): the value a result starts with."""
    return isinstance(value, ast.Constant) and value.value in (False, 0, 0.0, "") and value.value is not None


def _statements(node: ast.FunctionDef) -> list[ast.stmt]:
    """The statements of a function, without its docstring; none for an abstract one (``raise NotImplementedError``)."""
    body = list(node.body)
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
        body = body[1:]
    if len(body) == 1 and isinstance(body[0], ast.Raise) and _is_name(getattr(body[0], "exc", None), "NotImplementedError"):
        return []
    return body
