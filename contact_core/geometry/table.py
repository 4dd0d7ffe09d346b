"""The contact-geometry table of vehicle codes: every contact quantity of both wheels over y.

Built once (:func:`contact_table`) from the rigid contact search (:func:`.search.contact_search`
with roll and height following from both wheels touching, yaw 0) on a grid of lateral shifts,
then evaluated at run time by interpolation: one ``scipy.interpolate.PchipInterpolator`` (a
``PPoly`` of monotone cubic Hermite pieces, which does not overshoot where a contact point jumps)
holds every column, so that :meth:`ContactTable.values` costs one ``PPoly`` evaluation.

Per wheel (left, right) and slot (0 tread, 1 flange; :mod:`.search`), the columns
:data:`PATCH_QUANTITIES`:

- ``present``: 1 where the search finds the slot's patch, else 0 (then ``gap`` is
  :data:`ABSENT_GAP`, ``weight`` 0, and the geometry is held from the nearest y where the slot
  is present, so that the interpolation stays finite);
- ``gap``: vertical gap of the patch's deepest point above the wheel's rigid contact (m, >= 0;
  0 for the patch the wheel stands on): a vehicle model that computes its own approach d gives
  the patch the normal overlap (d − gap) cos ``delta_deepest``;
- ``weight``: the patch's share of the wheel's load at the table's nominal ``load`` per wheel
  (:mod:`.loads`: common approach, Hertz per patch): the flag/weight of the flange patch;
- ``delta``: contact angle (rad; :mod:`.search`); ``delta_deepest`` equal here (rigid contact:
  the reference point is the deepest point);
- ``radius``: rolling radius (m);
- ``A``, ``B``: relative curvatures (1/m), and ``ka``, ``kb``, ``kd``: Hertz's a = ka N^{1/3},
  b = kb N^{1/3}, approach = kd N^{2/3} for the table's E and ν
  (:func:`contact_core.hertz.hertz_geometry`);
- ``y``, ``z``: contact point in the track frame (m), ``y_rail``, ``y_wheel`` on the profiles;
- ``x_per_yaw``: longitudinal position of the contact point per unit yaw, m/rad (first order in
  ψ: the wheelset's rotation about its centre and the contact locus' lead,
  X ≈ −σ ψ (b + y_w + r dz_w/dy_w), derived here from the contact locus of :mod:`.search`,
  Vollebregt 2022).

Per wheel also ``radius_contact`` (the rolling radius of the rigid contact point) and per table
``roll`` and ``z`` of the wheelset. Both wheels are equal and the track symmetric, so the table is
computed for y >= 0 and completed by symmetry (the left wheel at −y is the right wheel at y,
mirrored).

A table is written to and read from a NumPy ``.npz`` archive of plain arrays
(:meth:`ContactTable.save`, :func:`load_table`), so that a model can ship one instead of building
it at start-up.

Rolling-radius difference Δr(y) = r_right − r_left of the rigid contact points (positive for a
shift to the right, y > 0), and the equivalent conicity (EN 15302) by harmonic linearisation of
Δr for a sinusoidal motion y = A sin τ (Polach 2010, "Characteristic parameters of nonlinear
wheel/rail contact geometry", Vehicle System Dynamics 48 S1):

    γ_e(A) = 1/(2πA) ∫_0^{2π} Δr(A sin τ) sin τ dτ,

exact (γ_e = γ) for a cone pair with Δr = 2γy.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.interpolate import PchipInterpolator

from .loads import patch_geometry, share_load
from .search import ContactPoint, WheelsetContact, contact_search, rigid_roll
from .track import SIDES, WheelsetOnTrack

#: Columns per wheel and slot, in order.
PATCH_QUANTITIES: tuple[str, ...] = (
    "present", "gap", "weight", "delta", "delta_deepest", "radius", "A", "B", "ka", "kb", "kd",
    "y", "z", "y_rail", "y_wheel", "x_per_yaw")
#: Columns per wheel.
WHEEL_QUANTITIES: tuple[str, ...] = ("radius_contact",)
#: Columns of the wheelset.
WHEELSET_QUANTITIES: tuple[str, ...] = ("roll", "z")
#: ``gap`` of an absent slot, m.
ABSENT_GAP = 1e-3
#: Version of the file format of :meth:`ContactTable.save`.
FORMAT_VERSION = 1
_SIDE_ORDER = ("left", "right")


def _column_names() -> tuple[str, ...]:
    names = list(WHEELSET_QUANTITIES)
    for side in _SIDE_ORDER:
        names += [f"{side}.{q}" for q in WHEEL_QUANTITIES]
        for slot in (0, 1):
            names += [f"{side}.{slot}.{q}" for q in PATCH_QUANTITIES]
    return tuple(names)


#: All columns of :meth:`ContactTable.values`, in order.
COLUMNS: tuple[str, ...] = _column_names()
_INDEX = {name: i for i, name in enumerate(COLUMNS)}


@dataclass(frozen=True)
class TablePatch:
    """One wheel's patch in one slot at a lateral shift (units of :data:`PATCH_QUANTITIES`;
    ``x`` the contact point's longitudinal position at the evaluated yaw, m)."""

    side: str
    slot: int
    present: float
    gap: float
    weight: float
    delta: float
    delta_deepest: float
    radius: float
    A: float
    B: float
    ka: float
    kb: float
    kd: float
    y: float
    z: float
    y_rail: float
    y_wheel: float
    x: float


