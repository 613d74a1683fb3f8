"""Pass 1: every declared name (POUs, data types, GVLs, members, methods, properties) into a symbol table.

The table resolves ST's case-insensitive names to their declared spelling and types each member, so pass 2
can type each expression and order the classes so a class exists before it is used.
"""

from __future__ import annotations


from collections.abc import Iterator, Sequence
from typing import Any, NoReturn

import blark.transform as tf

from iecoop.exceptions import DefinitionError
from iecoop.metadata import fields_of
from iecoop.st.language import ELEMENTARY, STANDARD_FBS, canonical_type
from iecoop.st.read.parse import StUnsupportedError, Unit
from iecoop.st.read.frames import Ex, Scope
from iecoop.st.read.lookup import BoundLibrary, Lookup, add_global, unknown_name
from iecoop.st.read.names import field_name, python_name
from iecoop.st.read.table import (
    ANYTYPE, GENERIC_FAMILIES,
    IQUERYINTERFACE, Callable_, Decl, FrozenDict, FrozenSet, Member, SYSTEM_DECLS, TypeRef, own_method_fields,
)
from iecoop.st.read.trees import (
    accessor_mark, inline_enumerations, lark_token_type, list_mark, names_read, nodes_below, signature, valued_constants,
)

_SECTION_OF = {
    tf.LocatedVariableDeclarations: "VAR", tf.IncompleteLocatedVariableDeclarations: "VAR",
    tf.VariableDeclarations: "VAR", tf.InputDeclarations: "VAR_INPUT", tf.OutputDeclarations: "VAR_OUTPUT",
    tf.InputOutputDeclarations: "VAR_IN_OUT", tf.StaticDeclarations: "VAR_STAT",
    tf.TemporaryVariableDeclarations: "VAR_TEMP", tf.MethodInstanceVariableDeclarations: "VAR_INST",
    tf.ExternalVariableDeclarations: "VAR_EXTERNAL", tf.FunctionVariableDeclarations: "VAR",
}



#: TwinCAT's platform pseudo types on a 64-bit target (Infosys: "Special data types XINT, UXINT, XWORD and
#: PVOID"); PVOID, an untyped address, is read as POINTER TO BYTE: ADR, MEMCPY, arithmetic and 0 work on it.
_PLATFORM_TYPES = {"UXINT": "ULINT", "__UXINT": "ULINT", "XINT": "LINT", "__XINT": "LINT", "XWORD": "LWORD",
                   "__XWORD": "LWORD", "PVOID": "PVOID"}

