"""The Structured Text lexer: keywords, types, typed and based literals, comments, pragmas, strings, operators."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re

import pytest

pytest.importorskip("pygments")

from pygments.token import Comment, Error, Keyword, Name, Number, Operator, String, Token, Whitespace  # noqa: E402

from iecoop.st_lexer import IecStLexer, looks_like_st  # noqa: E402


def lex(code: str) -> list[tuple[object, str]]:
    """The tokens of ``code`` without the whitespace between them."""
    return [(kind, text) for kind, text in IecStLexer().get_tokens(code) if kind is not Whitespace and text.strip()]


def kinds(code: str) -> dict[str, object]:
    return {text: kind for kind, text in lex(code)}


def test_keywords_and_types_in_any_case() -> None:
    found = lex("function_block FB_Motor EXTENDS FB_Base IMPLEMENTS I_Drive VAR_INPUT x : Bool; END_VAR")
    assert found[:6] == [
        (Keyword, "function_block"), (Name, "FB_Motor"), (Keyword, "EXTENDS"), (Name, "FB_Base"),
        (Keyword, "IMPLEMENTS"), (Name, "I_Drive"),
    ]
    assert (Keyword.Type, "Bool") in found and (Keyword, "END_VAR") in found
    assert kinds("IF a AND_THEN NOT b OR c MOD 2 = 0 THEN")["AND_THEN"] is Operator.Word
    assert kinds("x := TRUE; p := NULL;")["NULL"] is Keyword.Constant
    # A name that only starts like a keyword is a name.
    assert kinds("IFx := ENDING;") == {"IFx": Name, ":=": Operator, "ENDING": Name, ";": Token.Punctuation}


@pytest.mark.parametrize(
    ("code", "expected"),
    [
        ("16#FF_00", [(Number.Hex, "16#FF_00")]),
        ("8#777", [(Number.Oct, "8#777")]),
        ("2#1010_0101", [(Number.Bin, "2#1010_0101")]),
        ("INT#5", [(Keyword.Type, "INT#"), (Number.Integer, "5")]),
        ("WORD#16#FF", [(Keyword.Type, "WORD#"), (Number.Hex, "16#FF")]),
        ("BOOL#TRUE", [(Keyword.Type, "BOOL#"), (Keyword.Constant, "TRUE")]),
        ("REAL#-2.5", [(Keyword.Type, "REAL#"), (Operator, "-"), (Number.Float, "2.5")]),
        ("1.5E3", [(Number.Float, "1.5E3")]),
        ("T#1s", [(Number.Other, "T#1s")]),
        ("t#1h2m3s500ms", [(Number.Other, "t#1h2m3s500ms")]),
        ("LTIME#1ms500us", [(Number.Other, "LTIME#1ms500us")]),
        ("TIME#-250ms", [(Number.Other, "TIME#-250ms")]),
        ("DT#2024-01-28-12:00:00", [(Number.Other, "DT#2024-01-28-12:00:00")]),
        ("TOD#12:30:00.5", [(Number.Other, "TOD#12:30:00.5")]),
        ("D#2024-01-28", [(Number.Other, "D#2024-01-28")]),
        ("E_Mode#Auto", [(Name.Class, "E_Mode"), (Operator, "#"), (Name.Constant, "Auto")]),
    ],
)
def test_literals(code: str, expected: list[tuple[object, str]]) -> None:
    assert lex(code) == expected


def test_comments_of_every_kind_hide_the_words_inside() -> None:
    found = lex("x := 1; // while and IF\ny := 2;")
    assert (Comment.Single, "// while and IF") in found and (Keyword, "IF") not in found
    assert found[-4:] == [(Name, "y"), (Operator, ":="), (Number.Integer, "2"), (Token.Punctuation, ";")]
    nested = lex("(* a (* nested WHILE *) still OR *) END_IF")
    assert all(kind is Comment.Multiline for kind, _ in nested[:-1]) and nested[-1] == (Keyword, "END_IF")
    assert "".join(text for _, text in nested[:-1]).replace(" ", "") == "(*a(*nestedWHILE*)stillOR*)"
    c_style = lex("/* FOR * x */ FOR")
    assert [kind for kind, _ in c_style[:-1]] == [Comment.Multiline] * len(c_style[:-1]) and c_style[-1] == (Keyword, "FOR")


def test_pragmas_strings_and_addresses() -> None:
    found = lex("{attribute 'qualified_only'}\nVAR_GLOBAL x AT %IX0.1 : BOOL; y AT %Q* : INT; END_VAR")
    assert found[0] == (Comment.Preproc, "{attribute 'qualified_only'}")
    assert (Name.Builtin, "%IX0.1") in found and (Name.Builtin, "%Q*") in found
    text = lex("s := 'it$'s $N$0A done'; w := \"$0041\";")
    assert [t for k, t in text if k is String.Escape] == ["$'", "$N", "$0A", "$0041"]
    assert (String.Single, "done") in [(k, t.strip()) for k, t in text]


def test_operators() -> None:
    found = kinds("fb(IN := x, Q => done); p^.v := THIS^.v ** 2; r REF= x; b S= c; a := a <> b;")
    assert [found[o] for o in (":=", "=>", "^", "**", "REF=", "S=", "<>")] == [Operator] * 7


def _st_blocks() -> list[tuple[str, str]]:
    """Every literal block of the pattern and library docstrings that is ST."""
    import iecoop
    import patterns

    blocks = []
    for package in (patterns, iecoop):
        for info in pkgutil.walk_packages(package.__path__, prefix=f"{package.__name__}."):
            if info.name.endswith(("st_lexer", "plugin")) or ".showcase" in info.name:
                continue
            module = importlib.import_module(info.name)
            for owner in [module, *vars(module).values()]:
                doc = inspect.getdoc(owner) if inspect.ismodule(owner) or inspect.isclass(owner) else None
                for block in re.findall(r"::\n\n((?:(?: {4}.*)?\n)+)", (doc or "") + "\n"):
                    if looks_like_st(block):
                        blocks.append((info.name, block))
    return blocks


def test_the_st_of_every_docstring_lexes_without_an_error() -> None:
    blocks = _st_blocks()
    assert len(blocks) >= 28  # at least the IEC mapping of every pattern and principle
    for where, block in blocks:
        errors = [text for kind, text in IecStLexer().get_tokens(block) if kind is Error]
        assert errors == [], where


def test_looks_like_st_tells_st_from_python() -> None:
    assert looks_like_st("FUNCTION_BLOCK FB_X\nVAR\nEND_VAR")
    assert looks_like_st("    IF x THEN\n        y := 1;\n    END_IF")
    assert not looks_like_st("if x:\n    y = 1\n")
    assert not looks_like_st(">>> VAR(0)\n0")
    assert IecStLexer.analyse_text("PROGRAM MAIN\nEND_PROGRAM") > 0
