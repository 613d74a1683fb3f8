"""UML diagrams generated from declared classes."""

from __future__ import annotations

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
