"""Solution 2, an INTERFACE: I_Employee is a contract, each block writes all of it.

Any block can implement I_Employee, whatever it extends, and a program holds
employees in an ``ARRAY OF I_Employee`` directly. The price is repetition:
FB_FullTimeEmployee and FB_ContractEmployee each declare the same data, the
same properties and the same ``GetFullName``.

ST::

    INTERFACE I_Employee
    PROPERTY nPersonnelNumber : UINT      // Get
    PROPERTY sFirstName : STRING          // Get
    PROPERTY sLastName : STRING           // Get
    METHOD GetFullName : STRING
    METHOD GetMonthlySalary : LREAL

    FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee IMPLEMENTS I_Employee
    VAR
        _nPersonnelNumber : UINT; _sFirstName : STRING; _sLastName : STRING;
        _fAnnualSalary : LREAL;
    END_VAR
    // FB_init, nPersonnelNumber, sFirstName, sLastName, GetFullName: written here ...
    METHOD GetMonthlySalary : LREAL
    GetMonthlySalary := _fAnnualSalary / 14;

    FUNCTION_BLOCK PUBLIC FB_ContractEmployee IMPLEMENTS I_Employee
    VAR
        _nPersonnelNumber : UINT; _sFirstName : STRING; _sLastName : STRING;
        _fHourlyRate : LREAL; _nHours : UINT;
    END_VAR
    // ... and every line of it written again here
    METHOD GetMonthlySalary : LREAL
    GetMonthlySalary := _fHourlyRate * _nHours;

    PROGRAM MAIN
    VAR
        fbAna    : FB_FullTimeEmployee(1001, 'Ana', 'García', fAnnualSalary := 42000);
        fbLuis   : FB_ContractEmployee(1002, 'Luis', 'Pérez', fHourlyRate := 20, nHours := 80);
        aStaff   : ARRAY[1..2] OF I_Employee;
        fPayroll : LREAL;
        i        : INT;
    END_VAR
    aStaff[1] := fbAna;
    aStaff[2] := fbLuis;
    fPayroll := 0;
    FOR i := 1 TO 2 DO
        fPayroll := fPayroll + aStaff[i].GetMonthlySalary();
    END_FOR
"""

from __future__ import annotations

from iecoop import ARRAY, BOOL, LREAL, STRING, UINT, VAR, FunctionBlock, Interface, Program, method, prop

__all__ = ["ContractEmployee", "FullTimeEmployee", "IEmployee", "Main"]


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


class FullTimeEmployee(FunctionBlock, IEmployee):
    """``FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee IMPLEMENTS I_Employee``: all of the contract, here."""

    personnel_number_internal: UINT = VAR(0)
    first_name_internal: STRING = VAR("")
    last_name_internal: STRING = VAR("")
    annual_salary: LREAL = VAR(0.0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, personnel_number: UINT = 0, first_name: STRING = "",
        last_name: STRING = "", annual_salary: LREAL = 0.0,
    ) -> BOOL:
        self.personnel_number_internal = personnel_number
        self.first_name_internal = first_name
        self.last_name_internal = last_name
        self.annual_salary = annual_salary
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

    @method
    def get_monthly_salary(self) -> LREAL:
        return self.annual_salary / 14


class ContractEmployee(FunctionBlock, IEmployee):
    """``FUNCTION_BLOCK PUBLIC FB_ContractEmployee IMPLEMENTS I_Employee``: the same code, again."""

    personnel_number_internal: UINT = VAR(0)
    first_name_internal: STRING = VAR("")
    last_name_internal: STRING = VAR("")
    hourly_rate: LREAL = VAR(0.0)
    hours: UINT = VAR(0)

    def fb_init(
        self, init_retains: BOOL, in_copy_code: BOOL, personnel_number: UINT = 0, first_name: STRING = "",
        last_name: STRING = "", hourly_rate: LREAL = 0.0, hours: UINT = 0,
    ) -> BOOL:
        self.personnel_number_internal = personnel_number
        self.first_name_internal = first_name
        self.last_name_internal = last_name
        self.hourly_rate = hourly_rate
        self.hours = hours
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

    @method
    def get_monthly_salary(self) -> LREAL:
        return self.hourly_rate * self.hours


class Main(Program):
    """``PROGRAM MAIN``: the payroll through ``ARRAY[1..2] OF I_Employee``."""

    ana: FullTimeEmployee = VAR(
        fb_init={"personnel_number": 1001, "first_name": "Ana", "last_name": "García", "annual_salary": 42000.0}
    )
    luis: ContractEmployee = VAR(
        fb_init={
            "personnel_number": 1002, "first_name": "Luis", "last_name": "Pérez", "hourly_rate": 20.0, "hours": 80,
        }
    )
    staff: ARRAY[IEmployee] = VAR(bounds=(1, 2))
    payroll: LREAL = VAR(0.0)

    def body(self) -> None:
        self.staff[1] = self.ana
        self.staff[2] = self.luis
        self.payroll = 0.0
        for i in range(1, 3):
            self.payroll += self.staff[i].get_monthly_salary()
