"""A library written in Python, as a test binds one: ``libraries={"FsPy": fs_pylib}``.

ST::

    FUNCTION_BLOCK FB_Scaler  (rGain, rIn -> rOut; METHOD Reset; PROPERTY Calls : UDINT)
    TYPE ST_Range : STRUCT rLow, rHigh : REAL; END_STRUCT END_TYPE
    TYPE E_Dir : (STOPPED, FORWARD, BACKWARD) INT; END_TYPE
    TYPE T_Speed : REAL; END_TYPE
    INTERFACE I_Named  METHOD Name : STRING
    FUNCTION F_Split : INT  (VAR_INPUT nValue; VAR_OUTPUT nRest)
    FUNCTION F_Twice : DINT
    VAR_GLOBAL CONSTANT GVL_Py.cScale : REAL := 2.5; cMaxAxes : LINT := 8;
"""

from __future__ import annotations

from typing import Annotated

from iecoop import (
    DINT, INT, POINTER_TO, REAL, STRING, UDINT, VAR, VAR_INPUT, VAR_OUTPUT, Alias, FunctionBlock, GlobalVariables,
    IecEnum, Interface, Struct, function, gvl, method, prop,
)

__all__ = ["E_Dir", "FB_Scaler", "F_Split", "F_Twice", "GVL_Py", "I_Named", "ST_Range", "T_Speed", "cMaxAxes"]


class ST_Range(Struct):
    rLow: REAL = VAR()
    rHigh: REAL = VAR()


class E_Dir(IecEnum, base=INT):
    STOPPED = 0
    FORWARD = 1
    BACKWARD = 2


T_Speed = Annotated[REAL, Alias("T_Speed")]


class I_Named(Interface):
    @method
    def Name(self) -> STRING: ...


class FB_Scaler(FunctionBlock):
    rGain: REAL = VAR_INPUT(1.0)
    rIn: REAL = VAR_INPUT()
    rOut: REAL = VAR_OUTPUT()
    nCalls: UDINT = VAR()

    def body(self) -> None:
        self.nCalls += 1
        self.rOut = self.rIn * self.rGain

    @method
    def Reset(self) -> None:
        self.nCalls = 0

    @prop
    def Calls(self) -> UDINT:
        return self.nCalls


@function
def F_Split(nValue: INT, nRest: POINTER_TO[INT] = VAR_OUTPUT()) -> INT:
    nRest.deref = nValue % 10
    return nValue // 10


def F_Twice(nValue: DINT) -> DINT:
    return nValue * 2


@gvl
class GVL_Py(GlobalVariables):
    cScale: REAL = VAR(2.5)

#: a module-level constant: ``FsPy.cMaxAxes`` or ``cMaxAxes`` in ST
cMaxAxes = 8
