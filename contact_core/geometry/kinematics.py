"""Creepages of a contact patch from the wheelset's velocities.

Definitions (Kalker 1979, "Review of wheel–rail rolling contact theories", sec. 2, eqs 1–2; Kalker
1990, *Three-Dimensional Elastic Bodies in Rolling Contact*): the creepages are the rigid
slip of the wheel over the rail at the contact point, divided by the rolling speed V — the
velocity of the wheel's material particle at the contact point relative to the rail's, in the
contact frame, and the relative angular velocity about the contact normal:

    ξ = v_x / V,   η = v_y / V,   φ = ω_n / V   (1/m),

with contact_core's signs: wheel relative to rail, contact frame x along the track (the rolling
direction), y in the contact plane (the track y axis turned by δ about x), z along the contact
normal into the rail (n = (0, −sin δ, cos δ) in the track frame). The forces that
:func:`contact_core.solve` returns for them are those of the rail on the wheel in the same frame.

Velocities (rigid-body kinematics of the wheelset, rail at rest on straight track; e.g. Knothe &
Stichel 2017, *Rail Vehicle Dynamics*; Shabana, Zaazaa & Sugiyama 2008, *Railroad Vehicle
Dynamics*): the particle at the contact point P moves with v = v_O + ω × (P − O), O the wheelset
centre with velocity (V, ẏ, ż) in the track frame, and the wheelset's angular velocity for its
roll–yaw–pitch Euler angles (:mod:`.track`)

    ω = φ̇ x̂ + ψ̇ R_x(φ) ẑ + Ω R_x(φ) R_z(ψ) ŷ,

Ω the pitch rate (the spin about the axle, negative when rolling forwards: −V/r0 for free rolling
at the nominal radius). Spin: ω·n includes the contact angle's part −Ω sin δ (Kalker 1979, fig.
2c: the conicity's spin) and the yaw rate's ψ̇ cos δ.

Rolling speed: V = (|V_t| + |V_w|)/2, the mean of the speeds at which rail and wheel surfaces
move through the contact (Vollebregt, CONTACT user guide, module 1, "VELOC"): V_t the x
velocity of the wheel particle without the pitch rotation (the speed of the contact point along
the rail), V_w the x velocity of the pitch rotation alone.

CONTACT's own output (module 1) takes rail relative to wheel and forces on the rail: its creepages
and forces are the negatives of these in the same contact frame.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .search import ContactPoint, WheelsetPosition


@dataclass(frozen=True)
class WheelsetMotion:
    """The wheelset's velocities in the track frame: ``speed`` V (m/s) of its centre along the
    track; ``pitch_rate`` Ω (rad/s; None: free rolling, −V/r0); ``lateral_velocity`` ẏ and
    ``vertical_velocity`` ż (m/s); ``roll_rate`` φ̇ and ``yaw_rate`` ψ̇ (rad/s)."""

    speed: float
    pitch_rate: float | None = None
    lateral_velocity: float = 0.0
    vertical_velocity: float = 0.0
    roll_rate: float = 0.0
    yaw_rate: float = 0.0

    def __post_init__(self) -> None:
        for name in ("speed", "lateral_velocity", "vertical_velocity", "roll_rate", "yaw_rate"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name}={getattr(self, name)!r} is not finite")
        if self.pitch_rate is not None and not math.isfinite(self.pitch_rate):
            raise ValueError(f"pitch_rate={self.pitch_rate!r} is not finite")


@dataclass(frozen=True)
class Creepage:
    """Creepages ξ, η (–) and spin φ (1/m) of one patch, and the rolling speed V (m/s)."""

    xi: float
    eta: float
    phi: float
    speed: float


def creepages(position: WheelsetPosition, point: ContactPoint, motion: WheelsetMotion,
              nominal_radius: float) -> Creepage:
    """Creepages of the patch ``point`` of the wheelset at ``position`` moving with ``motion``
    (module docstring), for the wheel's particle on its undeformed surface at the patch's
    reference point (as CONTACT's module 1); ``nominal_radius`` r0 of the wheels (the wheelset
    centre's height and the free-rolling pitch rate)."""
    phi_, psi = position.roll, position.yaw
    cr, sr, cy, sy = math.cos(phi_), math.sin(phi_), math.cos(psi), math.sin(psi)
    omega_pitch = (-motion.speed / nominal_radius if motion.pitch_rate is None
                   else motion.pitch_rate)
    # axes of the Euler rotations in the track frame
    z_after_roll = np.array([0.0, -sr, cr])                    # R_x(φ) ẑ
    axle = np.array([-sy, cr * cy, sr * cy])                   # R_x(φ) R_z(ψ) ŷ
    w_pitch = omega_pitch * axle
    w = np.array([motion.roll_rate, 0.0, 0.0]) + motion.yaw_rate * z_after_roll + w_pitch
    rho = np.array([point.x, point.y, point.wheel_z]) - np.array(
        [0.0, position.y, position.z - nominal_radius])
    v = np.array([motion.speed, motion.lateral_velocity, motion.vertical_velocity]) \
        + np.cross(w, rho)
    v_roll = float(np.cross(w_pitch, rho)[0])
    speed = 0.5 * (abs(float(v[0]) - v_roll) + abs(v_roll))
    if speed == 0.0:
        raise ValueError("the rolling speed is zero: creepages are undefined")
    cd, sd = math.cos(point.delta), math.sin(point.delta)
    vx, vy = float(v[0]), cd * float(v[1]) + sd * float(v[2])
    wn = -sd * float(w[1]) + cd * float(w[2])
    return Creepage(vx / speed, vy / speed, wn / speed, speed)
