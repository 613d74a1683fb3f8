"""What a METHOD or PROPERTY can return: a struct, an interface, a function block, a reference.

A method need not return anything. When it returns a STRUCT or a
FUNCTION_BLOCK, the caller gets a copy: changing the result, or the block
afterwards, leaves the other as it was, and a single member can only be read
after the copy is stored. An INTERFACE result is a reference to an instance,
so calls through it reach the instance itself. A PROPERTY of type
``REFERENCE TO ST_Sample`` (Get: ``MyProp REF= stLocal``) gives direct access
to the block's own struct: ``fbSample.MyProp.nVar`` reads one member with no
copy, and its Set copies a whole struct in.

ST::

    TYPE ST_Sample :
    STRUCT
        bVar : BOOL;
        nVar : INT;
    END_STRUCT
    END_TYPE

    INTERFACE I_Sample
    METHOD Increment : INT

    FUNCTION_BLOCK FB_Counter
    VAR_OUTPUT nCount : UDINT; END_VAR
    METHOD Count
    nCount := nCount + 1;

    FUNCTION_BLOCK FB_Sample IMPLEMENTS I_Sample
    VAR
        stLocal : ST_Sample;
        fbCalls : FB_Counter;
    END_VAR

    METHOD Increment : INT
    stLocal.nVar := stLocal.nVar + 1;
    fbCalls.Count();
    Increment := stLocal.nVar;

    METHOD GetStruct : ST_Sample          // a copy of stLocal
    GetStruct := stLocal;

    METHOD GetInterface : I_Sample        // THIS^, seen through the interface
    GetInterface := THIS^;

    METHOD GetCounter : FB_Counter        // a copy of the whole instance
    GetCounter := fbCalls;

    PROPERTY MyProp : REFERENCE TO ST_Sample
        Get: MyProp REF= stLocal;
        Set: stLocal := MyProp;

    PROGRAM MAIN
    VAR
        fbSample   : FB_Sample;
        itfSample  : I_Sample;
        nSingleGet : INT;
        stGet      : ST_Sample;
        stCopy     : ST_Sample;
        fbCopy     : FB_Counter;
        bSet       : BOOL;
        stSet      : ST_Sample := (bVar := TRUE, nVar := 100);
    END_VAR
    // Set - only the complete structure
    IF bSet THEN
        fbSample.MyProp REF= stSet;
        bSet := FALSE;
    END_IF
    itfSample := fbSample.GetInterface();
    itfSample.Increment();                // fbSample's own nVar goes up
    // Get - a single member or the complete structure
    nSingleGet := fbSample.MyProp.nVar;
    stGet := fbSample.MyProp;
    stCopy := fbSample.GetStruct();
    fbCopy := fbSample.GetCounter();
"""

from __future__ import annotations

