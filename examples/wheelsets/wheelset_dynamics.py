"""Rigid-body equations of the reference wheelset models (no contact physics here).

The wheelset FMUs (``tangent_track.py``, ``curving.py``, ``driven_wheel.py``) are thin pythonfmu
adapters around the classes of this module, which is bundled into each FMU's ``resources/``. What
the models do: compute the creepages and normal loads of the left and right contacts from their
states (linearised kinematics), and integrate their equations of motion over one communication
step with the contact forces they received held constant (zero-order hold). The forces themselves
come from the contact FMUs: this module never evaluates a creep-force law.

Frames and signs
----------------
Track frame (and the contact frame of *both* contacts, as used by the contact FMU and
``contact_core``): x along the track in the direction of travel, y lateral to the right looking
along x, z downwards (into the rail). Yaw ψ and the spin are rotations about z (positive turns x
towards y, i.e. the wheelset's nose to the right). The left wheel is at y = -b0, the right wheel at
y = +b0. Forces ``Fx, Fy`` and the spin moment ``Mz`` are those of the rail on the wheel
(Kalker 1979 sec. 2); creepage = (velocity of the wheel particle relative to the
rail at the contact) / V, so that linear theory reads ``Fx = -f11 ξ``, ``Fy = -f22 η - f23 φ``,
``Mz = f23 η - f33 φ``.

Linearised kinematics of a wheelset with conical treads (conicity λ, nominal rolling radius r0,
half distance between the contact points b0), running at speed V on a track of curvature κ
(1/R; positive for a curve to the right; κ = 0 on tangent track), with lateral displacement y and
yaw angle ψ measured from the track centre line and tangent (Wickens 2003, the single wheelset
and its curving; Iwnicki (ed.) 2006, stability and curving; Knothe & Stichel 2017, hunting):

* rolling radii ``r_L = r0 - λy``, ``r_R = r0 + λy``; the wheelset spins at Ω = V/r0 (no pitch
  degree of freedom);
* absolute yaw rate ``ψ̇ + Vκ``; the left wheel's centre moves forward at ``V + b0(ψ̇ + Vκ)``, the
  right one at ``V - b0(ψ̇ + Vκ)``;
* longitudinal creepage (particle velocity minus rail, over V):

      ξ_L = +( λy/r0 + b0ψ̇/V + b0κ ),     ξ_R = -( λy/r0 + b0ψ̇/V + b0κ );

  a wheelset displaced to the right (y > 0) rolls on a larger right wheel: ξ_R < 0 gives a forward
  force on the right wheel, ξ_L > 0 a backward one on the left, hence a yaw moment
  ``b0(Fx_L - Fx_R) < 0`` that steers the nose to the left, back to the centre (Klingel's
  kinematic oscillation);
* lateral creepage, the same for both wheels: ``η = ẏ/V - ψ`` (a wheel yawed to the right,
  rolling straight on, slides to the left: η < 0, Fy > 0);
* spin creepage = (wheel's angular velocity about the contact normal) / V. The contact normal
  into the rail is tilted by the contact angle δ (δ = arctan λ ≈ λ for a cone): towards +y on the
  right wheel, towards -y on the left one, so the rolling speed -Ω about y contributes ∓Ω sin δ:

      φ_L = +λ/r0 + (ψ̇ + Vκ)/V,     φ_R = -λ/r0 + (ψ̇ + Vκ)/V.

  The constant parts ±λ/r0 are equal and opposite: in linear theory their forces cancel between
  the wheels, but each contact does feel them (saturation with FASTSIM/exact).

Equations of motion (the suspension connects the wheelset to a frame that moves along the track
centre line at constant speed V, tangent to it):

    m ÿ   = Fy_L + Fy_R - k_y y - c_y ẏ + F_flange(y)
    I_z ψ̈ = b0 (Fx_L - Fx_R) + Mz_L + Mz_R - k_ψ ψ - c_ψ ψ̇ - I_z V dκ/dt

(moments of the contact forces about the wheelset centre: the contacts sit at x = 0, y = ∓b0, so
``Fx`` gives ``-y_c Fx`` and ``Fy`` none). Small-angle linearisation throughout; the contact-plane
tilt is neglected in the creep forces (cos δ ≈ 1).

Gravitational stiffness: omitted. For pure cones (constant contact angle) the lateral components
of the two normal loads are equal and opposite and independent of y in the linear model
(Wickens 2003: the gravitational stiffness comes from the *change* of contact angle
with y, zero for a cone), so the consistent choice for this model is zero.

Curves: the track frame follows the curve; the cant is assumed to balance the centripetal
acceleration (running at the balance speed: no net lateral body force on the wheelset), so the
curvature enters through the creepages (the outer wheel must roll further) and, in a transition,
through the inertial yaw moment ``I_z V dκ/dt``. The curvature ramps linearly over a transition
(clothoid) of length ``L_transition`` and is then constant.

Flange contact (optional, ``flange_gap`` > 0 and ``k_flange`` > 0): the rail's flange restraint
is the usual simplification of hunting studies, a stiff linear spring with a dead band (flangeway
clearance), ``F_flange = -k_flange (|y| - gap) sign(y)`` for ``|y| > gap`` (as in the
nonlinear hunting studies of H. True and co-workers; Knothe & Stichel 2017, on hunting). It is a geometric constraint of the
wheelset model, not a creep force; it bounds the hunting limit cycle of conical wheels.

Integration within one communication step: the contact forces are held (zero-order hold, what an
FMI co-simulation gives); the remaining ODE (suspension, flange spring, transition inertia) is
integrated with classical Runge-Kutta (4th order) in ``ceil(h / max_substep)`` equal substeps.
The coupling is therefore explicit: see ``README.md`` for the step-size limit it implies. Given
the forces' rates (the FMUs' inputs ``Fx_L_rate``, ...), the forces change linearly over the
step instead, F(t) = F + Ḟ (t - t_k) (a first-order hold; the linearly implicit master,
``master.py``, ramps them to their predicted end values).

State as data: :meth:`LateralWheelset.state_values` and :meth:`DrivenWheelset.state_values` are
the models' states as a flat mapping name -> float (``set_state_values`` restores one), for the
FMUs' ``fmi2GetFMUstate``/``fmi2SetFMUstate`` (``wheelset_fmu_common``).

The driven wheelset (:class:`DrivenWheelset`) is a wheelset with cylindrical wheels (λ = 0, hence
η = φ = 0) on straight track at constant speed V, whose rotation Ω about its axle is driven by a
torque T:

    ξ_L = ξ_R = (V - Ω r0) / V,        I_y Ω̇ = T - r0 (Fx_L + Fx_R)

(the creep force Fx, rail on wheel, forward positive, acts at the contact point a distance r0 below
the axle and opposes the forward rolling rotation). Traction T > 0 spins the wheel faster than it rolls:
Ω r0 > V, ξ < 0, Fx > 0 (forward). The ODE is a pure integrator with held inputs; T is evaluated
at mid-step, which is exact for a torque linear in time over the step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

def _p(default: float, doc: str):
    """A documented parameter field."""
    return field(default=default, metadata={"doc": doc})


def check_params(params, positive: tuple[str, ...] = (),
                 non_negative: tuple[str, ...] = ()) -> None:
    """``ValueError`` naming the first field of ``params`` out of its range: of ``positive``
    outside 0 < v < inf, then of ``non_negative`` outside 0 <= v < inf, then a curve radius
    ``R`` (if ``params`` has one) of 0 or NaN."""
    for name in positive:
        v = getattr(params, name)
        if not (math.isfinite(v) and v > 0.0):
            raise ValueError(f"{name}={v!r} is out of range: allowed 0 < {name} < inf")
    for name in non_negative:
        v = getattr(params, name)
        if not (math.isfinite(v) and v >= 0.0):
            raise ValueError(f"{name}={v!r} is out of range: allowed 0 <= {name} < inf")
    R = getattr(params, "R", math.inf)
    if R == 0.0 or math.isnan(R):
        raise ValueError(f"R={R!r} is out of range: allowed |R| > 0 (inf: tangent track)")


def rk4(f, t: float, x: tuple[float, ...], h: float, max_substep: float,
        inputs=None) -> tuple[float, ...]:
    """The state ``x`` at ``t + h`` of x' = f(t, x, u): classical Runge-Kutta (4th order) in
    ``ceil(h / max_substep)`` equal substeps. ``inputs(t, dt)``: u at the start, the middle and
    the end of the substep of length dt from t (None: u is None throughout, inputs held)."""
    n = max(1, math.ceil(h / max_substep - 1e-9))
    dt = h / n
    u0 = u1 = u2 = None
    for _ in range(n):
        if inputs is not None:
            u0, u1, u2 = inputs(t, dt)
        k1 = f(t, x, u0)
        k2 = f(t + 0.5 * dt, tuple(a + 0.5 * dt * b for a, b in zip(x, k1)), u1)
        k3 = f(t + 0.5 * dt, tuple(a + 0.5 * dt * b for a, b in zip(x, k2)), u1)
        k4 = f(t + dt, tuple(a + dt * b for a, b in zip(x, k3)), u2)
        x = tuple(a + dt / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4)
                  for a, b1, b2, b3, b4 in zip(x, k1, k2, k3, k4))
        t += dt
    return x


#: Names of the contact-side signals of a wheelset model, per contact (L, R).
CONTACT_OUTPUTS = ("xi", "eta", "phi", "N")
CONTACT_INPUTS = ("Fx", "Fy", "Mz")


# ------------------------------------------------------------------------------------------------
# Lateral (tangent track / curve) wheelset
# ------------------------------------------------------------------------------------------------
@dataclass
class LateralParams:
    """Parameters of the lateral wheelset (SI units). Defaults: the reference values of issue 6."""

    V: float = _p(30.0, "forward speed, m/s (constant)")
    r0: float = _p(0.46, "nominal rolling radius, m")
    b0: float = _p(0.75, "half distance between the contact points, m")
    conicity: float = _p(0.15, "effective conicity λ, 1")
    m: float = _p(1500.0, "wheelset mass, kg")
    I_z: float = _p(800.0, "wheelset yaw moment of inertia, kg m²")
    axle_load: float = _p(100e3, "vertical axle load W, N (each wheel carries W/2)")
    k_y: float = _p(1.0e6, "lateral primary stiffness to the frame, N/m")
    k_psi: float = _p(2.0e6, "yaw primary stiffness to the frame, N m/rad")
    c_y: float = _p(0.0, "lateral primary damping, N s/m")
    c_psi: float = _p(0.0, "yaw primary damping, N m s/rad")
    flange_gap: float = _p(0.0, "flangeway clearance (dead band) of the flange spring, m (0: none)")
    k_flange: float = _p(0.0, "flange contact stiffness, N/m (0: no flange contact)")
    R: float = _p(math.inf, "curve radius, m (+: curve to the right, -: left, inf: tangent)")
    L_transition: float = _p(0.0, "length of the linear curvature ramp (clothoid) into the curve, m")
    max_substep: float = _p(5e-4, "largest RK4 substep inside one communication step, s")

    def check(self) -> None:
        check_params(self, ("V", "r0", "b0", "m", "I_z", "max_substep"),
                     ("conicity", "axle_load", "k_y", "k_psi", "c_y", "c_psi", "flange_gap",
                      "k_flange", "L_transition"))


@dataclass
class LateralState:
    y: float = _p(0.0, "lateral displacement, m (+ right)")
    psi: float = _p(0.0, "yaw angle, rad (+ nose to the right)")
    vy: float = _p(0.0, "lateral velocity, m/s")
    dpsi: float = _p(0.0, "yaw rate, rad/s")


class YawWheelset:
    """What the wheelsets with lateral and yaw freedom share (the conical one,
    :class:`LateralWheelset`, and the real-profile one of ``profile_dynamics``): parameters
    ``p`` (with ``V``, ``R``, ``L_transition``), the states y, ψ, ẏ, ψ̇ (``s``) at time ``t``,
    the track's curvature and the state as data."""

    def __init__(self, params, state: LateralState | None = None, t0: float = 0.0) -> None:
        params.check()
        self.p = params
        self.s = state or LateralState()
        self.t = t0
        self.kappa_end = 0.0 if math.isinf(params.R) else 1.0 / params.R

    # -- track geometry --------------------------------------------------------------------------
    def curvature(self, t: float) -> tuple[float, float]:
        """Track curvature κ (1/m) at the wheelset and its time derivative at time t."""
        p = self.p
        if self.kappa_end == 0.0:
            return 0.0, 0.0
        if p.L_transition <= 0.0:
            return self.kappa_end, 0.0
        s = p.V * t
        if s >= p.L_transition:
            return self.kappa_end, 0.0
        if s <= 0.0:
            return 0.0, 0.0
        rate = self.kappa_end / p.L_transition
        return rate * s, rate * p.V

    def state_values(self) -> dict[str, float]:
        """The state (time and the four states) as name -> float."""
        s = self.s
        return {"t": self.t, "y": s.y, "psi": s.psi, "vy": s.vy, "dpsi": s.dpsi}

    def set_state_values(self, values: dict[str, float]) -> None:
        self.t = values["t"]
        self.s = LateralState(values["y"], values["psi"], values["vy"], values["dpsi"])