class Symbols:
    """Pass 1's symbol table, and the error and line bookkeeping every phase shares."""

    def expr(self, node: Any, scope: Scope, *, store: bool = False, expected: TypeRef | None = None) -> Ex:
        """Defined by a later phase of the translator."""
        raise NotImplementedError

    def __init__(self, units: Sequence[Unit], externals: Sequence[str] = (), libraries: Sequence[BoundLibrary] = ()) -> None:
        self.units = units
        #: ST name (lower case) -> declaration; ``by_python``: the same by Python name (a TypeRef's name)
        self.decls: Lookup[Decl] = Lookup()
        self.by_python: Lookup[Decl] = Lookup()
        #: top-level ST names (lower case) -> what and where they are declared, for the duplicate check
        self.declared: dict[str, tuple[str, str]] = {}
        self.enum_values: Lookup[tuple[str, str]] = Lookup()
        self.globals: Lookup[tuple[str, Member]] = Lookup()
        self.global_lists: dict[str, list[str]] = {}  # a global's ST name (lower case) -> the lists declaring it
        #: the libraries the source uses, bound before pass 1 (``read.libraries``)
        self.libraries = libraries
        self.externals = {name.lower() for name in externals}
        self.imports: dict[str, set[str]] = {}
        self.out: list[str] = []
        #: how many lines of code (not comments, not blank) have been written: "is a body still empty?" asks this
        self.code_lines = 0
        #: lines written before the current declaration's class (the helper classes of its local blocks)
        self.preamble: list[str] = []
        self.unit: Unit | None = None
        self.line: int | None = None
        self.window: tuple[int, int] = (0, 0)
        #: ids of the comment tokens pass 1 read as marks (``// Get``, ``// GVL name``): never carried over
        self.marks: set[int] = set()
        #: ids of the comment tokens pass 2 has written (or that are marks)
        self.used_comments: set[int] = set()
        self.pending_references: list[Any] = []
        #: ``fb : FB_X := (ref := x, p := ADR(y))``: (the field's Python path, the member, its type, the value), bound after init
        self.pending_member_references: list[tuple[str, str, Any, Any]] = []
        #: the Python path of the field whose initial value is being written (``self.fb``), or None outside a block
        self.field_path: str | None = None
        #: id of a PROPERTY node -> "get" / "set", for accessors marked by a ``// Get`` / ``// Set`` line
        self.marked_accessors: dict[int, str] = {}
        #: PROGRAMs whose variables another POU reads or writes (P_Count.counter)
        self.named_programs: set[str] = set()
        #: by id: an inline enumeration's TYPE, a declaration's POU or METHOD (its bounds may name their VAR CONSTANTs), ...
        self.inline_enums: dict[int, str] = {}
        self.block_owner: dict[int, Any] = {}
        self.constants_owner: Any = None
        self._constants: dict[int, dict[str, Member]] = {}
        self._stdlib_decls()

    # --- errors and imports ---

    def fail(self, construct: str, node: Any = None) -> StUnsupportedError:
        line = getattr(getattr(node, "meta", None), "line", None) or self.line
        where = self.unit.where(line) if self.unit is not None else "<st>"
        return StUnsupportedError(f"{where}: {construct}")

    def generic_visit(self, node: Any, kind: str) -> NoReturn:
        """A ``statement`` or ``expression`` node no ``visit_<blark node>`` reads: named with its file and line."""
        raise self.fail(f"{kind} {type(node).__name__} is not supported", node)

    # --- pass 1: the symbol table ---

    def _stdlib_decls(self) -> None:
        import iecoop.stdlib as stdlib

        for name in STANDARD_FBS:
            cls = getattr(stdlib, name)
            decl = Decl("stdfb", name)
            for record in fields_of(cls):
                decl.members[record.name.lower()] = Member(record.name, self._elem_or_none(record.info.name), record.section)
            self.decls[name.lower()] = self.by_python[name] = decl

    def _elem_or_none(self, name: str) -> TypeRef | None:
        name = canonical_type(name)
        if name in ELEMENTARY:
            return TypeRef("string", name, length="80") if name in ("STRING", "WSTRING") else TypeRef("elem", name)
        return None

    def collect(self) -> None:
        for unit in self.units:
            self.unit = unit
            current: Decl | None = None
            for item in unit.tree.items:
                self.line = item.meta.line if item.meta else None
                self.block_owner.update((id(d), item) for b in getattr(item, "declarations", None) or [] for d in getattr(b, "items", None) or [])
                if isinstance(item, (tf.Method, tf.Property)):
                    if current is None or current.kind not in ("fb", "interface", "program"):
                        raise self.fail(f"{type(item).__name__.upper()} {item.name} does not follow a FUNCTION_BLOCK or INTERFACE", item)
                    (current.method_nodes if isinstance(item, tf.Method) else current.prop_nodes).append(item)
                    for init, declaration in inline_enumerations(item, f"{current.st}_{item.name}".replace(".", "_")):
                        self.inline_enums[id(init)] = str(self._collect_data_type(unit, declaration).st)
                    mark = accessor_mark(unit, item) if isinstance(item, tf.Property) else None
                    if mark is not None:
                        self.marked_accessors[id(item)] = mark[0]
                        self.marks.add(mark[1])  # a mark, not a comment to carry over
                    continue
                if isinstance(item, tf.Action):
                    if current is None or current.kind not in ("fb", "program"):
                        raise self.fail(f"ACTION {item.name} does not follow a FUNCTION_BLOCK or PROGRAM", item)
                    current.action_nodes.append(item)
                    continue
                current = self._collect_item(unit, item)
                if current is not None:
                    current.item = item

    def declare(self, registry: dict[str, tuple[str, str]], what: str, name: str, node: Any = None) -> None:
        """Note that ``what name`` is declared here; DefinitionError naming both if ``registry`` has it already."""
        line = getattr(getattr(node, "meta", None), "line", None) or self.line
        where = self.unit.where(line) if self.unit is not None else "<st>"
        first = registry.get(name.lower())
        if first is not None:
            raise DefinitionError(f"{where}: {what} is declared twice: as {first[0]} at {first[1]} and as {what} at {where} "
                                  "(ST names are case-insensitive)")
        registry[name.lower()] = (what, where)

    def _add(self, decl: Decl) -> Decl:
        keyword = {"fb": "FUNCTION_BLOCK", "gvl": "GVL", "alias": "TYPE"}.get(decl.kind, decl.kind.upper())
        self.declare(self.declared, f"{keyword} {decl.st}", decl.st, decl.node if decl.kind != "gvl" else decl.node[0])
        decl.name = python_name(decl.st)
        self.decls[decl.st.lower()] = self.by_python[decl.name] = decl
        return decl

    def _collect_item(self, unit: Unit, item: Any) -> Decl | None:
        """Declare one top-level item; the POU that its METHODs, PROPERTYs and ACTIONs follow, or None."""
        for init, declaration in inline_enumerations(item):  # a TYPE of its own; the code names its values bare
            self.inline_enums[id(init)] = str(self._collect_data_type(unit, declaration).st)
        if isinstance(item, tf.FunctionBlock):
            decl = self._add(Decl("fb", str(item.name), item, unit))
            if item.extends:
                decl.bases.append(str(item.extends.interfaces[0]))
            decl.implements = [str(i) for i in item.implements.interfaces] if item.implements else []
            return decl
        if isinstance(item, tf.Program):
            return self._add(Decl("program", str(item.name), item, unit))
        if isinstance(item, tf.Function):
            return self._add(Decl("function", str(item.name), item, unit))
        if isinstance(item, tf.Interface):
            decl = self._add(Decl("interface", str(item.name), item, unit))
            if item.extends:
                decl.bases.extend(str(i) for i in item.extends.interfaces)
            return decl
        if isinstance(item, tf.GlobalVariableDeclarations):
            self._collect_global_list(unit, item)
            return None
        if isinstance(item, tf.DataTypeDeclaration):
            self._collect_data_type(unit, item).item = item
            return None
        raise self.fail(f"{type(item).__name__} at the top level is not supported", item)

    def _collect_global_list(self, unit: Unit, item: Any) -> None:
        """A VAR_GLOBAL block: its list, named by the block, a ``// GVL name`` mark, or its file."""
        name = str(item.name or "")
        mark = list_mark(unit, item)  # flat text names each of its lists so (dump's files, a PLCopen export's)
        if mark is not None:
            self.marks.add(mark[1])  # a mark, not a comment to carry over
            name = mark[0]
        elif not name.isidentifier():
            stem = unit.filename.replace("\\", "/").rsplit("/", 1)[-1].split(".")[0]
            name = stem if stem.isidentifier() else "GVL"
        existing = dict.get(self.decls, str(name).lower())
        if existing is not None and existing.kind == "gvl" and not existing.library:
            existing.node.append(item)  # a list gathered from several sources (TwinCAT: one per file)
            existing.units[id(item)] = unit
            return
        decl = self._add(Decl("gvl", str(name), [item], unit))
        decl.units[id(item)] = unit

    def _collect_data_type(self, unit: Unit, item: Any) -> Decl:
        """A TYPE: STRUCT, UNION, enumeration (its values are names too) or alias."""
        inner = item.declaration
        if isinstance(inner, tf.StructureTypeDeclaration):
            decl = self._add(Decl("struct", str(inner.name), inner, unit))
            if inner.extends:
                decl.bases.append(str(inner.extends.interfaces[0]))
            return decl
        if isinstance(inner, tf.UnionTypeDeclaration):
            return self._add(Decl("union", str(inner.name), inner, unit))
        if isinstance(inner, tf.EnumeratedTypeDeclaration):
            decl = self._add(Decl("enum", str(inner.name), inner, unit))
            for value in inner.init.spec.values or []:
                self.declare(decl.declared, f"enumeration value {decl.st}.{value.name}", str(value.name), value)
                decl.values.append(str(value.name))
                self.enum_values.setdefault(str(value.name).lower(), (decl.name, python_name(str(value.name), attribute=True)))
            return decl
        if isinstance(inner, (tf.SimpleTypeDeclaration, tf.StringTypeDeclaration, tf.ArrayTypeDeclaration, tf.SubrangeTypeDeclaration)):
            return self._add(Decl("alias", str(inner.name), inner, unit))
        raise self.fail(f"TYPE {type(inner).__name__} is not supported", item)

    def resolve_members(self) -> None:
        """Second half of pass 1: member types, once every type name is known."""
        # the global lists first: a bound or length elsewhere may name their constants (ARRAY[1..GVL_Param.cMax])
        for decl in sorted(self.decls.values(), key=lambda d: d.kind != "gvl"):
            if decl.library:
                continue
            self.unit = decl.unit
            self._resolve_variables(decl)
            self.unit = decl.unit
            self._resolve_methods(decl)
            for node in decl.action_nodes:  # an ACTION is called as a method without inputs or result
                name = str(node.name).rsplit(".", 1)[-1]
                self.declare(decl.declared, f"ACTION {decl.st}.{name}", name, node)
                decl.methods[name.lower()] = Callable_(python_name(name, attribute=True), None, [], st=name)
            for node in decl.prop_nodes:
                name = str(node.name).split(".")[0]
                if name.lower() not in decl.props:  # its Get and its Set accessor: one PROPERTY
                    self.declare(decl.declared, f"PROPERTY {decl.st}.{name}", name, node)
                type_ = self._spec_type(node.return_type.spec, node)
                decl.props[name.lower()] = Member(python_name(name, attribute=True), type_, "PROPERTY", st=name)
            if decl.kind == "function":
                returns = self._spec_type(decl.node.return_type, decl.node) if decl.node.return_type else None
                params = signature(list(decl.members.values()))
                decl.methods["()"] = Callable_(decl.name, returns, params, st=decl.st)
            found = [(decl.methods[str(n.name).lower()].name, m) for n in decl.method_nodes for b in n.declarations
                     if isinstance(b, tf.MethodInstanceVariableDeclarations) for m in self._block_members(b, attribute=True)]
            for method, member, own in own_method_fields(found, decl.members):  # a METHOD's VAR_INST: fields of the instance
                self._add_member(decl, own)
                decl.method_inst.update({(method.lower(), member.st.lower()): own} if own is not member else {})

    def _resolve_variables(self, decl: Decl) -> None:
        """The variables of a POU, STRUCT, UNION or GVL, and an alias's target type."""
        if decl.kind in ("fb", "program", "function"):
            for block in decl.node.declarations:
                for member in self._block_members(block, attribute=decl.kind != "function"):
                    self._add_member(decl, member)
        elif decl.kind in ("struct", "union"):
            for element in decl.node.declarations:
                for member in self._element_members(element, decl.kind):
                    self._add_member(decl, member)
        elif decl.kind == "gvl":
            for block in decl.node:
                self.unit = decl.units.get(id(block), decl.unit)
                for member in self._block_members(block, attribute=True):
                    self._add_member(decl, member)
                    add_global(self.globals, self.global_lists, decl.st, (decl.name, member), member.st)
        elif decl.kind == "alias":
            decl.alias_of = self._alias_target(decl.node)

    def _resolve_methods(self, decl: Decl) -> None:
        """Each METHOD's signature; its locals are checked for duplicates."""
        for node in decl.method_nodes:
            name = str(node.name)
            self.declare(decl.declared, f"METHOD {decl.st}.{name}", name, node)
            local: dict[str, tuple[str, str]] = {}
            members = []
            for block in node.declarations:
                for member in self._block_members(block):
                    self.declare(local, f"{member.section} {member.st} of METHOD {decl.st}.{name}", member.st)
                    members.append(member)
            returns = self._spec_type(node.return_type.spec, node) if node.return_type is not None else None
            decl.methods[name.lower()] = Callable_(python_name(name, attribute=True), returns, signature(members), st=name)

    def collect_named_programs(self) -> None:
        """The PROGRAMs another POU reads by name (``P_Count.counter``, ``P_Count.Reset()``): each becomes its one instance.

        Known before any class is written, so the class is written with its decorator.
        """
        for unit in self.units:
            for node in nodes_below(unit.tree.items):
                if not (isinstance(node, tf.MultiElementVariable) and isinstance(node.name, tf.SimpleVariable)
                        and node.elements and isinstance(node.elements[0], tf.FieldSelector)):
                    continue
                decl = self.decls.get(str(node.name.name).lower())
                if decl is None or decl.kind != "program":
                    continue
                found = self.find_member(decl, str(node.elements[0].field))
                if found is not None and found[0] in ("member", "method"):
                    self.named_programs.add(decl.name)

    def freeze(self) -> None:
        """End of pass 1: the table is complete; from now on a write to it raises ``FrozenTableError``."""
        for decl in self.decls.values():
            decl.freeze()
        # The name tables stay lookups (a lookup of a library's name notes the import the module needs).
        for table in (self.decls, self.by_python, self.enum_values, self.globals):
            table.freeze()
        self.declared = FrozenDict(self.declared)
        self.marked_accessors = FrozenDict(self.marked_accessors)
        self.inline_enums = FrozenDict(self.inline_enums)
        self.marks = FrozenSet(self.marks)
        self.named_programs = FrozenSet(self.named_programs)
        self.used_comments = set(self.marks)

    def _add_member(self, decl: Decl, member: Member) -> None:
        """A variable of ``decl``, refused if ``decl`` declares its name already (its line is ``self.line``)."""
        self.declare(decl.declared, f"{member.section} {decl.st}.{member.st}", member.st)
        decl.members[member.st.lower()] = member

    def _alias_target(self, node: Any) -> TypeRef:
        if isinstance(node, tf.SimpleTypeDeclaration):
            return self._spec_type(node.init.spec, node)
        if isinstance(node, tf.StringTypeDeclaration):
            return self._string_type(node.string_type)
        if isinstance(node, tf.SubrangeTypeDeclaration):
            return self.init_type(node.init, node)
        return self._array_type(node.init.spec, None, node)

    # --- types from blark nodes ---

    def type_named(self, name: str, node: Any) -> TypeRef:
        builtin = self._elem_or_none(name) or self._builtin_type(name)
        if builtin is not None:
            return builtin
        decl = self.decls.get(name.lower())
        if decl is None:
            raise self.fail(unknown_name("type", name, self.decls), node)
        if decl.kind == "alias" and (decl.alias_of is not None or decl.node is not None):
            # TYPE T_MaxString : STRING(255): iecoop's Alias carries no length or bounds, so a variable of
            # such an alias is declared with its target's (T_MaxString is STRING(255) wherever it stands);
            # a library's alias whose target iecoop cannot tell has no node to read it from
            target = decl.alias_of or self._alias_target(decl.node)
            if target.kind == "string" and target.length not in (None, "80") or target.kind in ("array", "any"):
                return target
        return TypeRef("user", decl.name)

    def _builtin_type(self, name: str) -> TypeRef | None:
        """The type of a name the compiler knows, unless the project declares one so: BIT, the platform types,
        the generic families and __SYSTEM's types; None for any other name."""
        upper, declared = name.upper(), name.lower() in self.decls
        if upper == "BIT" and not declared:
            # TwinCAT's BIT (a STRUCT or block member) packs into bytes with its neighbours; here it is a BOOL
            # of its own byte: the same values, another layout
            return TypeRef("elem", "BOOL")
        platform = _PLATFORM_TYPES.get(upper) if not declared else None
        if platform is not None:  # TwinCAT's pseudo types, as a 64-bit target has them
            return TypeRef("pointer", "POINTER_TO", of=TypeRef("elem", "BYTE")) if platform == "PVOID" else TypeRef("elem", platform)
        system = {"__SYSTEM.EXCEPTIONCODE": "UDINT", "__SYSTEM.TYPE_CLASS": "DINT"}.get(upper)
        if system is not None:  # an enumeration's base type: it compares equal to the members (ExceptionCode, x.TypeClass)
            return TypeRef("elem", system)
        if upper == "__SYSTEM.VAR_INFO":
            return TypeRef("varinfo", "VarInfo")  # what __VARINFO(x) gives: a local of a METHOD or FUNCTION
        if upper == "__SYSTEM.IQUERYINTERFACE":
            return TypeRef("user", IQUERYINTERFACE.name)
        if upper in GENERIC_FAMILIES and not declared:
            return TypeRef("any", upper)
        if upper == "__SYSTEM.ANYTYPE":
            return TypeRef("any", "ANY")  # the structure an ANY input is (TypeClass, pValue, diSize): an ANY input
        return None

    def _string_type(self, spec: Any) -> TypeRef:
        kind = str(spec.type_name).upper()
        length = "80"
        if spec.length is not None:
            length = self.const_expr(spec.length.length)
        return TypeRef("string", kind, length=length)

    def _indirect(self, target: TypeRef, indirection: Any) -> TypeRef:
        if indirection is None:
            return target
        if indirection.reference:
            return TypeRef("reference", "REFERENCE_TO", of=target)
        for _ in range(indirection.pointer_depth):
            target = TypeRef("pointer", "POINTER_TO", of=target)
        return target

    def _spec_type(self, spec: Any, node: Any) -> TypeRef:
        if isinstance(spec, tf.SimpleSpecification):
            if isinstance(spec.type, tf.StringTypeSpecification):
                return self._string_type(spec.type)
            return self.type_named(str(spec.type), node)
        if isinstance(spec, tf.IndirectSimpleSpecification):
            return self._indirect(self._spec_type(spec.type, node), spec.indirection)
        if isinstance(spec, tf.StringTypeSpecification):
            return self._string_type(spec)
        if isinstance(spec, tf.DataType):
            if isinstance(spec.type_name, tf.StringTypeSpecification):
                inner = self._string_type(spec.type_name)
            else:
                inner = self.type_named(str(spec.type_name), node)
            return self._indirect(inner, spec.indirection)
        if isinstance(spec, tf.ArraySpecification):
            return self._array_type(spec, None, node)
        if isinstance(spec, lark_token_type()):
            return self.type_named(str(spec), node)
        raise self.fail(f"type specification {type(spec).__name__} is not supported", node)

    def _array_type(self, spec: Any, indirection: Any, node: Any) -> TypeRef:
        bounds: list[tuple[str, str]] | None = []
        for sub in spec.subranges:
            if not isinstance(sub, tf.PartialSubrange):
                bounds = None  # ARRAY[*]: a VAR_IN_OUT of a FUNCTION or METHOD takes any array of the element type
                continue
            if bounds is not None:
                bounds.append((self.const_expr(sub.start), self.const_expr(sub.stop)))
        element_spec = spec.type
        if isinstance(element_spec, tf.ArraySpecification):
            element = self._array_type(element_spec, None, node)
        else:
            element = self._spec_type(element_spec, node)
        open_dims = len(spec.subranges) if bounds is None else 0
        return self._indirect(TypeRef("array", "ARRAY", of=element, bounds=bounds, bound_names=frozenset(names_read(spec.subranges)),
                                      open_dims=open_dims), indirection)

    def const_expr(self, node: Any) -> str:
        """A constant expression (ARRAY bounds, STRING length) as Python text; it may name its POU's VAR CONSTANTs."""
        if isinstance(node, (tf.ParenthesizedExpression, tf.BracketedExpression)):
            node = node.expr if isinstance(node, tf.ParenthesizedExpression) else node.expression
        scope = Scope(None, "const")
        scope.locals.update(self.owner_constants(self.constants_owner))
        return self.expr(node, scope).code

    def owner_constants(self, owner: Any) -> dict[str, Member]:
        """The VAR CONSTANTs of ``owner`` with an elementary type and a value, each read as its value's Python text."""
        found = self._constants.get(id(owner)) if owner is not None else {}
        if found is not None:
            return found
        found = self._constants[id(owner)] = {}  # filled in order: a constant may name an earlier one
        saved, self.constants_owner = self.constants_owner, owner
        try:
            for item, init, names in valued_constants(owner):
                type_, code = self._spec_type(init.spec, item), f"({self.const_expr(init.value)})"
                found.update((name.lower(), Member(code, type_, "CONSTANT", st=name)) for name in names)
        finally:
            self.constants_owner = saved
        return found

    def init_type(self, init: Any, node: Any) -> TypeRef:
        if isinstance(init, tf.ArrayTypeInitialization):
            return self._array_type(init.spec, init.indirection, node)
        if isinstance(init, tf.StringTypeInitialization):
            return self._string_type(init.spec)
        if isinstance(init, tf.TypeInitialization):
            return self._spec_type(init.spec, node)
        if isinstance(init, tf.InitializedStructure):
            return self.type_named(str(init.name), node)
        if isinstance(init, tf.EnumeratedTypeInitialization):
            if id(init) in self.inline_enums:
                return self.type_named(self.inline_enums[id(init)], node)
            if init.spec.values:
                raise self.fail("an inline enumeration in a declaration is not supported (declare a TYPE)", node)
            return self.type_named(str(init.spec.type_name), node)
        if isinstance(init, tf.SubrangeTypeInitialization):
            if init.indirection is not None or not isinstance(init.spec.subrange, tf.PartialSubrange):
                raise self.fail("a subrange type needs both limits and no POINTER TO / REFERENCE TO", node)
            base = self.type_named(str(init.spec.type_name), node)
            if not base.is_int:
                raise self.fail(f"a subrange of {base.name} (subranges are of integer types)", node)
            limits = tuple(str(eval(self.const_expr(n), {})) for n in (init.spec.subrange.start, init.spec.subrange.stop))
            return TypeRef("elem", base.name, limits=(limits[0], limits[1]))
        raise self.fail(f"declaration {type(init).__name__} is not supported", node)

    def _block_members(self, block: Any, attribute: bool = False) -> Iterator[Member]:
        """The variables of one VAR block; ``attribute``: of a block or GVL (fields), not of a METHOD or FUNCTION."""
        section = _SECTION_OF.get(type(block))
        if isinstance(block, tf.GlobalVariableDeclarations):
            section = "VAR_GLOBAL"
        if isinstance(block, tf.LocatedVariableDeclarations):
            section = "VAR"
        if section is None:
            raise self.fail(f"{type(block).__name__} is not supported", block)
        for item in block.items:
            self.line = item.meta.line if item.meta else self.line
            for name, type_ in self._item_types(item):
                python = field_name(name, type_) if attribute else python_name(name)
                yield Member(python, type_, section, st=name)

    def _item_types(self, item: Any) -> Iterator[tuple[str, TypeRef | None]]:
        """The names and types one declaration declares (its bounds may name its POU's VAR CONSTANTs)."""
        saved, self.constants_owner = self.constants_owner, self.block_owner.get(id(item), self.constants_owner)
        try:
            found = list(self._declared_types(item))
        finally:
            self.constants_owner = saved
        yield from found

    def _declared_types(self, item: Any) -> Iterator[tuple[str, TypeRef | None]]:
        if isinstance(item, tf.ExternalVariableDeclaration):
            yield str(item.name), self._spec_type(item.spec, item)
            return
        if isinstance(item, tf.GlobalVariableDeclaration):
            init = item.init
            if isinstance(init, tf.FunctionCall):
                type_ = self.type_named(str(init.name.name), item)
            else:
                type_ = self.init_type(init, item)
            for name in item.spec.variables:
                yield str(name), type_
            return
        if isinstance(item, tf.FunctionBlockNameDeclaration):
            type_ = self.type_named(str(item.spec), item)
            for name in item.variables:
                yield str(name), type_
            return
        if isinstance(item, tf.FunctionBlockInvocationDeclaration):
            type_ = self.type_named(str(item.init.name.name), item)
            for name in item.variables:
                yield str(name), type_
            return
        if isinstance(item, tf.EdgeDeclaration):
            raise self.fail("R_EDGE / F_EDGE inputs are not supported (use R_TRIG / F_TRIG)", item)
        if isinstance(item, (tf.LocatedVariableDeclaration, tf.IncompleteLocatedVariableDeclaration)):
            if item.name is None:
                raise self.fail(f"a located variable without a name ({item.location}) is not supported: name it", item)
            incomplete = isinstance(item, tf.IncompleteLocatedVariableDeclaration)  # a VAR of ``x AT %I* : T`` alone
            yield str(item.name.name), self._spec_type(item.init, item) if incomplete else self.init_type(item.init, item)
            return
        init = getattr(item, "init", None)
        type_ = self.init_type(init, item)
        for var in item.variables:
            yield str(var.variable.name), type_

    def _element_members(self, element: Any, kind: str) -> Iterator[Member]:
        self.line = element.meta.line if element.meta else self.line
        if isinstance(element, tf.UnionElementDeclaration):
            type_ = self._spec_type(element.spec, element)
            yield Member(field_name(str(element.name), type_), type_, "VAR", st=str(element.name))
            return
        init = element.init
        if isinstance(init, tf.FunctionCall):
            type_ = self.type_named(str(init.name.name), element)
        else:
            type_ = self.init_type(init, element)
        for var in element.variables:
            yield Member(field_name(str(var.variable.name), type_), type_, "VAR", st=str(var.variable.name))

    # --- lookups ---

    def decl_of(self, type_: TypeRef | None) -> Decl | None:
        if type_ is None:
            return None
        type_ = type_.deref()
        if type_.kind == "any":
            return ANYTYPE
        if type_.kind != "user":
            return None
        decl = self.by_python.get(type_.name) or SYSTEM_DECLS.get(type_.name.lower())
        while decl is not None and decl.kind == "alias" and decl.alias_of is not None and decl.alias_of.kind == "user":
            decl = self.by_python.get(decl.alias_of.name)
        return decl

    def lineage(self, decl: Decl) -> Iterator[Decl]:
        seen = set()
        pending = [decl]
        while pending:
            current = pending.pop(0)
            if current.name in seen:
                continue
            seen.add(current.name)
            yield current
            for base in current.bases:
                if base.upper() == "__SYSTEM.IQUERYINTERFACE":
                    continue
                found = self.decls.get(base.lower())
                if found is not None:
                    pending.append(found)

    def find_member(self, decl: Decl, name: str) -> tuple[str, Member | Callable_] | None:
        key = name.lower()
        for current in self.lineage(decl):
            if key in current.members:
                return "member", current.members[key]
            if key in current.props:
                return "prop", current.props[key]
            if key in current.methods:
                return "method", current.methods[key]
        return None
