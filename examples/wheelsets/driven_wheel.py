"""Driven wheelset FMU: rotation about the axle under drive and brake torques, at a constant
forward speed or moving a mass (pythonfmu ``Fmi2Slave``).

The classical traction / adhesion model (Iwnicki (ed.), *Handbook of Railway Vehicle Dynamics*
(2006), on adhesion and traction; Knothe & Stichel, *Rail Vehicle Dynamics* (2017), on
longitudinal creepage): a wheelset with cylindrical wheels (λ = 0, so η = φ = 0) on
straight track, forward speed V held constant by the (much heavier) vehicle, one degree of
freedom, the angular speed Ω about the axle:

    ξ_L = ξ_R = (V - Ω r0) / V,          I_y dΩ/dt = T - r0 (Fx_L + Fx_R).

Kalker's sign convention (``wheelset_dynamics``): traction T > 0 makes the wheels turn faster than
they roll (Ω r0 > V), ξ < 0 and Fx > 0 (forward, rail on wheel). Beyond the adhesion limit
T > μ W r0 the creep forces cannot balance the torque and the wheelset spins up: ξ decreases
without bound (ξ -> -inf as Ω grows).

With ``m_vehicle`` > 0 the forward speed is a state too, ``m dV/dt = Fx_L + Fx_R``: the wheelset
can start from rest (V = 0) and brake to standstill, the creepage regularised at low speed as
``wheelset_dynamics.DrivenWheelset`` says (V_reg).

Parameters (SI; defaults): V = 20 m/s, r0 = 0.46 m, I_y = 120 kg m² (wheelset with its share of
the drive), axle load W = 100 kN, m_vehicle = 0 (V constant), V_reg = 0.5 m/s, initial creepage
xi0 = 0 (free rolling). Inputs: ``torque`` (N m), held over the communication step (the FMU uses
its value at the step's start; a master that wants mid-step accuracy for a ramp sets the
mid-step value), and ``brake`` (N m, the magnitude of a brake torque opposing the rotation).

Slip control (``slip_control.SlipController``): with ``xi_target`` > 0 the torque demanded is
cut by a PI controller on the creepage beyond ``xi_target`` (gains ``k_p``, N m, and ``k_i``,
N m/s; the defaults place the loop's poles at 20 rad/s, critically damped, for the default I_y,
V and r0: ``slip_control.gains``); output ``torque_applied``. The contact FMU of a scene with
falling friction takes the rolling speed from the output ``speed`` (``systems.make_system``,
``rolling_speed=True``).
"""
from __future__ import annotations

from .slip_control import SlipController, gains
from .wheelset_dynamics import DrivenParams, DrivenWheelset, param_fields
from .wheelset_fmu_common import WheelsetSlaveBase

_K_P, _K_I = gains(DrivenParams.V, DrivenParams.I_y, DrivenParams.r0)


class DrivenWheelsetFMU(WheelsetSlaveBase):
    """Wheelset spinning about its axle under a drive torque (see module docstring)."""

    description = ("Reference driven wheelset on straight track: rotation about the axle under "
                   "drive and brake torques, constant speed or a moved mass; Iwnicki 2006 "
                   "(adhesion)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._declare(param_fields(DrivenParams) + [
            ("xi0", 0.0, "initial creepage, 1"),
            ("xi_target", 0.0, "slip controller: the creepage magnitude it holds, 1 (0: off)"),
            ("k_p", _K_P, "slip controller: proportional gain, N m per unit creepage"),
            ("k_i", _K_I, "slip controller: integral gain, N m per unit creepage and s")],
                      extra_inputs=(("torque", "drive torque on the axle, N m"),
                                    ("brake", "brake torque magnitude (opposes the rotation), "
                                              "N m")),
                      extra_outputs=(("omega", "angular speed about the axle, rad/s"),
                                     ("speed", "forward speed V, m/s"),
                                     ("xi", "longitudinal creepage (both wheels), 1"),
                                     ("slip_velocity", "V - Omega r0, m/s"),
                                     ("torque_applied", "drive torque applied over the last "
                                                        "step (after the slip controller), N m"),
                                     ("adhesion", "(Fx_L + Fx_R) / axle load: used adhesion, 1")))

    def _make_model(self):
        p = DrivenParams(**{k: v for k, v in self.params().items()
                            if k in DrivenParams.__dataclass_fields__})
        self._controller = (SlipController(self.xi_target, self.k_p, self.k_i)
                            if self.xi_target > 0.0 else None)
        return DrivenWheelset(p, omega=p.V * (1.0 - self.xi0) / p.r0)

    def _model_state(self):
        state = self._model.state_values()
        if self._controller is not None:
            state["controller_integral"] = self._controller.integral
        return state

    def _set_model_state(self, values):
        self._model.set_state_values(values)
        if self._controller is not None:
            self._controller.integral = values["controller_integral"]

    def _update_outputs(self):
        m = self._model
        c = m.creepages()
        self._set_contact_outputs(c)
        self.omega = m.omega
        self.xi = c["xi_L"]
        self.speed = m.V
        self.slip_velocity = m.V - m.omega * m.p.r0
        load = m.p.axle_load
        self.adhesion = (self.Fx_L + self.Fx_R) / load if load > 0 else 0.0

    def do_step(self, current_time, step_size):
        torque = self.torque
        if self._controller is not None:
            torque = self._controller.torque(torque, self._model.creepages()["xi_L"], step_size)
        self.torque_applied = torque
        self._model.step(step_size, torque, self.Fx_L, self.Fx_R, self.brake,
                         self.Fx_L_rate + self.Fx_R_rate)
        self._update_outputs()
        return True
