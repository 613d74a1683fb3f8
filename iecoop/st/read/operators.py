"""Pass 2, the heap and reference operators: __NEW (a block, a STRUCT, or an array of n elements), __DELETE,
__ISVALIDREF, TEST_AND_SET, __QUERYINTERFACE and __QUERYPOINTER."""

from __future__ import annotations

from typing import Any

import blark.transform as tf

from iecoop.st.read.expressions import Expressions
from iecoop.st.read.frames import Ex, Scope
from iecoop.st.read.table import BOOL, Callable_, Decl, ReferenceLocal, TypeRef


class Operators(Expressions):
    def _op_new(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "new")
        target = params[0]
        if not isinstance(target, tf.SimpleVariable):
            raise self.fail("__NEW with FB_init arguments or an array is not supported", node)
        decl = self.decls.get(str(target.name).lower())
        if len(node.parameters) == 2 and node.parameters[1].name is None and getattr(decl, "kind", None) not in ("fb", "stdfb"):
            return self._new_array(str(target.name), decl, node.parameters[1].value, node, scope)
        if decl is None and self._elem_or_none(str(target.name)) is not None:
            raise self.fail(f"__NEW of {target.name} without a count is not supported (__NEW({target.name}, n) allocates n)", node)
        if decl is None or decl.kind not in ("fb", "struct", "stdfb"):
            raise self.fail(f"__NEW of {target.name}: only function blocks and structs are supported", node)
        if decl.kind == "stdfb":
            self.need("iecoop.stdlib", decl.name)
        # __NEW(FB_X, a := 1): FB_init's inputs by name, as iecoop's new() takes them
        fb_init = self.find_member(decl, "FB_init")
        inputs = fb_init[1].params if fb_init is not None and isinstance(fb_init[1], Callable_) else []
        args = [decl.name]
        for param in node.parameters[1:]:
            if not isinstance(param, tf.InputParameterAssignment) or param.name is None:
                raise self.fail(f"__NEW of {decl.name} with a length (an array) is not supported", node)
            name = str(param.name.name)
            match = next((p.name for p in inputs if p.st.lower() == name.lower()), None)
            if match is None:
                raise self.fail(f"__NEW of {decl.name}: FB_init has no input {name!r}", node)
            args.append(f"{match}={self.expr(param.value, scope).code}")
        return Ex(f"new({', '.join(args)})", TypeRef("pointer", "POINTER_TO", of=TypeRef("user", decl.name)))

    def _new_array(self, name: str, decl: Decl | None, count: Any, node: Any, scope: Scope) -> Ex:
        """``__NEW(BYTE, n)``: n elements of an elementary type, as a POINTER TO the element type."""
        element = self._elem_or_none(name) if decl is None else None
        if element is None or element.kind != "elem":
            # __DELETE frees a block through a pointer to its own type, which an array of STRUCTs is not
            raise self.fail(f"__NEW({name}, n): an array of a STRUCT or block is not supported (declare ARRAY[..] OF "
                            f"{name} in a block or GVL and take its ADR); n elements of an elementary type are", node)
        self.need("iecoop", element.name)
        self.need("iecoop.stdlib.heap", "new_array")
        return Ex(f"new_array({element.annotation()}, {self.expr(count, scope).code})", TypeRef("pointer", "POINTER_TO", of=element))

    def _op_delete(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        if level is None:
            raise self.fail("__DELETE inside an expression", node)
        self.need("iecoop", "delete")
        pointer = self.expr(params[0], scope)
        return Ex(f"delete({pointer.code})", None)  # delete() makes the pointer variable 0, as __DELETE does

    def _op_isvalidref(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        local = self.local_of(params[0], scope)
        if isinstance(local, ReferenceLocal):
            return Ex(f"bool({local.name})", BOOL)
        if local is not None and local.place is None and self._local_reference(local.type):
            # a METHOD's or FUNCTION's REFERENCE TO a STRUCT or block holds its target's view, None until REF= binds it
            return Ex(f"({local.name} is not None)", BOOL)
        self.need("iecoop", "is_valid_ref")
        holder, field = self.holder_field(params[0], scope)
        return Ex(f'is_valid_ref({holder}, "{field}")', BOOL)

    def _op_test_and_set(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        self.need("iecoop", "test_and_set")
        # the result is BOOL in TwinCAT and the old flag's value in CODESYS: typed as the integer it is
        return Ex(f"test_and_set({self.address_of(params[0], scope)})", TypeRef("elem", "DWORD"))

    def _op_query(self, upper: str, params: list[Any], node: Any, scope: Scope, level: int | None) -> Ex:
        at = scope.statement_level if level is None else level
        if at is None:
            raise self.fail(f"{upper} is supported as a statement or the right side of an assignment", node)
        source = self.expr(params[0], scope)
        dest = self.expr(params[1], scope, store=True)
        if upper == "__QUERYPOINTER":
            self.need("iecoop", "query_pointer")
            self.emit(f"{dest.code} = query_pointer({source.code})", at)
            return Ex(f"bool({dest.code})" if level is None else "", BOOL)
        decl = self.decl_of(dest.type)
        if decl is None or decl.kind != "interface":
            raise self.fail(f"__QUERYINTERFACE needs an interface variable as its second operand, got {dest.code}", node)
        self.need("iecoop", "query_interface", "null")
        self.emit(f"{dest.code} = query_interface({source.code}, {decl.name}) or null({decl.name})", at)
        return Ex(f"bool({dest.code})" if level is None else "", BOOL)

