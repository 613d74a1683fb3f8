"""The generated call with the block's body compiled into it: one Python frame per FB call.

A block's call sets the inputs and runs ``body()``. Run as two functions,
every call pays for a second frame; a scan of a thousand stations, each
calling an R_TRIG, a CTU and a TON, pays it four thousand times a cycle. So
when the class is built, the builder compiles one function from the lines
that set the inputs and the body's own statements, as attrs compiles
``__init__`` from its fields.

The body's statements keep their file and line numbers, so a traceback, a
debugger's breakpoint and coverage still point at the user's ``body``; the
lines that set the inputs carry the line of ``def body``. The body's closure
cells (``super()``'s ``__class__`` among them) are the body's own, shared, and
its globals are its module's. The body is compiled into the call only when
that is provably the same code: its source, compiled the same way, must give
a code object equal to the body's (so a file edited since import, a decorated
body or one made by ``exec`` without its source is left alone), it takes
``self`` alone, is no generator, returns no value and uses none of the
call's names. Otherwise the call calls the body, as before.

Compiled into the call, five of the body's own operations take the cheaper
way to the same result: a FOR over a block's integer variable with a
constant range reads the counter from the loop in its passes
(``CounterReads``); a block member read ``self.timer`` reads the view its
property's getter returns, kept as an instance attribute; a member call
``self.timer(IN=x)`` calls the member class's call directly (inputs by
position when the keywords follow the declared order) while it is the
class's ``__call__``; ``T("200ms")`` (and D, LTIME, TOD, DT) is read when
the class is built, guarded by the name still being iecoop's literal; and in
checked mode ``self.x = value`` is written out as the work the checked
``__setattr__`` does for ``x``.
"""

from __future__ import annotations

import __future__
import ast
import copy
import dis
import functools
import inspect
import linecache
import symtable
import types
import typing
from collections.abc import Callable
from typing import Any

from iecoop._codegen import definition, register_definition
from iecoop._inline_reads import CounterReads, GivenInputs, OwnCode, located
from iecoop._loop_locals import LoopLocals
from iecoop._value_class import value_class
from iecoop.literals import D, T
from iecoop.memory._views import ELEMENT_VIEWS, keep_member_views
from iecoop.members import adopt_code
from iecoop.types import DT, LTIME, TOD

__all__ = ["compile_own_loops", "compile_own_writes", "inline_call"]

_FUTURE_FLAGS = 0
for _feature in __future__.all_feature_names:
    _FUTURE_FLAGS |= getattr(__future__, _feature).compiler_flag
_NOT_PLAIN = inspect.CO_GENERATOR | inspect.CO_COROUTINE | inspect.CO_ASYNC_GENERATOR | inspect.CO_ITERABLE_COROUTINE
#: A METHOD compiled with its writes written out is an ordinary function (any parameters).
_NOT_ORDINARY = _NOT_PLAIN
_NOT_PLAIN |= inspect.CO_VARARGS | inspect.CO_VARKEYWORDS
#: ``direct(cls)``: the cell a member call calls ``cls`` through with the inputs by position, and their order.
Direct = Callable[[type], tuple[types.CellType, tuple[str, ...]]]
_STORE_ATTR, _EXTENDED_ARG = dis.opmap["STORE_ATTR"], dis.opmap["EXTENDED_ARG"]
_FOR_ITER = bytes([dis.opmap["FOR_ITER"]])
_JUMP_BACKWARD = bytes([dis.opmap["JUMP_BACKWARD"]])
_FACTORY = "_iec_factory_"
_CLASS = "_iec_class_"
_STORE = "_iec_w_"
_VALUE = f"{_STORE}value"