@dataclass(frozen=True, eq=False)
class ContactTable:
    """Contact geometry over the lateral shift (module docstring): the grid ``y`` (m), the
    tabulated ``data`` (one row per y, :data:`COLUMNS`), the nominal ``load`` per wheel (N) and
    the elastic constants ``E`` (Pa), ``nu`` of the weights and Hertz factors."""

    y: np.ndarray
    data: np.ndarray
    load: float
    E: float
    nu: float

    def __post_init__(self) -> None:
        y, data = np.array(self.y, dtype=float), np.array(self.data, dtype=float)
        if y.ndim != 1 or y.size < 2 or not np.all(np.diff(y) > 0.0):
            raise ValueError("y must be a strictly increasing 1-D grid of at least 2 shifts (m)")
        if data.shape != (y.size, len(COLUMNS)):
            raise ValueError(f"data must have the shape (len(y), {len(COLUMNS)}) of COLUMNS "
                             f"(got {data.shape})")
        for a in (y, data):
            a.setflags(write=False)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "data", data)

    def save(self, path) -> None:
        """Write the table as a NumPy ``.npz`` archive of plain arrays (format
        :data:`FORMAT_VERSION`, columns by name; read back with :func:`load_table`)."""
        np.savez(path, format_version=np.array(FORMAT_VERSION), columns=np.array(COLUMNS),
                 y=self.y, data=self.data, load=np.array(self.load), E=np.array(self.E),
                 nu=np.array(self.nu))

    @cached_property
    def interpolant(self) -> PchipInterpolator:
        return PchipInterpolator(self.y, self.data, axis=0, extrapolate=False)

    def values(self, y: float) -> np.ndarray:
        """Every column (:data:`COLUMNS`) at lateral shift ``y`` (m; NaN outside the table)."""
        return self.interpolant(y)

    def column(self, name: str, y) -> np.ndarray:
        """One column at ``y`` (scalar or array)."""
        return self.interpolant(y)[..., _INDEX[name]]

    def patches(self, y: float, yaw: float = 0.0) -> dict[tuple[str, int], TablePatch]:
        """Both wheels' patches at ``y`` (m) and small ``yaw`` (rad), by (side, slot)."""
        v = self.values(y)
        out = {}
        for side in _SIDE_ORDER:
            for slot in (0, 1):
                i = _INDEX[f"{side}.{slot}.present"]
                q = dict(zip(PATCH_QUANTITIES, (float(a) for a in v[i:i + len(PATCH_QUANTITIES)])))
                x = q.pop("x_per_yaw") * yaw
                out[side, slot] = TablePatch(side, slot, **q, x=x)
        return out

    def rolling_radius_difference(self, y) -> np.ndarray:
        """Δr(y) = r_right − r_left of the rigid contact points, m."""
        v = self.interpolant(y)
        return v[..., _INDEX["right.radius_contact"]] - v[..., _INDEX["left.radius_contact"]]

    def equivalent_conicity(self, amplitudes, n: int = 2048) -> np.ndarray:
        """γ_e at each amplitude (m; 0 < A <= the table's largest |y|) by harmonic
        linearisation (module docstring; midpoint rule with ``n`` points over a period)."""
        amp = np.atleast_1d(np.asarray(amplitudes, dtype=float))
        if np.any(~(amp > 0.0)) or np.any(amp > self.y[-1] * (1 + 1e-12)):
            raise ValueError(f"amplitudes must lie in 0 < A <= {self.y[-1]!r} m")
        def dr(y):
            return self.rolling_radius_difference(np.clip(y, self.y[0], self.y[-1]))

        return 0.5 * harmonic_gain(dr, amp, n)

    def flange_onset(self) -> float:
        """Smallest y >= 0 (m) on the grid at which the right wheel's flange slot carries load at
        the nominal load (weight > 0); NaN if it never does within the table."""
        return self._first(self.data[:, _INDEX["right.1.weight"]] > 0.0)

    def flange_contact(self, min_angle: float = 1.0) -> float:
        """Smallest y >= 0 (m) on the grid at which the right wheel's rigid contact point is on
        its flange, with a contact angle of at least ``min_angle`` (rad; S1002's flange face
        reaches 70°); NaN if it never is within the table."""
        d = self.data
        on = np.zeros(d.shape[0], dtype=bool)
        for slot in (0, 1):
            stands = (d[:, _INDEX[f"right.{slot}.present"]] > 0.5) & (
                d[:, _INDEX[f"right.{slot}.gap"]] <= 0.0)
            on |= stands & (np.abs(d[:, _INDEX[f"right.{slot}.delta"]]) >= min_angle)
        return self._first(on)

    def _first(self, mask: np.ndarray) -> float:
        idx = np.flatnonzero(mask & (self.y >= 0.0))
        return float(self.y[idx[0]]) if idx.size else math.nan


