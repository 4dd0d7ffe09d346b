"""Track and wheelset dimensions: where the two rails and the two wheel profiles sit.

Track frame (the frame of the reference wheelset models and of CONTACT's module 1): x along the
track in the direction of travel, y to the right, z down; origin on the track centre line in the
plane that touches the tops of both rails (the track plane). Track cant (superelevation) turns
the whole track frame and so leaves the wheel–rail geometry in it unchanged; the rail
*inclination* (e.g. 1:40 towards the track centre) turns each rail profile and is applied here.

Rail placement (Vollebregt, CONTACT user guide, sec. "Track and roller geometry", gauge point
computation): the canonical (right-hand) rail profile is inclined by ``inclination`` towards the
track centre, lifted so that its highest point touches the track plane, and moved laterally so
that its gauge face, measured ``gauge_height`` below the track plane, is at ``gauge``/2 from the
centre line. The left rail is the mirror image. A rail-profile point (y_r, z_r) of the inclined
profile is then at track y = σ (c + y_r), z = z_r − z_top, with σ = −1 left, +1 right and
c = :attr:`WheelsetOnTrack.rail_offset`.

Wheel placement (same source, "Wheelset geometry"): the wheel-profile origin is at lateral
distance b = d_fb/2 − y_fb from the wheelset centre (d_fb the flange-back distance, y_fb the
flange back's position on the canonical wheel profile, e.g. −70 mm for S1002 with its origin on
the tape circle) and r0 (nominal rolling radius) below the axle: a wheel-profile point (y_w, z_w)
is at wheelset lateral coordinate σ (b + y_w) on the circle of radius r0 + z_w.

Wheelset position (CONTACT's convention): centre at (0, y, z − r0) in the track frame (z = 0 is
the nominal height, positive down), orientation R = R_x(roll) R_z(yaw) (then pitch about the axle,
irrelevant for a round wheel); positive roll lowers the right wheel, positive yaw turns the
wheelset's heading towards +y.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.optimize import brentq

from .profiles import Profile, ProfileFunction, shipped_profile

#: Sides and their signs σ in the track frame.
SIDES: dict[str, float] = {"left": -1.0, "right": 1.0}


def _positive(name: str, v: float, unit: str) -> None:
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name}={v!r} is out of range: allowed 0 < {name} < inf ({unit})")


@dataclass(frozen=True, eq=False)
class Track:
    """Straight track with two equal rails (module docstring).

    ``rail``: canonical rail profile; ``gauge``: distance between the gauge faces, m, measured
    ``gauge_height`` (m) below the track plane; ``inclination``: rail inclination towards the
    track centre, rad (1:40 is ``atan(1/40)``; 0 for a profile given inclined, as the benchmark's).
    """

    rail: Profile
    gauge: float = 1.435
    gauge_height: float = 0.014
    inclination: float = 0.0

    def __post_init__(self) -> None:
        if self.rail.kind != "rail":
            raise ValueError(f"rail must be a rail profile (got a {self.rail.kind} profile)")
        _positive("gauge", self.gauge, "m")
        _positive("gauge_height", self.gauge_height, "m")
        if not (math.isfinite(self.inclination) and abs(self.inclination) < 0.2):
            raise ValueError(f"inclination={self.inclination!r} is out of range: allowed "
                             "|inclination| < 0.2 rad")


@dataclass(frozen=True, eq=False)
class Wheelset:
    """A wheelset with two equal wheels (module docstring): canonical ``wheel`` profile,
    ``flange_back_distance`` d_fb (m), ``flange_back_position`` y_fb on the wheel profile (m),
    ``nominal_radius`` r0 (m) at the wheel profile's origin."""

    wheel: Profile
    flange_back_distance: float = 1.360
    flange_back_position: float = -0.070
    nominal_radius: float = 0.460

    def __post_init__(self) -> None:
        if self.wheel.kind != "wheel":
            raise ValueError(f"wheel must be a wheel profile (got a {self.wheel.kind} profile)")
        _positive("flange_back_distance", self.flange_back_distance, "m")
        _positive("nominal_radius", self.nominal_radius, "m")
        if not math.isfinite(self.flange_back_position):
            raise ValueError(f"flange_back_position={self.flange_back_position!r} is not finite")

    @property
    def wheel_offset(self) -> float:
        """b: lateral distance from the wheelset centre to each wheel profile's origin, m."""
        return 0.5 * self.flange_back_distance - self.flange_back_position


@dataclass(frozen=True, eq=False)
class WheelsetOnTrack:
    """A :class:`Wheelset` on a :class:`Track`: the placed profiles the contact search uses."""

    track: Track
    wheelset: Wheelset

    @cached_property
    def rail_profile(self) -> Profile:
        """The rail profile as placed: canonical, inclined towards the track centre."""
        # the head leans towards the centre (canonical -y): rotation by -inclination (+y to +z)
        r = self.track.rail
        return r.rotated(-self.track.inclination) if self.track.inclination else r

    @cached_property
    def rail(self) -> ProfileFunction:
        """z(y) of the placed rail profile (its own origin, before the lift :attr:`rail_top`)."""
        return self.rail_profile.function()

    @cached_property
    def wheel(self) -> ProfileFunction:
        """z(y) of the canonical wheel profile."""
        return self.wheelset.wheel.function()

    @cached_property
    def rail_top(self) -> float:
        """z of the placed rail profile's highest point (the track plane is at z = 0)."""
        f = self.rail
        y = np.linspace(f.y_min, f.y_max, 4001)
        i = int(np.argmin(f.z(y)))
        lo, hi = y[max(i - 1, 0)], y[min(i + 1, y.size - 1)]
        return float(f.z(brentq(lambda v: float(f.slope(v)), lo, hi, xtol=1e-12))
                     if f.slope(lo) * f.slope(hi) < 0.0 else f.z(y[i]))

    @cached_property
    def gauge_point(self) -> float:
        """y (placed rail profile) of the gauge face ``gauge_height`` below the track plane."""
        curve = self.rail_profile.curve
        t = np.linspace(0.0, self.rail_profile.arc_length[-1], 20001)
        zs = curve(t)[:, 1]
        target = self.rail_top + self.track.gauge_height
        below = np.flatnonzero(zs[:int(np.argmin(zs))] >= target)  # gauge side: before the top
        if below.size == 0:
            raise ValueError(f"the rail profile does not reach gauge_height="
                             f"{self.track.gauge_height!r} m below its top on the gauge side")
        j = int(below[-1])
        tc = brentq(lambda v: float(curve(v)[1]) - target, t[j], t[j + 1], xtol=1e-13)
        return float(curve(tc)[0])

    @cached_property
    def rail_offset(self) -> float:
        """c: lateral distance from the track centre line to each placed rail profile's origin
        (m)."""
        return 0.5 * self.track.gauge - self.gauge_point

    def rail_point(self, side: str, y_track):
        """Lateral coordinate on the placed rail profile under the track's ``y_track``."""
        return SIDES[side] * np.asarray(y_track) - self.rail_offset

    def rail_height(self, side: str, y_track):
        """Track z of the rail surface under ``y_track`` (NaN off the rail's usable range)."""
        return self.rail.z(self.rail_point(side, y_track)) - self.rail_top

    def rail_profile_coordinates(self, y_placed: float, z_placed: float) -> tuple[float, float]:
        """A placed-rail-profile point in the rail profile's own (uninclined) coordinates."""
        a = self.track.inclination
        if not a:
            return y_placed, z_placed
        c, s = math.cos(a), math.sin(a)
        return c * y_placed - s * z_placed, s * y_placed + c * z_placed


def benchmark_model() -> WheelsetOnTrack:
    """The Manchester Contact Benchmark's wheelset on track (Shackleton & Iwnicki 2008; set-up
    of case A-2.2 as in CONTACT's example): new S1002 wheels and UIC60 rails inclined 1:40 (in
    the profile), gauge 1435 mm at 14 mm below the top of rail, flange-back distance 1360 mm,
    flange back at y = −70 mm of the wheel profile, nominal rolling radius 460 mm."""
    return WheelsetOnTrack(Track(shipped_profile("UIC60"), 1.435, 0.014, 0.0),
                           Wheelset(shipped_profile("S1002"), 1.360, -0.070, 0.460))