from iecoop import (
    BOOL,
    INT,
    REFERENCE_TO,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    Interface,
    Program,
    Struct,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Showcase

__all__ = ["Counter", "ISample", "Main", "Sample", "SampleData", "main"]


class SampleData(Struct):
    """``TYPE ST_Sample : STRUCT bVar : BOOL; nVar : INT; END_STRUCT END_TYPE``."""

    b_var: BOOL = False
    n_var: INT = 0


class ISample(Interface):
    """``INTERFACE I_Sample``."""

    @method
    def increment(self) -> INT:
        raise NotImplementedError


class Counter(FunctionBlock):
    """``FUNCTION_BLOCK FB_Counter``."""

    count_value: UDINT = VAR_OUTPUT(0)

    @method
    def count(self) -> None:
        """``METHOD Count``."""
        self.count_value += 1


class Sample(FunctionBlock, ISample):
    """``FUNCTION_BLOCK FB_Sample IMPLEMENTS I_Sample``: one member per kind of return value."""

    st_local: SampleData = VAR()
    fb_calls: Counter = VAR()
    struct_result: SampleData = VAR()
    counter_result: Counter = VAR()

    @method
    def increment(self) -> INT:
        """``METHOD Increment : INT``."""
        self.st_local.n_var += 1
        self.fb_calls.count()
        return self.st_local.n_var

    @method
    def get_struct(self) -> SampleData:
        """``METHOD GetStruct : ST_Sample``: the struct, copied as ST's assignment copies it.

        ``GetStruct := stLocal;`` copies. A Python ``return self.st_local`` would hand
        out the block's own struct, so the method copies it into the block's result
        variable ``stResult`` first (the assignment copies) and returns that. So
        ``iecoop.st`` exports it as ``METHOD get_struct : REFERENCE TO SampleData``
        with ``get_struct REF= struct_result``: the caller's assignment copies,
        and gets the same values as from the by-value result.
        """
        self.struct_result = self.st_local
        return self.struct_result

    @method
    def get_interface(self) -> ISample:
        """``METHOD GetInterface : I_Sample``: ``GetInterface := THIS^``, a reference."""
        return self

    @method
    def get_counter(self) -> Counter:
        """``METHOD GetCounter : FB_Counter``: the whole instance, copied (``GetCounter := fbCalls;``).

        As for ``get_struct``, the copy is the block's ``counter_result``, and the
        export returns ``REFERENCE TO Counter`` bound to it.
        """
        self.counter_result = self.fb_calls
        return self.counter_result

    @prop
    def my_prop(self) -> REFERENCE_TO[SampleData]:
        """``PROPERTY MyProp : REFERENCE TO ST_Sample``: Get is ``MyProp REF= stLocal``."""
        return self.st_local

    @my_prop.setter
    def my_prop(self, value: REFERENCE_TO[SampleData]) -> None:
        self.st_local = value  # Set: stLocal := MyProp, a copy of the referenced struct


class Main(Program):
    """``PROGRAM MAIN``: every kind of result, once per cycle."""

    set_cmd: BOOL = VAR_INPUT(False)
    sample: Sample = VAR()
    itf_sample: ISample = VAR()
    single_get: INT = VAR(0)
    st_get: SampleData = VAR()
    st_copy: SampleData = VAR()
    fb_copy: Counter = VAR()
    st_set: SampleData = VAR({"b_var": True, "n_var": 100})

    def body(self) -> None:
        if self.set_cmd:
            self.sample.my_prop = self.st_set
            self.set_cmd = False
        self.itf_sample = self.sample.get_interface()
        self.itf_sample.increment()
        self.single_get = self.sample.my_prop.n_var
        self.st_get = self.sample.my_prop
        self.st_copy = self.sample.get_struct()
        self.fb_copy = self.sample.get_counter()

    @method
    def change_copy(self) -> None:
        """``stGet.nVar := -1;``: stGet holds a copy of the property's struct."""
        self.st_get.n_var = -1


def main() -> None:
    """Run MAIN for five cycles, giving bSet in the fourth.

    >>> main()
    cycle  bSet   nSingleGet  stGet.nVar  stCopy.nVar  fbCopy.nCount
        1  False           1           1            1              1
        2  False           2           2            2              2
        3  False           3           3            3              3
        4  True          101         101          101              4
        5  False         102         102          102              5
    stGet.nVar := -1 changes a copy: fbSample.MyProp.nVar is still 102
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    print("cycle  bSet   nSingleGet  stGet.nVar  stCopy.nVar  fbCopy.nCount")
    for cycle in range(1, 6):
        program.set_cmd = cycle == 4
        rt.run(cycles=1)
        print(
            f"{cycle:5d}  {cycle == 4!s:<5} {program.single_get:11d} {program.st_get.n_var:11d} "
            f"{program.st_copy.n_var:12d} {program.fb_copy.count_value:14d}"
        )
    program.change_copy()
    print(f"stGet.nVar := -1 changes a copy: fbSample.MyProp.nVar is still {program.sample.my_prop.n_var}")


SHOWCASE = Showcase(
    demo=True,
)


if __name__ == "__main__":
    main()
