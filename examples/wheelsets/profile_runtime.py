"""The package the real-profile wheelset models run on: ``contact_core``'s contact geometry.

Inside a real-profile wheelset FMU (``build.build_profile_wheelsets``) the package ``wheelsets``
is a sub-package of the FMU's own bundle package, next to its copy of ``contact_core`` and the
contact-geometry table it ships (:data:`TABLE_FILE`, :data:`TABLE_INFO`): those are the ones to
use, never the host's. In a source checkout (building, testing, in-process use) ``contact_core``
is the installed package and there is no bundled table (:data:`BUNDLE` is None).
"""
from __future__ import annotations

from pathlib import Path

if "." in __package__:  # <bundle>.wheelsets
    from ..contact_core import geometry
    #: The FMU's bundle folder (its contact-geometry table and the table's description).
    BUNDLE: Path | None = Path(__file__).resolve().parent.parent
else:
    from contact_core import geometry
    BUNDLE = None

#: File names of the bundled contact-geometry table (``ContactTable.save``) and of its
#: description (JSON: the wheelset's nominal rolling radius and the set-up it was built for).
TABLE_FILE = "contact_table.npz"
TABLE_INFO = "contact_table.json"

__all__ = ["BUNDLE", "TABLE_FILE", "TABLE_INFO", "geometry"]
