"""UML diagrams generated from declared classes: class diagrams and state diagrams.

A class diagram is read from the classes themselves (their VAR sections,
METHODs, PROPERTYs, EXTENDS and IMPLEMENTS), so it cannot drift from the code.
Each diagram renders as Mermaid, PlantUML or D2 text (:mod:`iecoop.uml.text`)
and as a self-contained SVG (no script, no network) that a page can embed as
an image (:mod:`iecoop.uml.svg`); :meth:`ClassDiagram.participants` keeps the
few classes that play a pattern's roles, without their members.

================================  =============================================
UML                               IEC 61131-3
================================  =============================================
``+`` public                      PUBLIC members; VAR_INPUT / VAR_OUTPUT / VAR_IN_OUT
``#`` protected                   PROTECTED members; VAR, VAR_INST, VAR_TEMP (seen by derived blocks)
``-`` private                     PRIVATE members
``~`` package                     INTERNAL members
``{abstract}`` / italic           ABSTRACT
``{leaf}``                        FINAL
underlined / ``$``                VAR_STAT (one per class)
generalisation ``<|--``           EXTENDS
realisation ``<|..``              IMPLEMENTS
composition ``*--``               a nested FB / STRUCT instance (inline in memory)
aggregation ``o--``               an interface, POINTER TO or REFERENCE TO field
================================  =============================================

>>> from iecoop import FunctionBlock, Interface, BOOL, REAL, VAR, VAR_INPUT, VAR_OUTPUT, method
>>> class IDrive(Interface):
...     @method
...     def start(self) -> BOOL:
...         raise NotImplementedError
>>> class Drive(FunctionBlock, IDrive):
...     speed: REAL = VAR_INPUT(0.0)
...     running: BOOL = VAR_OUTPUT()
...     @method
...     def start(self) -> BOOL:
...         self.running = True
...         return True
>>> class Conveyor(FunctionBlock):
...     drive: Drive = VAR()
>>> print(class_diagram(IDrive, Drive, Conveyor).to_mermaid())
classDiagram
    class IDrive {
        <<INTERFACE>>
        +start() BOOL
    }
    class Drive {
        <<FUNCTION_BLOCK>>
        +speed : REAL «VAR_INPUT»
        +running : BOOL «VAR_OUTPUT»
        +start() BOOL
    }
    class Conveyor {
        <<FUNCTION_BLOCK>>
        #drive : Drive «VAR»
    }
    IDrive <|.. Drive : IMPLEMENTS
    Conveyor *-- Drive : drive
"""

from iecoop.uml.model import (
    ClassDiagram,
    Relation,
    StateDiagram,
    UmlClass,
    UmlField,
    UmlOperation,
    class_diagram,
    module_diagram,
    state_diagram,
)

__all__ = [
    "ClassDiagram",
    "Relation",
    "StateDiagram",
    "UmlClass",
    "class_diagram",
    "module_diagram",
    "state_diagram",
]
