"""The real-profile systems: one real-profile wheelset FMU + four contact FMU instances, one per
patch (left tread, left flange, right tread, right flange).

Component names: ``contact_Lt``, ``contact_Lf``, ``contact_Rt``, ``contact_Rf``, ``wheelset``
(stepped in that order by the Gauss-Seidel master, ``master.py``). Connections
(:func:`connections`), for each patch P:

    wheelset.xi_P/eta_P/phi_P/N_P/A_P/B_P -> contact_P.xi/eta/phi/N/A/B
    contact_P.Fx/Fy/Mz                    -> wheelset.Fx_P/Fy_P/Mz_P

The contact FMUs are of the scene ``vehicle`` (geometry inputs A, B at every step); each computes
its patch in the patch's contact frame, and the wheelset turns the forces into the track frame
(``profile_dynamics``). An absent or unloaded patch has N = 0: its contact FMU returns zero forces.
Each instance may have its own start values (``contact_params`` for all, ``patch_params`` per
patch), e.g. ``method`` and its grid for the flange patches.

Communication step: as for the conical wheelsets (``systems``), at most a quarter of the shortest
creep time constant, here with Kalker's coefficients of the centred tread contact
(:func:`centred_contact`, :func:`recommended_step`).

Contact methods (:func:`contact_start`): ``"table"``, the ``vehicle`` FMU's default, on every
patch (the table hands a patch with a/b outside its axes, 0.1 ... 10, e.g. a patch on the flange
face, to the exact method, as it always does); or ``"exact"`` on every patch, on a small grid
without extrapolation (:data:`EXACT_SMALL`) to keep the runs affordable.
"""
from __future__ import annotations

import io
import json
import math
import zipfile
from pathlib import Path
from typing import Callable, Mapping

from . import systems
from .master import CoSimulation
from .profile_dynamics import PATCH_INPUTS, PATCH_OUTPUTS, PATCHES
from .profile_runtime import TABLE_FILE, TABLE_INFO, geometry

#: Start values of a ``vehicle`` contact FMU for Kalker's exact theory on a small grid, one grid
#: (no extrapolation to zero element size).
EXACT_SMALL = {"method": "exact", "mx": 16, "my": 16, "extrapolate": False}
#: Contact methods of the real-profile runs and the contact FMUs' start values for them.
CONTACT_METHODS = {"table": {"method": "table"}, "exact": EXACT_SMALL}


def connections() -> list[tuple[str, str]]:
    """The connections of a real-profile wheelset and its four contacts."""
    out = []
    for p in PATCHES:
        out += [(f"wheelset.{v}_{p}", f"contact_{p}.{v}") for v in PATCH_OUTPUTS]
        out += [(f"contact_{p}.{v}", f"wheelset.{v}_{p}") for v in PATCH_INPUTS]
    return out


CONNECTIONS = connections()


def make_system(wheelset_fmu: str | Path, contact_fmu: str | Path,
                wheelset_params: Mapping | None = None, contact_params: Mapping | None = None,
                patch_params: Mapping[str, Mapping] | None = None,
                inputs: Mapping[str, Callable[[float], float]] | None = None) -> CoSimulation:
    """A real-profile wheelset FMU coupled to four instances of a ``vehicle`` contact FMU
    (Gauss-Seidel: the contacts, then the wheelset); ``contact_params`` start values of every
    contact, ``patch_params[P]`` of the patch P's on top of them."""
    comps = {f"contact_{p}": contact_fmu for p in PATCHES}
    comps["wheelset"] = wheelset_fmu
    starts = {"wheelset": dict(wheelset_params or {})}
    for p in PATCHES:
        starts[f"contact_{p}"] = {**(contact_params or {}), **(patch_params or {}).get(p, {})}
    return CoSimulation(comps, CONNECTIONS, starts, inputs=inputs)


def contact_start(method: str) -> dict:
    """Start values of the four contact FMUs for ``method`` (:data:`CONTACT_METHODS`)."""
    if method not in CONTACT_METHODS:
        raise ValueError(f"method={method!r} is unknown: allowed {list(CONTACT_METHODS)}")
    return dict(CONTACT_METHODS[method])


def bundled_table(wheelset_fmu: str | Path):
    """The contact-geometry table a real-profile wheelset FMU ships, and its wheels' nominal
    rolling radius (m): what the FMU runs on, read from its archive."""
    with zipfile.ZipFile(wheelset_fmu) as z:
        names = [n for n in z.namelist() if n.endswith("/" + TABLE_FILE)]
        if len(names) != 1:
            raise ValueError(f"{wheelset_fmu} holds {len(names)} contact-geometry tables: "
                             "expected one")
        table = geometry.load_table(io.BytesIO(z.read(names[0])))
        info = json.loads(z.read(names[0][:-len(TABLE_FILE)] + TABLE_INFO))
    return table, float(info["nominal_radius"])


def centred_contact(table, axle_load: float = 100e3) -> dict[str, float]:
    """The centred wheelset's tread contact from the contact-geometry ``table``: relative
    curvatures ``A``, ``B`` (1/m), rolling radius ``r`` (m), half distance between the contact
    points ``b0`` (m), and Kalker's coefficients (``systems.creep_coefficients_f``) at the load
    of half the ``axle_load`` (N) with the table's E and ν."""
    c = {q: float(table.column(f"right.0.{q}", 0.0)) for q in ("A", "B", "radius", "y")}
    f = systems.creep_coefficients_f(N=0.5 * axle_load, E=table.E, nu=table.nu,
                                     curvatures=(c["A"], c["B"]))
    return {"A": c["A"], "B": c["B"], "r": c["radius"], "b0": c["y"], **f}


def lateral_time_constant(table, V: float, m: float = 1500.0, I_z: float = 800.0,
                          axle_load: float = 100e3) -> float:
    """``systems.lateral_time_constant`` of the centred contact, s."""
    c = centred_contact(table, axle_load)
    return systems.lateral_time_constant(V, m, I_z, c["b0"], c)


#: Largest communication step of the real-profile runs, s: a flange impact changes the flange
#: patch's normal load within a few milliseconds, and its friction, held over a longer step, can
#: exceed what the axle load holds down (the wheelset FMU then stops with an error).
MAX_STEP = 5e-4


def recommended_step(table, V: float, **wheelset) -> float:
    """A quarter of :func:`lateral_time_constant` rounded down to a multiple of 0.1 ms (finer
    than ``systems.recommended_step``'s 1-2-5 steps, which would halve the step near 30 m/s; below
    0.1 ms ``systems.recommended_step``), at most :data:`MAX_STEP`."""
    tau = lateral_time_constant(table, V, **wheelset)
    if not math.isfinite(tau) or tau <= 0.0:
        raise ValueError(f"no creep time constant at V={V!r}")
    h = 1e-4 * math.floor(0.25 * tau / 1e-4 + 1e-9)
    return min(round(h, 12), MAX_STEP) if h > 0.0 else systems.recommended_step(tau)