def inline_call(
    name: str, body: types.FunctionType, params: list[str], lines: list[str], names: dict[str, Any],
    kwdefaults: dict[str, Any], owner: type, stores: dict[str, tuple[Any, bool, Any, str, Any]],
    members: dict[str, tuple[str, type | None]], *, positional: bool = False, direct: Direct | None = None,
    views: dict[str, str] | None = None, known: dict[str, type] | None = None,
    arrays: dict[str, tuple[type, int, int]] | None = None, counters: dict[str, tuple[int, int]] | None = None,
    plain: set[str] | None = None, bools: set[str] | None = None, loops: dict[str, Any] | None = None,
) -> Callable[..., None] | None:
    """``__call__(self, *, <params>)``: ``lines`` (which set the inputs, using ``names``) then ``body``'s statements.

    ``positional``: ``__call__(self, <params>)`` instead, every input by
    position. ``direct(cls)``: the cell through which a member call passes
    ``cls``'s inputs by position, and their order (see ``_MemberCalls``).

    ``stores`` (checked mode): per variable, what its checked ``__setattr__``
    does for a write (accepted class, inside only, validator, "Class.field",
    store); the body's own ``self.x = value`` is written out as that work.
    ``members``: per block member, the name its property's getter reads
    (``attrgetter(alias)``) and, for a member of one block type, that class;
    the body's own ``self.timer`` reads the alias, and ``self.timer(IN=...)``
    calls that class's ``__call__`` as Python's call would find it.
    ``views`` (checked mode): per STRUCT / ARRAY variable its own code may
    write, the key its view is kept under for that code, as a member's; the
    body's own ``self.stations`` reads it instead of the checked descriptor.
    ``known`` (checked mode): the class a read of each variable gives (see ``value_class``).
    ``arrays``: per one-dimensional ARRAY OF a block, its element class and
    bounds; the body's own ``self.stations[i]`` reads the kept element in place.
    ``counters``: per integer variable a FOR may count with, its range; a
    ``for self.i in range(...)`` pass reads ``i`` from its local (``CounterReads``).
    ``plain``: the elementary variables read from their ctypes fields;
    ``bools``: the BOOL inputs among them, whose first reads in the body take
    the argument given (``GivenInputs``). ``loops`` (fast mode): per variable a
    loop that calls nothing may keep in a local, its ctypes type (``LoopLocals``).
    None when the body cannot be compiled into the call as the same code.
    """
    code = body.__code__
    node = _function_node(body) if _plain(body) else None
    # `params` are "name=..."; the names themselves are the keys of `kwdefaults`.
    setting = _recompiles(node, body, {*kwdefaults, *names}) if node is not None and not _returns_value(node) else None
    if node is None or setting is None:
        return None
    flags, imports = setting
    # The rewrites add the objects their code reads; the builder's dict stays as given.
    names = dict(names)
    call = _rewritten(
        node, body, params, lines, names, owner, stores, members, positional, direct, views or {}, known or {}, arrays or {},
        counters or {}, plain or set(), bools or set(), loops or {},
    )
    merged = _compile_in(call, code, sorted(names), flags, imports)
    if merged is None:
        return None
    function = _call_function(merged, body, names, {} if positional else kwdefaults, f"{name}.__call__", owner.__module__)
    # Whoever owns the body owns its copy here; nested code (a comprehension) compiles equal to the original's.
    adopt_code(merged, code, owner)
    return function


def compile_own_writes(
    func: types.FunctionType, owner: type, stores: dict[str, tuple[Any, bool, Any, str, Any]], known: dict[str, type],
) -> types.FunctionType | None:
    """Checked mode: ``func`` (a METHOD of ``owner``) with its own ``self.x = value`` written out, as the call's are.

    The same function otherwise: its signature, defaults, attributes, closure
    cells, globals, file and lines. ``stores`` is the call's (see ``inline_call``);
    ``known``: the Python type a read of each elementary variable gives, so a
    value of known type skips the class check it would pass. None when the
    method cannot be compiled as the same code, or writes none of ``stores``.
    """
    code = func.__code__
    node = _function_node(func, decorated=True) if _may_compile_method(func, owner, stores) else None
    setting = _recompiles(node, func, set()) if node is not None and not _rebinds_self(node) else None
    if node is None or setting is None:
        return None
    flags, imports = setting
    names: dict[str, Any] = {}
    stores_out = _DirectStores(stores, names, known)
    statements = [stores_out.visit(statement) for statement in node.body]
    node.body = [s for item in statements for s in (item if isinstance(item, list) else [item])]
    merged = _compile_in(node, code, sorted(names), flags, imports) if names else None
    return _method_from(merged, func, names, owner) if merged is not None else None


def compile_own_loops(func: types.FunctionType, owner: type, loops: dict[str, Any]) -> types.FunctionType | None:
    """Fast mode: ``func`` (a METHOD of ``owner``) with its loops that call nothing keeping ``loops`` in locals.

    The same function otherwise, as ``compile_own_writes`` makes it; ``loops``
    is the call's (see ``inline_call``). None when the method cannot be
    compiled as the same code, writes none of ``loops``, or no loop of it
    keeps a variable.
    """
    code = func.__code__
    # Cheap tests first, on the code's opcodes and names: a loop, and a store of a variable (most loops that
    # write no variable of the block call something); the source is parsed only for what passes.
    if not (_has_loop(code) and not loops.keys().isdisjoint(code.co_names) and _stores_attribute(code, loops)):
        return None
    if not _may_compile_method(func, owner):
        return None
    node = _function_node(func, decorated=True)
    names: dict[str, Any] = {}
    local = {*code.co_varnames, *code.co_cellvars, *code.co_freevars}
    keeping = LoopLocals(loops, func.__globals__, local, names)
    if node is None or _rebinds_self(node) or not keeping.finds(node.body):
        return None
    setting = _recompiles(node, func, set())
    if setting is None:
        return None
    flags, imports = setting
    keeping.rewrite(node.body)
    merged = _compile_in(node, code, sorted(names), flags, imports)
    return _method_from(merged, func, names, owner) if merged is not None else None


def _has_loop(code: types.CodeType) -> bool:
    """Whether ``code`` itself has a loop: a FOR's iteration or a jump back (a scan of its opcodes, in C)."""
    ops = code.co_code[::2]
    return _FOR_ITER in ops or _JUMP_BACKWARD in ops


def _may_compile_method(func: types.FunctionType, owner: type, stores: dict[str, Any] | None = None) -> bool:
    """An ordinary function of ``self`` (no generator, no wrapper), the class's own code, storing one of
    ``stores`` when given."""
    code = func.__code__
    if code.co_flags & _NOT_ORDINARY or code.co_argcount < 1 or code.co_varnames[:1] != ("self",):
        return False
    own = not hasattr(func, "__wrapped__") and code in getattr(owner, "_iec_codes_", ())
    return own and (stores is None or _stores_attribute(code, stores))


