"""The reference systems: one wheelset FMU + two contact FMU instances (left, right).

Component names: ``contact_L``, ``contact_R``, ``wheelset`` (stepped in that order by the
Gauss-Seidel master). Connections (``CONNECTIONS``):

    wheelset.xi_L/eta_L/phi_L/N_L -> contact_L.xi/eta/phi/N     (and R)
    contact_L.Fx/Fy/Mz           -> wheelset.Fx_L/Fy_L/Mz_L     (and R)

Both contacts use the track frame (x along the track, y to the right, z down), which is the frame
in which the wheelset models compute creepages and apply forces: no sign flip between wheels.

Communication step (``recommended_step``): the explicit zero-order-hold coupling of a stiff creep
force is stable for h < 2τ (Gauss-Seidel) with τ the shortest creep time constant of the model,
and follows the continuous solution closely for h <~ τ/4. τ grows with speed: for the lateral
wheelset τ = min(m V / (2 f22), I_z V / (2 f11 b0²)), for the driven wheelset τ = I_y V /
(2 f11 r0²), with Kalker's f11 = G c² C11, f22 = G c² C22 (c² = ab) of the nominal contact.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Callable, Mapping

from .master import CoSimulation

CONTACTS = ("L", "R")


def connections(rolling_speed: bool = False) -> list[tuple[str, str]]:
    """The connections of a wheelset and its two contacts; ``rolling_speed``: also the
    wheelset's forward speed to each contact's rolling speed ``V`` (a contact scene with
    falling friction; the driven wheelset's output ``speed``)."""
    out = []
    for s in CONTACTS:
        for v in ("xi", "eta", "phi", "N"):
            out.append((f"wheelset.{v}_{s}", f"contact_{s}.{v}"))
        for v in ("Fx", "Fy", "Mz"):
            out.append((f"contact_{s}.{v}", f"wheelset.{v}_{s}"))
        if rolling_speed:
            out.append(("wheelset.speed", f"contact_{s}.V"))
    return out


CONNECTIONS = connections()


def make_system(wheelset_fmu: str | Path, contact_fmu: str | Path,
                wheelset_params: Mapping | None = None, contact_params: Mapping | None = None,
                contact_fmu_R: str | Path | None = None,
                inputs: Mapping[str, Callable[[float], float]] | None = None,
                scheme: str = "gauss-seidel", initial_exchange: bool = True,
                rolling_speed: bool = False, hold: str = "constant") -> CoSimulation:
    """A wheelset FMU coupled to two instances of a contact FMU (same file unless
    ``contact_fmu_R`` is given); ``rolling_speed``: see :func:`connections`; ``scheme`` and
    ``hold``: :class:`master.CoSimulation`."""
    comps = {"contact_L": contact_fmu, "contact_R": contact_fmu_R or contact_fmu,
             "wheelset": wheelset_fmu}
    starts = {"wheelset": dict(wheelset_params or {}),
              "contact_L": dict(contact_params or {}), "contact_R": dict(contact_params or {})}
    return CoSimulation(comps, connections(rolling_speed) if rolling_speed else CONNECTIONS,
                        starts, inputs=inputs, scheme=scheme, initial_exchange=initial_exchange,
                        hold=hold)


# ------------------------------------------------------------------------------------------------
# Creep time constants and the communication step
# ------------------------------------------------------------------------------------------------
def creep_coefficients_f(N: float = 50e3, r0: float = 0.46, R_rail: float = 0.3,
                         E: float = 210e9, nu: float = 0.28,
                         curvatures: tuple[float, float] | None = None) -> dict[str, float]:
    """Kalker's linear creep coefficients f11, f22, f23, f33 of the nominal contact (conical tread
    on a rail crown of radius ``R_rail``; or, given ``curvatures``, the relative curvatures A, B
    in 1/m of a contact from real profiles), from ``contact_core`` (Hertz + Kalker's table)."""
    import contact_core as cc
    p = (cc.hertz_from_radii(N, r0, math.inf, R_rail, E, nu) if curvatures is None
         else cc.hertz(N, *curvatures, E, nu))
    G = cc.shear_modulus(E, nu)
    c11, c22, c23, c33 = cc.creep_coefficients(p.a / p.b, nu)
    c = math.sqrt(p.a * p.b)
    return {"f11": G * c * c * c11, "f22": G * c * c * c22, "f23": G * c ** 3 * c23,
            "f33": G * c ** 4 * c33, "a": p.a, "b": p.b}


def lateral_time_constant(V: float, m: float = 1500.0, I_z: float = 800.0, b0: float = 0.75,
                          f: Mapping[str, float] | None = None, **contact) -> float:
    """τ = min(m V / (2 f22), I_z V / (2 f11 b0²)) (module docstring), s, with the creep
    coefficients ``f`` (None: :func:`creep_coefficients_f` of ``contact``)."""
    f = f or creep_coefficients_f(**contact)
    return min(m * V / (2 * f["f22"]), I_z * V / (2 * f["f11"] * b0 ** 2))


def driven_time_constant(V: float, I_y: float = 120.0, r0: float = 0.46, **contact) -> float:
    f = creep_coefficients_f(r0=r0, **contact)
    return I_y * V / (2 * f["f11"] * r0 ** 2)


def regularisation_speed(h: float, I_y: float = 120.0, r0: float = 0.46,
                         m_vehicle: float = 0.0, **contact) -> float:
    """The smallest creepage regularisation speed V_reg (``DrivenWheelset``) for which the
    Gauss-Seidel coupling at step h is free of chatter at low speed: the slip-velocity time
    constant V_reg / (2 f11 (r0²/I_y + 1/m)) at least h (monotone up to h = τ, see master.py)."""
    f = creep_coefficients_f(r0=r0, **contact)
    return h * 2.0 * f["f11"] * (r0 ** 2 / I_y + (1.0 / m_vehicle if m_vehicle > 0 else 0.0))


def recommended_step(tau: float, fraction: float = 0.25) -> float:
    """The largest "round" step (1, 2 or 5 times a power of ten) not above ``fraction`` * τ:
    about a quarter of the creep time constant by default (see the module docstring)."""
    target = fraction * tau
    k = math.floor(math.log10(target))
    for mant in (5.0, 2.0, 1.0):
        h = mant * 10.0 ** k
        if h <= target * (1 + 1e-12):
            return float(f"{h:.12g}")
    return float(f"{10.0 ** k:.12g}")
