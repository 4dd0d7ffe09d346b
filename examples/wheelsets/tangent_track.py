"""Tangent-track wheelset FMU: lateral displacement y and yaw ψ, primary suspension to a frame
moving at constant speed V (pythonfmu ``Fmi2Slave``).

Equations and sign conventions: ``wheelset_dynamics`` (module docstring), after Wickens,
*Fundamentals of Rail Vehicle Dynamics* (2003) (the single wheelset with lateral and yaw restraint,
conical wheels, linearised creepages), and Iwnicki (ed.), *Handbook of Railway Vehicle Dynamics*
(2006) (wheelset stability). Four states (y, ψ, ẏ, ψ̇); inputs the creep forces and spin moments of the left and
right contacts; outputs their creepages ξ, η, spin φ and normal loads N, plus the states.

Parameters (SI; defaults): V = 30 m/s, r0 = 0.46 m, b0 = 0.75 m, conicity λ = 0.15,
m = 1500 kg, I_z = 800 kg m², axle load 100 kN (50 kN per wheel), k_y = 1 MN/m,
k_ψ = 2 MN m/rad, no primary damping, no flange contact (flange_gap = k_flange = 0), initial
state y0, psi0, vy0, dpsi0 (default y0 = 1 mm).
"""
from __future__ import annotations

from .wheelset_dynamics import LateralParams, LateralState, LateralWheelset, param_fields
from .wheelset_fmu_common import WheelsetSlaveBase

_CURVE_ONLY = ("R", "L_transition")
INITIAL_STATE = (("y0", 1e-3, "initial lateral displacement, m"),
                 ("psi0", 0.0, "initial yaw angle, rad"),
                 ("vy0", 0.0, "initial lateral velocity, m/s"),
                 ("dpsi0", 0.0, "initial yaw rate, rad/s"))
STATE_OUTPUTS = (("y", "lateral displacement of the wheelset, m (+ right)"),
                 ("psi", "yaw angle of the wheelset, rad (+ nose to the right)"),
                 ("vy", "lateral velocity, m/s"), ("dpsi", "yaw rate, rad/s"),
                 ("F_flange", "lateral flange force on the wheelset, N"))


class TangentTrackWheelset(WheelsetSlaveBase):
    """Wheelset with lateral and yaw freedom on tangent track (see module docstring)."""

    description = ("Reference wheelset on tangent track (lateral + yaw, conical wheels, primary "
                   "stiffness to a frame at constant speed); Wickens 2003")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        params = [f for f in param_fields(LateralParams) if f[0] not in _CURVE_ONLY]
        self._declare(params + list(INITIAL_STATE), extra_outputs=STATE_OUTPUTS)

    def _lateral_params(self) -> LateralParams:
        p = self.params()
        return LateralParams(**{k: v for k, v in p.items() if k in LateralParams.__dataclass_fields__})

    def _make_model(self):
        return LateralWheelset(self._lateral_params(),
                               LateralState(self.y0, self.psi0, self.vy0, self.dpsi0))

    def _update_outputs(self):
        m = self._model
        self._set_contact_outputs(m.creepages())
        s = m.s
        self.y, self.psi, self.vy, self.dpsi = s.y, s.psi, s.vy, s.dpsi
        self.F_flange = m.flange_force(s.y)

    def do_step(self, current_time, step_size):
        self._model.step(step_size, self.Fx_L, self.Fy_L, self.Mz_L,
                         self.Fx_R, self.Fy_R, self.Mz_R, self.rates())
        self._update_outputs()
        return True
