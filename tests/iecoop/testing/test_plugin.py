"""The pytest plugin and the cycle helpers of iecoop.testing."""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings

from iecoop import BOOL, DINT, INT, FunctionBlock, IecEnum, Program, STRING, T, VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.runtime import Runtime
from iecoop.stdlib import TON
from iecoop.testing import RunUntilTimeout, VirtualPlc, run_until
from iecoop.testing.strategies import enum_values, fb_inputs, input_sequences

pytest_plugins = ["pytester"]


class Counter(Program):
    count: DINT = VAR()
    timer: TON = VAR()
    done: BOOL = VAR()

    def body(self) -> None:
        self.count += 1
        self.timer(IN=True, PT=T("250ms"))
        self.done = self.timer.Q


def test_the_plc_fixture_starts_empty_at_time_zero(plc: VirtualPlc, plc_runtime: Runtime) -> None:
    assert plc.time_ms == 0
    assert plc.runtime is plc_runtime
    assert plc_runtime.tasks == []
    assert plc_runtime.profile.name == "twincat"


def test_a_second_test_gets_a_fresh_plc(plc: VirtualPlc) -> None:
    main = plc.add(Counter())
    plc.run_cycles(5)
    assert (main.count, plc.time_ms) == (5, 50)


@pytest.mark.iecoop_profile("codesys")
def test_the_profile_marker_selects_the_vendor(plc: VirtualPlc) -> None:
    assert plc.runtime.profile.name == "codesys"


def test_run_until_returns_the_plc_time_the_condition_took(plc: VirtualPlc) -> None:
    main = plc.add(Counter())
    assert plc.run_until(lambda: main.count == 0) == 0  # checked before the first tick
    took = plc.run_until(lambda: main.done, timeout=T("1s"))
    # TON starts timing in the first cycle (t=0) and is done in the cycle at t=250
    assert took == 260 and main.timer.ET == 250 and main.count == 26


def test_run_until_raises_on_timeout_naming_the_condition(plc: VirtualPlc) -> None:
    main = plc.add(Counter(), interval=T("20ms"))

    def never() -> bool:
        return main.count < 0

    with pytest.raises(RunUntilTimeout, match=r"condition never still false after 100 ms of PLC time \(5 base ticks of 20 ms"):
        plc.run_until(never, timeout=T("100ms"))
    assert main.count == 5 and plc.time_ms == 100
    assert isinstance(RunUntilTimeout("x"), AssertionError)  # pytest reports it as a failed assertion
    with pytest.raises(ValueError, match="timeout must not be negative"):
        run_until(plc.runtime, never, timeout=-1)


def test_add_puts_programs_on_one_task_in_order(plc: VirtualPlc) -> None:
    first, second = plc.add(Counter()), plc.add(Counter())
    assert [path for path, _ in plc.runtime.tasks[0].programs] == ["PlcTask.Counter", "PlcTask.Counter_2"]
    plc.run_cycles(2)
    assert first.count == second.count == 2
    with pytest.raises(ValueError, match="task PlcTask already runs every 10 ms at priority 20"):
        plc.add(Counter(), interval=T("5ms"))
    slow = plc.add(Counter(), task="Slow", interval=T("50ms"), priority=25)
    plc.run_cycles(10)  # base tick is 10 ms: the slow task runs at 20, 70 ms... every fifth tick
    assert first.count == 12 and slow.count == 2


def test_the_plugin_is_loaded_by_the_entry_point(pytester: pytest.Pytester) -> None:
    pytester.makepyfile(
        """
        import pytest
        from iecoop import DINT, Program, VAR

        class Blink(Program):
            n: DINT = VAR()
            def body(self) -> None:
                self.n += 1

        def test_blink(plc):
            main = plc.add(Blink())
            assert plc.run_until(lambda: main.n == 3) == 30

        @pytest.mark.iecoop_profile("beckhoff")
        def test_unknown_profile(plc):
            pass

        @pytest.mark.iecoop_profile()
        def test_marker_without_name(plc):
            pass
        """
    )
    result = pytester.runpytest_subprocess("-p", "no:cacheprovider", "-W", "ignore::DeprecationWarning")
    result.assert_outcomes(passed=1, errors=2)
    result.stdout.fnmatch_lines(["*unknown vendor profile 'beckhoff'; known profiles: codesys, twincat*"])
    result.stdout.fnmatch_lines(["*iecoop_profile takes one profile name*"])


class Mode(IecEnum, base=INT):
    AUTO = 1
    MANUAL = 2


class Dosing(FunctionBlock):
    enable: BOOL = VAR_INPUT()
    setpoint: INT = VAR_INPUT()
    mode: Mode = VAR_INPUT(Mode.AUTO)
    recipe: STRING = VAR_INPUT("", length=4)
    total: DINT = VAR_OUTPUT()

    def body(self) -> None:
        if self.enable and self.mode == Mode.AUTO:
            self.total += self.setpoint


@settings(max_examples=60, deadline=None)
@given(input_sequences(Dosing, max_size=20))
def test_input_sequences_draw_every_input_within_its_type(sequence: list[dict[str, Any]]) -> None:
    assert 1 <= len(sequence) <= 20
    fb = Dosing()
    expected = 0
    for inputs in sequence:
        assert set(inputs) == {"enable", "setpoint", "mode", "recipe"}
        assert isinstance(inputs["enable"], bool)
        assert isinstance(inputs["setpoint"], int) and -32768 <= inputs["setpoint"] <= 32767
        assert inputs["mode"] in (Mode.AUTO, Mode.MANUAL)
        assert isinstance(inputs["recipe"], str) and len(inputs["recipe"]) <= 4
        fb(**inputs)  # every drawn value is accepted by the checked call
        if inputs["enable"] and inputs["mode"] == Mode.AUTO:
            expected += inputs["setpoint"]
        assert fb.recipe == inputs["recipe"]
    assert fb.total == expected


@settings(max_examples=20, deadline=None)
@given(fb_inputs(TON, ["IN"]), enum_values(Mode))
def test_fb_inputs_can_name_a_subset(inputs: dict[str, object], mode: Mode) -> None:
    assert list(inputs) == ["IN"] and isinstance(inputs["IN"], bool)
    assert mode in (Mode.AUTO, Mode.MANUAL)


def test_fb_inputs_refuses_what_is_not_an_input() -> None:
    with pytest.raises(TypeError, match="Dosing has no VAR_INPUT 'total'"):
        fb_inputs(Dosing, ["total"])
    with pytest.raises(TypeError, match="is not a function block class"):
        fb_inputs(int)
