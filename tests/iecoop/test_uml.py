"""UML diagrams generated from declared classes."""

from __future__ import annotations

import importlib
import pkgutil
import re
import xml.etree.ElementTree as ET
from types import ModuleType

import pytest

from iecoop import (
    ABSTRACT, ARRAY, BOOL, FINAL, INT, INTERNAL, POINTER_TO, PRIVATE, PROTECTED, REAL, REFERENCE_TO, FunctionBlock,
    IecEnum, Interface, Program, Struct, VAR, VAR_INPUT, VAR_OUTPUT, VAR_STAT, method, prop,
)
from iecoop.stdlib import TON
from iecoop.uml import class_diagram, module_diagram, state_diagram


class Mode(IecEnum):
    AUTO = 0
    MANUAL = 1


class Recipe(Struct):
    setpoint: REAL = 0.0
    steps: INT = 0


class IDrive(Interface):
    @method
    def start(self, speed: REAL = 1.0) -> BOOL:
        raise NotImplementedError

    @prop
    def running(self) -> BOOL:
        raise NotImplementedError


class DriveBase(FunctionBlock, IDrive, abstract=True):
    instances: INT = VAR_STAT(0)

    @method(ABSTRACT)
    def start(self, speed: REAL = 1.0) -> BOOL:
        raise NotImplementedError

    @prop
    def running(self) -> BOOL:
        return False


class Vfd(DriveBase, final=True):
    setpoint: REAL = VAR_INPUT(0.0)
    fault: BOOL = VAR_OUTPUT()
    mode: Mode = VAR(Mode.AUTO)
    ramp_timer: TON = VAR()

    @method(FINAL)
    def start(self, speed: REAL = 1.0) -> BOOL:
        return True

    @method(PRIVATE)
    def ramp(self) -> None:
        pass

    @method(PROTECTED)
    def check(self) -> BOOL:
        return True

    @method(INTERNAL)
    def calibrate(self) -> None:
        pass

    @prop
    def limit(self) -> REAL:
        return 1.0

    @limit.setter
    @method(PRIVATE)
    def limit(self, value: REAL) -> None:
        pass


class Line(Program):
    drives: ARRAY[Vfd] = VAR(bounds=(1, 4))
    main: IDrive = VAR()
    recipe: REFERENCE_TO[Recipe] = VAR()
    spare: POINTER_TO[Vfd] = VAR()


def test_members_carry_their_uml_visibility_and_modifiers() -> None:
    text = class_diagram(IDrive, DriveBase, Vfd, Line).to_mermaid()
    for line in [
        "<<INTERFACE>>",
        "+start(speed: REAL) BOOL",
        "+running : BOOL «PROPERTY get»",
        "<<ABSTRACT FUNCTION_BLOCK>>",
        "#instances : INT «VAR_STAT»$",  # static: $
        "+start(speed: REAL) BOOL*",  # abstract: *
        "<<FINAL FUNCTION_BLOCK>>",
        "+setpoint : REAL «VAR_INPUT»",
        "+fault : BOOL «VAR_OUTPUT»",
        "#mode : Mode «VAR»",
        "+start(speed: REAL) BOOL {leaf}",  # FINAL
        "-ramp()",
        "#check() BOOL",
        "~calibrate()",
        "+limit : REAL «PROPERTY get/-set»",
        "#drives : ARRAY[1..4] OF Vfd «VAR»",
    ]:
        assert line in text, line


