"""Variables of a function block as mypy sees them: the Python type of their IEC type.

ST::

    FUNCTION_BLOCK FB_Tank
    VAR_INPUT  fill : BOOL; setpoint : REAL := 50.0; END_VAR
    VAR_OUTPUT level : INT; alarm : BOOL; status : STRING(20); END_VAR
    VAR        history : ARRAY[1..5] OF INT; total : LINT; END_VAR
"""

from __future__ import annotations

from typing import assert_type

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    LINT,
    LREAL,
    REAL,
    REFERENCE_TO,
    STRING,
    TIME,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_OUTPUT,
    VAR_STAT,
    VAR_TEMP,
    FunctionBlock,
    Struct,
    T,
    adr,
)


class Recipe(Struct):
    temperature: REAL = 20.0
    steps: INT = 0


class Tank(FunctionBlock):
    fill: BOOL = VAR_INPUT(False)
    setpoint: REAL = VAR_INPUT(50.0)
    delay: TIME = VAR_INPUT(T("2s"))
    level: INT = VAR_OUTPUT(0)
    alarm: BOOL = VAR_OUTPUT()
    status: STRING = VAR_OUTPUT("idle", length=20)
    history: ARRAY[INT] = VAR(bounds=(1, 5))
    total: LINT = VAR(0)
    ratio: LREAL = 0.5
    instances: DINT = VAR_STAT(0)
    scratch: INT = VAR_TEMP(0)
    recipe: Recipe = VAR_IN_OUT()
    target: REFERENCE_TO[INT] = VAR_INPUT()

    def body(self) -> None:
        self.scratch = self.level + 1
        if self.fill:
            self.level = self.scratch
        self.alarm = self.level > self.setpoint
        self.status = "alarm" if self.alarm else "ok"
        self.history[1] = self.level
        self.total += sum(self.history)
        self.recipe.steps += 1
        self.target = self.target + self.level


def read_tank(tank: Tank) -> None:
    assert_type(tank.fill, bool)
    assert_type(tank.setpoint, float)
    assert_type(tank.delay, int)
    assert_type(tank.level, int)
    assert_type(tank.alarm, bool)
    assert_type(tank.status, str)
    assert_type(tank.history[3], int)
    assert_type(tank.total, int)
    assert_type(tank.ratio, float)
    assert_type(tank.instances, int)
    assert_type(tank.recipe, Recipe)
    assert_type(tank.recipe.temperature, float)
    assert_type(tank.target, int)
    for value in tank.history:
        assert_type(value, int)
    length: int = len(tank.history)
    first: int = tank.history.low
    assert length >= first


def drive_tank(tank: Tank, recipe: Recipe) -> int:
    tank(fill=True, setpoint=80.0, recipe=recipe, target=adr(recipe, "steps"))
    tank.fill = False
    tank.setpoint = 75
    return tank.level


def main() -> None:
    tank, recipe = Tank(), Recipe()
    for _ in range(3):
        assert drive_tank(tank, recipe) >= 0
    read_tank(tank)
    # Each call adds one step and then the level through the reference: 1+1, +1+2, +1+3.
    assert (tank.level, recipe.steps, tank.history[1]) == (3, 9, 3)