class LateralWheelset(YawWheelset):
    """Wheelset with lateral and yaw freedom on tangent track or in a curve (see module doc)."""

    # -- kinematics ------------------------------------------------------------------------------
    def creepages(self) -> dict[str, float]:
        """Creepages, spin and normal load of both contacts at the current state and time."""
        p, s = self.p, self.s
        kappa, _ = self.curvature(self.t)
        lon = p.conicity * s.y / p.r0 + p.b0 * s.dpsi / p.V + p.b0 * kappa
        eta = s.vy / p.V - s.psi
        yaw_spin = (s.dpsi + p.V * kappa) / p.V
        cone_spin = p.conicity / p.r0
        n = 0.5 * p.axle_load
        return {"xi_L": lon, "eta_L": eta, "phi_L": cone_spin + yaw_spin, "N_L": n,
                "xi_R": -lon, "eta_R": eta, "phi_R": -cone_spin + yaw_spin, "N_R": n}

    def flange_force(self, y: float) -> float:
        p = self.p
        if p.k_flange <= 0.0:
            return 0.0
        excess = abs(y) - p.flange_gap
        if excess <= 0.0:
            return 0.0
        return -math.copysign(p.k_flange * excess, y)

    # -- dynamics --------------------------------------------------------------------------------
    def _deriv(self, t, x, forces):
        p = self.p
        y, psi, vy, dpsi = x
        fy, mz = forces
        _, dkappa = self.curvature(t)
        ay = (fy - p.k_y * y - p.c_y * vy + self.flange_force(y)) / p.m
        apsi = (mz - p.k_psi * psi - p.c_psi * dpsi) / p.I_z - p.V * dkappa
        return vy, dpsi, ay, apsi

    def step(self, h: float, Fx_L: float, Fy_L: float, Mz_L: float, Fx_R: float, Fy_R: float,
             Mz_R: float, rates: tuple[float, ...] | None = None) -> None:
        """Advance by h with the contact forces (rail on wheel, track frame) held constant, or,
        given ``rates`` (their time derivatives in the same order), changing linearly from their
        values at the step's start."""
        if not (h > 0.0):
            return
        p, s = self.p, self.s
        fy = Fy_L + Fy_R
        mz = p.b0 * (Fx_L - Fx_R) + Mz_L + Mz_R
        dfy = dmz = 0.0
        if rates is not None:
            dFx_L, dFy_L, dMz_L, dFx_R, dFy_R, dMz_R = rates
            dfy = dFy_L + dFy_R
            dmz = p.b0 * (dFx_L - dFx_R) + dMz_L + dMz_R
        t0 = self.t

        def forces(t, dt):             # at the substep's start, middle and end
            fy0, mz0 = fy + dfy * (t - t0), mz + dmz * (t - t0)
            return ((fy0, mz0), (fy0 + 0.5 * dt * dfy, mz0 + 0.5 * dt * dmz),
                    (fy0 + dt * dfy, mz0 + dt * dmz))

        s.y, s.psi, s.vy, s.dpsi = rk4(self._deriv, t0, (s.y, s.psi, s.vy, s.dpsi), h,
                                       p.max_substep, forces)
        self.t += h


