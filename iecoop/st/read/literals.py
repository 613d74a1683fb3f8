"""Pass 2, literals: one ``visit_<blark node>`` per literal kind (numbers, strings, durations, dates), each an ``Ex``."""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from typing import Any

import blark.transform as tf

from iecoop import literals
from iecoop.st.read.frames import Ex, Scope
from iecoop.st.read.pywriter import PyWriter
from iecoop.st.read.table import BOOL, LINT, LREAL, STRING, TypeRef
from iecoop.st.read.trees import python_string


#: ULINT's largest value: no integer literal of any type is larger
_LARGEST = (1 << 64) - 1


class Literals(PyWriter):
    """ST literals as Python: ``16#FF`` is ``0xFF``, ``T#1s`` is ``T("1s")``, ``INT#5`` is 5 typed INT."""

    def _literal_type(self, type_name: Any, default: TypeRef) -> TypeRef:
        if type_name is None:
            return default
        found = self._elem_or_none(str(type_name))
        return found or default

    def visit_Integer(self, node: tf.Integer, scope: Scope) -> Ex:
        text = str(node.value).replace("_", "")
        type_ = self._literal_type(node.type_name, LINT)
        if type_.is_real:  # REAL#5: any number of digits is a float (inf beyond LREAL's range)
            return Ex(f"{text.lstrip('0') or '0'}.0", type_, constant=float(text))
        if len(text.lstrip("0")) > len(str(_LARGEST)):  # before int(): Python refuses to read very long digit strings
            raise self._literal_too_large(text, node)
        value = int(text)
        self._literal_fits(value, text, node)
        if type_.is_bool:
            return Ex("True" if value else "False", BOOL)
        return Ex(str(value), type_ if node.type_name is not None else None, constant=value)  # 007 is 7; Python refuses the zeros

    def _based(self, node: Any, prefix: str, base: int) -> Ex:
        text = str(node.value).replace("_", "")
        type_ = self._literal_type(node.type_name, LINT)
        digits = text.lstrip("0")
        if base != 10 or digits.isdigit():  # more than 64 digits is more than 64 bits in any base
            self._literal_fits(int(digits or "0", base) if len(digits) <= 64 else _LARGEST + 1, str(node.value), node)
        return Ex(f"{prefix}{text.upper() if base == 16 else text}", type_ if node.type_name is not None else None)

    def _literal_fits(self, value: int, text: str, node: Any) -> None:
        if value > _LARGEST:
            raise self._literal_too_large(text, node)

    def _literal_too_large(self, text: str, node: Any) -> Exception:
        shown = text if len(text) <= 40 else f"{text[:20]}...{text[-10:]} ({len(text)} digits)"
        return self.fail(f"the integer literal {shown} is larger than any integer type holds (ULINT: 0..{_LARGEST})", node)

    def visit_HexInteger(self, node: tf.HexInteger, scope: Scope) -> Ex:
        return self._based(node, "0x", 16)

    def visit_BinaryInteger(self, node: tf.BinaryInteger, scope: Scope) -> Ex:
        return self._based(node, "0b", 2)

    def visit_OctalInteger(self, node: tf.OctalInteger, scope: Scope) -> Ex:
        return self._based(node, "0o", 8)

    def visit_HexBitString(self, node: tf.HexBitString, scope: Scope) -> Ex:
        return self._based(node, "0x", 16)

    def visit_BinaryBitString(self, node: tf.BinaryBitString, scope: Scope) -> Ex:
        return self._based(node, "0b", 2)

    def visit_OctalBitString(self, node: tf.OctalBitString, scope: Scope) -> Ex:
        return self._based(node, "0o", 8)

    def visit_BitString(self, node: tf.BitString, scope: Scope) -> Ex:
        return self._based(node, "", 10)

    def visit_Real(self, node: tf.Real, scope: Scope) -> Ex:
        text = str(node.value).replace("_", "")
        if "." not in text and "e" not in text.lower():
            text += ".0"
        plain = re.fullmatch(r"\d+(\.\d+)?", text) is not None  # 2.5, not 2.5e3: -2.5e3 keeps its unary minus
        return Ex(text, self._literal_type(node.type_name, LREAL), constant=float(text) if plain else None)

    def visit_Boolean(self, node: tf.Boolean, scope: Scope) -> Ex:
        return Ex("True" if str(node.value).upper() in ("TRUE", "1") else "False", BOOL)

    def visit_String(self, node: tf.String, scope: Scope) -> Ex:
        return Ex(python_string(str(node.value)), STRING)

    def _duration(self, node: Any, units: Sequence[tuple[str, str]]) -> str:
        parts = []
        for attr, suffix in units:
            value = getattr(node, attr, None)
            if value is not None:
                parts.append(f"{str(value).replace('_', '')}{suffix}")
        return "".join(parts) or "0ms"

    def _checked(self, parse: Callable[[str], int], text: str, node: Any) -> str:
        """``text`` when ``parse`` takes it; else the load fails at the literal's line (not the cycle that reads it)."""
        try:
            parse(text)
        except ValueError as exc:
            raise self.fail(str(exc), node) from None
        return text

    def visit_Duration(self, node: tf.Duration, scope: Scope) -> Ex:
        self.need("iecoop", "T")
        text = self._duration(node, [("days", "d"), ("hours", "h"), ("minutes", "m"), ("seconds", "s"), ("milliseconds", "ms")])
        self._checked(literals.T, text, node)
        code = f'T("{text}")'
        return Ex(f"-{code}" if node.negative else code, TypeRef("elem", "TIME"), compound=node.negative)

    def visit_Lduration(self, node: tf.Lduration, scope: Scope) -> Ex:
        self.need("iecoop", "LTIME")
        text = self._duration(node, [("days", "d"), ("hours", "h"), ("minutes", "m"), ("seconds", "s"),
                                     ("milliseconds", "ms"), ("microseconds", "us"), ("nanoseconds", "ns")])
        self._checked(literals.parse_ltime, text, node)
        code = f'LTIME("{text}")'
        return Ex(f"-{code}" if node.negative else code, TypeRef("elem", "LTIME"), compound=node.negative)

    def visit_Date(self, node: tf.Date, scope: Scope) -> Ex:
        self.need("iecoop", "D")
        text = self._checked(literals.parse_date, f"{node.year}-{node.month}-{node.day}", node)
        return Ex(f'D("{text}")', TypeRef("elem", "DATE"))

    def visit_TimeOfDay(self, node: tf.TimeOfDay, scope: Scope) -> Ex:
        self.need("iecoop", "TOD")
        second = f":{node.second}" if node.second is not None else ""
        text = self._checked(literals.parse_tod, f"{node.hour}:{node.minute}{second}", node)
        return Ex(f'TOD("{text}")', TypeRef("elem", "TOD"))

    def visit_DateTime(self, node: tf.DateTime, scope: Scope) -> Ex:
        self.need("iecoop", "DT")
        date, time = node.date, node.time
        second = f":{time.second}" if time.second is not None else ""
        text = self._checked(literals.parse_dt, f"{date.year}-{date.month}-{date.day}-{time.hour}:{time.minute}{second}", node)
        return Ex(f'DT("{text}")', TypeRef("elem", "DT"))