def harmonic_gain(f, amplitudes, n: int) -> np.ndarray:
    """The gain of the first harmonic of f(y) for y = A sin τ at each amplitude A (harmonic
    linearisation, the describing function of f; EN 15302 and Polach 2010 for the equivalent
    conicity, module docstring):

        g(A) = 1/(πA) ∫_0^{2π} f(A sin τ) sin τ dτ,

    by the midpoint rule with ``n`` points over a period. ``f`` takes the array of the y, of
    shape (amplitudes, n), and returns its values in the same shape; g = c for f = c y."""
    amp = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    s = np.sin((np.arange(n) + 0.5) * (2.0 * math.pi / n))
    values = f(amp[:, None] * s[None, :])
    return (values * s).sum(axis=1) * (2.0 * math.pi / n) / (math.pi * amp)


def load_table(path) -> ContactTable:
    """A table written by :meth:`ContactTable.save` (no pickled objects are read; the format
    version and the columns are checked)."""
    with np.load(path, allow_pickle=False) as f:
        version = int(f["format_version"])
        if version != FORMAT_VERSION:
            raise ValueError(f"{path}: table format {version}, this version reads "
                             f"{FORMAT_VERSION}")
        if tuple(str(c) for c in f["columns"]) != COLUMNS:
            raise ValueError(f"{path}: the columns differ from this version's COLUMNS")
        return ContactTable(f["y"], f["data"], float(f["load"]), float(f["E"]), float(f["nu"]))


def _weights(points: tuple[ContactPoint, ...], load: float, E: float,
             nu: float) -> tuple[list[float], list]:
    """Load shares of a wheel's patches at ``load`` (:func:`.loads.share_load`) and their Hertz
    factors."""
    N = share_load(points, load, E, nu)
    return [n / sum(N) for n in N], [patch_geometry(p, E, nu) for p in points]


