"""The fluent interface: methods that return the instance, so calls chain.

Each method of I_Calculator does its step and returns ``THIS^`` as an
``I_Calculator``, so the next call can follow on the same line:
``fbCalculator.SetNumber(4).Add(3).MultiplyBy(2).Result`` reads as the
calculation it performs. The chain ends with something that is not the
interface, here the ``Result`` property. A division by zero does not stop the
PLC: ``DivideBy`` leaves the result as it was, sets ``Error`` and still returns
``THIS^``, so the chain goes on and the caller checks ``Error`` at the end.

ST::

    INTERFACE I_Calculator
    METHOD SetNumber : I_Calculator    VAR_INPUT fValue : LREAL; END_VAR
    METHOD Add : I_Calculator          VAR_INPUT fValue : LREAL; END_VAR
    METHOD Subtract : I_Calculator     VAR_INPUT fValue : LREAL; END_VAR
    METHOD MultiplyBy : I_Calculator   VAR_INPUT fValue : LREAL; END_VAR
    METHOD DivideBy : I_Calculator     VAR_INPUT fValue : LREAL; END_VAR
    PROPERTY Result : LREAL            // Get
    PROPERTY Error : BOOL              // Get

    FUNCTION_BLOCK FB_Calculator IMPLEMENTS I_Calculator
    VAR fResult : LREAL; bError : BOOL; END_VAR

    METHOD SetNumber : I_Calculator
    VAR_INPUT fValue : LREAL; END_VAR
    fResult := fValue;
    bError := FALSE;
    SetNumber := THIS^;

    METHOD Add : I_Calculator
    VAR_INPUT fValue : LREAL; END_VAR
    fResult := fResult + fValue;
    Add := THIS^;

    // Subtract and MultiplyBy alike

    METHOD DivideBy : I_Calculator
    VAR_INPUT fValue : LREAL; END_VAR
    IF fValue = 0.0 THEN
        bError := TRUE;
    ELSE
        fResult := fResult / fValue;
    END_IF
    DivideBy := THIS^;

    PROGRAM MAIN
    VAR
        fbCalculator : FB_Calculator;
        nCycle       : INT;
        fResult      : LREAL;           // (nCycle + 3) * 2 - 1
        fHalf        : LREAL;           // fResult / 2
        bError       : BOOL;            // set by the / 0
    END_VAR
    nCycle := nCycle + 1;
    fResult := fbCalculator.SetNumber(nCycle).Add(3).MultiplyBy(2).Subtract(1).Result;
    fHalf := fbCalculator.DivideBy(2).Result;
    bError := fbCalculator.DivideBy(0).Add(1).Error;
"""

from __future__ import annotations

from iecoop import BOOL, INT, LREAL, VAR, FunctionBlock, Interface, Program, T, method, prop
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = ["Calculator", "ICalculator", "Main", "main"]


class ICalculator(Interface):
    """``INTERFACE I_Calculator``: every step returns the calculator again."""

    @method
    def set_number(self, value: LREAL) -> ICalculator:
        raise NotImplementedError

    @method
    def add(self, value: LREAL) -> ICalculator:
        raise NotImplementedError

    @method
    def subtract(self, value: LREAL) -> ICalculator:
        raise NotImplementedError

    @method
    def multiply_by(self, value: LREAL) -> ICalculator:
        raise NotImplementedError

    @method
    def divide_by(self, value: LREAL) -> ICalculator:
        raise NotImplementedError

    @prop
    def result(self) -> LREAL:
        raise NotImplementedError

    @prop
    def error(self) -> BOOL:
        raise NotImplementedError


class Calculator(FunctionBlock, ICalculator):
    """``FUNCTION_BLOCK FB_Calculator IMPLEMENTS I_Calculator``."""

    result_internal: LREAL = VAR(0.0)
    error_internal: BOOL = VAR(False)

    @method
    def set_number(self, value: LREAL) -> ICalculator:
        self.result_internal = value
        self.error_internal = False
        return self

    @method
    def add(self, value: LREAL) -> ICalculator:
        self.result_internal += value
        return self

    @method
    def subtract(self, value: LREAL) -> ICalculator:
        self.result_internal -= value
        return self

    @method
    def multiply_by(self, value: LREAL) -> ICalculator:
        self.result_internal *= value
        return self

    @method
    def divide_by(self, value: LREAL) -> ICalculator:
        if value == 0.0:
            self.error_internal = True
        else:
            self.result_internal /= value
        return self

    @prop
    def result(self) -> LREAL:
        return self.result_internal

    @prop
    def error(self) -> BOOL:
        return self.error_internal


class Main(Program):
    """``PROGRAM MAIN``: one chained calculation per cycle."""

    calculator: Calculator = VAR()
    cycle: INT = VAR(0)
    result: LREAL = VAR(0.0)
    half: LREAL = VAR(0.0)
    error: BOOL = VAR(False)

    def body(self) -> None:
        self.cycle += 1
        self.result = self.calculator.set_number(self.cycle).add(3).multiply_by(2).subtract(1).result
        self.half = self.calculator.divide_by(2).result
        self.error = self.calculator.divide_by(0).add(1).error


def main() -> None:
    """Run MAIN for three cycles and print what each chain produced.

    >>> main()
    cycle  fResult  fHalf  bError  Result after DivideBy(0).Add(1)
        1      7.0    3.5  True    4.5
        2      9.0    4.5  True    5.5
        3     11.0    5.5  True    6.5
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    print("cycle  fResult  fHalf  bError  Result after DivideBy(0).Add(1)")
    for _ in range(3):
        rt.run(cycles=1)
        print(
            f"{program.cycle:5d} {program.result:8.1f} {program.half:6.1f}  {program.error!s:<6}  "
            f"{program.calculator.result}"
        )


SHOWCASE = Showcase(
    columns=(Column("MAIN.cycle", lambda p: p.cycle), Column("fResult", lambda p: p.result, ".1f"), Column("fHalf", lambda p: p.half, ".1f"),
             Column("bError", lambda p: p.error)),
    cycles=5,
)


if __name__ == "__main__":
    main()