def test_relations_cover_extends_implements_composition_and_aggregation() -> None:
    diagram = class_diagram(IDrive, DriveBase, Vfd, Line)
    kinds = {(r.source, r.kind, r.target, r.label, r.multiplicity) for r in diagram.relations}
    assert kinds == {
        ("IDrive", "implements", "DriveBase", "", ""),
        ("DriveBase", "extends", "Vfd", "", ""),
        ("Vfd", "association", "Mode", "mode", ""),
        ("Vfd", "composition", "TON", "ramp_timer", ""),
        ("Line", "composition", "Vfd", "drives", "1..4"),
        ("Line", "aggregation", "IDrive", "main", ""),
        ("Line", "aggregation", "Recipe", "recipe", ""),
        ("Line", "aggregation", "Vfd", "spare", ""),
    }
    mermaid = diagram.to_mermaid()
    assert "IDrive <|.. DriveBase : IMPLEMENTS" in mermaid
    assert "DriveBase <|-- Vfd : EXTENDS" in mermaid
    assert 'Line *-- "1..4" Vfd : drives' in mermaid
    assert "Line o-- IDrive : main" in mermaid
    # classes not listed but related are drawn as plain boxes
    assert diagram.names() == ["IDrive", "DriveBase", "Vfd", "Line", "Mode", "TON", "Recipe"]
    assert [c.detailed for c in diagram.classes] == [True] * 4 + [False] * 3
    assert class_diagram(Vfd, related=False).names() == ["Vfd"]


def test_plantuml_marks_abstract_static_and_leaf() -> None:
    text = class_diagram(IDrive, DriveBase, Vfd, Mode, Recipe).to_plantuml()
    assert text.startswith("@startuml") and text.endswith("@enduml")
    assert "interface IDrive {" in text
    assert "abstract class DriveBase <<FUNCTION_BLOCK>> {" in text
    assert "{static} #instances : INT «VAR_STAT»" in text
    assert "{abstract} +start(speed: REAL) BOOL" in text
    assert "{leaf} +start(speed: REAL) BOOL" in text
    assert "enum Mode {" in text and "+AUTO : 0 «value»" in text
    assert "class Recipe <<STRUCT>> {" in text and "+setpoint : REAL «VAR»" in text
    assert "IDrive <|.. DriveBase" in text and "DriveBase <|-- Vfd" in text


def test_the_svg_is_self_contained_and_shows_every_box() -> None:
    diagram = class_diagram(IDrive, DriveBase, Vfd, Line, title="Drives")
    svg = diagram.to_svg()
    root = ET.fromstring(svg)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    texts = {t.text for t in root.iter("{http://www.w3.org/2000/svg}text")}
    assert set(diagram.names()) <= texts
    assert "«ABSTRACT FUNCTION_BLOCK»" in texts and "-ramp()" in texts
    assert "<script" not in svg and "http://" not in svg.replace("http://www.w3.org/2000/svg", "")
    # boxes do not overlap
    rects = [
        (float(r.get("x", 0)), float(r.get("y", 0)), float(r.get("width", 0)), float(r.get("height", 0)))
        for r in root.iter("{http://www.w3.org/2000/svg}rect") if r.get("stroke")
    ]
    for i, a in enumerate(rects):
        for b in rects[i + 1:]:
            assert a[0] + a[2] <= b[0] or b[0] + b[2] <= a[0] or a[1] + a[3] <= b[1] or b[1] + b[3] <= a[1]
    assert svg == class_diagram(IDrive, DriveBase, Vfd, Line, title="Drives").to_svg()  # stable output


def test_module_diagram_collects_a_modules_own_classes() -> None:
    module = ModuleType("plant")
    for cls in (IDrive, Vfd):
        module.__dict__[cls.__name__] = cls
    with pytest.raises(ValueError, match="module plant defines no FUNCTION_BLOCK"):
        module_diagram(module)
    here = module_diagram(__import__(__name__, fromlist=["x"]))
    assert here.names()[:7] == ["Mode", "Recipe", "IDrive", "DriveBase", "Vfd", "Line", "TON"]


def test_class_diagram_refuses_what_is_not_an_iec_class() -> None:
    with pytest.raises(TypeError, match="is not a FUNCTION_BLOCK, PROGRAM, INTERFACE, STRUCT, UNION or ENUM"):
        class_diagram(int)