def _method_from(merged: types.CodeType, func: types.FunctionType, names: dict[str, Any], owner: type) -> types.FunctionType:
    """``func`` with the code ``merged``: its closure cells and a cell for each of ``names``, its attributes."""
    code = func.__code__
    cells = dict(zip(code.co_freevars, func.__closure__ or ()))
    closure = tuple(cells[v] if v in cells else types.CellType(names[v]) for v in merged.co_freevars)
    method = types.FunctionType(merged, func.__globals__, func.__name__, func.__defaults__, closure)
    method.__kwdefaults__ = func.__kwdefaults__
    method.__annotations__ = func.__annotations__
    method.__dict__.update(func.__dict__)
    method.__qualname__, method.__module__, method.__doc__ = func.__qualname__, func.__module__, func.__doc__
    adopt_code(merged, code, owner)
    registered = definition(code)
    if registered is not None:  # loaded ST: the writer reads the method's Python from its recorded definition
        register_definition(merged, *registered)
    return method


def _recompiles(node: ast.FunctionDef, func: types.FunctionType, call_names: set[str]) -> tuple[int, list[str]] | None:
    """The ``__future__`` flags and module imports under which ``node`` compiles to ``func``'s own code.

    None when it does not (the source is not the running code), or when a name it uses meets ``call_names``
    or one the rewrites add.
    """
    code = func.__code__
    used = _used_names(node)
    if _meets_call(used, call_names):
        return None
    flags = code.co_flags & _FUTURE_FLAGS
    imports = _imports_used(node, func, used)
    same = _compile_in(node, code, [], flags, imports)
    if same is None or _without_nested(same) != _without_nested(code):
        return None
    return flags, imports


def _plain(body: types.FunctionType) -> bool:
    """``def body(self)``: no other parameter, no default, no generator or coroutine, no decorator's wrapper."""
    code = body.__code__
    return not (
        code.co_flags & _NOT_PLAIN or code.co_argcount != 1 or code.co_posonlyargcount or code.co_kwonlyargcount
        or code.co_varnames[:1] != ("self",) or body.__defaults__ or body.__kwdefaults__
        or hasattr(body, "__wrapped__")
    )


def _meets_call(used: set[str], call_names: set[str]) -> bool:
    """Whether a name the body uses is one of the call's (its inputs, its names, the compile's and the rewrites')."""
    return bool(used & {*call_names, _FACTORY, _CLASS}) or any(n.startswith(_STORE) for n in used)


def _returns_value(node: ast.FunctionDef) -> bool:
    """Whether the body's own code has ``return value``: the call returns None."""
    known = _survey(node).returns_value
    if known is not None:
        return known
    return any(isinstance(n, ast.Return) and n.value is not None for n in _own_nodes(node))


def _imports_used(node: ast.FunctionDef, body: types.FunctionType, used: set[str]) -> list[str]:
    """The module's top-level imports the body uses, when it calls ``name.attr(...)`` on a name; else none."""
    # Only `name.attr(...)` compiles differently when `name` is imported; most bodies call only `self.x(...)`.
    called = _survey(node).calls_attribute
    return sorted(_module_imports(body.__code__, body.__globals__) & used) if called else []


def _rewritten(
    node: ast.FunctionDef, body: types.FunctionType, params: list[str], lines: list[str], names: dict[str, Any],
    owner: type, stores: dict[str, tuple[Any, bool, Any, str, Any]], members: dict[str, tuple[str, type | None]],
    positional: bool, direct: Direct | None, views: dict[str, str], known: dict[str, type],
    arrays: dict[str, tuple[type, int, int]], counters: dict[str, tuple[int, int]], plain: set[str], bools: set[str],
    loops: dict[str, Any],
) -> ast.FunctionDef:
    """The call's ``def``: the input lines, then the body's statements with stores, members and literals rewritten.

    The rewrites add the objects their code reads to ``names``.
    """
    code = body.__code__
    local = {*code.co_varnames, *code.co_cellvars, *code.co_freevars}
    if bools and not _rebinds_self(node):
        blocks = {member for member, (_key, cls) in members.items() if cls is not None}
        GivenInputs(bools, plain, blocks).rewrite(node.body)
    # The rule check is skipped only where __setattr__ skips it: the body is the block's own code.
    own = code in getattr(owner, "_iec_codes_", ())
    writes = {field: spec for field, spec in stores.items() if own or not spec[1]}
    if own:
        # Only the block's own code may read a STRUCT / ARRAY view without the read-only rule.
        members = {**members, **{field: (key, None) for field, key in views.items()}}
    spans: dict[str, range] = {}
    # The rewrites see the body's own statements only: the input lines are the builder's, with nothing to rewrite.
    statements = node.body
    # Only a body with a loop has a FOR to rewrite (its code has a FOR_ITER: a scan in C, no walk of the tree).
    if counters and _FOR_ITER in code.co_code[::2] and not _rebinds_self(node):
        CounterReads(counters, spans, body.__globals__, local).rewrite(statements)
    if loops and _has_loop(code) and not _rebinds_self(node):
        LoopLocals(loops, body.__globals__, local, names).rewrite(statements)
    if (writes or members) and not _rebinds_self(node):
        statements = _with_members(statements, writes, members, names, direct, known, arrays, spans)
    # Only a body that names one of the literal functions has a literal to read (a walk of its tree otherwise saved).
    if any(body.__globals__.get(name) is literal for name in code.co_names for literal in _LITERALS):
        statements = [_Literals(body.__globals__, local, names).visit(statement) for statement in statements]
    node.body = _with_views_kept(statements, {key for key, _cls in members.values()}, names, node)
    call = _with_inputs(node, [p.removesuffix("=...") for p in params] if positional else params, lines, positional)
    return call


