"""The libraries an export uses: referenced from its ``.plcproj``, never written into it.

A class of a library iecoop ships (a class of ``iecoop.libraries.tc2_mc2`` is Tc2_MC2's) is on the PLC
already: the export names the library in a ``<PlaceholderReference>`` of the project file, as TwinCAT
XAE writes one, and loading the folder binds it again (``st.load``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from iecoop.gvl import GlobalVariables
from iecoop.libraries import KNOWN, Library
from iecoop.st.write.files import _NL, _attr, _xml_text, guid
from iecoop.st.write.model import ClassMeta, _uses

__all__ = ["plcproj", "used_libraries"]

#: where iecoop's own standard blocks live in a TwinCAT project
_STANDARD = "Tc2_Standard"


def used_libraries(metas: Iterable[ClassMeta]) -> list[Library]:
    """The shipped libraries whose classes ``metas`` use, in the order they are first used.

    iecoop's standard blocks (TON, R_TRIG...) need no reference on their own: every PLC project has them
    and the ST reader knows them. Beside another library they are named too (as Tc2_Standard).
    """
    by_module = {library.module: library for library in KNOWN}
    standard = next(library for library in KNOWN if library.name == _STANDARD)
    found: list[Library] = []
    for meta in metas:
        for obj in _uses(meta):
            module = str(getattr(type(obj) if isinstance(obj, GlobalVariables) else obj, "__module__", "") or "")
            library = by_module.get(module) or (standard if module.split(".")[:2] == ["iecoop", "stdlib"] else None)
            if library is not None and library not in found:
                found.append(library)
    return found if any(library is not standard for library in found) else []


def plcproj(name: str, files: Sequence[str], libraries: Sequence[Library], others: Sequence[str] = ()) -> str:
    """A TwinCAT ``.plcproj`` that compiles ``files``, holds ``others`` (task files) and references ``libraries``
    by placeholder and namespace."""
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        '<Project DefaultTargets="Build" xmlns="http://schemas.microsoft.com/developer/msbuild/2003">',
        "  <PropertyGroup>",
        f"    <ProjectGuid>{guid(name, 'plcproj')}</ProjectGuid>",
        f"    <Name>{_attr(name)}</Name>",
        "  </PropertyGroup>",
        "  <ItemGroup>",
    ]
    for file in files:
        lines += [f'    <Compile Include="{_attr(file)}">', "      <SubType>Code</SubType>", "    </Compile>"]
    for file in others:
        lines += [f'    <None Include="{_attr(file)}">', "      <SubType>Code</SubType>", "    </None>"]
    lines += ["  </ItemGroup>", "  <ItemGroup>"]
    for library in libraries:
        lines += [
            f'    <PlaceholderReference Include="{_attr(library.name)}">',
            f"      <DefaultResolution>{_attr(library.name)}, * ({_attr(library.company)})</DefaultResolution>",
            f"      <Namespace>{_attr(library.namespace)}</Namespace>",
            "    </PlaceholderReference>",
        ]
    lines += ["  </ItemGroup>", "</Project>"]
    return _NL.join(lines) + _NL
