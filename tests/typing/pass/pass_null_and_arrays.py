"""User code mypy --strict must accept: NULL and null() for interfaces, list / dict initialisers, enum indexes."""

from __future__ import annotations

from iecoop import (
    ARRAY, BOOL, INT, NULL, REAL, FunctionBlock, IecEnum, Interface, Struct, VAR, method, null,
)


class IValve(Interface):
    @method
    def open(self) -> BOOL:
        raise NotImplementedError

    @method
    def successor(self) -> IValve:
        raise NotImplementedError


class Station(IecEnum):
    INFEED = 1
    FILLER = 2


class Point(Struct):
    x: REAL = 0.0
    y: REAL = 0.0


class Valve(FunctionBlock, IValve):
    @method
    def open(self) -> BOOL:
        return True

    @method
    def successor(self) -> IValve:
        return null(IValve)  # ST: Successor := 0;


class Manifold(FunctionBlock):
    valves: ARRAY[IValve] = VAR(bounds=(1, 4))
    counts: ARRAY[INT] = VAR([0, 0], bounds=(Station.INFEED, Station.FILLER))
    origin: Point = VAR({"x": 1.0})
    path: ARRAY[Point] = VAR([{"x": 1.0}, {"y": 2.0}], bounds=(1, 2))

    @method
    def release(self, slot: INT) -> BOOL:
        was_set = bool(self.valves[slot])  # a null interface reference is FALSE
        self.valves[slot] = NULL
        self.counts[Station.FILLER] += 1
        return was_set


def main() -> None:
    manifold = Manifold()
    assert manifold.release(1) is False
    count: int = manifold.counts[Station.FILLER]
    assert count == 1
    successor: IValve = Valve().successor()
    assert not successor
    assert (manifold.origin.x, manifold.path[2].y) == (1.0, 2.0)