def _with_members(
    statements: list[ast.stmt], writes: dict[str, tuple[Any, bool, Any, str, Any]],
    members: dict[str, tuple[str, type | None]], names: dict[str, Any], direct: Direct | None,
    known: dict[str, type], arrays: dict[str, tuple[type, int, int]], spans: dict[str, range],
) -> list[ast.stmt]:
    """``statements`` with the direct stores, then the member calls, then the member reads written out.

    ``spans``: per FOR counter a loop reads from its local (``CounterReads``), the values it takes.
    """
    if writes:
        statements = [_DirectStores(writes, names, known).visit(statement) for statement in statements]
        # A store becomes a list of statements.
        statements = [s for item in statements for s in (item if isinstance(item, list) else [item])]
    if members:
        statements = [_MemberCalls(members, names, direct, arrays, spans).visit(statement) for statement in statements]
        keys = {member: key for member, (key, _cls) in members.items()}
        statements = [_MemberReads(keys).visit(statement) for statement in statements]
    return statements


def _with_views_kept(statements: list[ast.stmt], keys: set[str], names: dict[str, Any], where: ast.AST) -> list[ast.stmt]:
    """``statements``, first making sure the member views they read are kept under their keys.

    ::

        try:
            self._iec_m_0timer
        except AttributeError:
            _iec_w_keep_views(self)

    One key present means every key of the instance's class is (``keep_member_views``).
    """
    # The first key read, in the order of the statements: the walk ends there.
    probed = next((
        n.attr for statement in statements for n in ast.walk(statement)
        if isinstance(n, ast.Attribute) and n.attr in keys and isinstance(n.value, ast.Name) and n.value.id == "self"
    ), None) if keys else None
    if probed is None:
        return statements
    keep, error = f"{_STORE}keep_views", f"{_STORE}attribute_error"
    # The builtin itself: the body's module may bind the name AttributeError to something else.
    names.update({keep: keep_member_views, error: AttributeError})
    probe = ast.Expr(ast.Attribute(value=ast.Name(id="self", ctx=ast.Load()), attr=probed, ctx=ast.Load()))
    fill = ast.Expr(ast.Call(func=ast.Name(id=keep, ctx=ast.Load()), args=[ast.Name(id="self", ctx=ast.Load())], keywords=[]))
    handler = ast.ExceptHandler(type=ast.Name(id=error, ctx=ast.Load()), name=None, body=[fill])
    prologue = ast.Try(body=[probe], handlers=[handler], orelse=[], finalbody=[])
    return [located(prologue, where), *statements]  # at the def line, as the input lines


def _call_function(
    merged: types.CodeType, body: types.FunctionType, names: dict[str, Any], kwdefaults: dict[str, Any],
    qualname: str, module: str,
) -> types.FunctionType:
    """``__call__`` from the merged code: the body's globals and cells, a new cell for each of the call's names."""
    code = body.__code__
    cells = dict(zip(code.co_freevars, body.__closure__ or ()))
    # A cell among the names is shared as it is: a member class's direct-call cell, which its class keeps current.
    cells.update((v, value) for v, value in names.items() if isinstance(value, types.CellType))
    closure = tuple(cells[v] if v in cells else types.CellType(names[v]) for v in merged.co_freevars)
    function = types.FunctionType(merged, body.__globals__, "__call__", None, closure)
    function.__kwdefaults__ = dict(kwdefaults)
    function.__annotations__ = {"return": None}
    function.__qualname__ = qualname
    function.__module__ = module
    return function


def _function_node(body: types.FunctionType, decorated: bool = False) -> ast.FunctionDef | None:
    """The body's ``def`` as the source holds it, at its own lines and columns; None without its source.

    ``decorated``: a ``def`` under decorators (a METHOD's ``@method``) is taken too; its code
    starts at the first decorator's line, as the function's does.
    """
    registered = definition(body.__code__)
    if registered is not None:  # loaded ST: the file holds ST, the generated def is recorded
        node = copy.deepcopy(registered[0])
        named = isinstance(node, ast.FunctionDef) and node.name == body.__code__.co_name
        return node if isinstance(node, ast.FunctionDef) and named and (decorated or not node.decorator_list) else None
    line = body.__code__.co_firstlineno
    try:
        tree = _parsed(_source_of(body), line)
    except SyntaxError:  # the lines the code covers end before the def does (a docstring alone, say)
        try:
            tree = _parsed(inspect.getsource(body), line)
        except (OSError, TypeError, SyntaxError, ValueError, RecursionError):
            return None
    except (OSError, TypeError, ValueError, RecursionError):
        return None
    top = tree.body[0]
    node = top.body[0] if isinstance(top, ast.If) else top
    if not isinstance(node, ast.FunctionDef) or (node.decorator_list and not decorated) or node.name != body.__code__.co_name:
        return None
    first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
    if first != line:
        ast.increment_lineno(node, line - first)
    return node


