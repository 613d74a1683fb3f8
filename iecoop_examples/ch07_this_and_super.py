"""THIS^ and SUPER^: the instance itself, and the base block's code.

``THIS^`` is the current instance: ``THIS^.iCnt`` is the block's variable
even where a method input of the same name hides it, and a call
``THIS^.METH_DoIt()`` reaches the most derived override, even from code
written in the base. ``SUPER^`` is the
base block: ``SUPER^()`` runs the base's body, ``SUPER^.METH_DoIt()`` runs the
base's version of the method and nothing of the derived one. FB_1 uses both in
its body, so one call of ``fb1`` adds 1 (base body) + 110 (its own METH_DoIt,
which calls the base's) + 10 (the base's METH_DoIt) = 121 to ``iCnt``.

ST::

    FUNCTION_BLOCK FB_Base
    VAR_OUTPUT iCnt : INT; END_VAR
    iCnt := iCnt + 1;

    METHOD METH_DoIt : BOOL
    iCnt := iCnt + 10;
    METH_DoIt := TRUE;

    METHOD METH_DoTwice : BOOL
    THIS^.METH_DoIt();
    THIS^.METH_DoIt();
    METH_DoTwice := TRUE;

    METHOD METH_SetCount
    VAR_INPUT iCnt : INT; END_VAR      // hides the block's iCnt
    THIS^.iCnt := iCnt;

    FUNCTION_BLOCK FB_1 EXTENDS FB_Base
    VAR_OUTPUT iThis : INT; iBase : INT; END_VAR
    SUPER^();                  // FB_Base's body
    THIS^.METH_DoIt();         // FB_1's METH_DoIt
    iThis := iCnt;
    SUPER^.METH_DoIt();        // FB_Base's METH_DoIt only
    iBase := iCnt;

    METHOD METH_DoIt : BOOL
    SUPER^.METH_DoIt();
    iCnt := iCnt + 100;
    METH_DoIt := TRUE;

    PROGRAM MAIN
    VAR
        fbBase   : FB_Base;
        fb1      : FB_1;
        iBaseCnt : INT;
        iFb1Cnt  : INT;
    END_VAR
    fbBase();
    fb1();
    iBaseCnt := fbBase.iCnt;
    iFb1Cnt := fb1.iCnt;
"""

from __future__ import annotations

from iecoop import BOOL, INT, VAR, VAR_OUTPUT, FunctionBlock, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = ["Base", "Derived", "Main", "main"]


class Base(FunctionBlock):
    """``FUNCTION_BLOCK FB_Base``."""

    i_cnt: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.i_cnt += 1

    @method
    def meth_do_it(self) -> BOOL:
        """``METHOD METH_DoIt : BOOL``: +10."""
        self.i_cnt += 10
        return True

    @method
    def meth_do_twice(self) -> BOOL:
        """``METHOD METH_DoTwice : BOOL``: ``THIS^.METH_DoIt()`` twice, the override if there is one."""
        self.meth_do_it()
        self.meth_do_it()
        return True

    @method
    def meth_set_count(self, i_cnt: INT) -> None:
        """``METHOD METH_SetCount``: ``THIS^.iCnt := iCnt``, the input copied to the block's variable."""
        self.i_cnt = i_cnt


class Derived(Base):
    """``FUNCTION_BLOCK FB_1 EXTENDS FB_Base``."""

    i_this: INT = VAR_OUTPUT(0)
    i_base: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        super().body()  # SUPER^();
        self.meth_do_it()  # THIS^.METH_DoIt();
        self.i_this = self.i_cnt
        super().meth_do_it()  # SUPER^.METH_DoIt();
        self.i_base = self.i_cnt

    @method
    def meth_do_it(self) -> BOOL:
        """``METHOD METH_DoIt : BOOL``: the base's +10, then +100."""
        super().meth_do_it()
        self.i_cnt += 100
        return True


class Main(Program):
    """``PROGRAM MAIN``."""

    fb_base: Base = VAR()
    fb1: Derived = VAR()
    i_base_cnt: INT = VAR(0)
    i_fb1_cnt: INT = VAR(0)

    def body(self) -> None:
        self.fb_base()
        self.fb1()
        self.i_base_cnt = self.fb_base.i_cnt
        self.i_fb1_cnt = self.fb1.i_cnt


def main() -> None:
    """Run MAIN for three cycles, then METH_DoTwice on a fresh instance of each block.

    >>> main()
    cycle  iBaseCnt  iFb1Cnt  fb1.iThis  fb1.iBase
        1         1      121        111        121
        2         2      242        232        242
        3         3      363        353        363
    METH_DoTwice: FB_Base adds 20, FB_1 adds 220 (THIS^ reaches FB_1's METH_DoIt)
    fb1.METH_SetCount(iCnt := 1000), then fb1(): fb1.iCnt = 1121
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    print("cycle  iBaseCnt  iFb1Cnt  fb1.iThis  fb1.iBase")
    for cycle in range(1, 4):
        rt.run(cycles=1)
        fb1 = program.fb1
        print(f"{cycle:5d} {program.i_base_cnt:9d} {program.i_fb1_cnt:8d} {fb1.i_this:10d} {fb1.i_base:10d}")
    base, derived = Base(), Derived()
    base.meth_do_twice()
    derived.meth_do_twice()
    print(
        f"METH_DoTwice: FB_Base adds {base.i_cnt}, FB_1 adds {derived.i_cnt} "
        "(THIS^ reaches FB_1's METH_DoIt)"
    )
    derived.meth_set_count(1000)
    derived()
    print(f"fb1.METH_SetCount(iCnt := 1000), then fb1(): fb1.iCnt = {derived.i_cnt}")


SHOWCASE = Showcase(
    columns=(Column("iBaseCnt", lambda p: p.i_base_cnt), Column("iFb1Cnt", lambda p: p.i_fb1_cnt), Column("fb1.iThis", lambda p: p.fb1.i_this),
             Column("fb1.iBase", lambda p: p.fb1.i_base)),
    cycles=5,
)


if __name__ == "__main__":
    main()
