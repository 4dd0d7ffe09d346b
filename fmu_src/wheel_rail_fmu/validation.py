"""Validation helpers for built FMUs (used by ``build_fmu.py``, the tests and the benchmark).

fmpy is imported lazily: these helpers are bundled into the FMU but never run inside it.
"""
from __future__ import annotations

import os
import zipfile
from typing import Any


def validate(path: str | os.PathLike) -> list[str]:
    """fmpy's full validation (schema, names, ModelStructure, start values, units), plus a check
    that every Real input/parameter/output declares a unit defined in UnitDefinitions."""
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    problems = list(validate_fmu(str(path)))
    if problems:
        return problems
    md = read_model_description(str(path))
    for v in md.modelVariables:
        if v.type == "Real" and v.unit is None:
            problems.append(f"Real variable {v.name!r} has no unit")
    with zipfile.ZipFile(path) as z:
        names = set(z.namelist())
    ident = md.coSimulation.modelIdentifier
    for required in ("modelDescription.xml", "resources/slavemodule.txt",
                     "resources/requirements.txt", f"binaries/linux64/{ident}.so"):
        if required not in names:
            problems.append(f"the archive lacks {required}")
    return problems


def variables(path: str | os.PathLike) -> dict[str, dict[str, Any]]:
    """The FMU's variables: name -> {type, causality, variability, initial, unit, start,
    valueReference, description}."""
    from fmpy import read_model_description

    md = read_model_description(str(path))
    return {v.name: {"type": v.type, "causality": v.causality, "variability": v.variability,
                     "initial": v.initial, "unit": v.unit, "start": v.start,
                     "valueReference": v.valueReference, "description": v.description}
            for v in md.modelVariables}


def names_by_causality(path: str | os.PathLike) -> dict[str, set[str]]:
    """``{"input": {...}, "output": {...}, "parameter": {...}}`` of the FMU at ``path``."""
    out: dict[str, set[str]] = {}
    for name, v in variables(path).items():
        out.setdefault(v["causality"], set()).add(name)
    return out
