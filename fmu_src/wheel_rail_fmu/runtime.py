"""The packages the FMU's runtime code runs on: ``contact_core`` and pythonfmu's Python side.

Inside an FMU, ``wheel_rail_fmu`` is a sub-package of the build's own package (see
:mod:`wheel_rail_fmu.entry`) next to its copies of ``contact_core`` and ``pythonfmu``: those are
the ones to use, never the host's. In a source checkout (building, testing) they are the
installed packages.
"""
from __future__ import annotations

import sys

if "." in __package__:  # <bundle>.wheel_rail_fmu
    from .. import contact_core, pythonfmu
else:
    import contact_core
    import pythonfmu

__all__ = ["contact_core", "load_notices", "pythonfmu"]


def load_notices() -> tuple[str, ...]:
    """What the FMU's loader had to say about this bundle (``LOAD_NOTICES`` of the bundle
    package, see :mod:`wheel_rail_fmu.entry`); empty in a source checkout."""
    return tuple(getattr(sys.modules.get(__package__.rpartition(".")[0]), "LOAD_NOTICES", ()))