# ------------------------------------------------------------------------------------------------
# Driven wheelset (rotational degree of freedom)
# ------------------------------------------------------------------------------------------------
@dataclass
class DrivenParams:
    """Parameters of the driven wheelset (SI units)."""

    V: float = _p(20.0, "forward speed, m/s: constant when m_vehicle = 0, else the initial speed "
                  "(0: start from rest)")
    r0: float = _p(0.46, "rolling radius, m (cylindrical wheels: λ = 0)")
    I_y: float = _p(120.0, "polar moment of inertia of wheelset + drive about the axle, kg m²")
    axle_load: float = _p(100e3, "vertical axle load W, N (each wheel carries W/2)")
    m_vehicle: float = _p(0.0, "mass moved by the wheelset, kg (0: V held constant, the vehicle "
                          "much heavier)")
    V_reg: float = _p(0.5, "creepage regularisation speed, m/s: xi = (V - Omega r0) / "
                      "max(|V|, V_reg)")

    def check(self) -> None:
        check_params(self, ("r0", "I_y", "V_reg"))
        if not (math.isfinite(self.V) and (self.V > 0.0 or self.m_vehicle > 0.0 and self.V >= 0.0)):
            raise ValueError(f"V={self.V!r} is out of range: allowed 0 < V < inf (0 <= V with "
                             "m_vehicle > 0)")
        check_params(self, non_negative=("axle_load", "m_vehicle"))


