"""Validation of built FMUs (used by the build, ``build-fmu``, and the tests).

Host side: never bundled into an FMU (not in :data:`wheel_rail_fmu.build.RUNTIME_MODULES`). fmpy
(the ``host`` extra) is imported when a validation runs.
"""
from __future__ import annotations

import os
import zipfile


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

