"""A wheelset on real wheel and rail profiles: lateral and yaw dynamics, with its contact geometry
from a contact-geometry table (no creep-force law here).

The real-profile wheelset FMUs (``profile_fmus.py``) are thin pythonfmu adapters around
:class:`ProfileWheelset`. It is the tangent-track / curving wheelset of ``wheelset_dynamics``
(states y, ψ, ẏ, ψ̇; primary springs to a frame that follows the track centre line at constant
speed V; curves at balance speed, the curvature ramping over a clothoid) with the geometry of real
profiles instead of cones: the contact-geometry table (:class:`contact_core.geometry.ContactTable`
from :func:`contact_core.geometry.contact_table`, e.g. new S1002 wheels on new UIC60 rails 1:40)
gives at the lateral shift y the wheelset's roll and height with both wheels touching (rigid
contact) and, per wheel and slot (0 tread, 1 flange), the patch's vertical gap above the wheel's
rigid contact, contact angle δ, rolling radius, relative curvatures A, B, Hertz's approach factor
kd and contact point (track y and z, lead per unit yaw). That makes four patches
(:data:`PATCHES`: left tread, left flange, right tread, right flange), each evaluated by a
contact FMU of its own; an absent or unloaded patch gets N = 0.

Frames and the transformation
-----------------------------
Track frame (contact_core.geometry's): x along the track, y to the right, z down; the left wheel
at y < 0. A patch's contact frame is the track frame turned by its contact angle δ about x: x
along the track, y in the contact plane, z along the normal n = (0, −sin δ, cos δ) into the rail
(δ > 0 on the left wheel's tread and flange, < 0 on the right wheel's). A contact FMU's forces
(Fx, Fy, Mz) are those of the rail on the wheel in that frame (Kalker's convention); with the
normal load N (pressing the wheel away from the rail, −N n) the patch's force and moment on the
wheelset in the track frame are

    f = (Fx,  Fy cos δ + N sin δ,  Fy sin δ − N cos δ),      m = Mz (0, −sin δ, cos δ).

Kinematics
----------
Creepages ξ, η, φ of each patch in its contact frame: :func:`contact_core.geometry.creepages`
(Kalker's definition: the wheel particle's velocity relative to the rail over the rolling speed,
spin including the contact angle's part), for the wheelset at (y, table roll and height, ψ), the
patch's contact point (longitudinal lead x = (dx/dψ) ψ from the table; the wheel's surface the
patch's gap above the rail) and the velocities: V forward, ẏ, the height and roll rates that keep
both wheels on their rails (z'(y) ẏ, roll'(y) ẏ from the table), yaw rate ψ̇ + Vκ (the track
frame turns at Vκ in a curve of curvature κ) and pitch rate −V/r_c, free rolling on the centred
rolling radius r_c (no pitch freedom: ξ = 0 at y = 0).

Normal loads
------------
Quasi-static vertical and roll equilibrium (the wheelset's vertical and roll inertia neglected;
derived here from the rigid wheelset's statics with the patch forces f above, the normal load
projected through the contact angle as in Wickens 2003, the single wheelset on profiles of
arbitrary shape, and in Ayasse & Chollet, "Wheel–rail contact", in Iwnicki (ed.), *Handbook of
Railway Vehicle Dynamics*, 2006):
the suspension presses the wheelset down with the axle load W, half on each axle box (no roll
moment), and holds it laterally at axle height. The patches of a wheel share its rigid approach d
beyond the wheel's rigid contact (multi-Hertzian contact with a common approach: Piotrowski &
Chollet 2005, Vehicle System Dynamics 43; the table's gap g and kd), so that Hertz's
approach–load relation (approach = kd N^{2/3}, :func:`contact_core.hertz.hertz_geometry`) gives

    N_i = ((d − g_i) cos δ_i / kd_i)^{3/2}  for d > g_i, else 0

(δ_i at the patch's deepest point; the same relation as ``contact_core.geometry.loads``). The
two wheels' approaches follow from

    Σ f_z,i = −W,        Σ (ρ_y,i f_z,i − ρ_z,i f_y,i − Mz_i sin δ_i) = 0     (vertical, roll)

with ρ_i the contact point relative to the wheelset centre and the creep forces as received. A
wheel whose load would be negative is lifted (its patches N = 0, :attr:`Loads.lifted`): the roll
equilibrium cannot be met then — the lateral force lifts the wheelset over its flange, which this
model does not follow.

Equations of motion
-------------------
Newton–Euler equations of the wheelset's lateral and yaw freedoms with the patch forces f and
moments m above (derived here; with cones and cos δ ≈ 1 they reduce to ``wheelset_dynamics``'
equations, Wickens 2003's single wheelset; the lateral components of the normal loads are the
gravitational stiffness of Wickens 2003 and Iwnicki (ed.) 2006):

    m ÿ   = Σ f_y,i − k_y y − c_y ẏ
    I_z ψ̈ = Σ (ρ_x,i f_y,i − ρ_y,i f_x,i + Mz_i cos δ_i) − k_ψ ψ − c_ψ ψ̇ − I_z V dκ/dt

The lateral components of the normal loads, N sin δ, are the gravitational stiffness on the
treads and the flange force at the flange: nothing else restrains the wheelset there (no flange
spring).

Integration within a communication step: the contact FMUs' forces are held in their contact
frames (zero-order hold); the geometry, the normal loads and the rotation into the track frame
follow the state at every Runge-Kutta stage, as the wheelset's own
mechanics.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .profile_runtime import geometry
from .wheelset_dynamics import LateralState, YawWheelset, _p, check_params, rk4

#: The patches: name -> (side, slot) in the contact-geometry table (slot 0 tread, 1 flange).
PATCHES: dict[str, tuple[str, int]] = {"Lt": ("left", 0), "Lf": ("left", 1),
                                       "Rt": ("right", 0), "Rf": ("right", 1)}
#: The wheels and their patches.
WHEELS: dict[str, tuple[str, str]] = {"L": ("Lt", "Lf"), "R": ("Rt", "Rf")}
#: A patch's signals to its contact FMU, and from it.
PATCH_OUTPUTS = ("xi", "eta", "phi", "N", "A", "B")
PATCH_INPUTS = ("Fx", "Fy", "Mz")
_TABLE_QUANTITIES = ("gap", "delta", "delta_deepest", "kd", "y", "z", "x_per_yaw", "A", "B",
                     "radius", "y_rail", "y_wheel")


@dataclass
class ProfileParams:
    """Parameters of the real-profile wheelset (SI units); geometry from the table."""

    V: float = _p(30.0, "forward speed, m/s (constant)")
    m: float = _p(1500.0, "wheelset mass, kg")
    I_z: float = _p(800.0, "wheelset yaw moment of inertia, kg m²")
    axle_load: float = _p(100e3, "vertical load W from the suspension, N (half on each axle box)")
    k_y: float = _p(1.0e6, "lateral primary stiffness to the frame, N/m")
    k_psi: float = _p(2.0e6, "yaw primary stiffness to the frame, N m/rad")
    c_y: float = _p(0.0, "lateral primary damping, N s/m")
    c_psi: float = _p(0.0, "yaw primary damping, N m s/rad")
    R: float = _p(math.inf, "curve radius, m (+: curve to the right, -: left, inf: tangent)")
    L_transition: float = _p(0.0, "length of the linear curvature ramp (clothoid) into the "
                             "curve, m")
    max_substep: float = _p(2.5e-4, "largest RK4 substep inside one communication step, s")

    def check(self) -> None:
        check_params(self, ("V", "m", "I_z", "axle_load", "max_substep"),
                     ("k_y", "k_psi", "c_y", "c_psi", "L_transition"))


@dataclass(frozen=True)
class Loads:
    """The patches' normal loads ``N`` (N, in :data:`PATCHES` order) and, per wheel, its
    vertical and lateral force on the rail ``Q`` and ``Y`` (N; Y positive to the right, track
    frame); ``lifted``: a wheel would have carried a negative load (module docstring)."""

    N: tuple[float, ...]
    Q: dict[str, float]
    Y: dict[str, float]
    lifted: bool


def _approach(load: float, gaps: tuple[float, float], factors: tuple[float, float]) -> float:
    """The common approach d of a wheel's two patches whose vertical normal loads Σ c_i N_i add
    up to ``load`` (N), with N_i = k_i (d − g_i)^{3/2}; ``factors`` c_i k_i. Newton's iteration
    from the approach at which the deeper patch alone carries the load: the sum is convex and
    increasing in d, so the iterates fall monotonically onto the root."""
    j = 0 if gaps[0] <= gaps[1] else 1
    d = gaps[j] + (load / factors[j]) ** (2.0 / 3.0)
    for _ in range(60):
        f = -load
        df = 0.0
        for g, a in zip(gaps, factors):
            e = d - g
            if e > 0.0:
                r = math.sqrt(e)
                f += a * e * r
                df += 1.5 * a * r
        step = f / df
        d -= step
        if step <= 1e-9 * (d - gaps[j]):
            break
    return d


class ProfileWheelset(YawWheelset):
    """The wheelset of the module docstring on the contact-geometry ``table`` of wheels of
    nominal rolling radius ``nominal_radius`` (m; the radius at the wheel profile's origin, as
    the table was built with). :meth:`step` takes the contact FMUs' forces per patch."""

    def __init__(self, params: ProfileParams, table, nominal_radius: float,
                 state: LateralState | None = None, t0: float = 0.0) -> None:
        super().__init__(params, state, t0)
        if not (math.isfinite(nominal_radius) and nominal_radius > 0.0):
            raise ValueError(f"nominal_radius={nominal_radius!r} is out of range: allowed "
                             "0 < nominal_radius < inf (m)")
        if not table.y[0] < 0.0 < table.y[-1]:
            raise ValueError("the contact-geometry table must span both sides of y = 0")
        self.table = table
        self.r0 = float(nominal_radius)
        index = {n: i for i, n in enumerate(geometry.table.COLUMNS)}
        self._at = {q: tuple(index[f"{side}.{slot}.{q}"] for side, slot in PATCHES.values())
                    for q in _TABLE_QUANTITIES}
        self._roll, self._z = index["roll"], index["z"]
        self._interp = table.interpolant
        self._slope = self._interp.derivative()
        centre = self._interp(0.0)
        #: r_c: the rolling radius of both wheels on the centred wheelset, m (free rolling)
        self.rolling_radius = 0.5 * float(centre[index["left.radius_contact"]]
                                          + centre[index["right.radius_contact"]])
        #: the contact FMUs' forces (Fx, Fy, Mz) per patch, held over a step
        self.held: tuple[tuple[float, float, float], ...] = ((0.0, 0.0, 0.0),) * len(PATCHES)

    # -- geometry and loads ----------------------------------------------------------------------
    def _row(self, y: float) -> list[float]:
        row = self._interp(y)
        if not row[0] == row[0]:
            raise ValueError(f"y={y!r} m is outside the contact-geometry table "
                             f"({self.table.y[0]!r} ... {self.table.y[-1]!r} m): the wheelset "
                             "has left the rails the table describes")
        return row.tolist()

    def _loads(self, row: list[float], y: float) -> tuple[Loads, list, list, list]:
        """Normal loads at the geometry ``row`` of shift ``y`` with the held forces (module
        docstring), and per patch cos δ, sin δ and the lateral arm ρ_y."""
        at, held, W = self._at, self.held, self.p.axle_load
        z_centre = row[self._z] - self.r0
        c, s, ry, arm, k, gap = [], [], [], [], [], []
        total, moment = W, 0.0                 # Σ c_i N_i and Σ arm_i N_i must equal these
        for i in range(len(PATCHES)):
            d = row[at["delta"][i]]
            ci, si = math.cos(d), math.sin(d)
            ryi = row[at["y"][i]] - y
            rzi = row[at["z"][i]] - z_centre
            _, Fy, Mz = held[i]
            total += Fy * si
            moment -= ryi * Fy * si - rzi * Fy * ci - Mz * si
            c.append(ci)
            s.append(si)
            ry.append(ryi)
            arm.append(-ryi * ci - rzi * si)
            k.append((math.cos(row[at["delta_deepest"][i]]) / row[at["kd"][i]]) ** 1.5)
            gap.append(row[at["gap"][i]])
        if not total > 0.0:
            raise ValueError(f"the tangential forces lift the wheelset off the track (vertical "
                             f"load {total!r} N)")
        wheels = ((0, 1), (2, 3))
        deepest = [min(w, key=gap.__getitem__) for w in wheels]
        mean_arm = [arm[j] / c[j] for j in deepest]
        N = [0.0] * len(PATCHES)
        lifted = False
        for _ in range(50):
            left = (moment - mean_arm[1] * total) / (mean_arm[0] - mean_arm[1])
            lifted = not 0.0 <= left <= total
            left = min(max(left, 0.0), total)
            new_arm = []
            for w, load in zip(wheels, (left, total - left)):
                for i in w:
                    N[i] = 0.0
                if load <= 0.0:
                    new_arm.append(mean_arm[len(new_arm)])
                    continue
                d = _approach(load, (gap[w[0]], gap[w[1]]),
                              (c[w[0]] * k[w[0]], c[w[1]] * k[w[1]]))
                for i in w:
                    if d > gap[i]:
                        N[i] = k[i] * (d - gap[i]) ** 1.5
                new_arm.append(sum(arm[i] * N[i] for i in w) / load)
            done = max(abs(a - b) for a, b in zip(new_arm, mean_arm)) < 1e-12
            mean_arm = new_arm
            if done:
                break
        Q, Y = {}, {}
        for (wheel, names), w in zip(WHEELS.items(), wheels):
            Q[wheel] = sum(N[i] * c[i] - held[i][1] * s[i] for i in w)
            Y[wheel] = -sum(held[i][1] * c[i] + N[i] * s[i] for i in w)
        return Loads(tuple(N), Q, Y, lifted), c, s, ry

    def loads(self) -> Loads:
        """The normal loads at the present state, with the forces held now."""
        return self._loads(self._row(self.s.y), self.s.y)[0]

    def _resultants(self, y: float, psi: float) -> tuple[float, float]:
        """Lateral force and yaw moment of the contacts on the wheelset (track frame)."""
        row = self._row(y)
        loads, c, s, ry = self._loads(row, y)
        lead = self._at["x_per_yaw"]
        fy_sum = mz_sum = 0.0
        for i, (Fx, Fy, Mz) in enumerate(self.held):
            fy = Fy * c[i] + loads.N[i] * s[i]
            fy_sum += fy
            mz_sum += row[lead[i]] * psi * fy - ry[i] * Fx + Mz * c[i]
        return fy_sum, mz_sum

    # -- kinematics ------------------------------------------------------------------------------
    def contact_outputs(self) -> dict[str, float]:
        """Per patch (suffix the patch name): ξ, η, φ, N, A, B and the contact angle δ; per wheel
        Q and Y (suffix L, R); ``F_flange``, the flange patches' lateral force on the wheelset
        (N, track frame); ``lifted`` (1.0 if a wheel is lifted)."""
        p, st = self.p, self.s
        row = self._row(st.y)
        loads, c, s, _ = self._loads(row, st.y)
        slope = self._slope(st.y)
        kappa, _ = self.curvature(self.t)
        position = geometry.WheelsetPosition(st.y, row[self._z], row[self._roll], st.psi)
        motion = geometry.WheelsetMotion(
            speed=p.V, pitch_rate=-p.V / self.rolling_radius, lateral_velocity=st.vy,
            vertical_velocity=float(slope[self._z]) * st.vy,
            roll_rate=float(slope[self._roll]) * st.vy, yaw_rate=st.dpsi + p.V * kappa)
        out = {}
        at = self._at
        for i, (name, (side, slot)) in enumerate(PATCHES.items()):
            q = {k: row[at[k][i]] for k in _TABLE_QUANTITIES}
            # the wheel's surface is the patch's vertical gap above the rail (rigid contact)
            point = geometry.ContactPoint(
                side, slot, q["gap"], q["delta_deepest"], q["A"], q["B"],
                q["x_per_yaw"] * st.psi, q["y"], q["z"], q["z"] - q["gap"], q["y_rail"], math.nan,
                q["y_wheel"], q["radius"] - self.r0, q["delta"], q["radius"], math.nan)
            cr = geometry.creepages(position, point, motion, self.r0)
            out.update({f"xi_{name}": cr.xi, f"eta_{name}": cr.eta, f"phi_{name}": cr.phi,
                        f"N_{name}": loads.N[i], f"A_{name}": q["A"], f"B_{name}": q["B"],
                        f"delta_{name}": q["delta"]})
        for wheel in WHEELS:
            out[f"Q_{wheel}"] = loads.Q[wheel]
            out[f"Y_{wheel}"] = loads.Y[wheel]
        out["F_flange"] = sum(self.held[i][1] * c[i] + loads.N[i] * s[i]
                              for i, (_, slot) in enumerate(PATCHES.values()) if slot == 1)
        out["lifted"] = float(loads.lifted)
        return out

    # -- dynamics --------------------------------------------------------------------------------
    def _deriv(self, t, x, _):
        p = self.p
        y, psi, vy, dpsi = x
        fy, mz = self._resultants(y, psi)
        _, dkappa = self.curvature(t)
        ay = (fy - p.k_y * y - p.c_y * vy) / p.m
        apsi = (mz - p.k_psi * psi - p.c_psi * dpsi) / p.I_z - p.V * dkappa
        return vy, dpsi, ay, apsi

    def step(self, h: float, forces) -> None:
        """Advance by h with the contact FMUs' ``forces`` (per patch, :data:`PATCHES` order,
        (Fx, Fy, Mz) of the rail on the wheel in the patch's contact frame) held: classical
        Runge-Kutta (4th order) in ``ceil(h / max_substep)`` equal substeps."""
        held = tuple((float(fx), float(fy), float(mz)) for fx, fy, mz in forces)
        if len(held) != len(PATCHES):
            raise ValueError(f"forces: expected {len(PATCHES)} patches, got {len(held)}")
        self.held = held
        if not h > 0.0:
            return
        s = self.s
        s.y, s.psi, s.vy, s.dpsi = rk4(self._deriv, self.t, (s.y, s.psi, s.vy, s.dpsi), h,
                                       self.p.max_substep)
        self.t += h

    def state_values(self) -> dict[str, float]:
        """The state as name -> float: time, the four states and the forces held per patch
        (the normal loads depend on them); for the FMU's state (``wheelset_fmu_common``)."""
        out = super().state_values()
        for patch, forces in zip(PATCHES, self.held):
            out.update({f"{q}_{patch}": v for q, v in zip(PATCH_INPUTS, forces)})
        return out

    def set_state_values(self, values: dict[str, float]) -> None:
        super().set_state_values(values)
        self.held = tuple(tuple(values[f"{q}_{patch}"] for q in PATCH_INPUTS)
                          for patch in PATCHES)
