"""Chapter 11: the employee example as an ABSTRACT FB, as an INTERFACE, and as both."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch11_abstract_fb_vs_interface import main
from iecoop_examples.ch11_abstract_fb_vs_interface import solution1_abstract_fb as s1
from iecoop_examples.ch11_abstract_fb_vs_interface import solution2_interface as s2
from iecoop_examples.ch11_abstract_fb_vs_interface import solution3_combination as s3
from iecoop import BOOL, LREAL, STRING, UINT, DefinitionError, FunctionBlock, T, adr, method, prop
from iecoop.runtime import Runtime, Task

ANNUAL = st.floats(min_value=0.0, max_value=500_000.0)
RATES = st.floats(min_value=0.0, max_value=200.0)
HOURS = st.integers(min_value=0, max_value=300)


def test_the_three_programs_cycle_by_cycle() -> None:
    main1, main2, main3 = s1.Main(), s2.Main(), s3.Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), main1, main2, main3)
    for _ in range(3):
        rt.run(cycles=1)
        assert main1.payroll == main2.payroll == 4600.0
        assert main3.payroll == 5200.0


def test_fb_init_fills_the_common_data_in_every_solution() -> None:
    for program in (s1.Main(), s2.Main(), s3.Main()):
        assert (program.ana.personnel_number, program.ana.first_name, program.ana.last_name) == (1001, "Ana", "García")
        assert program.luis.get_full_name() == "Luis Pérez (1002)"


def test_solution_1_reaches_the_derived_blocks_through_pointers() -> None:
    program = s1.Main()
    program()
    assert [type(program.staff[i].deref) for i in (1, 2)] == [s1.FullTimeEmployee, s1.ContractEmployee]
    assert program.staff[1] == adr(program, "ana")


def test_solution_3_pays_the_trainee_through_the_same_interface() -> None:
    program = s3.Main()
    program()
    assert [e.get_full_name() for e in program.staff] == ["Ana García (1001)", "Luis Pérez (1002)", "trainee Pablo"]
    assert isinstance(program.pablo, s3.IEmployee) and s3.Employee not in type(program.pablo).__mro__


@given(ANNUAL, RATES, HOURS)
def test_the_three_solutions_always_pay_the_same(annual: float, rate: float, hours: int) -> None:
    monthly = []
    for module in (s1, s2, s3):
        full = module.FullTimeEmployee(annual_salary=annual)
        contract = module.ContractEmployee(hourly_rate=rate, hours=hours)
        monthly.append(full.get_monthly_salary() + contract.get_monthly_salary())
    assert monthly[0] == monthly[1] == monthly[2] == annual / 14 + rate * hours


def test_only_the_interface_solutions_make_employees_interchangeable() -> None:
    assert not any(issubclass(cls, s2.IEmployee) for cls in (s1.FullTimeEmployee, s1.ContractEmployee))
    assert issubclass(s2.FullTimeEmployee, s2.IEmployee) and issubclass(s3.FullTimeEmployee, s3.IEmployee)


@pytest.mark.parametrize("abstract", [s1.Employee, s3.Employee])
def test_the_abstract_employee_cannot_be_instantiated(abstract: type) -> None:
    with pytest.raises(DefinitionError, match="ABSTRACT FUNCTION_BLOCK Employee cannot be instantiated"):
        abstract()


def test_a_derived_employee_must_write_its_salary() -> None:
    message = r"Volunteer must be ABSTRACT or implement PUBLIC METHOD Employee\.get_monthly_salary"
    with pytest.raises(DefinitionError, match=message):

        class Volunteer(s1.Employee):
            pass


def test_the_interface_alone_demands_every_member_again() -> None:
    with pytest.raises(
        DefinitionError, match=r"there is no implementation for method 'get_full_name' defined in interface 'IEmployee'"
    ):

        class Volunteer(FunctionBlock, s2.IEmployee):
            @prop
            def personnel_number(self) -> UINT:
                return 0

            @prop
            def first_name(self) -> STRING:
                return ""

            @prop
            def last_name(self) -> STRING:
                return ""

            @method
            def get_monthly_salary(self) -> LREAL:
                return 0.0


def test_one_base_only_so_the_trainee_cannot_extend_two_blocks() -> None:
    # Built with type(): mypy rejects the two incompatible FB_init signatures as well.
    with pytest.raises(DefinitionError, match=r"EXTENDS allows one function block, got Trainee, Employee"):
        type("Intern", (s3.Trainee, s3.Employee), {"__module__": __name__})


def test_a_derived_fb_init_must_repeat_the_base_inputs_first() -> None:
    def fb_init(self: s1.Employee, init_retains: BOOL, in_copy_code: BOOL, grant: LREAL = 0.0) -> BOOL:
        return True

    @method
    def get_monthly_salary(self: s1.Employee) -> LREAL:
        return 0.0

    namespace = {"__module__": __name__, "fb_init": fb_init, "get_monthly_salary": get_monthly_salary}
    with pytest.raises(DefinitionError, match=r"Intern: fb_init must declare the base's FB_init inputs"):
        type("Intern", (s1.Employee,), namespace)


def test_main_prints_the_three_payrolls(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert out.count("payroll 4600.00") == 2
    assert "payroll 5200.00" in out
    assert "ABSTRACT Employee cannot be instantiated" in out
