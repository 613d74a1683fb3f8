"""Visitor: diagnostics exports over a plant tree, checked after cycles on the virtual clock."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from iecoop import ARRAY, INT, STRING, VAR, VAR_OUTPUT, AccessError, ExceptionCode, FunctionBlock, PlcException, Program, T, method
from iecoop.runtime import Runtime, Task
from patterns.behavioral.visitor import (
    MAX_AREAS,
    MAX_DEVICES,
    MAX_LINES,
    AddRefusal,
    CsvHealthReport,
    EnergyTotals,
    Health,
    IArea,
    IDeviceVisitor,
    IMotor,
    ISensor,
    IValve,
    Motor,
    Plant,
    PlantMain,
    Sensor,
    Valve,
    health_text,
    one_decimal,
)


def start(program: Program) -> Runtime:
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    return rt


def export(rt: Runtime, program: PlantMain) -> None:
    program.export = True
    rt.run(cycles=1)
    program.export = False
    rt.run(cycles=1)


def report_lines(report: CsvHealthReport) -> list[str]:
    return [report.lines[i] for i in range(1, report.count + 1)]


class Recorder(FunctionBlock, IDeviceVisitor):
    """Writes down every visit, in order: which method the double dispatch chose, for which path."""

    calls: ARRAY[STRING] = VAR_OUTPUT(bounds=(1, 20), length=60)
    count: INT = VAR_OUTPUT(0)

    @method
    def note(self, text: STRING) -> None:
        self.count += 1
        self.calls[self.count] = text

    @method
    def visit_area(self, area: IArea) -> None:
        self.note(f"area {area.number} {area.instance_path}")

    @method
    def visit_motor(self, motor: IMotor) -> None:
        self.note(f"motor {motor.instance_path}")

    @method
    def visit_valve(self, valve: IValve) -> None:
        self.note(f"valve {valve.instance_path}")

    @method
    def visit_sensor(self, sensor: ISensor) -> None:
        self.note(f"sensor {sensor.instance_path}")


# ---------------------------------------------------------------------------
# Double dispatch and instance paths
# ---------------------------------------------------------------------------


def test_each_device_calls_the_visit_method_of_its_own_kind_in_tree_order() -> None:
    program = PlantMain()
    recorder = Recorder()
    program.plant.accept(recorder)
    assert [recorder.calls[i] for i in range(1, recorder.count + 1)] == [
        "area 1 Plant.Area1",
        "motor Plant.Area1.Motor1",
        "motor Plant.Area1.Motor2",
        "valve Plant.Area1.Valve1",
        "sensor Plant.Area1.TT101",
        "area 2 Plant.Area2",
        "motor Plant.Area2.Motor3",
        "valve Plant.Area2.Valve2",
        "sensor Plant.Area2.LT201",
    ]


def test_instance_paths_are_composed_once_when_devices_join_an_area() -> None:
    program = PlantMain()
    assert program.motor2.instance_path == "Plant.Area1.Motor2"
    assert program.lt201.instance_path == "Plant.Area2.LT201"
    assert program.plant.areas[2].instance_path == "Plant.Area2"
    assert (program.plant.count, program.plant.areas[1].count, program.plant.areas[2].count) == (2, 4, 3)


# ---------------------------------------------------------------------------
# The CSV health report
# ---------------------------------------------------------------------------


def test_a_healthy_plant_reports_every_device_ok_after_running() -> None:
    program = PlantMain()
    rt = start(program)
    program.motor1.run = True
    program.tt101.raw_ma = 8.0
    program.lt201.raw_ma = 20.0
    rt.run(cycles=300)
    export(rt, program)
    assert report_lines(program.report) == [
        "path,device,health,detail",
        "Plant.Area1.Motor1,motor,OK,starts=1 run=3.0s",
        "Plant.Area1.Motor2,motor,OK,starts=0 run=0.0s",
        "Plant.Area1.Valve1,valve,OK,strokes=0",
        "Plant.Area1.TT101,sensor,OK,value=37.5 current=8.0mA",
        "Plant.Area2.Motor3,motor,OK,starts=0 run=0.0s",
        "Plant.Area2.Valve2,valve,OK,strokes=0",
        "Plant.Area2.LT201,sensor,OK,value=100.0 current=20.0mA",
    ]
    assert (program.report.faults, program.report.warnings, program.report.overflow) == (0, 0, False)


def test_faults_and_warnings_found_across_cycles_appear_in_the_report() -> None:
    program = PlantMain()
    rt = start(program)
    program.motor2.run = True
    program.valve2.stuck = True
    program.valve2.open_cmd = True
    program.tt101.raw_ma = 21.0
    program.lt201.raw_ma = 0.0
    rt.run(cycles=99)
    export(rt, program)
    lines = report_lines(program.report)
    # Not yet: the discrepancy TON needs 1 s, and the 3.6 s service interval of Motor2 is not reached.
    assert lines[2] == "Plant.Area1.Motor2,motor,OK,starts=1 run=1.0s"
    assert lines[6] == "Plant.Area2.Valve2,valve,OK,strokes=0"
    rt.run(cycles=300)
    export(rt, program)
    lines = report_lines(program.report)
    assert lines[2] == "Plant.Area1.Motor2,motor,WARNING,starts=1 run=4.0s service due"
    assert lines[4] == "Plant.Area1.TT101,sensor,WARNING,value=159.4 current=21.0mA"
    assert lines[6] == "Plant.Area2.Valve2,valve,FAULT,no end position feedback"
    assert lines[7] == "Plant.Area2.LT201,sensor,FAULT,wire break current=0.0mA"
    assert (program.report.faults, program.report.warnings) == (2, 2)


def test_the_export_runs_once_per_rising_edge_and_the_report_stays_put_while_held() -> None:
    program = PlantMain()
    rt = start(program)
    program.motor1.run = True
    program.export = True
    rt.run(cycles=50)
    assert program.exports == 1
    assert program.report.lines[2] == "Plant.Area1.Motor1,motor,OK,starts=1 run=0.0s"
    program.export = False
    rt.run(cycles=1)
    program.export = True
    rt.run(cycles=1)
    assert program.exports == 2
    assert program.report.lines[2] == "Plant.Area1.Motor1,motor,OK,starts=1 run=0.5s"
    assert program.report.count == 8


def test_a_latched_valve_fault_clears_in_the_next_report_after_reset() -> None:
    program = PlantMain()
    rt = start(program)
    program.valve1.stuck = True
    program.valve1.open_cmd = True
    rt.run(cycles=150)
    export(rt, program)
    assert program.report.lines[4] == "Plant.Area1.Valve1,valve,FAULT,no end position feedback"
    program.valve1.stuck = False
    rt.run(cycles=50)
    assert program.valve1.is_open and program.valve1.fault
    program.valve1.reset = True
    rt.run(cycles=1)
    program.valve1.reset = False
    export(rt, program)
    assert program.report.lines[4] == "Plant.Area1.Valve1,valve,OK,strokes=1"


class CrowdedPlant(Program):
    plant: Plant = VAR(fb_init={"name": "Plant"})


def test_a_report_that_does_not_fit_sets_overflow_and_counts_the_dropped_lines() -> None:
    program = CrowdedPlant()
    sensors = [Sensor(name=f"PT{i:02d}") for i in range(1, 2 * MAX_DEVICES + 1)]
    for a in range(2):
        area = program.plant.add_area(f"Area{a + 1}")
        for sensor in sensors[a * MAX_DEVICES : (a + 1) * MAX_DEVICES]:
            area.add(sensor)
    report = CsvHealthReport()
    report.clear()
    program.plant.accept(report)
    assert report.count == MAX_LINES
    assert report.overflow is True
    assert report.dropped == 1 + 2 * MAX_DEVICES - MAX_LINES
    assert report.lines[MAX_LINES] == f"Plant.Area2.PT{MAX_LINES - 1:02d},sensor,OK,value=0.0 current=4.0mA"
    report.clear()
    assert (report.count, report.overflow, report.dropped, report.lines[2]) == (1, False, 0, "")


# ---------------------------------------------------------------------------
# The energy totals
# ---------------------------------------------------------------------------


def test_energy_totals_follow_run_time_and_strokes_per_area() -> None:
    program = PlantMain()
    rt = start(program)
    program.motor1.run = True  # 7.5 kW, Area1
    program.motor3.run = True  # 4 kW, Area2
    rt.run(cycles=360)  # 3.6 s = 1/1000 h
    program.motor1.run = program.motor3.run = False
    for _ in range(4):
        program.valve2.open_cmd = True
        rt.run(cycles=40)
        program.valve2.open_cmd = False
        rt.run(cycles=40)
    export(rt, program)
    energy = program.energy
    assert energy.motors_wh == pytest.approx(7.5 + 4.0)
    assert energy.valves_wh == pytest.approx(4 * 0.5)
    assert energy.area_wh[1] == pytest.approx(7.5)
    assert energy.area_wh[2] == pytest.approx(4.0 + 2.0)
    assert energy.total_wh == pytest.approx(13.5)
    assert [energy.area_wh[i] for i in range(3, MAX_AREAS + 1)] == [0.0, 0.0]


@settings(max_examples=25, deadline=None)
@given(schedule=st.lists(st.tuples(st.booleans(), st.booleans(), st.booleans(), st.booleans()), max_size=12))
def test_energy_equals_the_model_and_the_areas_add_up_to_the_total(
    schedule: list[tuple[bool, bool, bool, bool]],
) -> None:
    program = PlantMain()
    rt = start(program)
    motors = [(program.motor1, 7.5), (program.motor2, 15.0), (program.motor3, 4.0)]
    model_seconds = [0.0, 0.0, 0.0]
    strokes = 0
    for m1, m2, m3, stroke in schedule:
        for i, run in enumerate((m1, m2, m3)):
            motors[i][0].run = run
            model_seconds[i] += 0.5 if run else 0.0
        program.valve1.open_cmd = stroke
        rt.run(cycles=50)
        if stroke:
            program.valve1.open_cmd = False
            rt.run(cycles=40)
            strokes += 1
            for i, (motor, _) in enumerate(motors):
                model_seconds[i] += 0.4 if motor.run else 0.0
    export(rt, program)
    # The devices run before the export in the scan of the rising edge.
    for i, (motor, _) in enumerate(motors):
        model_seconds[i] += 0.01 if motor.run else 0.0
    energy = program.energy
    motors_wh = sum(kw * 1000.0 * s / 3600.0 for (_, kw), s in zip(motors, model_seconds))
    assert energy.motors_wh == pytest.approx(motors_wh, abs=1e-6)
    assert program.valve1.strokes == strokes
    assert energy.valves_wh == pytest.approx(0.5 * strokes)
    assert energy.total_wh == pytest.approx(energy.motors_wh + energy.valves_wh)
    assert energy.total_wh == pytest.approx(sum(energy.area_wh[i] for i in range(1, MAX_AREAS + 1)))


def test_a_second_export_restarts_the_totals_instead_of_adding_to_them() -> None:
    program = PlantMain()
    rt = start(program)
    program.motor2.run = True
    rt.run(cycles=240)
    export(rt, program)
    first = program.energy.total_wh
    export(rt, program)
    assert first == pytest.approx(15000.0 * 2.41 / 3600.0)
    assert program.energy.total_wh == pytest.approx(15000.0 * 2.43 / 3600.0)


# ---------------------------------------------------------------------------
# Failure paths: bounded arrays, ownership, configuration errors
# ---------------------------------------------------------------------------


def test_a_full_area_refuses_the_next_device() -> None:
    plant = Plant(name="Plant")
    area = plant.add_area("Area1")
    motors = [Motor(name=f"M{i}") for i in range(MAX_DEVICES + 1)]
    for motor in motors[:MAX_DEVICES]:
        assert area.add(motor) is True
    assert area.refusal == AddRefusal.NONE
    assert (area.add(motors[-1]), area.refusal, area.count) == (False, AddRefusal.AREA_FULL, MAX_DEVICES)
    assert motors[-1].instance_path == ""


def test_a_full_plant_faults_on_the_next_area_with_array_bounds() -> None:
    plant = Plant(name="Plant")
    for i in range(MAX_AREAS):
        plant.add_area(f"A{i}")
    with pytest.raises(PlcException, match=r"index 5 .*1\.\.4") as info:
        plant.add_area("Extra")
    assert info.value.code == ExceptionCode.RTSEXCPT_ARRAYBOUNDS
    assert plant.count == MAX_AREAS
    assert [plant.areas[i].instance_path for i in range(1, MAX_AREAS + 1)] == [f"Plant.A{i}" for i in range(MAX_AREAS)]


def test_a_device_belongs_to_one_area_only_and_null_is_refused() -> None:
    program = PlantMain()
    area2 = program.plant.areas[2]
    assert (area2.add(program.motor1), area2.refusal) == (False, AddRefusal.ALREADY_IN_AREA)
    assert program.motor1.instance_path == "Plant.Area1.Motor1"
    assert (area2.add(area2.devices[MAX_DEVICES]), area2.refusal) == (False, AddRefusal.NULL_DEVICE)
    assert area2.count == 3
    spare = Valve(name="Valve9")
    assert (area2.add(spare), area2.refusal, area2.count) == (True, AddRefusal.NONE, 4)
    assert spare.instance_path == "Plant.Area2.Valve9"


def test_devices_need_a_name_and_paths_must_fit_their_string() -> None:
    plant = Plant(name="Plant")
    area = plant.add_area("AreaWithAVeryLongName")
    nameless = Valve()
    assert (area.add(nameless), area.refusal, nameless.instance_path) == (False, AddRefusal.NO_PATH, "")
    sensor = Sensor(name="TransmitterTT101")
    assert (area.add(sensor), area.refusal, sensor.instance_path) == (False, AddRefusal.NO_PATH, "")
    # 40 characters exactly fit STRING(40): "Plant.AreaWithAVeryLongName" + "." + 12.
    fits = Sensor(name="Transmitter1")
    assert area.add(fits) is True
    assert (fits.instance_path, len(fits.instance_path), area.count) == ("Plant.AreaWithAVeryLongName.Transmitter1", 40, 1)


def test_one_decimal_and_health_text_give_the_csv_words() -> None:
    # Away from the halves, tenths as Python prints them; -0.04 has no sign, as it rounds to 0.
    for value in (0.0, 0.04, 0.06, 2.1, 12.0, 75.0, 19.94, 143.24, -0.5, -0.04, -12.34):
        assert one_decimal(value) == f"{value:.1f}".replace("-0.0", "0.0"), value
    assert [health_text(h) for h in Health] == [h.name for h in Health]


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_one_decimal_reads_back_within_a_twentieth(value: float) -> None:
    assert abs(float(one_decimal(value)) - value) <= 0.05 + 1e-9


def test_only_the_plant_attaches_an_area() -> None:
    plant = Plant(name="Plant")
    area = plant.add_area("Area1")
    with pytest.raises(AccessError, match=r"INTERNAL METHOD Area\.attach"):
        area.attach("Other", "Area9", 9)
    assert (area.instance_path, area.number) == ("Plant.Area1", 1)


def test_health_is_derived_from_the_device_inputs() -> None:
    sensor = Sensor(name="TT1", low=0.0, high=100.0)
    for raw, health in ((3.5, Health.FAULT), (3.6, Health.OK), (20.5, Health.OK), (20.6, Health.WARNING)):
        sensor(raw_ma=raw)
        assert sensor.health == health, raw
    energy = EnergyTotals()
    energy.clear()
    sensor.accept(energy)
    assert energy.total_wh == 0.0
