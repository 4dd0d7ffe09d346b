"""Contact search: the contact points of a wheelset on a track at a lateral shift y and yaw ψ.

Method (the "contact locus" of a yawed wheelset on a prismatic rail, as in CONTACT's planar
contact approach: Vollebregt 2022, "Detailed wheel/rail geometry processing using the planar
contact approach", Vehicle System Dynamics 60): a rail that is straight along x can only touch
the wheel where the wheel's surface normal is perpendicular to x.
On the circle of wheel-profile coordinate y_w (radius r = r0 + z_w, at wheelset lateral
coordinate Y = σ(b + y_w)) that point is at the angle t from the bottom with

    sin t = −tan ψ · dr/dY          (normal (sin t, −dr/dY, cos t) ⊥ R^T x̂ = (cos ψ, −sin ψ, 0)),

so the wheel's silhouette seen along the track is the curve (X, Y, Z)(y_w) = O + R (r sin t, Y,
r cos t), R = R_x(roll) R_z(ψ) (:mod:`.track`). The vertical gap between the rail surface and that
curve, g(y_w) = z_rail(Y) − Z, is evaluated on a grid of y_w; its local minima, refined on a
finer grid with a parabola, are the candidate contact points.

Patches. Two minima belong to separate patches when the gap rises by more than ``separation``
(default 20 µm, the order of the Hertz approach of a 10 kN wheel load) between them; otherwise
they are one patch located at the deeper one. A wheel keeps at most two patches, the two deepest.
Slot 0 (tread) and slot 1 (flange): of two patches, the one nearer the flange is slot 1; a single
patch is slot 1 when the wheel profile's inclination at it exceeds ``flange_angle`` (default
0.2 rad, 11.5°: S1002 treads touch UIC60 rails below 0.14 rad, its flange root above 0.29 rad),
else slot 0. How the load divides between two patches is :mod:`.loads`.

Per patch:

- at its deepest point (the minimum of the gap, where both surfaces are parallel): the vertical
  gap, the contact angle there, and the relative curvatures (Hertz: gap ≈ A x² + B y² in the
  contact plane, A and B half the sums of both bodies' principal curvatures along x and across
  when their principal axes are parallel: Johnson 1985, sec. 4.1). With the wheel a surface of
  revolution and the rail straight along x, the wheel's curvature along x is cos δ_w / r
  (Meusnier's theorem, e.g. do Carmo 1976, *Differential Geometry of Curves and Surfaces*,
  sec. 3-2: the normal curvature of the wheel's circle of radius r = r0 + z_w, δ_w the wheel
  profile's inclination to the axle), so A = cos δ_w / (2r), and B = (κ_rail − κ_wheel)/2 with
  κ = z''/(1 + z'²)^{3/2} the curvature of each profile curve (:class:`ProfileFunction`
  signs). For |ψ| ≪ 1 the
  principal directions of both bodies are taken as x and the profile tangent (the yaw turns the
  wheel's by ψ, a second-order effect on A and B);
- its reference point: where the patch overlaps the rail (gap < 0), the centre of the overlap
  weighted by the square of the overlap, integrated across x for the parabolic gap along x, so
  that each lateral strip weighs overlap^{5/2} (Vollebregt 2022, the "weighted centre" that
  CONTACT's module 1 uses); with no overlap, the deepest point. There: the contact point on the
  rail in the track frame and on both profiles, the rolling radius r = r0 + z_w, and the contact
  angle δ, the rotation about the track x axis from the track z axis to the contact normal
  (positive on the left rail's gauge side, negative on the right rail's; Vollebregt, CONTACT
  user guide, "DELTTR"): atan(dz_rail/dy) in the track frame, averaged over the overlap with the same
  weights. For a parabolic gap both points coincide; they differ where the curvatures vary across
  a wide patch (near-conformal treads).

Heights. With ``roll`` and ``z`` given, the gaps are those of that position (negative: overlap).
With neither, both follow from both wheels touching (rigid contact: the smallest gap of each wheel
is zero, :func:`rigid_roll`). With ``roll`` only, ``z`` puts the lower wheel on its rail.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..cache import cached
from .track import SIDES, WheelsetOnTrack

#: Default separation of two patches (rise of the gap between two minima), m.
SEPARATION = 2e-5
#: Wheel-profile inclination above which a single patch is a flange patch, rad.
FLANGE_ANGLE = 0.2
#: Grid step of the search along the wheel profile, m.
STEP = 2e-4
_FINE = 41
_REFERENCE_POINTS = 201


@dataclass(frozen=True)
class ContactPoint:
    """One contact patch's geometry (m, rad; module docstring).

    ``slot``: 0 tread, 1 flange. ``gap``: vertical gap at the deepest point at the wheelset's
    position (negative: overlap); ``delta_deepest``: contact angle there; ``A, B``: relative
    curvatures there (along x and across, 1/m). At the reference point: ``x, y, z`` on the rail
    surface (track frame), ``wheel_z`` track z of the wheel's (undeformed) surface there,
    ``y_rail, z_rail`` on the rail profile (its own canonical coordinates, y towards the field
    side), ``y_wheel, z_wheel`` on the canonical wheel profile, ``delta`` contact angle,
    ``radius`` rolling radius. ``width``: lateral extent of the overlap along the rail surface
    (0 without overlap); a parabolic gap of curvature B gives 2 (−gap cos δ_deepest / B)^{1/2},
    and a patch whose width differs much from that is far from Hertz's ellipse.
    """

    side: str
    slot: int
    gap: float
    delta_deepest: float
    A: float
    B: float
    x: float
    y: float
    z: float
    wheel_z: float
    y_rail: float
    z_rail: float
    y_wheel: float
    z_wheel: float
    delta: float
    radius: float
    width: float


@dataclass(frozen=True)
class WheelContact:
    """The contact points of one wheel, ordered by slot."""

    side: str
    points: tuple[ContactPoint, ...]


@dataclass(frozen=True)
class WheelsetPosition:
    """A wheelset's position on the track (:mod:`.track`): lateral shift ``y`` and height ``z``
    (m, positive down from the nominal height), ``roll`` and ``yaw`` (rad)."""

    y: float
    z: float
    roll: float
    yaw: float


@dataclass(frozen=True)
class WheelsetContact:
    """The wheelset's ``position`` and the contact points of both wheels."""

    position: WheelsetPosition
    left: WheelContact
    right: WheelContact

    def wheel(self, side: str) -> WheelContact:
        return self.left if side == "left" else self.right


