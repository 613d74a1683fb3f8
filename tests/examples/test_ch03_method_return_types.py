"""Chapter 3: structs and FBs come back as copies, interfaces and references as the original."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from iecoop_examples.ch03_method_return_types import Counter, ISample, Main, Sample, SampleData, main
from iecoop import T, adr
from iecoop.runtime import Runtime, Task


def test_main_cycle_by_cycle_with_a_set_in_the_middle() -> None:
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for cycle in range(1, 21):
        program.set_cmd = cycle == 10
        rt.run(cycles=1)
        expected = cycle if cycle < 10 else 100 + cycle - 9
        assert program.single_get == program.st_get.n_var == program.st_copy.n_var == expected
        assert program.st_get.b_var is (cycle >= 10)  # the Set copied the whole struct
        assert program.fb_copy.count_value == cycle
        assert program.set_cmd is False


def test_a_returned_struct_is_a_copy_both_ways() -> None:
    sample = Sample()
    sample.increment()
    st_copy = sample.get_struct()
    assert st_copy == SampleData(b_var=False, n_var=1)
    assert adr(st_copy) != adr(sample, "st_local")
    st_copy.n_var = 99
    assert sample.st_local.n_var == 1
    sample.increment()
    assert st_copy.n_var == 99


def test_a_returned_interface_is_the_instance_itself() -> None:
    sample = Sample()
    itf = sample.get_interface()
    assert isinstance(itf, ISample)
    assert itf == sample and adr(itf) == adr(sample)
    assert [itf.increment() for _ in range(3)] == [1, 2, 3]
    assert sample.st_local.n_var == 3


def test_a_returned_function_block_is_a_frozen_copy() -> None:
    sample = Sample()
    sample.increment()
    sample.increment()
    fb_copy = sample.get_counter()
    assert isinstance(fb_copy, Counter)
    assert adr(fb_copy) != adr(sample, "fb_calls")
    sample.increment()
    assert (fb_copy.count_value, sample.fb_calls.count_value) == (2, 3)
    fb_copy.count()
    assert (fb_copy.count_value, sample.fb_calls.count_value) == (3, 3)


def test_the_reference_property_designates_the_blocks_own_struct() -> None:
    sample = Sample()
    assert adr(sample.my_prop) == adr(sample, "st_local")
    sample.my_prop.n_var = 5  # one member, written through the reference
    assert sample.st_local.n_var == 5
    assert sample.increment() == 6


def test_the_set_accessor_copies_the_whole_struct_in() -> None:
    sample, source = Sample(), SampleData(b_var=True, n_var=100)
    sample.my_prop = source
    assert sample.st_local == source
    assert adr(sample.my_prop) != adr(source)
    source.n_var = 7
    assert sample.st_local.n_var == 100


@given(st.integers(min_value=0, max_value=200), st.integers(min_value=-32768, max_value=32767))
def test_the_int_member_wraps_and_the_copies_follow(increments: int, start: int) -> None:
    sample = Sample()
    sample.my_prop = SampleData(n_var=start)
    for _ in range(increments):
        sample.increment()
    expected = (start + increments + 32768) % 65536 - 32768
    assert sample.my_prop.n_var == sample.get_struct().n_var == expected
    assert sample.get_counter().count_value == increments


def test_main_prints_five_cycles_and_the_copy(capsys: pytest.CaptureFixture[str]) -> None:
    main()
    out = capsys.readouterr().out
    assert "    4  True          101         101          101              4" in out
    assert "fbSample.MyProp.nVar is still 102" in out
