"""ABSTRACT FB or INTERFACE? The employee example, solved three ways.

Full-time and contract employees share a personnel number, a first and a last
name, a ``GetFullName`` and a ``GetMonthlySalary``, computed differently for
each kind. An ABSTRACT FB shares code but allows one base only; an INTERFACE
allows any block but shares no code; the usual answer is both at once: the
program works with the interface, an abstract FB implements it once for the
blocks that can extend it, and any other block implements it directly. Each
solution is a module of this package, with the same ST names as the course.

==========================================  =========  =======================
\\                                           INTERFACE  ABSTRACT FB
==========================================  =========  =======================
multiple inheritance                        yes        no
local variables                             no         yes
non-abstract methods and properties         no         yes
access specifiers other than PUBLIC         no         yes
usable in an ARRAY                          yes        only as POINTER TO
==========================================  =========  =======================

ST::

    // solution1_abstract_fb
    FUNCTION_BLOCK PUBLIC ABSTRACT FB_Employee        // data, properties, GetFullName
    METHOD PUBLIC ABSTRACT GetMonthlySalary : LREAL
    FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee EXTENDS FB_Employee
    FUNCTION_BLOCK PUBLIC FB_ContractEmployee EXTENDS FB_Employee
    aStaff : ARRAY[1..2] OF POINTER TO FB_Employee;

    // solution2_interface
    INTERFACE I_Employee                              // prototypes only
    FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee IMPLEMENTS I_Employee    // everything
    FUNCTION_BLOCK PUBLIC FB_ContractEmployee IMPLEMENTS I_Employee    // everything again
    aStaff : ARRAY[1..2] OF I_Employee;

    // solution3_combination
    INTERFACE I_Employee
    FUNCTION_BLOCK PUBLIC ABSTRACT FB_Employee IMPLEMENTS I_Employee
    FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee EXTENDS FB_Employee
    FUNCTION_BLOCK PUBLIC FB_ContractEmployee EXTENDS FB_Employee
    FUNCTION_BLOCK PUBLIC FB_Trainee IMPLEMENTS I_Employee             // no FB_Employee
    aStaff : ARRAY[1..3] OF I_Employee;
"""

from __future__ import annotations

from collections.abc import Sequence

from iecoop import DefinitionError, Program, T, VAR
from iecoop.runtime import Runtime, Task

from iecoop_examples.ch11_abstract_fb_vs_interface import solution1_abstract_fb, solution2_interface, solution3_combination
from patterns.showcase.entry import Showcase

__all__ = ["main"]


def _report(title: str, lines: Sequence[str], payroll: float) -> None:
    print(title)
    for line in lines:
        print(f"  {line}")
    print(f"  payroll {payroll:.2f}")


def main() -> None:
    """Run the three MAIN programs in one task for one cycle and print each payroll.

    >>> main()
    solution 1, ABSTRACT FB_Employee, ARRAY OF POINTER TO FB_Employee
      Ana García (1001): 3000.00
      Luis Pérez (1002): 1600.00
      payroll 4600.00
    solution 2, INTERFACE I_Employee, ARRAY OF I_Employee
      Ana García (1001): 3000.00
      Luis Pérez (1002): 1600.00
      payroll 4600.00
    solution 3, I_Employee + ABSTRACT FB_Employee, ARRAY OF I_Employee
      Ana García (1001): 3000.00
      Luis Pérez (1002): 1600.00
      trainee Pablo: 600.00
      payroll 5200.00
    fbEmployee : FB_Employee: DefinitionError: Office.employee: ABSTRACT Employee cannot be instantiated; use REFERENCE_TO, POINTER_TO or an interface
    """
    main1, main2, main3 = solution1_abstract_fb.Main(), solution2_interface.Main(), solution3_combination.Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), main1, main2, main3)
    rt.run(cycles=1)
    _report(
        "solution 1, ABSTRACT FB_Employee, ARRAY OF POINTER TO FB_Employee",
        [f"{p.deref.get_full_name()}: {p.deref.get_monthly_salary():.2f}" for p in main1.staff],
        main1.payroll,
    )
    _report(
        "solution 2, INTERFACE I_Employee, ARRAY OF I_Employee",
        [f"{e.get_full_name()}: {e.get_monthly_salary():.2f}" for e in main2.staff],
        main2.payroll,
    )
    _report(
        "solution 3, I_Employee + ABSTRACT FB_Employee, ARRAY OF I_Employee",
        [f"{e.get_full_name()}: {e.get_monthly_salary():.2f}" for e in main3.staff],
        main3.payroll,
    )
    try:

        class Office(Program):  # VAR fbEmployee : FB_Employee; END_VAR
            employee: solution3_combination.Employee = VAR()

    except DefinitionError as exc:
        print(f"fbEmployee : FB_Employee: DefinitionError: {exc}")


SHOWCASE = Showcase(
    demo=True,
)