@dataclass(frozen=True)
class _Position:
    m: WheelsetOnTrack
    side: str
    y: float
    z: float
    roll: float
    yaw: float

    def silhouette(self, yw: np.ndarray, zw: np.ndarray | None = None,
                   dzw: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
        """Track (X, Y, Z) of the wheel's locus points at profile coordinates ``yw`` (with the
        profile's ``zw`` and slope ``dzw`` there, if known) and their vertical gaps to the rail
        (inf off the usable profiles)."""
        m, sig, r0 = self.m, SIDES[self.side], self.m.wheelset.nominal_radius
        if zw is None:
            zw, dzw = m.wheel.z(yw), m.wheel.slope(yw)
        r = r0 + zw
        Yw = sig * (m.wheelset.wheel_offset + yw)
        st = -math.tan(self.yaw) * sig * dzw                 # dr/dY = σ dz_w/dy_w
        px, pz = r * st, r * np.sqrt(1.0 - st * st)
        cy, sy = math.cos(self.yaw), math.sin(self.yaw)
        cr, sr = math.cos(self.roll), math.sin(self.roll)
        qx, qy = cy * px - sy * Yw, sy * px + cy * Yw
        Y = self.y + cr * qy - sr * pz
        Z = (self.z - r0) + sr * qy + cr * pz
        g = m.rail_height(self.side, Y) - Z
        return qx, Y, Z, np.where(np.isfinite(g), g, np.inf)

    def grid(self, step: float) -> tuple[np.ndarray, np.ndarray]:
        """The search grid along the wheel profile and the gaps there."""
        yw, zw, dzw = _wheel_grid(self.m, step)
        return yw, self.silhouette(yw, zw, dzw)[3]


@cached(8)
def _wheel_grid(m: WheelsetOnTrack, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Grid of step ``step`` over the wheel's usable profile, with z and slope there."""
    f = m.wheel
    yw = np.linspace(f.y_min, f.y_max, max(int(math.ceil((f.y_max - f.y_min) / step)), 4) + 1)
    return yw, f.z(yw), f.slope(yw)


def _minima(pos: _Position, yw: np.ndarray, g: np.ndarray, separation: float) -> list[int]:
    """Grid indices of the separated local minima of the gap, deepest first (at most two)."""
    inner = np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] < g[2:]) & np.isfinite(g[1:-1])) + 1
    if inner.size == 0:
        raise ValueError(f"{pos.side} wheel: no contact point found within the usable profiles "
                         f"(y={pos.y!r} m, yaw={pos.yaw!r} rad): the wheel is off its rail")
    keep = list(inner)
    while len(keep) > 1:                         # merge the least separated neighbours first
        rises = [g[a:b + 1].max() - max(g[a], g[b]) for a, b in zip(keep[:-1], keep[1:])]
        k = int(np.argmin(rises))
        if rises[k] >= separation:
            break
        a, b = keep[k], keep[k + 1]
        keep.remove(a if g[a] > g[b] else b)
    return sorted(keep, key=lambda i: g[i])[:2]


