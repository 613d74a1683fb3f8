"""Pointers and references: an address instead of a copy.

A ``POINTER TO`` holds the address of a variable: ``ADR`` takes it, ``^``
reads and writes through it, and arithmetic on it counts bytes, so
``pint := paint + 4 * SIZEOF(INT)`` is element 5 of an INT array. A
``REFERENCE TO`` is an alias of the variable: bound once, used without ``^``.
Passing data to a function by value copies every input; a pointer or a
reference passes one address instead. The three rectangle functions give the
same area, 50, and the 20-value average is the same by value (20 inputs, all
copied) and by reference (one).

ST::

    TYPE ST_Rectangle :
    STRUCT
        fASide : REAL;
        fBSide : REAL;
        fArea  : REAL;
    END_STRUCT
    END_TYPE

    FUNCTION F_AreaCalcVal : REAL                     // by value: the sides are copied
    VAR_INPUT fASide : REAL; fBSide : REAL; END_VAR
    F_AreaCalcVal := fASide * fBSide;

    FUNCTION F_AreaCalcPointer : BOOL                 // by pointer: the area is written back
    VAR_INPUT pRect : POINTER TO ST_Rectangle; END_VAR
    IF pRect = 0 THEN
        RETURN;                                       // FALSE: nothing to write to
    END_IF
    pRect^.fArea := pRect^.fASide * pRect^.fBSide;
    F_AreaCalcPointer := TRUE;

    FUNCTION F_AreaCalcRef : REAL                     // by reference: no ^, no check for 0
    VAR_INPUT rRect : REFERENCE TO ST_Rectangle; END_VAR
    rRect.fArea := rRect.fASide * rRect.fBSide;
    F_AreaCalcRef := rRect.fArea;

    PROGRAM SR_Rectangles
    VAR
        stRectangle1 : ST_Rectangle := (fASide := 5, fBSide := 10);
        stRectangle2 : ST_Rectangle := (fASide := 5, fBSide := 10);
        stRectangle3 : ST_Rectangle := (fASide := 5, fBSide := 10);
        refRectangle : REFERENCE TO ST_Rectangle := stRectangle3;
    END_VAR
    stRectangle1.fArea := F_AreaCalcVal(stRectangle1.fASide, stRectangle1.fBSide);
    F_AreaCalcPointer(ADR(stRectangle2));
    F_AreaCalcRef(refRectangle);

    PROGRAM SR_Arrays
    VAR
        aintFIFO  : ARRAY[1..20] OF INT;
        aintFIFO2 : ARRAY[1..20] OF INT;
        paint     : POINTER TO ARRAY[1..20] OF INT;
        pint      : POINTER TO INT;
        nSum      : DINT;
        i         : INT;
    END_VAR
    paint := ADR(aintFIFO);
    paint^[3] := 4;                       // one element through the pointer to the array
    aintFIFO2 := paint^;                  // or the whole array, copied
    pint := paint + (4 * SIZEOF(INT));    // 8 bytes on: element 5
    pint^ := 5;                           // the same as aintFIFO[5] := 5
    nSum := 0;
    pint := ADR(aintFIFO[1]);
    FOR i := 1 TO 20 DO
        nSum := nSum + pint^;
        pint := pint + SIZEOF(INT);       // the next element
    END_FOR

    FUNCTION F_AverageValues : REAL                   // 20 inputs, 20 copies
    VAR_INPUT fV1, fV2, fV3, (* ... *) fV20 : REAL; END_VAR
    F_AverageValues := (fV1 + fV2 + fV3 + (* ... *) fV20) / 20.0;

    FUNCTION F_AverageReference : REAL                // one input: the array itself
    VAR_INPUT rValues : REFERENCE TO ARRAY[1..20] OF REAL; END_VAR
    VAR i : INT; fSum : REAL; END_VAR
    FOR i := 1 TO 20 DO fSum := fSum + rValues[i]; END_FOR
    F_AverageReference := fSum / 20.0;

    PROGRAM SR_Average
    VAR
        arFIFO  : ARRAY[1..20] OF REAL;   // force readings: 124.0 with a sine of amplitude 6
        refFIFO : REFERENCE TO ARRAY[1..20] OF REAL := arFIFO;
        fAngle  : REAL;
        fAvgValues, fAvgReference : REAL;
        i       : INT;
    END_VAR
    fAngle := 0;
    FOR i := 1 TO 20 DO
        arFIFO[i] := 124.0 + SIN(fAngle) * 6;
        fAngle := fAngle + 2 * 3.14159 / 20.0;
    END_FOR
    fAvgValues := F_AverageValues(arFIFO[1], arFIFO[2], arFIFO[3], (* ... *) arFIFO[20]);
    fAvgReference := F_AverageReference(refFIFO);
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    DINT,
    INT,
    POINTER_TO,
    REAL,
    REFERENCE_TO,
    VAR,
    VAR_IN_OUT,
    Program,
    Struct,
    T,
    adr,
    ref_assign,
    sizeof,
)
from iecoop.functions import SIN
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = [
    "Rectangle",
    "SrArrays",
    "SrAverage",
    "SrRectangles",
    "area_calc_pointer",
    "area_calc_ref",
    "area_calc_val",
    "average_reference",
    "average_values",
    "main",
]


class Rectangle(Struct):
    """``TYPE ST_Rectangle : STRUCT fASide, fBSide, fArea : REAL; END_STRUCT END_TYPE``."""

    a_side: REAL = 0.0
    b_side: REAL = 0.0
    area: REAL = 0.0


def area_calc_val(a_side: REAL, b_side: REAL) -> REAL:
    """``FUNCTION F_AreaCalcVal : REAL``: the two sides, passed by value."""
    return a_side * b_side


def area_calc_pointer(rect: POINTER_TO[Rectangle]) -> BOOL:
    """``FUNCTION F_AreaCalcPointer : BOOL``: writes ``pRect^.fArea``; FALSE, and nothing written, for a null pointer."""
    if not rect:
        return False
    rect.deref.area = rect.deref.a_side * rect.deref.b_side
    return True


def area_calc_ref(rect: REFERENCE_TO[Rectangle]) -> REAL:
    """``FUNCTION F_AreaCalcRef : REAL``: writes ``rRect.fArea`` through the reference."""
    rect.area = rect.a_side * rect.b_side
    area: REAL = rect.area
    return area


class SrRectangles(Program):
    """``PROGRAM SR_Rectangles``: one rectangle per way of passing it."""

    rectangle1: Rectangle = VAR({"a_side": 5.0, "b_side": 10.0})
    rectangle2: Rectangle = VAR({"a_side": 5.0, "b_side": 10.0})
    rectangle3: Rectangle = VAR({"a_side": 5.0, "b_side": 10.0})
    ref_rectangle: REFERENCE_TO[Rectangle] = VAR()

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        ref_assign(self, "ref_rectangle", self.rectangle3)  # refRectangle : ... := stRectangle3

    def body(self) -> None:
        self.rectangle1.area = area_calc_val(self.rectangle1.a_side, self.rectangle1.b_side)
        area_calc_pointer(adr(self, "rectangle2"))
        area_calc_ref(self.ref_rectangle)


class SrArrays(Program):
    """``PROGRAM SR_Arrays``: a pointer to the array, a pointer to its elements."""

    fifo: ARRAY[INT] = VAR(bounds=(1, 20))
    fifo2: ARRAY[INT] = VAR(bounds=(1, 20))
    paint: POINTER_TO[ARRAY[INT]] = VAR(bounds=(1, 20))
    pint: POINTER_TO[INT] = VAR()
    total: DINT = VAR(0)

    def body(self) -> None:
        self.paint = adr(self, "fifo")
        self.paint.deref[3] = 4
        self.fifo2 = self.paint.deref
        self.pint = (self.paint + 4 * sizeof(INT)).typed(INT)  # the same address, as POINTER TO INT
        self.pint.deref = 5
        self.total = 0
        self.pint = adr(self, "fifo", 1)
        for _ in range(20):
            self.total += self.pint.deref
            self.pint = self.pint + sizeof(INT)


def average_values(
    v1: REAL, v2: REAL, v3: REAL, v4: REAL, v5: REAL, v6: REAL, v7: REAL, v8: REAL, v9: REAL, v10: REAL,
    v11: REAL, v12: REAL, v13: REAL, v14: REAL, v15: REAL, v16: REAL, v17: REAL, v18: REAL, v19: REAL, v20: REAL,
) -> REAL:
    """``FUNCTION F_AverageValues : REAL``: twenty inputs, each one a copy."""
    return (
        v1 + v2 + v3 + v4 + v5 + v6 + v7 + v8 + v9 + v10 + v11 + v12 + v13 + v14 + v15 + v16 + v17 + v18 + v19 + v20
    ) / 20.0


def average_reference(values: POINTER_TO[ARRAY[REAL]] = VAR_IN_OUT(bounds=(1, 20))) -> REAL:
    """``FUNCTION F_AverageReference : REAL``: the caller's array itself, no copy.

    ``VAR_IN_OUT aValues : ARRAY[1..20] OF REAL; END_VAR``: an in-out passes the
    variable by reference, as a ``REFERENCE TO ARRAY[1..20] OF REAL`` input
    does, with the bounds in the declaration; Python passes ``adr(...)`` of the
    array the reference designates. The exported ST declares it this way.
    """
    total: REAL = 0.0
    for i in range(1, 21):
        total += values.deref[i]
    return total / 20.0


class SrAverage(Program):
    """``PROGRAM SR_Average``: the same 20 readings averaged by value and by reference."""

    fifo: ARRAY[REAL] = VAR(bounds=(1, 20))
    ref_fifo: REFERENCE_TO[ARRAY[REAL]] = VAR(bounds=(1, 20))
    angle: REAL = VAR(0.0)
    avg_values: REAL = VAR(0.0)
    avg_reference: REAL = VAR(0.0)

    def fb_init(self, init_retains: bool, in_copy_code: bool) -> None:
        ref_assign(self, "ref_fifo", adr(self, "fifo"))  # refFIFO : ... := arFIFO

    def body(self) -> None:
        self.angle = 0.0
        for i in range(1, 21):
            self.fifo[i] = 124.0 + SIN(self.angle) * 6
            self.angle += 2 * 3.14159 / 20.0
        f = self.fifo
        self.avg_values = average_values(
            f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9], f[10],
            f[11], f[12], f[13], f[14], f[15], f[16], f[17], f[18], f[19], f[20],
        )
        self.avg_reference = average_reference(adr(self.ref_fifo))


def main() -> None:
    """Run the three programs in one task for one cycle and print what they computed.

    >>> main()
    areas: by value 50.0, by pointer 50.0, by reference 50.0
    aintFIFO[3] = 4, aintFIFO[5] = 5, aintFIFO2[3] = 4, aintFIFO2[5] = 0
    pint - ADR(aintFIFO[1]) = 40 bytes after the loop: 20 steps of SIZEOF(INT) = 2; nSum = 9
    average of 20 readings: by value 124.0000, by reference 124.0000
    copied per call: by value SIZEOF(arFIFO) = 80 bytes, by reference one address, 8 bytes
    """
    rectangles, arrays, average = SrRectangles(), SrArrays(), SrAverage()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), rectangles, arrays, average)
    rt.run(cycles=1)
    r = rectangles
    print(f"areas: by value {r.rectangle1.area}, by pointer {r.rectangle2.area}, by reference {r.rectangle3.area}")
    print(
        f"aintFIFO[3] = {arrays.fifo[3]}, aintFIFO[5] = {arrays.fifo[5]}, "
        f"aintFIFO2[3] = {arrays.fifo2[3]}, aintFIFO2[5] = {arrays.fifo2[5]}"
    )
    span = arrays.pint - adr(arrays, "fifo", 1)
    print(
        f"pint - ADR(aintFIFO[1]) = {span} bytes after the loop: {span // sizeof(INT)} steps of "
        f"SIZEOF(INT) = {sizeof(INT)}; nSum = {arrays.total}"
    )
    print(f"average of 20 readings: by value {average.avg_values:.4f}, by reference {average.avg_reference:.4f}")
    print(
        f"copied per call: by value SIZEOF(arFIFO) = {sizeof(average, 'fifo')} bytes, "
        f"by reference one address, {sizeof(arrays, 'paint')} bytes"
    )


SHOWCASE = Showcase(
    program=SrAverage,
    columns=(Column("avg by value", lambda p: p.avg_values, ".4f"), Column("by reference", lambda p: p.avg_reference, ".4f")),
    cycles=3,
)


if __name__ == "__main__":
    main()