def _row(m: WheelsetOnTrack, c: WheelsetContact, load: float, E: float, nu: float) -> np.ndarray:
    row = np.full(len(COLUMNS), np.nan)
    row[_INDEX["roll"]], row[_INDEX["z"]] = c.position.roll, c.position.z
    b = m.wheelset.wheel_offset
    for side in _SIDE_ORDER:
        sig, pts = SIDES[side], c.wheel(side).points
        w, geo = _weights(pts, load, E, nu)
        deepest = min(pts, key=lambda p: p.gap)
        row[_INDEX[f"{side}.radius_contact"]] = deepest.radius
        for p, wi, h in zip(pts, w, geo):
            dzw = float(m.wheel.slope(p.y_wheel))
            vals = dict(present=1.0, gap=p.gap - deepest.gap, weight=wi, delta=p.delta,
                        delta_deepest=p.delta_deepest, radius=p.radius, A=p.A, B=p.B, ka=h.ka,
                        kb=h.kb, kd=h.kd, y=p.y, z=p.z, y_rail=p.y_rail, y_wheel=p.y_wheel,
                        x_per_yaw=-sig * (b + p.y_wheel + p.radius * dzw))
            for q, v in vals.items():
                row[_INDEX[f"{side}.{p.slot}.{q}"]] = v
    return row


def _mirror(row: np.ndarray) -> np.ndarray:
    """The row of −y from the row of y: the wheels swap sides, mirrored."""
    out = row.copy()
    out[_INDEX["roll"]] = -row[_INDEX["roll"]]
    for side, other in (("left", "right"), ("right", "left")):
        out[_INDEX[f"{side}.radius_contact"]] = row[_INDEX[f"{other}.radius_contact"]]
        for slot in (0, 1):
            for q in PATCH_QUANTITIES:
                v = row[_INDEX[f"{other}.{slot}.{q}"]]
                out[_INDEX[f"{side}.{slot}.{q}"]] = -v if q in ("delta", "delta_deepest", "y",
                                                                 "x_per_yaw") else v
    return out


def _fill_absent(data: np.ndarray) -> None:
    """Absent slots: present 0, weight 0, gap ABSENT_GAP, geometry held from the nearest row
    where the slot is present (else from slot 0 of that wheel)."""
    for side in _SIDE_ORDER:
        for slot in (0, 1):
            cols = [_INDEX[f"{side}.{slot}.{q}"] for q in PATCH_QUANTITIES]
            present = ~np.isnan(data[:, cols[0]])
            if not present.any():
                other = [_INDEX[f"{side}.{1 - slot}.{q}"] for q in PATCH_QUANTITIES]
                data[:, cols] = data[:, other]
            else:
                idx = np.flatnonzero(present)
                nearest = idx[np.abs(np.arange(data.shape[0])[:, None] - idx[None, :]).argmin(1)]
                data[np.ix_(~present, cols)] = data[np.ix_(nearest[~present], cols)]
            missing = ~present
            data[missing, _INDEX[f"{side}.{slot}.present"]] = 0.0
            data[missing, _INDEX[f"{side}.{slot}.weight"]] = 0.0
            data[missing, _INDEX[f"{side}.{slot}.gap"]] = ABSENT_GAP


def contact_table(model: WheelsetOnTrack, y_max: float = 0.010, step: float = 5e-5, *,
                  load: float = 50e3, E: float = 210e9, nu: float = 0.28) -> ContactTable:
    """Tabulate the contact geometry of ``model`` for lateral shifts −``y_max`` ... ``y_max``
    (m) every ``step`` m (module docstring); weights at ``load`` N per wheel, Hertz factors for
    Young's modulus ``E`` (Pa) and Poisson's ratio ``nu``."""
    if not (0.0 < step <= y_max <= 0.05 and math.isfinite(y_max)):
        raise ValueError(f"y_max={y_max!r}, step={step!r}: allowed 0 < step <= y_max <= 0.05 m")
    if not (math.isfinite(load) and load > 0.0):
        raise ValueError(f"load={load!r} is out of range: allowed 0 < load < inf (N per wheel)")
    n = int(round(y_max / step))
    ys = np.linspace(0.0, n * step, n + 1)
    rows, roll = [], 0.0
    for y in ys:
        roll = rigid_roll(model, float(y), roll=roll)
        rows.append(_row(model, contact_search(model, float(y), roll=roll), load, E, nu))
    pos = np.array(rows)
    data = np.vstack([np.array([_mirror(r) for r in pos[:0:-1]]), pos])
    _fill_absent(data)
    return ContactTable(np.concatenate((-ys[:0:-1], ys)), data, float(load), float(E), float(nu))
