"""The vendors' dialect blark's grammar does not read: grammar added with Lark's ``%extend`` / ``%override``,
and the rewrite of the raw parse tree into the shapes blark's transformer knows.

Each addition is a form TwinCAT, CODESYS or IEC 61131-3 (3rd edition) code is written in:

- a METHOD or PROPERTY written inside its FUNCTION_BLOCK or INTERFACE (the IEC / open-compiler form), a PROPERTY there
  with ``GET ... END_GET`` and ``SET ... END_SET`` accessors, and ``CLASS ... END_CLASS`` (a FUNCTION_BLOCK
  without a body): the members are moved after their block, where the flat form has them;
- ``REF_TO`` (IEC 61131-3's spelling of ``REFERENCE TO``), ``PROGRAM INTERNAL``, ``INTERFACE INTERNAL``,
  ``VAR_TEMP`` in a FUNCTION;
- ``LTIME#1US5NS`` (a unit followed by a smaller one below the millisecond), a trailing comma after the
  names of ``EXTENDS``, an empty initialiser ``:= ()`` and an array literal assigned in code
  (``aPoints := [(x := 1), (x := 2)];``), and a member of what a call's pointer result points to (``F(x)^.y``).
"""

from __future__ import annotations

import re
from typing import Any

__all__ = ["DIALECT_OVERLAY", "needs_dialect", "rewrite"]

DIALECT_OVERLAY = r"""
%extend _library_element_declaration: class_declaration
class_declaration: _CLASS [ access_specifier ] derived_function_block_name [ extends ] [ implements ] fb_var_declaration* [ nested_members ] _END_CLASS ";"*
%extend function_block_type_declaration: FUNCTION_BLOCK [ access_specifier ] derived_function_block_name [ extends ] [ implements ] fb_var_declaration* nested_members [ function_block_body ] END_FUNCTION_BLOCK ";"*
nested_members: ( function_block_method_declaration | function_block_property_declaration | nested_property )+
nested_property: _PROPERTY [ access_specifier ] DOTTED_IDENTIFIER ":" property_return_type ";"* nested_accessor+ _END_PROPERTY ";"*
nested_accessor: ACCESSOR [ access_specifier ] property_var_declaration* [ function_block_body ] _END_ACCESSOR ";"*
ACCESSOR.2: /\b(GET|SET)\b/i
_END_ACCESSOR.2: /\bEND_(GET|SET)\b/i
_CLASS.2: /\bCLASS\b/i
_END_CLASS.2: /\bEND_CLASS\b/i
%extend program_declaration: _PROGRAM _PROGRAM_ACCESS program_type_name program_var_declarations [ function_block_body ] _END_PROGRAM ";"*
_PROGRAM_ACCESS.2: /\b(INTERNAL|PUBLIC)\b/i
%extend interface_declaration: _INTERFACE _PROGRAM_ACCESS IDENTIFIER [ extends ] interface_var_declaration* _END_INTERFACE? ";"*
%extend interface_declaration: _INTERFACE _PROGRAM_ACCESS? IDENTIFIER [ extends ] interface_var_declaration* nested_members _END_INTERFACE ";"*
%extend function_var_block: temp_var_decls
%override REFERENCE_TO: /\bREFERENCE\b\s+\bTO\b/i | /\bREF_TO\b/i
%override extends: _EXTENDS DOTTED_IDENTIFIER ("," DOTTED_IDENTIFIER)* [ "," ]
%override milliseconds: FIXED_POINT "ms"i | INTEGER "ms"i "_"? microseconds | INTEGER "ms"i
%override microseconds: FIXED_POINT "us"i | INTEGER "us"i "_"? nanoseconds | INTEGER "us"i
%extend structure_initialization: "(" ")"
%extend primary_expression: call_member
call_member: function_call field_selector+
%extend primary_expression: "[" array_initial_element ( "," array_initial_element )* "]" -> bracketed_array_initialization
"""