def _parsed(source: str, line: int) -> ast.Module:
    """``source``, whose first line is the file's ``line``, parsed at the file's line numbers."""
    # An indented def (a method) parses inside an `if`, which keeps its columns; blank lines before it put it at its line.
    if source[:1].isspace():
        return ast.parse("\n" * (line - 2) + f"if 1:\n{source}" if line >= 2 else f"if 1:\n{source}")
    return ast.parse("\n" * (line - 1) + source)


def _source_of(func: types.FunctionType) -> str:
    """The lines of ``func``'s ``def`` (from its first decorator), as ``inspect.getsource`` gives them.

    The ``def`` ends at the last line its code (nested code included) covers,
    read from the code rather than by tokenizing the file again; a ``def`` cut
    short does not parse, or does not compile to the running code, which the
    callers check.
    """
    code = func.__code__
    lines = linecache.getlines(code.co_filename, func.__globals__)
    if not lines:
        return inspect.getsource(func)
    return "".join(lines[code.co_firstlineno - 1:_last_line(code)])


def _last_line(code: types.CodeType) -> int:
    last = max((end for _start, end, _col, _end_col in code.co_positions() if end is not None), default=code.co_firstlineno)
    nested = (_last_line(const) for const in code.co_consts if isinstance(const, types.CodeType))
    return max([last, *nested])


def _stores_attribute(code: types.CodeType, names: Any) -> bool:
    """Whether ``code`` itself (not code nested in it) stores an attribute named in ``names`` (``self.x = ...``)."""
    raw, extended = code.co_code, 0
    for i in range(0, len(raw), 2):
        op, arg = raw[i], raw[i + 1] | extended
        if op == _EXTENDED_ARG:
            extended = arg << 8
            continue
        extended = 0
        if op == _STORE_ATTR and code.co_names[arg] in names:
            return True
    return False


class _Survey(typing.NamedTuple):
    """What one walk over a ``def`` finds: the names it uses, whether it rebinds ``self``, whether it calls ``name.attr()``."""

    used: set[str]
    rebinds_self: bool
    calls_attribute: bool
    #: Whether it has ``return value``, when the walk can tell (None: a nested def or lambda may hold it).
    returns_value: bool | None


def _survey(node: ast.FunctionDef) -> _Survey:
    """One walk over ``node``, kept on it (the checks below each ask a part of it)."""
    kept: _Survey | None = getattr(node, "_iec_survey_", None)
    if kept is None:
        kept = _walk_survey(node)
        setattr(node, "_iec_survey_", kept)
    return kept


def _used_names(node: ast.FunctionDef) -> set[str]:
    """Every name the body binds or reads (not attribute names): the call's names must not meet them."""
    return _survey(node).used


def _walk_survey(node: ast.FunctionDef) -> _Survey:
    found: set[str] = set()
    rebinds = called = returns = nested = False
    for n in ast.walk(node):
        if isinstance(n, ast.Return):
            returns = returns or n.value is not None
        elif isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)) and n is not node:
            nested = True
        if isinstance(n, ast.Name):
            found.add(n.id)
            rebinds = rebinds or (n.id == "self" and not isinstance(n.ctx, ast.Load))
        elif isinstance(n, ast.Call):
            func = n.func
            called = called or (isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id != "self")
        elif isinstance(n, (ast.Global, ast.Nonlocal)):
            found.update(n.names)
            rebinds = rebinds or "self" in n.names
        elif (bound := _bound_name(n, node)) is not None:
            found.add(bound)
    return _Survey(found, rebinds, called, None if returns and nested else returns)


def _bound_name(n: ast.AST, top: ast.FunctionDef) -> str | None:
    """The name ``n`` binds other than by a plain name (a parameter, a def, an import, ``except ... as``, a match)."""
    if isinstance(n, ast.arg):
        return n.arg
    if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and n is not top:
        return n.name
    if isinstance(n, ast.alias):
        return (n.asname or n.name).split(".")[0]
    if isinstance(n, (ast.ExceptHandler, ast.MatchAs, ast.MatchStar)):
        return n.name or None
    if isinstance(n, ast.MatchMapping):
        return n.rest or None
    return None


def _own_nodes(node: ast.FunctionDef) -> list[ast.AST]:
    """The nodes of the function itself, not of the functions, lambdas and classes nested in it."""
    found: list[ast.AST] = []
    todo: list[ast.AST] = list(node.body)
    while todo:
        n = todo.pop()
        found.append(n)
        if not isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)):
            todo.extend(ast.iter_child_nodes(n))
    return found


def _with_inputs(node: ast.FunctionDef, params: list[str], lines: list[str], positional: bool) -> ast.FunctionDef:
    """The body's ``def`` with the call's signature and the input lines first, all at the ``def`` line."""
    signature = ", ".join(["self", *params] if positional or not params else ["self", "*", *params])
    template = ast.parse(f"def {node.name}({signature}) -> None:\n" + "\n".join([*lines, "    pass"]) + "\n")
    head = template.body[0]
    assert isinstance(head, ast.FunctionDef)
    for n in ast.walk(head):
        if hasattr(n, "lineno"):
            located: Any = n
            located.lineno = located.end_lineno = node.lineno
            located.col_offset = located.end_col_offset = node.col_offset
    head.body[-1:] = node.body
    head.returns = None
    return head


