"""Variable misuse mypy must report. Never run: each mistake sits in a function nobody calls."""

from __future__ import annotations

from iecoop import ARRAY, BOOL, INT, REAL, REFERENCE_TO, STRING, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock


class Tank(FunctionBlock):
    fill: BOOL = VAR_INPUT(False)
    setpoint: REAL = VAR_INPUT(50.0)
    level: INT = VAR_OUTPUT(0)
    status: STRING = VAR_OUTPUT("idle", length=20)
    history: ARRAY[INT] = VAR(bounds=(1, 5))
    target: REFERENCE_TO[INT] = VAR_INPUT()

    def body(self) -> None:
        self.level = "full"  # E: Incompatible types in assignment (expression has type "str", variable has type "int")
        self.status = self.level  # E: expression has type "int", variable has type "str"
        self.history[1] = 2.5  # E: expression has type "float", target has type "int"
        self.target = "ten"  # E: expression has type "str", variable has type "int"


def declare_wrong_initial_values() -> None:
    class Silo(FunctionBlock):
        level: INT = VAR_OUTPUT("empty")  # E: expression has type "str", variable has type "int"
        ratio: REAL = VAR("half")  # E: expression has type "str", variable has type "float"
        ready: BOOL = VAR_INPUT(None)  # E: expression has type "None", variable has type "bool"

    del Silo


def read_with_wrong_types(tank: Tank) -> None:
    name: str = tank.level  # E: expression has type "int", variable has type "str"
    level: int = tank.status  # E: expression has type "str", variable has type "int"
    first: str = tank.history[1]  # E: expression has type "int", variable has type "str"
    referenced: str = tank.target  # E: expression has type "int", variable has type "str"
    tank.setpoint = "fast"  # E: expression has type "str", variable has type "float"
    tank.fill = "yes"  # E: expression has type "str", variable has type "bool"
    del name, level, first, referenced
