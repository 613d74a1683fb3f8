"""The text forms of the diagrams: Mermaid, PlantUML and D2.

Mermaid and PlantUML paste into a Markdown page or a PlantUML server; D2
is what the D2 layout engines read (the documentation renders its class
diagrams with ``d2 --layout elk``).
"""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from iecoop.uml.model import ClassDiagram, StateDiagram

__all__ = ["class_d2", "class_mermaid", "class_plantuml", "state_mermaid", "state_plantuml"]

# Relation kind -> arrow, the same in Mermaid and PlantUML.
_ARROWS = {"extends": "<|--", "implements": "<|..", "composition": "*--", "aggregation": "o--", "association": "-->"}


def _plantuml_start(title: str) -> list[str]:
    return ["@startuml", *([f"title {title}"] if title else [])]


def class_mermaid(diagram: ClassDiagram) -> str:
    """Mermaid ``classDiagram`` text."""
    lines = ["classDiagram"]
    for box in diagram.classes:
        lines.append(f"    class {box.name} {{")
        lines.append(f"        <<{box.heading}>>")
        for f in box.fields:
            lines.append(f"        {f.text()}{'$' if f.static else ''}")
        for op in box.operations:
            lines.append(f"        {op.text()}{'*' if op.abstract else ''}{' {leaf}' if op.final else ''}")
        lines.append("    }")
    arrows = _ARROWS
    for r in diagram.relations:
        if r.kind in ("extends", "implements"):
            lines.append(f"    {r.source} {arrows[r.kind]} {r.target} : {r.kind.upper()}")
        else:
            many = f' "{r.multiplicity}"' if r.multiplicity else ""
            lines.append(f"    {r.source} {arrows[r.kind]}{many} {r.target} : {r.label}")
    return "\n".join(lines)


def class_plantuml(diagram: ClassDiagram) -> str:
    """PlantUML class diagram text."""
    lines = [*_plantuml_start(diagram.title), "hide empty members"]
    for box in diagram.classes:
        if box.stereotype == "INTERFACE":
            head = f"interface {box.name}"
        elif box.stereotype == "ENUM":
            head = f"enum {box.name}"
        elif box.abstract:
            head = f'abstract class {box.name} <<{box.stereotype}>>'
        else:
            head = f"class {box.name} <<{box.heading}>>"
        lines.append(head + " {")
        for f in box.fields:
            lines.append(f"  {'{static} ' if f.static else ''}{f.text()}")
        for op in box.operations:
            mods = ("{abstract} " if op.abstract else "") + ("{leaf} " if op.final else "")
            lines.append(f"  {mods}{op.text()}")
        lines.append("}")
    arrows = _ARROWS
    for r in diagram.relations:
        many = f' "{r.multiplicity}"' if r.multiplicity else ""
        label = f" : {r.label}" if r.label else ""
        lines.append(f"{r.source} {arrows[r.kind]}{many} {r.target}{label}")
    lines.append("@enduml")
    return "\n".join(lines)


def state_mermaid(diagram: StateDiagram) -> str:
    """Mermaid ``stateDiagram-v2`` text."""
    lines = ["stateDiagram-v2", f"    [*] --> {diagram.initial}"]
    for (source, target), labels in diagram.merged().items():
        lines.append(f"    {source} --> {target} : {' / '.join(labels)}")
    return "\n".join(lines)


def state_plantuml(diagram: StateDiagram) -> str:
    """PlantUML state diagram text."""
    lines = [*_plantuml_start(diagram.title), f"[*] --> {diagram.initial}"]
    for (source, target), labels in diagram.merged().items():
        lines.append(f"{source} --> {target} : {' / '.join(labels)}")
    lines.append("@enduml")
    return "\n".join(lines)


def _d2_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


# Relation kind -> (D2 connection, arrowheads) of an edge from the relation's source (base, container) to its
# target: D2 draws a source arrowhead only on "<-" or "<->", and lays the source out above the target either way.
_D2_ENDS = {
    "extends": ("<-", "source-arrowhead.shape: triangle; source-arrowhead.style.filled: false"),
    "implements": ("<-", "source-arrowhead.shape: triangle; source-arrowhead.style.filled: false; style.stroke-dash: 4"),
    "composition": ("<->", "source-arrowhead.shape: diamond; source-arrowhead.style.filled: true"),
    "aggregation": ("<->", "source-arrowhead.shape: diamond; source-arrowhead.style.filled: false"),
    "association": ("->", ""),
}


def class_d2(diagram: ClassDiagram) -> str:
    """D2 text: a ``class`` shape per box with its members, or a labelled box per participant.

    Every edge runs from the base or container to the class that extends or
    is held by it, so that a layered layout (``direction: down``) puts bases
    and containers above; the arrowheads say which end is which, as in UML.
    """
    lines = ["direction: down"]
    for box in diagram.classes:
        name = _d2_string(box.name)
        heading = f"«{box.heading}»"
        if not box.detailed:
            # A participant box stays narrow: ABSTRACT is the italic name, a long role wraps.
            role = textwrap.wrap(f"({box.role})", 24) if box.role else []
            label = "\\n".join([f"«{box.stereotype}»", box.name, *role])
            italic = "; style.italic: true" if box.abstract else ""
            fill = "#eef4fb" if box.stereotype == "INTERFACE" else "#fdf7e3"
            lines.append(f'{name}: "{label}" {{style.fill: "{fill}"{italic}}}')
            continue
        lines.append(f"{name}: {{")
        lines.append("  shape: class")
        lines.append(f"  label: {_d2_string(f'{box.name} {heading}')}")
        for f in box.fields:
            static = " {static}" if f.static else ""
            lines.append(f"  {_d2_string(f.visibility + f.name)}: {_d2_string(f'{f.type_name} «{f.section}»{static}')}")
        for op in box.operations:
            mods = "".join(m for m, on in ((" {abstract}", op.abstract), (" {leaf}", op.final)) if on)
            if op.is_property:
                key, value = op.visibility + op.name, f"{op.returns} «PROPERTY {op.accessors}»{mods}"
            else:
                key, value = f"{op.visibility}{op.name}({op.params})", f"{'' if op.returns == 'None' else op.returns}{mods}"
            lines.append(f"  {_d2_string(key)}: {_d2_string(value or ' ')}")
        lines.append("}")
    for r in diagram.relations:
        label = f"{r.label} {r.multiplicity}".strip() if r.kind not in ("extends", "implements") else ""
        text = f": {_d2_string(label)}" if label else ""
        connection, ends = _D2_ENDS[r.kind]
        lines.append(f"{_d2_string(r.source)} {connection} {_d2_string(r.target)}{text}" + (f" {{{ends}}}" if ends else ""))
    return "\n".join(lines) + "\n"