def _rebinds_self(node: ast.FunctionDef) -> bool:
    return _survey(node).rebinds_self


class _MemberReads(OwnCode):
    """``self.timer`` (a read) becomes ``self._iec_m_0timer``, the view the member property's getter returns."""

    def __init__(self, aliases: dict[str, str]) -> None:
        self.aliases = aliases

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        self.generic_visit(node)
        alias = self.aliases.get(node.attr)
        if alias is not None and isinstance(node.ctx, ast.Load) and isinstance(node.value, ast.Name) and node.value.id == "self":
            return ast.copy_location(ast.Attribute(value=node.value, attr=alias, ctx=node.ctx), node)
        return node


#: The literal functions (ST: T#200ms, LTIME#1ms, D#..., TOD#..., DT#...): the same int for the same text.
_LITERALS: tuple[Any, ...] = (T, D, LTIME, TOD, DT)


class _Literals(OwnCode):
    """``T("200ms")`` with a constant text becomes ``(200 if T is <iecoop's T> else T("200ms"))``.

    The literal is read once, when the class is built; the name is still looked
    up at every call, so a module that rebinds ``T`` calls its own ``T``. A text
    the literal refuses is left to fail at the call, as before.
    """

    def __init__(self, module_globals: dict[str, Any], local: set[str], names: dict[str, Any]) -> None:
        self.globals, self.local, self.names = module_globals, local, names

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        func = node.func
        if not (isinstance(func, ast.Name) and func.id not in self.local and len(node.args) == 1 and not node.keywords):
            return node
        text = node.args[0]
        literal: Any = self.globals.get(func.id)
        if not (isinstance(text, ast.Constant) and isinstance(text.value, str) and any(literal is f for f in _LITERALS)):
            return node
        try:
            value = literal(text.value)
        except (ValueError, TypeError):
            return node
        if type(value) is not int:
            return node
        known = f"{_STORE}literal_{func.id}"
        self.names[known] = literal
        test = ast.Compare(left=ast.Name(id=func.id, ctx=ast.Load()), ops=[ast.Is()], comparators=[ast.Name(id=known, ctx=ast.Load())])
        return located(ast.IfExp(test=test, body=ast.Constant(value), orelse=node), node)


