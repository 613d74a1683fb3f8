"""Run Python code against the Structured Text of its own classes: export, load back, rebind.

``round_trip(module)`` writes the module's declared classes as Structured
Text (:func:`iecoop.st.export`), reads the files back with
:func:`iecoop.st.load`, and for the duration of the ``with`` binds each name
the module shares with the loaded text to the loaded object. Code that looks
its classes up in the module at call time (the module's own ``main()``, a
test that writes ``module.Conveyor()``) then runs the ST, and can be
compared with a run of the Python original. A PROGRAM is bound to its class
(``st.load`` gives its single instance), so ``Main()`` still builds one. At
exit every name is restored.

Names imported elsewhere before the ``with`` (``from plant import Conveyor``)
keep the Python class: look them up through the module. A test comparing
the two runs of a module's ``main()``::

    python_output = capture(plant.main)
    with round_trip(plant, format="twincat"):
        assert capture(plant.main) == python_output

The documentation page *Testing your function blocks* runs one.
"""

from __future__ import annotations

import contextlib
import tempfile
import types
from collections.abc import Iterator
from typing import Any

from iecoop.metadata import kind_of
from iecoop.gvl import GlobalVariables, register_global_list

__all__ = ["FORMATS", "load_back", "loaded_names", "rebound", "round_trip"]

#: The export formats ``st.load`` reads back (PLCopen XML is written only).
FORMATS = ("twincat", "st")


def loaded_names(loaded: types.ModuleType) -> dict[str, Any]:
    """The objects the loaded text itself declares, by ST name: PROGRAMs as their class, GVLs as their instance.

    Names the generated Python imports (``INT``, ``FunctionBlock``, ``TON``)
    are left out.
    """
    found: dict[str, Any] = {}
    for name, value in vars(loaded).items():
        instance = not isinstance(value, (type, types.FunctionType))  # a PROGRAM's or a GVL's single instance
        owner = type(value) if instance else value
        if name.startswith("__") or getattr(owner, "__module__", None) != loaded.__name__:
            continue
        found[name] = owner if instance and kind_of(owner) == "program" else value
    return found


@contextlib.contextmanager
def rebound(module: types.ModuleType, loaded: types.ModuleType) -> Iterator[list[str]]:
    """Bind the names ``module`` shares with ``loaded`` to the loaded objects; restore them at exit.

    Yields the names rebound, in the module's order.
    """
    replacements = loaded_names(loaded)
    names = [name for name in vars(module) if name in replacements]
    saved = {name: vars(module)[name] for name in names}
    try:
        for name in names:
            setattr(module, name, replacements[name])
        yield names
    finally:
        for name, value in saved.items():
            setattr(module, name, value)
            if isinstance(value, GlobalVariables):
                # The loaded list took the name in the registry VAR_EXTERNAL looks in: give it back.
                register_global_list(value)


def load_back(module: types.ModuleType, format: str = "twincat") -> types.ModuleType:
    """Export ``module``'s declared classes (``format`` "twincat" or "st") to a scratch folder and ``st.load`` it.

    The loaded POUs belong to ``module``'s package (``st.load(package=...)``),
    as the Python classes did, so the module's code still reaches their
    INTERNAL members.

    Raises what :func:`~iecoop.st.export` raises for a statement outside the
    translated subset, and what :func:`~iecoop.st.load` raises for text it
    cannot read.
    """
    from iecoop import st

    if format not in FORMATS:
        raise ValueError(f"round_trip format must be one of {', '.join(map(repr, FORMATS))}, got {format!r}")
    with tempfile.TemporaryDirectory(prefix="iecoop_round_trip_") as folder:
        st.export(module, folder, format=format)
        return st.load(folder, package=module.__name__.partition(".")[0])


@contextlib.contextmanager
def round_trip(*modules: types.ModuleType, format: str = "twincat") -> Iterator[list[types.ModuleType]]:
    """:func:`load_back` each module and :func:`rebound` its names for the ``with``; yields the loaded modules.

    Each module is loaded on its own, so two modules may declare the same ST name.
    """
    loaded = [load_back(module, format) for module in modules]
    with contextlib.ExitStack() as stack:
        for module, back in zip(modules, loaded):
            stack.enter_context(rebound(module, back))
        yield loaded