def _deepest(pos: _Position, yw: np.ndarray, i: int) -> tuple[float, float]:
    """(y_w, gap) of the minimum near grid index ``i``: a finer grid over the two neighbouring
    steps, then a parabola through its smallest value."""
    fine = np.linspace(yw[i - 1], yw[i + 1], _FINE)
    g = pos.silhouette(fine)[3]
    k = int(np.clip(np.argmin(g), 1, _FINE - 2))
    g0, g1, g2 = g[k - 1], g[k], g[k + 1]
    den = g0 - 2.0 * g1 + g2
    u = 0.5 * (g0 - g2) / den if den > 0.0 and np.isfinite(den) else 0.0
    return float(fine[k] + u * (fine[1] - fine[0])), float(g1 - 0.25 * (g0 - g2) * u)


def _overlap(yw: np.ndarray, g: np.ndarray, i: int, lo_end: int,
             hi_end: int) -> tuple[float, float] | None:
    """Ends (y_w) of the overlap (gap < 0) around grid index ``i`` within the indices
    [``lo_end``, ``hi_end``], one grid step beyond each end, or None without overlap."""
    if not g[i] < 0.0:
        return None
    lo, hi = i, i
    while lo > lo_end and g[lo - 1] < 0.0:
        lo -= 1
    while hi < hi_end and g[hi + 1] < 0.0:
        hi += 1
    return float(yw[max(lo - 1, lo_end)]), float(yw[min(hi + 1, hi_end)])


