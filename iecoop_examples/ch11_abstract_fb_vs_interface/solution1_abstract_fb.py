"""Solution 1, an ABSTRACT FB: FB_Employee holds everything the employees share.

The data, the properties and ``GetFullName`` are written once in the abstract
FB_Employee; only ``GetMonthlySalary`` is ABSTRACT and written by each kind of
employee. Every employee must EXTEND FB_Employee, and a program can hold
employees in an array only through ``POINTER TO FB_Employee``.

ST::

    FUNCTION_BLOCK PUBLIC ABSTRACT FB_Employee
    VAR
        _nPersonnelNumber : UINT;
        _sFirstName       : STRING;
        _sLastName        : STRING;
    END_VAR

    METHOD FB_init : BOOL
    VAR_INPUT
        bInitRetains : BOOL; bInCopyCode : BOOL;
        nPersonnelNumber : UINT; sFirstName : STRING; sLastName : STRING;
    END_VAR
    _nPersonnelNumber := nPersonnelNumber;
    _sFirstName := sFirstName;
    _sLastName := sLastName;

    PROPERTY nPersonnelNumber : UINT      Get: nPersonnelNumber := _nPersonnelNumber;
    PROPERTY sFirstName : STRING          Get: sFirstName := _sFirstName;
    PROPERTY sLastName : STRING           Get: sLastName := _sLastName;

    METHOD GetFullName : STRING           // 'Ana García (1001)'
    GetFullName := CONCAT(CONCAT(CONCAT(_sFirstName, ' '), _sLastName),
                          CONCAT(CONCAT(' (', UINT_TO_STRING(_nPersonnelNumber)), ')'));

    METHOD PUBLIC ABSTRACT GetMonthlySalary : LREAL

    FUNCTION_BLOCK PUBLIC FB_FullTimeEmployee EXTENDS FB_Employee
    VAR _fAnnualSalary : LREAL; END_VAR   // FB_init(..., fAnnualSalary : LREAL)
    METHOD GetMonthlySalary : LREAL
    GetMonthlySalary := _fAnnualSalary / 14;   // 14 payments a year

    FUNCTION_BLOCK PUBLIC FB_ContractEmployee EXTENDS FB_Employee
    VAR _fHourlyRate : LREAL; _nHours : UINT; END_VAR   // FB_init(..., fHourlyRate, nHours)
    METHOD GetMonthlySalary : LREAL
    GetMonthlySalary := _fHourlyRate * _nHours;

    PROGRAM MAIN
    VAR
        fbAna    : FB_FullTimeEmployee(nPersonnelNumber := 1001, sFirstName := 'Ana',
                                       sLastName := 'García', fAnnualSalary := 42000);
        fbLuis   : FB_ContractEmployee(nPersonnelNumber := 1002, sFirstName := 'Luis',
                                       sLastName := 'Pérez', fHourlyRate := 20, nHours := 80);
        aStaff   : ARRAY[1..2] OF POINTER TO FB_Employee;
        fPayroll : LREAL;
        i        : INT;
    END_VAR
    aStaff[1] := ADR(fbAna);
    aStaff[2] := ADR(fbLuis);
    fPayroll := 0;
    FOR i := 1 TO 2 DO
        fPayroll := fPayroll + aStaff[i]^.GetMonthlySalary();
    END_FOR
"""

from __future__ import annotations

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    LREAL,
    POINTER_TO,
    STRING,
    UINT,
    VAR,
    FunctionBlock,
    Program,
    adr,
    method,
    prop,
)

__all__ = ["ContractEmployee", "Employee", "FullTimeEmployee", "Main"]


class Employee(FunctionBlock, abstract=True):
    """``FUNCTION_BLOCK PUBLIC ABSTRACT FB_Employee``: the common data and code, once."""

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
        """``METHOD GetFullName : STRING``."""
        return f"{self.first_name_internal} {self.last_name_internal} ({self.personnel_number_internal})"

    @method(ABSTRACT)
    def get_monthly_salary(self) -> LREAL:
        """``METHOD PUBLIC ABSTRACT GetMonthlySalary : LREAL``."""
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


class Main(Program):
    """``PROGRAM MAIN``: the payroll through ``ARRAY[1..2] OF POINTER TO FB_Employee``."""

    ana: FullTimeEmployee = VAR(
        fb_init={"personnel_number": 1001, "first_name": "Ana", "last_name": "García", "annual_salary": 42000.0}
    )
    luis: ContractEmployee = VAR(
        fb_init={
            "personnel_number": 1002, "first_name": "Luis", "last_name": "Pérez", "hourly_rate": 20.0, "hours": 80,
        }
    )
    staff: ARRAY[POINTER_TO[Employee]] = VAR(bounds=(1, 2))
    payroll: LREAL = VAR(0.0)

    def body(self) -> None:
        self.staff[1] = adr(self, "ana")
        self.staff[2] = adr(self, "luis")
        self.payroll = 0.0
        for i in range(1, 3):
            self.payroll += self.staff[i].deref.get_monthly_salary()
