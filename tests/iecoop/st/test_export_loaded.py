"""What a loaded module holds goes back out: null interface references and their defaults."""

from __future__ import annotations

import pytest

pytest.importorskip("blark")

from iecoop import st  # noqa: E402

SOURCE = """
INTERFACE ILogger
END_INTERFACE
METHOD Log : BOOL
VAR_INPUT
    text : STRING;
END_VAR
END_METHOD

FUNCTION_BLOCK Pump
VAR
    logger : ILogger;
    nLogged : INT;
END_VAR
END_FUNCTION_BLOCK
METHOD FB_init : BOOL
VAR_INPUT
    bInitRetains : BOOL;
    bInCopyCode : BOOL;
    itfLogger : ILogger;
END_VAR
logger := itfLogger;
END_METHOD
METHOD Start : BOOL
IF logger <> 0 THEN
    logger.Log('start');
    nLogged := nLogged + 1;
END_IF
logger := 0;
Start := TRUE;
IF Start THEN
    nLogged := nLogged + 10;
END_IF
END_METHOD
"""


def test_a_loaded_block_with_interface_inputs_and_null_assignments_is_written_back() -> None:
    loaded = st.load(SOURCE)
    text = st.dump(loaded)
    assert "itfLogger : ILogger;" in text  # the null default is the type's zero: no initial value
    assert "logger := 0;" in text
    again = st.load(text)
    pump = again.Pump()
    assert pump.Start() is True and pump.nLogged == 10
    assert "VAR\n    Start" not in text and "VAR\n    FB_init" not in text  # no local named like its member
    assert st.dump(again) == text
