"""``st.load`` of a PLCopen XML export: CODESYS's text form of a project, read as the ST it declares.

``data/plcopen/BottleLine.xml`` is written as CODESYS V3.5 exports a project: TC6 data types (an enumeration,
a STRUCT, a subrange), a FUNCTION_BLOCK with an ACTION, CODESYS's addData METHOD (PRIVATE), PROPERTY,
IMPLEMENTS, INTERFACE and global variable list, array and struct initial values.
"""

from __future__ import annotations

import pathlib

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies

pytest.importorskip("blark")

from iecoop import DefinitionError, ExceptionCode, PlcException, st  # noqa: E402
from iecoop.runtime import Runtime, Task  # noqa: E402

PROJECT = pathlib.Path(__file__).parent / "data" / "plcopen" / "BottleLine.xml"
TEXT = PROJECT.read_text(encoding="utf-8")


def _run(module: object, cycles: int) -> list[tuple[int, int, int]]:
    """(state, parts done, the GVL's total) after each cycle."""
    runtime = Runtime(store=":memory:")
    main = getattr(module, "PLC_PRG")
    runtime.add_task(Task("PlcTask", interval=10), main)
    rows = []
    for _ in range(cycles):
        runtime.run(cycles=1)
        rows.append((int(main.fbFiller.eState), main.fbFiller.nDone, getattr(module, "GVL").nTotal))
    return rows


def test_a_codesys_export_loads_and_runs_over_cycles() -> None:
    plc = st.load(PROJECT)
    rows = _run(plc, 14)
    # Idle -> Filling while the 30 ms TON runs (four 10 ms cycles) -> Capping, where the ACTION counts -> Idle
    assert [state for state, _, _ in rows[:7]] == [10, 10, 10, 10, 20, 0, 10]
    assert rows[4][1:] == (0, 0) and rows[5][1:] == (1, 1)  # the PROPERTY read through the INTERFACE, into the GVL
    assert rows[-1][1] == 2
    station = plc.PLC_PRG.fbFiller
    assert station.nFill == 100  # the PRIVATE METHOD's MIN held the subrange's top
    assert [(b.nId, b.rVolume, b.sLabel) for b in station.aLast] == [(2, 0.5, "water"), (0, 1.5, "water"), (0, 1.5, "water")]


def test_the_xml_lines_are_where_errors_and_faults_point(tmp_path: pathlib.Path) -> None:
    line = next(i for i, text in enumerate(TEXT.splitlines(), 1) if "nDone := nDone + 1;" in text)
    bad = tmp_path / "Typo.xml"
    bad.write_text(TEXT.replace("nDone := nDone + 1;", "nDone := nDonne + 1;"))
    with pytest.raises(st.StUnsupportedError, match=rf"Typo\.xml:{line}: unknown variable 'nDonne'"):
        st.load(bad)
    faulty = tmp_path / "Divide.xml"
    faulty.write_text(TEXT.replace("nDone := nDone + 1;", "nDone := nDone + 1 / (nDone - nDone);"))
    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=10), st.load(faulty).PLC_PRG)
    with pytest.raises(PlcException) as caught:
        runtime.run(cycles=10)
    assert caught.value.code == ExceptionCode.RTSEXCPT_DIVIDEBYZERO
    assert f"Divide.xml:{line}" in str(caught.value)


@pytest.mark.parametrize("change, error, words", [
    (("<ST>", "<FBD>", "</ST>", "</FBD>"), st.StUnsupportedError,
     r"BottleLine\.xml:\d+: FUNCTION_BLOCK FB_Station: its body is written in FBD, not Structured Text"),
    (("</pous>", "</pous"), st.StSyntaxError, r"BottleLine\.xml:\d+: not well-formed XML"),
    (('<?xml version="1.0" encoding="utf-8"?>', '<?xml version="1.0"?>\n<!DOCTYPE project [<!ENTITY a "aaaa">]>'),
     st.StSyntaxError, r"BottleLine\.xml:2: a DOCTYPE is not allowed"),
    (('pouType="program"', 'pouType="class"'), st.StUnsupportedError, r"POU PLC_PRG: pouType 'class' is not read"),
    (("<string length=\"20\" />", "<struct />"), st.StUnsupportedError, r"BottleLine\.xml:30: ST_Bottle\.sLabel: an inline STRUCT is not supported"),
])
def test_what_is_not_read_is_named_with_its_line(tmp_path: pathlib.Path, change: tuple[str, ...], error: type[Exception],
                                                 words: str) -> None:
    text = TEXT
    for old, new in zip(change[::2], change[1::2]):
        text = text.replace(old, new, 1)
    bad = tmp_path / "BottleLine.xml"
    bad.write_text(text)
    with pytest.raises(error, match=words):
        st.load(bad)