def _point(pos: _Position, yw_deep: float, gap: float, span: tuple[float, float] | None,
           slot: int) -> ContactPoint:
    m, sig = pos.m, SIDES[pos.side]

    def contact_angle(Y):
        return np.arctan(sig * m.rail.slope(m.rail_point(pos.side, Y)))
    _, Yd, _, _ = pos.silhouette(np.array([yw_deep]))
    yr_deep = float(m.rail_point(pos.side, Yd[0]))
    delta_deep = float(contact_angle(Yd)[0])
    dzw = float(m.wheel.slope(yw_deep))
    A = 0.5 / ((m.wheelset.nominal_radius + float(m.wheel.z(yw_deep))) * math.sqrt(1.0 + dzw * dzw))
    B = 0.5 * (float(m.rail.curvature(yr_deep)) - float(m.wheel.curvature(yw_deep)))
    yw_ref, delta, width = yw_deep, delta_deep, 0.0
    if span is not None:                     # weighted centre of the overlap, strips ∝ overlap^2.5
        fine = np.linspace(*span, _REFERENCE_POINTS)
        _, Yf, _, gf = pos.silhouette(fine)
        inside = gf < 0.0
        w = (-gf[inside]) ** 2.5
        yw_ref = float(np.sum(fine[inside] * w) / np.sum(w))
        delta = float(np.sum(contact_angle(Yf[inside]) * w) / np.sum(w))
        s = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(Yf), np.diff(m.rail_height(
            pos.side, Yf))))))               # arc length along the rail surface
        k = np.flatnonzero(inside)
        i0, i1 = k[0], k[-1]                 # overlap ends by linear interpolation of the gap
        s0 = s[i0] - (s[i0] - s[i0 - 1]) * gf[i0] / (gf[i0] - gf[i0 - 1]) if i0 > 0 else s[i0]
        s1 = (s[i1] + (s[i1 + 1] - s[i1]) * gf[i1] / (gf[i1] - gf[i1 + 1])
              if i1 < gf.size - 1 else s[i1])
        width = float(s1 - s0)
    X, Y, Z, _ = (float(v[0]) for v in pos.silhouette(np.array([yw_ref])))
    yr = float(m.rail_point(pos.side, Y))
    zr = float(m.rail.z(yr))
    y_rail, z_rail = m.rail_profile_coordinates(yr, zr)
    zw = float(m.wheel.z(yw_ref))
    return ContactPoint(pos.side, slot, gap, delta_deep, A, B, X, Y, zr - m.rail_top, Z, y_rail,
                        z_rail, yw_ref, zw, delta, m.wheelset.nominal_radius + zw, width)


def wheel_contact(model: WheelsetOnTrack, side: str, y: float, z: float, roll: float,
                  yaw: float = 0.0, *, separation: float = SEPARATION,
                  flange_angle: float = FLANGE_ANGLE, step: float = STEP) -> WheelContact:
    """Contact points of the ``side`` wheel of the wheelset at ``y``, ``z`` (m), ``roll``,
    ``yaw`` (rad) (module docstring)."""
    if side not in SIDES:
        raise ValueError(f"side={side!r} is invalid: allowed {list(SIDES)}")
    _check_position(y, z, roll, yaw, separation, step)
    pos = _Position(model, side, float(y), float(z), float(roll), float(yaw))
    yw, g = pos.grid(step)
    found = _minima(pos, yw, g, separation)
    deep = [_deepest(pos, yw, i) for i in found]
    ends = [(0, g.size - 1)] * len(found)
    if len(found) == 2:                      # two patches: their overlaps meet at the gap's peak
        a, b = sorted(found)
        peak = a + int(np.argmax(g[a:b + 1]))
        ends = [(0, peak) if i == a else (peak, g.size - 1) for i in found]
        order = sorted(range(2), key=lambda k: -deep[k][0])  # field side (larger y_w) first
        slots = (0, 1)
    else:
        order = [0]
        wheel_angle = abs(math.atan(float(model.wheel.slope(deep[0][0]))))
        slots = (int(wheel_angle > flange_angle),)
    return WheelContact(side, tuple(
        _point(pos, deep[k][0], deep[k][1], _overlap(yw, g, found[k], *ends[k]), s)
        for k, s in zip(order, slots)))