#: Words and forms that need the overlay; a source without them is parsed by blark's grammar as it is.
_TRIGGERS = re.compile(
    r"\bEND_CLASS\b|\bEND_GET\b|\bEND_SET\b|\bREF_TO\b|\b(?:PROGRAM|INTERFACE)\s+(?:INTERNAL|PUBLIC)\b|\bVAR_TEMP\b"
    r"|\bL?T(?:IME)?#[-\d_.a-z]*\d(?:ms|us)_?\d|\bEXTENDS\b[ \t\w.,]*,[ \t]*(?:\r?\n|$)|:=\s*\(\s*\)"
    r"|^\s*[\w.\[\]^]+\s*:=\s*\[|\)\s*\^\s*\.\s*[a-z_]",
    re.IGNORECASE | re.MULTILINE,
)
_BLOCK_WORDS = re.compile(r"\b(END_FUNCTION_BLOCK|FUNCTION_BLOCK|END_INTERFACE|INTERFACE|METHOD|PROPERTY)\b", re.IGNORECASE)


def needs_dialect(text: str) -> bool:
    """Whether ``text`` uses a form only the overlay reads."""
    if _TRIGGERS.search(text):
        return True
    inside = False  # a METHOD or PROPERTY before its block's END_FUNCTION_BLOCK
    for word in _BLOCK_WORDS.finditer(text):
        keyword = word.group(1).upper()
        if keyword in ("FUNCTION_BLOCK", "INTERFACE"):
            inside = True
        elif keyword in ("END_FUNCTION_BLOCK", "END_INTERFACE"):
            inside = False
        elif inside:
            return True
    return False


def rewrite(tree: Any) -> None:
    """Rewrite the overlay's rules in blark's raw tree into blark's own, in place (see the module docstring)."""
    import lark

    for subtree in tree.iter_subtrees():
        # blark tells a reference by the text "REFERENCE TO": REF_TO is spelled so
        subtree.children = [
            lark.Token("REFERENCE_TO", "REFERENCE TO") if isinstance(c, lark.Token) and c.type == "REFERENCE_TO" else c
            for c in subtree.children
        ]
    items: list[Any] = []
    for child in tree.children:
        if not isinstance(child, lark.Tree):
            items.append(child)
            continue
        if child.data == "class_declaration":
            child = _as_function_block(child, lark)
        members: list[Any] = []
        if child.data in ("function_block_type_declaration", "interface_declaration"):
            kept = []
            for part in child.children:
                if isinstance(part, lark.Tree) and part.data == "nested_members":
                    members.extend(_members(part, lark))
                else:
                    kept.append(part)
            child.children = kept
        items.append(child)
        items.extend(members)
    tree.children = items


def _as_function_block(node: Any, lark: Any) -> Any:
    """``CLASS C ... END_CLASS``: the FUNCTION_BLOCK C without a body (IEC 61131-3 3rd edition, CODESYS)."""
    head = [lark.Token("FUNCTION_BLOCK", "FUNCTION_BLOCK")] + list(node.children)
    nested = head.pop() if isinstance(head[-1], lark.Tree) and head[-1].data == "nested_members" else None
    if head[-1] is None:
        head.pop()  # the optional nested members left out
    children = head + ([nested] if nested is not None else []) + [None, lark.Token("END_FUNCTION_BLOCK", "END_FUNCTION_BLOCK")]
    return lark.Tree(lark.Token("RULE", "function_block_type_declaration"), children, node.meta)


def _members(node: Any, lark: Any) -> list[Any]:
    """The METHODs and PROPERTYs written inside a block, as the flat form has them after it."""
    found = []
    for member in node.children:
        if member.data != "nested_property":
            found.append(member)
            continue
        access, name, returns, *accessors = member.children
        for accessor in accessors:
            kind, own, *rest = accessor.children
            body = rest.pop() if rest and isinstance(rest[-1], lark.Tree) and rest[-1].data == "statement_list" else None
            if rest and rest[-1] is None:
                rest.pop()
            dotted = lark.Token("DOTTED_IDENTIFIER", f"{name}.{str(kind).capitalize()}")
            found.append(lark.Tree(
                lark.Token("RULE", "function_block_property_declaration"),
                [access, dotted, returns, own, *rest, body], accessor.meta,
            ))
    return found