PACKML_PART = [
    ("Stopped", "Reset", "Resetting"),
    ("Resetting", "SC", "Idle"),
    ("Idle", "Start", "Execute"),
    ("Execute", "Stop", "Stopped"),
    ("Idle", "Stop", "Stopped"),
    ("Execute", "Abort", "Aborted"),
    ("Aborted", "Abort", "Aborted"),
]


def test_state_diagram_text_forms_merge_parallel_transitions() -> None:
    diagram = state_diagram(PACKML_PART + [("Execute", "Hold", "Stopped")], "Stopped", title="PackML")
    mermaid = diagram.to_mermaid().splitlines()
    assert mermaid[:2] == ["stateDiagram-v2", "    [*] --> Stopped"]
    assert "    Execute --> Stopped : Stop / Hold" in mermaid
    plant = diagram.to_plantuml()
    assert "[*] --> Stopped" in plant and "Stopped --> Resetting : Reset" in plant and "title PackML" in plant
    svg = diagram.to_svg()
    texts = {t.text for t in ET.fromstring(svg).iter("{http://www.w3.org/2000/svg}text")}
    assert {"Stopped", "Resetting", "Idle", "Execute", "Aborted", "Reset", "SC", "Stop / Hold", "Abort"} <= texts


def test_state_diagram_positions_and_errors() -> None:
    grid = {"Stopped": (0, 0), "Resetting": (1, 0), "Idle": (2, 0), "Execute": (2, 1), "Aborted": (0, 1)}
    svg = state_diagram(PACKML_PART, "Stopped", positions=grid).to_svg()
    assert ET.fromstring(svg) is not None
    with pytest.raises(ValueError, match=r"no position for the states \['Aborted'\]"):
        state_diagram(PACKML_PART, "Stopped", positions={k: v for k, v in grid.items() if k != "Aborted"}).to_svg()
    with pytest.raises(ValueError, match="a transition is \\(source, event, target\\)"):
        state_diagram([("Idle", "Start")], "Idle")  # type: ignore[list-item]
    with pytest.raises(ValueError, match="the initial state 'Held' takes part in no transition"):
        state_diagram(PACKML_PART, "Held")


# -- the package, the participants, the D2 text ----------------------------------------------------


def test_the_public_names_live_in_the_model_module() -> None:
    import iecoop.uml as uml
    from iecoop.uml import model, svg, text

    for name in uml.__all__:
        assert getattr(uml, name) is getattr(model, name)
    diagram = class_diagram(IDrive, Vfd)
    assert diagram.to_mermaid() == text.class_mermaid(diagram) and diagram.to_svg() == svg.class_svg(diagram)


def test_participants_keep_the_named_classes_with_their_roles_and_relations() -> None:
    full = class_diagram(IDrive, DriveBase, Vfd, Line)
    focused = full.participants({"IDrive": "Target", "Vfd": "Adapter", "Line": "Client"})
    assert [(box.name, box.role, box.detailed, box.fields, box.operations) for box in focused.classes] == [
        ("IDrive", "Target", False, (), ()), ("Vfd", "Adapter", False, (), ()), ("Line", "Client", False, (), ()),
    ]
    # Only relations among the participants, without the field names (one arrow per pair and kind).
    assert [(r.source, r.target, r.kind, r.label, r.multiplicity) for r in focused.relations] == [
        ("Line", "Vfd", "composition", "", "1..4"), ("Line", "IDrive", "aggregation", "", ""),
        ("Line", "Vfd", "aggregation", "", ""),
    ]
    with pytest.raises(ValueError, match="the diagram has no class 'Pump'"):
        full.participants({"Pump": "Adaptee"})