def _check_position(y: float, z: float, roll: float, yaw: float, separation: float,
                    step: float) -> None:
    for name, v in (("y", y), ("z", z)):
        if not math.isfinite(v):
            raise ValueError(f"{name}={v!r} is not finite")
    for name, v in (("roll", roll), ("yaw", yaw)):
        if not (math.isfinite(v) and abs(v) < 0.2):
            raise ValueError(f"{name}={v!r} is out of range: allowed |{name}| < 0.2 rad")
    if not (0.0 <= separation and 0.0 < step <= 1e-3):
        raise ValueError(f"separation={separation!r}, step={step!r}: allowed separation >= 0, "
                         "0 < step <= 1e-3 m")


def touch_height(model: WheelsetOnTrack, side: str, y: float, roll: float, yaw: float = 0.0,
                 *, step: float = STEP) -> float:
    """z (m) at which the ``side`` wheel's smallest gap is zero (the gap falls one-for-one
    with z)."""
    return _touch(model, side, y, roll, yaw, step)[0]


def _touch(model: WheelsetOnTrack, side: str, y: float, roll: float, yaw: float,
           step: float) -> tuple[float, float]:
    """:func:`touch_height` and the track y of that wheel's deepest point."""
    _check_position(y, 0.0, roll, yaw, 0.0, step)
    pos = _Position(model, side, float(y), 0.0, float(roll), float(yaw))
    yw, g = pos.grid(step)
    yw_deep, gap = _deepest(pos, yw, _minima(pos, yw, g, math.inf)[0])
    return gap, float(pos.silhouette(np.array([yw_deep]))[1][0])


def rigid_roll(model: WheelsetOnTrack, y: float, yaw: float = 0.0, *, step: float = STEP,
               roll: float = 0.0) -> float:
    """The roll (rad) at which both wheels touch their rails at once (rigid contact), from the
    start value ``roll``: Newton's iteration on the height mismatch of the two wheels, whose
    derivative with respect to the roll is the lateral distance between their contact points;
    Brent's method on ±0.02 rad if that does not converge (a contact point jumping)."""
    for _ in range(12):
        zl, yl = _touch(model, "left", y, roll, yaw, step)
        zr, yr = _touch(model, "right", y, roll, yaw, step)
        if abs(zl - zr) < 1e-11:
            return roll
        roll -= (zl - zr) / (yr - yl)
        if not abs(roll) < 0.02:
            break

    def mismatch(phi: float) -> float:
        return (_touch(model, "left", y, phi, yaw, step)[0]
                - _touch(model, "right", y, phi, yaw, step)[0])
    if mismatch(-0.02) * mismatch(0.02) > 0.0:
        raise ValueError(f"y={y!r} m, yaw={yaw!r} rad: no roll within ±0.02 rad puts both "
                         "wheels on their rails")
    return brentq(mismatch, -0.02, 0.02, xtol=1e-12)


def contact_search(model: WheelsetOnTrack, y: float, yaw: float = 0.0, roll: float | None = None,
                   z: float | None = None, *, separation: float = SEPARATION,
                   flange_angle: float = FLANGE_ANGLE, step: float = STEP) -> WheelsetContact:
    """Contact points of both wheels at lateral shift ``y`` (m) and yaw ``yaw`` (rad); ``roll``
    (rad) and ``z`` (m, positive down from the nominal height) given, or following from the
    wheels touching (module docstring)."""
    _check_position(y, 0.0 if z is None else z, 0.0 if roll is None else roll, yaw, separation,
                    step)
    if roll is None:
        if z is not None:
            raise ValueError("z given without roll: give roll too, or neither (rigid contact)")
        roll = rigid_roll(model, y, yaw, step=step)
    if z is None:
        z = min(touch_height(model, s, y, roll, yaw, step=step) for s in SIDES)
    return WheelsetContact(WheelsetPosition(float(y), float(z), float(roll), float(yaw)),
                           *(wheel_contact(model, s, y, z, roll, yaw, separation=separation,
                                           flange_angle=flange_angle, step=step) for s in SIDES))