class _MemberCalls(OwnCode):
    """``self.timer(IN=x)`` calls the member's class's ``__call__`` without the call protocol's detour.

    Python runs ``type(view).__call__`` with the arguments packed into a tuple
    and a dict and unpacked again; a member's view is always of its declared
    class, so the call is made directly, through a cell the class keeps: it
    holds the class's built call while that is the class's ``__call__``, and a
    function making Python's ordinary call once ``__call__`` is rebound or
    deleted. Keywords in the order the class declares its inputs (any of them
    left out) pass by position, ``...`` for one not given; any other call passes
    them as written, so its arguments are still evaluated in the source's order::

        _iec_w_position_timer(self._iec_m_0timer, x, ...)    # self.timer(IN=x)
        _iec_w_call_timer(self._iec_m_0timer, PT=t, IN=x)   # self.timer(PT=t, IN=x)

    An element of an ``ARRAY[lo..hi] OF`` a block (``arrays``: per such
    variable its element class and bounds) is a view of exactly that class
    too, and indexing it reads the array's kept element views in place, the
    bounds checked as ``__getitem__`` checks them (an exact ``int`` in bounds;
    any other index goes to ``__getitem__``, which refuses or converts it)::

        _iec_w_position_stations(                            # self.stations[i](sensor=x)
            self._iec_m_0stations._iec_m_elements[_iec_w_index - 1]
            if _iec_w_type(_iec_w_index := i) is _iec_w_int and 1 <= _iec_w_index <= 1000
            else self._iec_m_0stations[_iec_w_index],
            x)
    """

    def __init__(
        self, members: dict[str, tuple[str, type | None]], names: dict[str, Any], direct: Direct | None,
        arrays: dict[str, tuple[type, int, int]] | None = None, spans: dict[str, range] | None = None,
    ) -> None:
        self.members, self.names, self.direct = members, names, direct
        self.arrays, self.spans = arrays or {}, spans or {}

    def _array(self, node: ast.expr) -> str | None:
        """The ARRAY OF blocks variable ``node`` indexes once (``self.stations[i]``, a read), else None."""
        if not (isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Load) and not isinstance(node.slice, (ast.Tuple, ast.Slice))):
            return None
        value = node.value
        if isinstance(value, ast.Attribute) and isinstance(value.value, ast.Name) and value.value.id == "self":
            return value.attr if value.attr in self.arrays and value.attr in self.members else None
        return None

    def visit_Subscript(self, node: ast.Subscript) -> ast.AST:
        self.generic_visit(node)
        array = self._array(node)
        if array is None:
            return node
        _cls, lo, hi = self.arrays[array]
        index, kind, whole = f"{_STORE}index", f"{_STORE}type", f"{_STORE}int"
        view = ast.Attribute(value=ast.Name(id="self", ctx=ast.Load()), attr=self.members[array][0], ctx=ast.Load())
        counted = self.spans.get(node.slice.id) if isinstance(node.slice, ast.Name) else None
        if counted is not None and lo <= min(counted) and max(counted) <= hi:  # a FOR counter that stays in bounds
            elements = ast.Attribute(value=view, attr=ELEMENT_VIEWS, ctx=ast.Load())
            offset = ast.BinOp(left=node.slice, op=ast.Sub(), right=ast.Constant(lo))
            return located(ast.Subscript(value=elements, slice=offset, ctx=ast.Load()), node)
        self.names.update({kind: type, whole: int})

        def name(identifier: str) -> ast.Name:
            return ast.Name(id=identifier, ctx=ast.Load())

        given = ast.NamedExpr(target=ast.Name(id=index, ctx=ast.Store()), value=node.slice)
        exact = ast.Compare(left=ast.Call(func=name(kind), args=[given], keywords=[]), ops=[ast.Is()], comparators=[name(whole)])
        inside = ast.Compare(left=ast.Constant(lo), ops=[ast.LtE(), ast.LtE()], comparators=[name(index), ast.Constant(hi)])
        elements = ast.Attribute(value=view, attr=ELEMENT_VIEWS, ctx=ast.Load())
        kept = ast.Subscript(value=elements, slice=ast.BinOp(left=name(index), op=ast.Sub(), right=ast.Constant(lo)), ctx=ast.Load())
        general = ast.Subscript(value=view, slice=name(index), ctx=ast.Load())
        test = ast.BoolOp(op=ast.And(), values=[exact, inside])
        return located(ast.IfExp(test=test, body=kept, orelse=general), node)

    def visit_Call(self, node: ast.Call) -> ast.AST:
        array = self._array(node.func)
        self.generic_visit(node)
        func = node.func
        cls: type | None
        view: ast.expr
        if array is not None:  # an element of an ARRAY OF blocks, read in place by visit_Subscript
            name, cls, view = array, self.arrays[array][0], func
        elif isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id == "self":
            key, cls = self.members.get(func.attr, ("", None))
            name, view = func.attr, ast.Attribute(value=ast.Name(id="self", ctx=ast.Load()), attr=key, ctx=ast.Load())
        else:
            return node
        cell = cls.__dict__.get("_iec_call_cell_") if cls is not None else None
        if cls is None or not isinstance(cell, types.CellType):
            return node
        by_position = self._by_position(node, cls)
        if by_position is not None:
            known = f"{_STORE}position_{name}"
            self.names[known], values = by_position
            direct = ast.Call(func=ast.Name(id=known, ctx=ast.Load()), args=[view, *values], keywords=[])
        else:
            known = f"{_STORE}call_{name}"
            self.names[known] = cell
            direct = ast.Call(func=ast.Name(id=known, ctx=ast.Load()), args=[view, *node.args], keywords=node.keywords)
        return located(direct, node)

    def _by_position(self, node: ast.Call, cls: type) -> tuple[types.CellType, list[ast.expr]] | None:
        """The positional call's cell and the arguments in the class's input order (``...`` for one not
        given), if the keywords are in that order."""
        if self.direct is None or node.args or any(k.arg is None for k in node.keywords):
            return None
        cell, order = self.direct(cls)
        given = [k.arg for k in node.keywords]
        if not set(given) <= set(order) or [n for n in order if n in given] != given:
            return None  # an unknown or repeated name, or another order: the call as written
        values = {k.arg: k.value for k in node.keywords}
        return cell, [values[n] if n in values else ast.Constant(value=...) for n in order]


