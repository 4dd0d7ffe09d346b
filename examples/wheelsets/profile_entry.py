"""Slave module of a real-profile wheelset FMU: it loads the code the FMU bundles, under its own
name.

The build (``wheelsets.build.build_profile_wheelsets``) copies this file into the FMU as
``resources/<class>_<digest>.py`` (named in ``resources/slavemodule.txt``) next to the bundle
package ``resources/_wheelset_profiles_<digest>/``: the modules of ``wheelsets`` the models
need, a copy of ``contact_core`` (without the exact theory's table, which a wheelset never
evaluates) and the contact-geometry table with its description. ``<digest>`` is the SHA-256 of
the bundle's files (``wheel_rail_fmu.entry.bundle_digest``), so the FMU runs the code it
bundles whatever the host has imported (no ``contact_core`` or ``wheelsets`` in ``sys.modules``
is used), and FMUs share modules only when their code is the same byte for byte. pythonfmu's
Python side is found by name, as for every pythonfmu-built FMU (the host's, else the FMU's
``resources/pythonfmu``).

Only the standard library is used here: nothing else can be imported before the bundle is.
"""
from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path

#: The bundle package's name is this prefix and the digest.
PREFIX = "_wheelset_profiles_"


def load_slave_class(resources: Path, module_name: str) -> type:
    """Import the bundle next to the slave module ``module_name`` (``<class>_<digest>``) and
    return the slave class it names."""
    class_name, _, digest = module_name.rpartition("_")
    name = PREFIX + digest
    if name not in sys.modules:
        root = resources / name
        spec = importlib.util.spec_from_file_location(
            name, root / "__init__.py", submodule_search_locations=[str(root)])
        package = importlib.util.module_from_spec(spec)
        sys.modules[name] = package
        try:
            spec.loader.exec_module(package)
        except BaseException:
            del sys.modules[name]
            raise
    return getattr(importlib.import_module(f"{name}.wheelsets.profile_fmus"), class_name)


# Loaded as an FMU's slave module (a top-level module), not as wheelsets.profile_entry.
if not __package__:
    _slave = load_slave_class(Path(__file__).resolve().parent, __name__)
    globals()[_slave.__name__] = _slave
