"""Solution 3, both: programs use I_Employee, an ABSTRACT FB_Employee implements it once.

FB_Employee IMPLEMENTS I_Employee and writes the common part a single time,
leaving ``GetMonthlySalary`` ABSTRACT, so FB_FullTimeEmployee and
FB_ContractEmployee only EXTEND it and write their salary. Programs see only
I_Employee, so a block that cannot or should not extend FB_Employee (here
FB_Trainee, paid a fixed grant) implements the interface directly and joins
the same payroll.

ST::

    INTERFACE I_Employee                  // as in solution 2

    FUNCTION_BLOCK PUBLIC ABSTRACT FB_Employee IMPLEMENTS I_Employee
    // _nPersonnelNumber, _sFirstName, _sLastName, FB_init, the three properties
    // and GetFullName: written once, as in solution 1
    METHOD PUBLIC ABSTRACT GetMonthlySalary : LREAL

    FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee EXTENDS FB_Employee
    METHOD GetMonthlySalary : LREAL       GetMonthlySalary := _fAnnualSalary / 14;

    FUNCTION_BLOCK PUBLIC FB_ContractEmployee EXTENDS FB_Employee
    METHOD GetMonthlySalary : LREAL       GetMonthlySalary := _fHourlyRate * _nHours;

    FUNCTION_BLOCK PUBLIC FB_Trainee IMPLEMENTS I_Employee
    // its own short version of the contract, no FB_Employee
    METHOD GetFullName : STRING           GetFullName := CONCAT('trainee ', _sFirstName);
    METHOD GetMonthlySalary : LREAL       GetMonthlySalary := _fGrant;

    PROGRAM MAIN
    VAR
        fbAna    : FB_FullTimeEmployee(1001, 'Ana', 'García', fAnnualSalary := 42000);
        fbLuis   : FB_ContractEmployee(1002, 'Luis', 'Pérez', fHourlyRate := 20, nHours := 80);
        fbPablo  : FB_Trainee(sFirstName := 'Pablo', fGrant := 600);
        aStaff   : ARRAY[1..3] OF I_Employee;
        fPayroll : LREAL;
        i        : INT;
    END_VAR
    aStaff[1] := fbAna;
    aStaff[2] := fbLuis;
    aStaff[3] := fbPablo;
    fPayroll := 0;
    FOR i := 1 TO 3 DO
        fPayroll := fPayroll + aStaff[i].GetMonthlySalary();
    END_FOR
"""

from __future__ import annotations

from iecoop import ABSTRACT, ARRAY, BOOL, LREAL, STRING, UINT, VAR, FunctionBlock, Interface, Program, method, prop

__all__ = ["ContractEmployee", "Employee", "FullTimeEmployee", "IEmployee", "Main", "Trainee"]


class IEmployee(Interface):
    """``INTERFACE I_Employee``."""

    @prop
    def personnel_number(self) -> UINT:
        raise NotImplementedError

    @prop
    def first_name(self) -> STRING:
        raise NotImplementedError

    @prop
    def last_name(self) -> STRING:
        raise NotImplementedError

    @method
    def get_full_name(self) -> STRING:
        raise NotImplementedError

    @method
    def get_monthly_salary(self) -> LREAL:
        raise NotImplementedError


class Employee(FunctionBlock, IEmployee, abstract=True):
    """``FUNCTION_BLOCK PUBLIC ABSTRACT FB_Employee IMPLEMENTS I_Employee``: the common part, once."""

    personnel_number_internal: UINT = VAR(0)
    first_name_internal: STRING = VAR("")
    last_name_internal: STRING = VAR("")

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, personnel_number: UINT = 0, first_name: STRING = "",
        last_name: STRING = "",
    ) -> BOOL:
        self.personnel_number_internal = personnel_number
        self.first_name_internal = first_name
        self.last_name_internal = last_name
        return True

    @prop
    def personnel_number(self) -> UINT:
        return self.personnel_number_internal

    @prop
    def first_name(self) -> STRING:
        return self.first_name_internal

    @prop
    def last_name(self) -> STRING:
        return self.last_name_internal

    @method
    def get_full_name(self) -> STRING:
        return f"{self.first_name_internal} {self.last_name_internal} ({self.personnel_number_internal})"

    @method(ABSTRACT)
    def get_monthly_salary(self) -> LREAL:
        raise NotImplementedError


class FullTimeEmployee(Employee):
    """``FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee EXTENDS FB_Employee``."""

    annual_salary: LREAL = VAR(0.0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, personnel_number: UINT = 0, first_name: STRING = "",
        last_name: STRING = "", annual_salary: LREAL = 0.0,
    ) -> BOOL:
        self.annual_salary = annual_salary
        return True

    @method
    def get_monthly_salary(self) -> LREAL:
        return self.annual_salary / 14


class ContractEmployee(Employee):
    """``FUNCTION_BLOCK PUBLIC FB_ContractEmployee EXTENDS FB_Employee``."""

    hourly_rate: LREAL = VAR(0.0)
    hours: UINT = VAR(0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, personnel_number: UINT = 0, first_name: STRING = "",
        last_name: STRING = "", hourly_rate: LREAL = 0.0, hours: UINT = 0,
    ) -> BOOL:
        self.hourly_rate = hourly_rate
        self.hours = hours
        return True

    @method
    def get_monthly_salary(self) -> LREAL:
        return self.hourly_rate * self.hours


class Trainee(FunctionBlock, IEmployee):
    """``FUNCTION_BLOCK PUBLIC FB_Trainee IMPLEMENTS I_Employee``: the interface, without the base."""

    first_name_internal: STRING = VAR("")
    grant: LREAL = VAR(0.0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, first_name: STRING = "", grant: LREAL = 0.0) -> BOOL:
        self.first_name_internal = first_name
        self.grant = grant
        return True

    @prop
    def personnel_number(self) -> UINT:
        return 0

    @prop
    def first_name(self) -> STRING:
        return self.first_name_internal

    @prop
    def last_name(self) -> STRING:
        return ""

    @method
    def get_full_name(self) -> STRING:
        return f"trainee {self.first_name_internal}"

    @method
    def get_monthly_salary(self) -> LREAL:
        return self.grant


class Main(Program):
    """``PROGRAM MAIN``: the payroll through ``ARRAY[1..3] OF I_Employee``, the trainee included."""

    ana: FullTimeEmployee = VAR(
        fb_init={"personnel_number": 1001, "first_name": "Ana", "last_name": "García", "annual_salary": 42000.0}
    )
    luis: ContractEmployee = VAR(
        fb_init={
            "personnel_number": 1002, "first_name": "Luis", "last_name": "Pérez", "hourly_rate": 20.0, "hours": 80,
        }
    )
    pablo: Trainee = VAR(fb_init={"first_name": "Pablo", "grant": 600.0})
    staff: ARRAY[IEmployee] = VAR(bounds=(1, 3))
    payroll: LREAL = VAR(0.0)

    def body(self) -> None:
        self.staff[1] = self.ana
        self.staff[2] = self.luis
        self.staff[3] = self.pablo
        self.payroll = 0.0
        for i in range(1, 4):
            self.payroll += self.staff[i].get_monthly_salary()