class _DirectStores(OwnCode):
    """``self.x = value`` / ``self.x += value`` / ``for self.x in ...`` in the body's own statements, as checked
    ``__setattr__`` does it::

        _iec_w_value = value
        if _iec_w_value.__class__ is not _iec_w_accepted_x: _iec_w_check_x(_iec_w_value, "Class.x")
        _iec_w_store_x(self, _iec_w_value)

    A value whose class is known from the code alone (``self.n + 1`` with ``n``
    an INT, ``self.timer.Q``, a constant) skips the class check it would pass.
    Nested functions, lambdas and classes are left alone (their code must stay the body's).
    """

    def __init__(
        self, writes: dict[str, tuple[Any, bool, Any, str, Any]], names: dict[str, Any], known: dict[str, type] | None = None,
    ) -> None:
        self.writes, self.names, self.known = writes, names, known or {}

    def _field(self, target: ast.expr) -> str | None:
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self":
            return target.attr if target.attr in self.writes else None
        return None

    def generic_visit(self, node: ast.AST) -> ast.AST:
        """Statements only: the writes rewritten are statements (an expression stores no attribute)."""
        for field in ("body", "orelse", "finalbody", "handlers", "cases"):
            statements = getattr(node, field, None)
            if not isinstance(statements, list):
                continue
            rewritten: list[Any] = []
            for statement in statements:
                result = self.visit(statement)
                rewritten.extend(result if isinstance(result, list) else [result])
            statements[:] = rewritten
        return node

    def visit_Assign(self, node: ast.Assign) -> Any:
        fields = [self._field(target) for target in node.targets]
        if not any(fields):
            return node
        # `self.CV = cv = 0` assigns the one value to each target, left to right.
        statements: list[ast.stmt] = [located(ast.Assign(targets=[ast.Name(id=_VALUE, ctx=ast.Store())], value=node.value), node)]
        for target, field in zip(node.targets, fields):
            if field is None:
                statements.append(located(ast.Assign(targets=[target], value=ast.Name(id=_VALUE, ctx=ast.Load())), node))
            else:
                statements.extend(self._write(node, field, value_class(node.value, self.known)))
        return statements

    def visit_AugAssign(self, node: ast.AugAssign) -> Any:
        field = self._field(node.target)
        if field is None:
            return node
        current = ast.Attribute(value=ast.Name(id="self", ctx=ast.Load()), attr=field, ctx=ast.Load())
        value = ast.BinOp(left=ast.copy_location(current, node.target), op=node.op, right=node.value)
        return self._store(node, field, ast.copy_location(value, node))

    def visit_For(self, node: ast.For) -> Any:
        """``for self.i in ...:`` (ST's FOR with a variable of the block): each pass stores the counter written out."""
        self.generic_visit(node)
        field = self._field(node.target)
        if field is None:
            return node
        # The loop hands each value to the store, then the statements run, as Python's for assigns its target.
        node.target = ast.copy_location(ast.Name(id=_VALUE, ctx=ast.Store()), node.target)
        node.body = [*self._write(node, field), *node.body]
        return node

    def _store(self, node: ast.stmt, field: str, value: ast.expr) -> list[ast.stmt]:
        first = located(ast.Assign(targets=[ast.Name(id=_VALUE, ctx=ast.Store())], value=value), node)
        return [first, *self._write(node, field, value_class(value, self.known))]

    def _write(self, node: ast.stmt, field: str, known: type | None = None) -> list[ast.stmt]:
        """Store the value held in ``_VALUE`` into ``self.<field>`` as the checked ``__setattr__`` does.

        ``known``: the value's class, when the code alone says it (the check is left out when it would pass).
        """
        accepted, _inside, check, where, store = self.writes[field]
        self.names.update({f"{_STORE}accepted_{field}": accepted, f"{_STORE}check_{field}": check, f"{_STORE}store_{field}": store})
        v = _VALUE

        def name(identifier: str) -> ast.Name:
            return ast.Name(id=identifier, ctx=ast.Load())

        kind = ast.Compare(left=ast.Attribute(value=name(v), attr="__class__", ctx=ast.Load()), ops=[ast.IsNot()],
                           comparators=[name(f"{_STORE}accepted_{field}")])
        check = ast.Call(func=name(f"{_STORE}check_{field}"), args=[name(v), ast.Constant(where)], keywords=[])
        store_call = ast.Call(func=name(f"{_STORE}store_{field}"), args=[name("self"), name(v)], keywords=[])
        statements: list[ast.stmt] = [ast.Expr(store_call)]
        if known is None or known is not accepted:
            statements.insert(0, ast.If(test=kind, body=[ast.Expr(check)], orelse=[]))
        return [located(statement, node) for statement in statements]


def _module_imports(code: types.CodeType, module_globals: dict[str, Any]) -> frozenset[str]:
    """The names the body's module imports at its top level (the compiler calls ``name.attr()`` of those differently)."""
    registered = definition(code)
    text = registered[1] if registered is not None else "".join(linecache.getlines(code.co_filename, module_globals))
    return _imports_in(code.co_filename, text)


@functools.lru_cache(maxsize=16)
def _imports_in(filename: str, text: str) -> frozenset[str]:
    try:
        table = symtable.symtable(text, filename, "exec")
    except (SyntaxError, ValueError):
        return frozenset()
    return frozenset(symbol.get_name() for symbol in table.get_symbols() if symbol.is_imported())


def _compile_in(
    node: ast.FunctionDef, code: types.CodeType, extra: list[str], flags: int, imports: list[str]
) -> types.CodeType | None:
    """Compile ``node`` where the body was: inside a function giving its free variables (and ``extra``).

    ``__class__`` (``super()``) comes from a class statement around it, as in the source, and the
    module's imports the body uses are declared (never run) as the module declares them.
    """
    free = [v for v in code.co_freevars if v != "__class__"]
    wrapper = "".join(f"import {name}\n" for name in imports)
    wrapper += f"def {_FACTORY}({', '.join([*free, *extra])}):\n"
    wrapper += f" class {_CLASS}:\n  pass\n" if "__class__" in code.co_freevars else " pass\n"
    tree = ast.parse(wrapper)
    factory = tree.body[-1]
    assert isinstance(factory, ast.FunctionDef)
    holder = factory.body[0] if isinstance(factory.body[0], ast.ClassDef) else factory
    holder.body = [node]
    try:
        module = compile(tree, code.co_filename, "exec", flags=flags, dont_inherit=True)
    except (SyntaxError, ValueError, TypeError, RecursionError):
        return None
    return _find(module, code.co_name, code.co_firstlineno)


def _find(code: types.CodeType, name: str, line: int) -> types.CodeType | None:
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            if const.co_name == name and const.co_firstlineno == line:
                return const
            found = _find(const, name, line)
            if found is not None:
                return found
    return None


def _without_nested(code: types.CodeType) -> types.CodeType:
    # CO_NESTED only says the def sat in another function; it changes nothing the code does.
    return code.replace(co_flags=code.co_flags & ~inspect.CO_NESTED)
