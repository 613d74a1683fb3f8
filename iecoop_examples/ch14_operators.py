"""Other operators: __NEW and __DELETE, __ISVALIDREF, the interface queries, __TRY, __VARINFO, TEST_AND_SET.

``__NEW`` creates an instance at run time (FB_init runs) and returns a pointer;
``__DELETE`` runs FB_exit, frees it and sets the pointer to 0, so any other
pointer still aimed at it is an access violation. ``__ISVALIDREF`` tells
whether a REFERENCE is bound. ``__QUERYINTERFACE`` asks the object behind one
interface for another one it implements, ``__QUERYPOINTER`` for the instance
itself; both need interfaces that extend ``__SYSTEM.IQueryInterface``.
``__TRY / __CATCH / __FINALLY`` turns a runtime fault into an exception code
and the task goes on; ``__VARINFO`` describes a variable; ``TestAndSet``
takes a lock flag atomically (TwinCAT: TRUE when taken; CODESYS's
``TEST_AND_SET`` returns the old value instead).

ST::

    INTERFACE I_Drive EXTENDS __SYSTEM.IQueryInterface
    METHOD Move : BOOL   VAR_INPUT fSetSpeed : LREAL; END_VAR
    INTERFACE I_Diagnosis EXTENDS __SYSTEM.IQueryInterface
    PROPERTY Healthy : BOOL                          // Get
    INTERFACE I_Printer EXTENDS __SYSTEM.IQueryInterface
    METHOD PrintLine   VAR_INPUT sLine : STRING; END_VAR

    {attribute 'enable_dynamic_creation'}
    FUNCTION_BLOCK FB_Motor IMPLEMENTS I_Drive, I_Diagnosis
    VAR_INPUT nAxis : INT; END_VAR
    VAR       fSpeed : LREAL; END_VAR
    VAR_STAT  nInstances : INT; END_VAR
    METHOD FB_init : BOOL    nInstances := nInstances + 1;
    METHOD FB_exit : BOOL    nInstances := nInstances - 1;
    METHOD Move : BOOL       fSpeed := fSetSpeed; Move := TRUE;
    PROPERTY Healthy : BOOL  Get: Healthy := fSpeed < 3000.0;
    PROPERTY Instances : INT Get: Instances := nInstances;

    PROGRAM MAIN_Operators                          // everything runs in the first cycle
    VAR
        fbMotor : FB_Motor;
        pMotor, pCopy, pAny : POINTER TO FB_Motor;
        rMotor : REFERENCE TO FB_Motor;
        itfDrive : I_Drive; itfDiag : I_Diagnosis; itfPrinter : I_Printer;
        exc : __SYSTEM.ExceptionCode;
        stInfo : __SYSTEM.VAR_INFO;
        bLock : BOOL;
        (* ... one result variable per line below ... *)
    END_VAR
    nBefore := fbMotor.Instances;
    pMotor := __NEW(FB_Motor);                      // FB_init runs
    nAfterNew := fbMotor.Instances;
    pMotor^.nAxis := 3;
    pMotor^.Move(1500.0);
    pCopy := pMotor;                                // a second pointer to the same instance
    bValidBefore := __ISVALIDREF(rMotor);           // FALSE: not bound yet
    rMotor REF= pMotor^;
    bValidAfter := __ISVALIDREF(rMotor);            // TRUE
    __DELETE(pMotor);                               // FB_exit runs, pMotor := 0
    nAfterDelete := fbMotor.Instances;
    __TRY
        fDangling := pCopy^.fSpeed;                 // the instance is gone
    __CATCH(exc)
        excDangling := exc;                         // RTSEXCPT_ACCESS_VIOLATION
    __ENDTRY
    rMotor REF= 0;
    bValidUnbound := __ISVALIDREF(rMotor);          // FALSE
    itfDrive := fbMotor;
    bDiag := __QUERYINTERFACE(itfDrive, itfDiag);         // TRUE: FB_Motor is an I_Diagnosis
    bPrinter := __QUERYINTERFACE(itfDrive, itfPrinter);   // FALSE: itfPrinter stays 0
    bPointer := __QUERYPOINTER(itfDrive, pAny);           // pAny = ADR(fbMotor)
    stInfo := __VARINFO(fbMotor.fSpeed);
    bFirstTake := TestAndSet(bLock);                // TRUE: the lock was free
    bSecondTake := TestAndSet(bLock);               // FALSE: already taken
    bLock := FALSE;                                 // release

    PROGRAM MAIN_Try                                // every cycle
    VAR_INPUT nDivisor : INT; END_VAR
    VAR nResult : INT; nErrors, nCalls : UDINT; excLast : __SYSTEM.ExceptionCode; END_VAR
    __TRY
        nResult := 100 / nDivisor;
    __CATCH(exc)
        nResult := -1;
        nErrors := nErrors + 1;
        excLast := exc;
    __FINALLY
        nCalls := nCalls + 1;
    __ENDTRY
"""