class DrivenWheelset:
    """Wheelset spinning about its axle under drive and brake torques; with ``m_vehicle`` > 0 it
    also moves a mass forward (start from rest, braking to standstill).

    Creepage at low speed (the regularisation multibody codes use): ξ = (V - Ω r0) / max(|V|,
    V_reg). Above V_reg this is the textbook ξ; below, the creep force acts as a viscous damper on
    the slip velocity V - Ω r0, with the time constant τ = max(|V|, V_reg) / (2 f11 (r0²/I_y +
    1/m_vehicle)) (f11 = G c² C11 per wheel, Kalker 1979 eq 17), so that an explicit coupling
    stays free of chatter for a communication step h <= τ at V_reg
    (``systems.regularisation_speed``). The brake torque is regularised Coulomb friction on the
    axle: -T_b Ω / max(|Ω|, V_reg/r0), zero at standstill.
    """

    def __init__(self, params: DrivenParams, omega: float | None = None, t0: float = 0.0):
        params.check()
        self.p = params
        self.V = params.V
        self.omega = params.V / params.r0 if omega is None else omega
        self.t = t0

    def creepages(self) -> dict[str, float]:
        p = self.p
        xi = (self.V - self.omega * p.r0) / max(abs(self.V), p.V_reg)
        n = 0.5 * p.axle_load
        return {"xi_L": xi, "eta_L": 0.0, "phi_L": 0.0, "N_L": n,
                "xi_R": xi, "eta_R": 0.0, "phi_R": 0.0, "N_R": n}

    def step(self, h: float, torque_mid: float, Fx_L: float, Fx_R: float,
             brake: float = 0.0, Fx_rate: float = 0.0) -> None:
        """Advance by h: ``I_y dΩ/dt = T - T_b(Ω) - r0 (Fx_L + Fx_R)`` and, with a vehicle mass,
        ``m dV/dt = Fx_L + Fx_R``, with the forces held (or, with ``Fx_rate`` = d(Fx_L + Fx_R)/dt,
        changing linearly: their mean over the step is then the value at mid-step) and the torque
        at mid-step (exact for a torque linear in time)."""
        if not (h > 0.0):
            return
        p = self.p
        force = Fx_L + Fx_R + 0.5 * h * Fx_rate
        w_reg = p.V_reg / p.r0
        brake_torque = -abs(brake) * self.omega / max(abs(self.omega), w_reg)
        self.omega += h * (torque_mid + brake_torque - p.r0 * force) / p.I_y
        if p.m_vehicle > 0.0:
            self.V += h * force / p.m_vehicle
        self.t += h

    def state_values(self) -> dict[str, float]:
        """The state (time, forward speed, angular speed) as name -> float."""
        return {"t": self.t, "V": self.V, "omega": self.omega}

    def set_state_values(self, values: dict[str, float]) -> None:
        self.t, self.V, self.omega = values["t"], values["V"], values["omega"]


def param_fields(cls) -> list[tuple[str, float, str]]:
    """(name, default, description) of the fields of a parameter dataclass."""
    return [(f.name, f.default, f.metadata.get("doc", "")) for f in fields(cls)]
