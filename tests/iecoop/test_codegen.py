"""Generated Python: one helper compiles it, registers its lines and numbers each script."""

from __future__ import annotations

import traceback
from typing import Any

import pytest

from iecoop._codegen import compile_source, compiled, script_number


def test_a_traceback_through_generated_code_shows_the_generated_line() -> None:
    namespace: dict[str, Any] = compile_source("def fail():\n    raise ValueError('from the script')\n", "Demo.fail", {})
    with pytest.raises(ValueError) as info:
        namespace["fail"]()
    text = "".join(traceback.format_exception(info.value))
    assert "<iecoop generated Demo.fail #" in text
    assert "raise ValueError('from the script')" in text


def test_each_script_gets_its_own_file_name() -> None:
    first = compile_source("def f(): pass\n", "same", {})["f"].__code__.co_filename
    second = compile_source("def f(): pass\n", "same", {})["f"].__code__.co_filename
    assert first != second
    assert script_number() < script_number()


def test_compiled_registers_the_text_before_a_syntax_error_is_raised() -> None:
    import linecache

    with pytest.raises(SyntaxError):
        compiled("x = (\n", "<iecoop test broken>")
    assert linecache.getline("<iecoop test broken>", 1) == "x = (\n"