def test_a_file_that_is_no_plcopen_project_or_nests_without_end_is_refused(tmp_path: pathlib.Path) -> None:
    other = tmp_path / "settings.xml"
    other.write_text('<?xml version="1.0"?><configuration><item/></configuration>')
    with pytest.raises(st.StUnsupportedError, match=r"settings\.xml: not a PLCopen XML project \(its root element is <configuration>"):
        st.load(other)
    deep = tmp_path / "deep.xml"
    deep.write_text("<project>" + "<a>" * 10_000 + "</a>" * 10_000 + "</project>")
    with pytest.raises(st.StSyntaxError, match=r"deep\.xml:1: not well-formed XML: Excessive depth"):
        st.load(deep)


_TOKENS = ["<", ">", "/", '"', "=", "name", "variable", "type", "INT", "derived", ":=", ";", "END_IF", "&amp;", "\n", " "]


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(strategies.lists(strategies.tuples(strategies.integers(0, len(TEXT) - 1), strategies.sampled_from(_TOKENS),
                                          strategies.booleans()), min_size=1, max_size=3))
def test_a_mutated_export_gives_a_named_error_or_loads(tmp_path: pathlib.Path, edits: list[tuple[int, str, bool]]) -> None:
    text = TEXT
    for at, token, insert in edits:
        text = text[:at] + token + text[at if insert else at + len(token):]
    path = tmp_path / "Mutated.xml"
    path.write_text(text, encoding="utf-8")
    try:
        st.load(path, cache=False)
    except DefinitionError as exc:
        assert "Mutated.xml" in str(exc) or "<st" in str(exc)


SUITE = """<?xml version="1.0" encoding="utf-8"?>
<project xmlns="http://www.plcopen.org/xml/tc6_0200">
  <types><dataTypes /><pous>
    <pou name="FB_Scale_Test" pouType="functionBlock">
      <interface />
      <body><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">TestGain();
TestOffset();</xhtml></ST></body>
      <addData>
        <data name="http://www.3s-software.com/plcopenxml/method" handleUnknown="implementation">
          <Method name="TestGain" ObjectId="1"><interface /><body><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">TEST('TestGain');
AssertEquals_INT(Expected := 8, Actual := 2 * 4, Message := 'gain');
TEST_FINISHED();</xhtml></ST></body></Method>
        </data>
        <data name="http://www.3s-software.com/plcopenxml/method" handleUnknown="implementation">
          <Method name="TestOffset" ObjectId="2"><interface /><body><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">TEST('TestOffset');
AssertEquals_INT(Expected := 5, Actual := 2 + 4, Message := 'offset');
TEST_FINISHED();</xhtml></ST></body></Method>
        </data>
        <data name="http://www.3s-software.com/plcopenxml/pouinheritance" handleUnknown="implementation">
          <Inheritance><Extends>CfUnit.FB_TestSuite</Extends></Inheritance>
        </data>
      </addData>
    </pou>
    <pou name="PRG_TEST" pouType="program">
      <interface><localVars><variable name="fbScale"><type><derived name="FB_Scale_Test" /></type></variable></localVars></interface>
      <body><ST><xhtml xmlns="http://www.w3.org/1999/xhtml">CfUnit.RUN();</xhtml></ST></body>
    </pou>
  </pous></types>
</project>
"""


def test_cfunit_suites_of_a_codesys_export_run_as_tcunit_ones(tmp_path: pathlib.Path) -> None:
    from iecoop.testing.tcunit import run_project

    path = tmp_path / "Scale.xml"
    path.write_text(SUITE)
    result = run_project(path, profile="codesys")
    assert [(t.suite, t.name, t.status) for t in result.tests] == [
        ("PRG_TEST.fbScale", "TestGain", "passed"), ("PRG_TEST.fbScale", "TestOffset", "failed")]
    (failure,) = result.tests[1].failures
    line = next(number for number, text in enumerate(SUITE.splitlines(), 1) if "'offset'" in text)
    assert (failure.message, failure.expected, failure.actual) == ("offset", "5", "6")
    assert (failure.file, failure.lineno) == ("Scale.xml", line)  # the assertion's line in the XML file