def test_d2_text_draws_bases_above_with_uml_arrowheads() -> None:
    full = class_diagram(IDrive, DriveBase, Vfd, Line)
    text = full.to_d2().splitlines()
    assert text[0] == "direction: down"
    assert '"DriveBase" <- "Vfd" {source-arrowhead.shape: triangle; source-arrowhead.style.filled: false}' in text
    assert ('"IDrive" <- "DriveBase" {source-arrowhead.shape: triangle; source-arrowhead.style.filled: false; '
            'style.stroke-dash: 4}') in text
    assert ('"Line" <-> "Vfd": "drives 1..4" {source-arrowhead.shape: diamond; source-arrowhead.style.filled: true}'
            in text)
    vfd = text[text.index('"Vfd": {'):]
    assert vfd[1:5] == ["  shape: class", '  label: "Vfd «FINAL FUNCTION_BLOCK»"', '  "+setpoint": "REAL «VAR_INPUT»"',
                        '  "+fault": "BOOL «VAR_OUTPUT»"']
    assert '  "+start(speed: REAL)": "BOOL {leaf}"' in vfd and '  "-ramp()": " "' in vfd
    roles = full.participants({"DriveBase": "Abstract adapter with a very long role name", "Vfd": "Adapter"}).to_d2()
    assert '"DriveBase": "«FUNCTION_BLOCK»\\nDriveBase\\n(Abstract adapter with a\\nvery long role name)" ' \
           '{style.fill: "#fdf7e3"; style.italic: true}' in roles


# -- labels never overlap --------------------------------------------------------------------------

_SVG = "{http://www.w3.org/2000/svg}"


def label_boxes(svg: str) -> list[tuple[str, float, float, float, float]]:
    """``(text, left, top, right, bottom)`` of every line of text in ``svg``, its width estimated from its length."""
    boxes = []
    for text in ET.fromstring(svg).iter(f"{_SVG}text"):
        style = text.get("style", "")
        in_style = re.search(r"font-size:\s*([\d.]+)", style)
        size = float(in_style.group(1) if in_style else text.get("font-size", "12"))
        anchor = re.search(r"text-anchor:\s*(\w+)", style)
        align = anchor.group(1) if anchor else text.get("text-anchor", "start")
        x, y = float(text.get("x", "0")), float(text.get("y", "0"))
        lines = [(x, y, text.text or "")]
        for span in text.iter(f"{_SVG}tspan"):
            y += float(span.get("dy", "0"))
            lines.append((float(span.get("x", x)), y, span.text or ""))
        for left, base, line in lines:
            if not line.strip():
                continue
            width = 0.55 * size * len(line)
            left -= width / 2 if align == "middle" else width if align == "end" else 0
            boxes.append((line, left, base - 0.8 * size, left + width, base + 0.2 * size))
    return boxes


def overlapping(boxes: list[tuple[str, float, float, float, float]]) -> list[tuple[str, str]]:
    found = []
    for i, (a, al, at, ar, ab) in enumerate(boxes):
        for b, bl, bt, br, bb in boxes[i + 1:]:
            if al < br - 1 and bl < ar - 1 and at < bb - 1 and bt < ab - 1:
                found.append((a, b))
    return found


def test_the_label_check_sees_an_overlap() -> None:
    svg = ('<svg xmlns="http://www.w3.org/2000/svg"><text x="10" y="20" font-size="10">current, previous_state</text>'
           '<text x="60" y="22" font-size="10">last_refused</text><text x="10" y="60" font-size="10">apart</text></svg>')
    assert overlapping(label_boxes(svg)) == [("current, previous_state", "last_refused")]


def _pattern_modules() -> list[str]:
    found = []
    for package in ("patterns.creational", "patterns.structural", "patterns.behavioral", "patterns.solid"):
        root = importlib.import_module(package)
        found += [f"{package}.{m.name}" for m in pkgutil.iter_modules(root.__path__) if not m.name.startswith("_")]
    return found


@pytest.mark.parametrize("name", _pattern_modules())
def test_no_label_of_a_pattern_diagram_covers_another(name: str) -> None:
    diagram = module_diagram(importlib.import_module(name))
    assert overlapping(label_boxes(diagram.to_svg())) == []
    participants = diagram.participants({box.name: "role" for box in diagram.classes[:10]})
    assert overlapping(label_boxes(participants.to_svg())) == []
