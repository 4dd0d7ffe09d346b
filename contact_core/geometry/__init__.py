"""Contact geometry of a wheelset on a track from real wheel and rail profiles.

Profiles (:mod:`.profiles`), the wheelset on its track (:mod:`.track`), the contact search
(:mod:`.search`), creepages from the wheelset's velocities (:mod:`.kinematics`), the load sharing
between patches and a wheel's forces (:mod:`.loads`), and the contact-geometry table of vehicle
codes (:mod:`.table`).

Frames and signs: the track frame has x along the track, y to the right, z down (the reference
wheelset models' and CONTACT's module 1); the left wheel is at y < 0. Profiles are kept in the
canonical right-hand form (y towards the field side, z down); the left side is their mirror image.
A patch's contact frame is the track frame turned by its contact angle δ about x: x along the
track (the rolling direction), y in the contact plane, z along the normal into the rail.
Creepages are the wheel's particle velocity relative to the rail over the rolling speed and the
forces are those of the rail on the wheel (contact_core's convention, Kalker's); CONTACT prints
the negatives of both.
"""
from .kinematics import Creepage, WheelsetMotion, creepages
from .loads import (PatchSolution, WheelSolution, normal_loads, patch_geometry, share_load,
                    solve_wheel)
from .profiles import (Profile, ProfileFunction, read_profile, read_simpack, read_yz_table,
                       shipped_profile, write_simpack, write_yz_table)
from .search import (ContactPoint, WheelContact, WheelsetContact, WheelsetPosition,
                     contact_search, rigid_roll, touch_height, wheel_contact)
from .table import ContactTable, TablePatch, contact_table, load_table
from .track import SIDES, Track, Wheelset, WheelsetOnTrack, benchmark_model

__all__ = [
    "ContactPoint", "ContactTable", "Creepage", "PatchSolution", "Profile", "ProfileFunction",
    "SIDES", "TablePatch", "Track", "WheelContact", "WheelSolution", "Wheelset",
    "WheelsetContact", "WheelsetMotion", "WheelsetOnTrack", "WheelsetPosition",
    "benchmark_model", "contact_search", "contact_table", "creepages", "load_table",
    "normal_loads", "patch_geometry", "read_profile", "read_simpack", "read_yz_table",
    "rigid_roll", "share_load", "shipped_profile", "solve_wheel", "touch_height", "wheel_contact",
    "write_simpack", "write_yz_table",
]