from __future__ import annotations

from iecoop import (
    BOOL,
    DINT,
    INT,
    LREAL,
    POINTER_TO,
    REFERENCE_TO,
    STRING,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_STAT,
    ExceptionCode,
    FunctionBlock,
    IQueryInterface,
    Program,
    T,
    adr,
    delete,
    is_valid_ref,
    method,
    new,
    prop,
    query_interface,
    query_pointer,
    ref_assign,
    test_and_set,
    try_catch,
    var_info,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = ["IDiagnosis", "IDrive", "IPrinter", "MainOperators", "MainTry", "Motor", "main"]


class IDrive(IQueryInterface):
    """``INTERFACE I_Drive EXTENDS __SYSTEM.IQueryInterface``."""

    @method
    def move(self, set_speed: LREAL) -> BOOL:
        raise NotImplementedError


class IDiagnosis(IQueryInterface):
    """``INTERFACE I_Diagnosis EXTENDS __SYSTEM.IQueryInterface``."""

    @prop
    def healthy(self) -> BOOL:
        raise NotImplementedError


class IPrinter(IQueryInterface):
    """``INTERFACE I_Printer EXTENDS __SYSTEM.IQueryInterface``: not implemented by FB_Motor."""

    @method
    def print_line(self, line: STRING) -> None: ...


class Motor(FunctionBlock, IDrive, IDiagnosis):
    """``FUNCTION_BLOCK FB_Motor IMPLEMENTS I_Drive, I_Diagnosis`` (``enable_dynamic_creation``)."""

    axis: INT = VAR_INPUT(0)
    speed: LREAL = VAR(0.0)
    instance_count: INT = VAR_STAT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> BOOL:
        self.instance_count += 1
        return True

    def fb_exit(self, in_copy_code: BOOL) -> BOOL:
        self.instance_count -= 1
        return True

    @method
    def move(self, set_speed: LREAL) -> BOOL:
        self.speed = set_speed
        return True

    @prop
    def healthy(self) -> BOOL:
        return self.speed < 3000.0

    @prop
    def instances(self) -> INT:
        """``PROPERTY Instances : INT``: how many FB_Motor instances exist (FB_init minus FB_exit)."""
        return self.instance_count


class MainOperators(Program):
    """``PROGRAM MAIN_Operators``: each operator once, in the first cycle."""

    motor: Motor = VAR()
    p_motor: POINTER_TO[Motor] = VAR()
    p_copy: POINTER_TO[Motor] = VAR()
    p_any: POINTER_TO[Motor] = VAR()
    r_motor: REFERENCE_TO[Motor] = VAR()
    itf_drive: IDrive = VAR()
    itf_diag: IDiagnosis = VAR()
    lock: BOOL = VAR(False)
    done: BOOL = VAR(False)
    before: INT = VAR(0)
    after_new: INT = VAR(0)
    after_delete: INT = VAR(0)
    new_speed: LREAL = VAR(0.0)
    deleted_is_null: BOOL = VAR(False)
    valid_before: BOOL = VAR(False)
    valid_after: BOOL = VAR(False)
    valid_unbound: BOOL = VAR(True)
    dangling_exception: UDINT = VAR(0)
    query_diag: BOOL = VAR(False)
    query_printer: BOOL = VAR(True)
    pointer_is_motor: BOOL = VAR(False)
    speed_offset: DINT = VAR(0)
    speed_bits: UDINT = VAR(0)
    speed_type: STRING = VAR("")
    first_take: BOOL = VAR(False)
    second_take: BOOL = VAR(True)

    def body(self) -> None:
        if self.done:
            return
        self.done = True
        # __NEW / __DELETE
        self.before = self.motor.instances
        self.p_motor = new(Motor)
        self.after_new = self.motor.instances
        self.p_motor.deref.axis = 3
        self.p_motor.deref.move(1500.0)
        self.new_speed = self.p_motor.deref.speed
        self.p_copy = self.p_motor
        # __ISVALIDREF
        self.valid_before = is_valid_ref(self, "r_motor")
        ref_assign(self, "r_motor", self.p_motor)
        self.valid_after = is_valid_ref(self, "r_motor")
        delete(self.p_motor)
        self.after_delete = self.motor.instances
        self.deleted_is_null = self.p_motor == 0
        with try_catch() as exc:
            self.new_speed = self.p_copy.deref.speed
        self.dangling_exception = exc.code
        ref_assign(self, "r_motor", None)
        self.valid_unbound = is_valid_ref(self, "r_motor")
        # __QUERYINTERFACE / __QUERYPOINTER
        self.itf_drive = self.motor
        diag = query_interface(self.itf_drive, IDiagnosis)
        self.query_diag = diag is not None
        if diag is not None:
            self.itf_diag = diag
        printer = query_interface(self.itf_drive, IPrinter)
        self.query_printer = printer is not None
        self.p_any = query_pointer(self.itf_drive)
        self.pointer_is_motor = self.p_any == adr(self, "motor")
        # __VARINFO
        info = var_info(self.motor, "speed")
        self.speed_offset, self.speed_bits, self.speed_type = info.ByteOffset, info.BitSize, info.TypeName
        # TestAndSet
        self.first_take = bool(test_and_set(adr(self, "lock")))
        self.second_take = bool(test_and_set(adr(self, "lock")))
        self.lock = False


class MainTry(Program):
    """``PROGRAM MAIN_Try``: a division by zero caught every time it happens; the task goes on."""

    divisor: INT = VAR_INPUT(1)
    result: INT = VAR(0)
    errors: UDINT = VAR(0)
    calls: UDINT = VAR(0)
    last_exception: UDINT = VAR(0)

    def body(self) -> None:
        with try_catch() as exc:  # __TRY
            self.result = 100 // self.divisor
        if exc.code != ExceptionCode.RTSEXCPT_NOEXCEPTION:  # __CATCH(exc)
            self.result = -1
            self.errors += 1
            self.last_exception = exc.code
        self.calls += 1  # __FINALLY


def main() -> None:
    """Run MAIN_Operators once, and MAIN_Try with the divisors 5, 0 and 4.

    >>> main()
    __NEW(FB_Motor): FB_init ran (Instances +1), pMotor^.Move(1500.0) gave fSpeed = 1500.0
    __DELETE(pMotor): FB_exit ran (Instances -1), pMotor = 0: True
    pCopy^ after __DELETE: RTSEXCPT_ACCESS_VIOLATION
    __ISVALIDREF(rMotor): before REF= False, after REF= True, after REF= 0 False
    __QUERYINTERFACE(itfDrive, itfDiag) = True, (itfDrive, itfPrinter) = False
    __QUERYPOINTER(itfDrive, pAny): pAny = ADR(fbMotor) is True
    __VARINFO(fbMotor.fSpeed): ByteOffset 16, BitSize 64, TypeName LREAL
    TestAndSet(bLock): True, then False
    __TRY 100 / 5: nResult = 20, nErrors = 0, nCalls = 1
    __TRY 100 / 0: nResult = -1, nErrors = 1, nCalls = 2, RTSEXCPT_DIVIDEBYZERO
    __TRY 100 / 4: nResult = 25, nErrors = 1, nCalls = 3
    """
    operators, division = MainOperators(), MainTry()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), operators, division)
    division.divisor = 5
    rt.run(cycles=1)
    o = operators
    print(
        f"__NEW(FB_Motor): FB_init ran (Instances {o.after_new - o.before:+d}), "
        f"pMotor^.Move(1500.0) gave fSpeed = {o.new_speed}"
    )
    print(
        f"__DELETE(pMotor): FB_exit ran (Instances {o.after_delete - o.after_new:+d}), "
        f"pMotor = 0: {o.deleted_is_null}"
    )
    print(f"pCopy^ after __DELETE: {ExceptionCode(o.dangling_exception).name}")
    print(
        f"__ISVALIDREF(rMotor): before REF= {o.valid_before}, after REF= {o.valid_after}, "
        f"after REF= 0 {o.valid_unbound}"
    )
    print(f"__QUERYINTERFACE(itfDrive, itfDiag) = {o.query_diag}, (itfDrive, itfPrinter) = {o.query_printer}")
    print(f"__QUERYPOINTER(itfDrive, pAny): pAny = ADR(fbMotor) is {o.pointer_is_motor}")
    print(f"__VARINFO(fbMotor.fSpeed): ByteOffset {o.speed_offset}, BitSize {o.speed_bits}, TypeName {o.speed_type}")
    print(f"TestAndSet(bLock): {o.first_take}, then {o.second_take}")
    for divisor in (5, 0, 4):
        if divisor != 5:
            division.divisor = divisor
            rt.run(cycles=1)
        caught = f", {ExceptionCode(division.last_exception).name}" if divisor == 0 else ""
        print(
            f"__TRY 100 / {divisor}: nResult = {division.result}, nErrors = {division.errors}, "
            f"nCalls = {division.calls}{caught}"
        )


SHOWCASE = Showcase(
    program=MainOperators,
    # Instances is the VAR_STAT count of every FB_Motor the application made, in this program or not:
    # the trace shows what __NEW and __DELETE change, which does not depend on what ran before.
    columns=(Column("Instances by __NEW", lambda p: p.after_new - p.before, "+d"),
             Column("by __DELETE", lambda p: p.after_delete - p.after_new, "+d"), Column("p = 0", lambda p: p.deleted_is_null),
             Column("__ISVALIDREF", lambda p: p.valid_before)),
    cycles=3,
)


if __name__ == "__main__":
    main()
