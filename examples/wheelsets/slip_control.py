"""A slip controller for the driven wheelset: PI on the creepage, cutting the drive torque.

With falling friction (the contact scene ``traction_falling``) the creep-force curve has a
peak, the adhesion limit, beyond which the force falls as the slip grows: a drive torque above
it makes the wheel run away into macro-slip, since every increase of the slip lowers the force
that holds it back (Polach 2005, running on the adhesion limit; Iwnicki (ed.), *Handbook of
Railway Vehicle Dynamics* (2006), on traction and adhesion control). A traction controller keeps
the creepage near the peak by cutting the torque. This one is the simplest form of it, a PI
controller on the excess creepage e = |ξ| - ξ* (ξ* = ``xi_target``):

    cut = clamp(k_p e + ∫ k_i e dt, 0, |T|),     T_applied = T - sign(T) cut,

the integral held in [0, |T|] (no wind-up: the integrator clamped to the actuator's range, one of
the anti-windup schemes of K. J. Åström & T. Hägglund, *Advanced PID Control*, ISA 2006, on
integrator windup; K. J. Åström & R. M. Murray, *Feedback Systems*, Princeton 2008, ch. 10), so
that below ξ* the torque demanded is applied unchanged and above it the cut grows until the
creepage comes back to ξ*.

Gains (:func:`gains`): near the peak the force's slope is small and the wheelset's creepage
obeys d|ξ|/dt = r0/(V I_y) (T_applied - r0 ΣFx) (``wheelset_dynamics.DrivenWheelset``), an
integrator of gain g = r0/(V I_y); with the controller the excess creepage follows
ë + g k_p ė + g k_i e = 0, a second-order system of natural frequency ω = √(g k_i) and damping
g k_p/(2ω). On the falling branch the force adds an unstable pole of about g r0 |dΣFx/dξ|,
which g k_p must exceed. The defaults take ω = 20 rad/s, critical damping. (The plant is derived
here from the driven wheelset's I_y Ω̇ = T − r0 ΣFx with ξ = (V − Ω r0)/V; the gains are the
pole placement of PI control of a first-order plant, Åström & Murray 2008, ch. 10, here with
the plant's own pole at zero.)
"""
from __future__ import annotations

import math
from dataclasses import dataclass


def gains(V: float, I_y: float, r0: float, omega: float = 20.0,
          damping: float = 1.0) -> tuple[float, float]:
    """(k_p in N m, k_i in N m/s) placing the closed loop's poles at natural frequency
    ``omega`` (rad/s) and ``damping`` for a wheelset at speed V (module docstring)."""
    g = r0 / (V * I_y)
    return 2.0 * damping * omega / g, omega * omega / g


@dataclass
class SlipController:
    """PI controller on the creepage (module docstring): ``xi_target`` (1, > 0), ``k_p``
    (N m per unit creepage), ``k_i`` (N m per unit creepage and second)."""

    xi_target: float
    k_p: float
    k_i: float
    integral: float = 0.0

    def __post_init__(self) -> None:
        for name in ("xi_target", "k_p", "k_i"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ValueError(f"{name}={v!r} is out of range: allowed 0 <= {name} < inf")

    def torque(self, demand: float, xi: float, h: float) -> float:
        """The torque (N m) applied over the next step of length ``h`` (s) for the torque
        ``demand`` (N m) at the creepage ``xi``."""
        e = abs(xi) - self.xi_target
        top = abs(demand)
        self.integral = min(top, max(0.0, self.integral + self.k_i * e * h))
        cut = min(top, max(0.0, self.k_p * e + self.integral))
        return demand - math.copysign(cut, demand)
