"""Wheel and rail profiles: canonical form, SIMPACK ``.prw``/``.prr`` files, y–z tables, splines.

Canonical form (the form of Vollebregt's CONTACT user guide, sec. "Inputs regarding wheel and rail
profiles", and of SIMPACK's profile files after their processing flags): the profile of a **right**
wheel or rail seen from behind, lengths in m,

- ``y`` lateral, positive towards the field side (away from the track centre);
- ``z`` vertical, positive **down**: into the rail below its running surface, away from the axle
  for a wheel (a wheel's rolling radius at a profile point is ``r0 + z``);
- points ordered with the material on the right: a rail from the track-centre side to the field
  side (``y`` ascending), a wheel from the field side to the flange (``y`` descending).

A left wheel or rail uses the same profile mirrored (:mod:`.track` places both).

Interpolation: a cubic spline of the arc length (summed chord length) through the points for
``y(s)`` and ``z(s)``. ``smoothing`` = 0 interpolates the points (scipy ``make_interp_spline``,
not-a-knot ends); ``smoothing`` = L > 0 is the weighted smoothing spline of Vollebregt (2022,
"Detailed wheel/rail geometry processing using the planar contact approach", Vehicle System
Dynamics 60) as CONTACT's user guide states it: it minimises Σ w_i |x_i − f(s_i)|² + λ ∫|f''|² ds
with w_i = (s_{i+1} − s_{i−1})/2 and λ = (L/2π)⁴, a low-pass filter that suppresses wavelengths
below L (scipy ``make_smoothing_spline``). :meth:`Profile.function` resamples that curve as a
function z(y) (a cubic Hermite ``PPoly``) on the part whose inclination stays below a bound, for
the vectorised contact search.

SIMPACK files: the processing flags of the ``spline`` block are applied in SIMPACK's numbered
order (as CONTACT's reader does): 1 ``point.dist.min`` (drop points closer than this to the last
kept one), 2 ``shift.y``/``shift.z``, 3 ``rotate`` (about the profile's x axis, positive from +y
towards +z, in ``units.ang.f`` units; CONTACT does not implement it, our assumption of its sign is
stated here), 4 ``bound.y.min/max`` (drop points outside, when min < max) and ``bound.z.min/max``
(clip, when min < max), 5 ``mirror.y``/``mirror.z`` (negate), 7 ``units.len.f`` (user length per
m), 6 ``inversion`` (reverse the order). A profile that is not in the canonical order after the
flags is reversed (as CONTACT does). ``approx.smooth`` is SIMPACK's own smoothing value: 0 means
interpolation and is honoured; a non-zero value has no published definition we can reproduce, so
it must be replaced by an explicit ``smoothing=`` (our L above) or the reader raises.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
from scipy.interpolate import (BSpline, CubicHermiteSpline, PPoly, make_interp_spline,
                               make_smoothing_spline)

KINDS: tuple[str, ...] = ("wheel", "rail")
#: Folder of the profiles shipped with the package (see its README.md for their sources).
DATA_DIR = Path(__file__).resolve().parent.parent / "data" / "profiles"
#: Shipped profiles by name.
SHIPPED: dict[str, str] = {"S1002": "MBench_S1002_v3.prw", "UIC60": "MBench_UIC60_v3.prr"}


def _as_points(name: str, v) -> np.ndarray:
    a = np.array(v, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of profile coordinates in m")
    return a


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile in the canonical form (module docstring).

    Parameters
    ----------
    y, z : array_like
        Profile points, m (at least 4, finite, distinct consecutive points). Reversed into the
        canonical order if given the other way round.
    kind : str
        ``"wheel"`` or ``"rail"``.
    smoothing : float
        Filter wavelength L of the smoothing spline, m; 0 interpolates the points.
    name : str
        Label (the file it was read from).
    """

    y: np.ndarray
    z: np.ndarray
    kind: str
    smoothing: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        y, z = _as_points("y", self.y), _as_points("z", self.z)
        if self.kind not in KINDS:
            raise ValueError(f"kind={self.kind!r} is invalid: allowed {list(KINDS)}")
        if y.shape != z.shape or y.size < 4:
            raise ValueError(f"y and z must have the same length >= 4 (got {y.size}, {z.size})")
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise ValueError("y and z must be finite")
        if np.any(np.hypot(np.diff(y), np.diff(z)) == 0.0):
            raise ValueError("the profile repeats a point: consecutive points must differ")
        if not (math.isfinite(self.smoothing) and self.smoothing >= 0.0):
            raise ValueError(f"smoothing={self.smoothing!r} is out of range: allowed 0 <= smoothing"
                             " < inf (filter wavelength, m; 0 interpolates)")
        ascending = y[-1] > y[0]
        if ascending != (self.kind == "rail"):
            y, z = y[::-1].copy(), z[::-1].copy()
        y.setflags(write=False)
        z.setflags(write=False)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)

    @cached_property
    def arc_length(self) -> np.ndarray:
        """Summed chord length at each point, m (0 at the first point)."""
        s = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(self.y), np.diff(self.z)))))
        s.setflags(write=False)
        return s

    @cached_property
    def curve(self) -> BSpline:
        """The cubic spline s -> (y, z) of the module docstring (vector-valued ``BSpline``)."""
        s, pts = self.arc_length, np.column_stack((self.y, self.z))
        if self.smoothing == 0.0:
            return make_interp_spline(s, pts, k=3)
        w = np.empty_like(s)                 # w_i = (s_{i+1} - s_{i-1})/2, one-sided at the ends
        w[1:-1] = 0.5 * (s[2:] - s[:-2])
        w[0], w[-1] = 0.5 * (s[1] - s[0]), 0.5 * (s[-1] - s[-2])
        lam = (self.smoothing / (2.0 * math.pi)) ** 4
        sy = make_smoothing_spline(s, self.y, w=w, lam=lam)
        sz = make_smoothing_spline(s, self.z, w=w, lam=lam)
        return BSpline(sy.t, np.column_stack((sy.c, sz.c)), 3)

    def function(self, max_angle: float = math.radians(80.0),
                 step: float = 2e-5) -> "ProfileFunction":
        """The profile as a function z(y) (:class:`ProfileFunction`) on the longest run of the curve
        that is single-valued in y with inclination |atan dz/dy| <= ``max_angle`` (rad), sampled
        every ``step`` m of arc length."""
        return _profile_function(self, float(max_angle), float(step))

    def rotated(self, angle: float) -> "Profile":
        """The profile rotated about the origin by ``angle`` (rad), positive from +y towards +z."""
        c, s = math.cos(angle), math.sin(angle)
        return Profile(c * self.y - s * self.z, s * self.y + c * self.z, self.kind,
                       self.smoothing, self.name)


@dataclass(frozen=True, eq=False)
class ProfileFunction:
    """A profile as a function z(y) (m) with its derivatives: a cubic Hermite ``PPoly`` through
    samples of the profile's spline with their exact slopes; NaN outside ``[y_min, y_max]``."""

    pp: CubicHermiteSpline
    y_min: float
    y_max: float

    @cached_property
    def _d1(self) -> PPoly:
        return self.pp.derivative(1)

    @cached_property
    def _d2(self) -> PPoly:
        return self.pp.derivative(2)

    def z(self, y):
        """Profile height z(y), m (positive down)."""
        return self.pp(y)

    def slope(self, y):
        """dz/dy."""
        return self._d1(y)

    def curvature(self, y):
        """Signed curvature z''/(1 + z'²)^{3/2}, 1/m: positive where the profile bends towards +z
        on both sides (a rail crown, bulging up); a wheel tread that bulges down towards the rail
        has negative values."""
        return self._d2(y) / (1.0 + self._d1(y) ** 2) ** 1.5


def _profile_function(p: Profile, max_angle: float, step: float) -> ProfileFunction:
    if not (0.0 < max_angle < 0.5 * math.pi):
        raise ValueError(f"max_angle={max_angle!r} is out of range: allowed 0 < max_angle < pi/2")
    curve = p.curve
    s_end = float(p.arc_length[-1])
    s = np.linspace(0.0, s_end, max(int(math.ceil(s_end / step)), 8) + 1)
    (y, z), (dy, dz) = curve(s).T, curve(s, 1).T
    sign = 1.0 if p.kind == "rail" else -1.0      # canonical direction of y along the curve
    ok = (sign * dy > 0.0) & (np.abs(dz) <= math.tan(max_angle) * sign * dy)
    # longest run of consecutive admissible samples
    edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.astype(np.int8), [0]))))
    starts, ends = edges[::2], edges[1::2]
    if starts.size == 0 or (ends - starts).max() < 4:
        raise ValueError(f"profile {p.name!r}: no part with inclination below {max_angle} rad")
    i = int(np.argmax(ends - starts))
    sl = slice(starts[i], ends[i])
    y, z, slope = y[sl], z[sl], dz[sl] / dy[sl]
    if sign < 0.0:
        y, z, slope = y[::-1], z[::-1], slope[::-1]
    return ProfileFunction(CubicHermiteSpline(y, z, slope, extrapolate=False), float(y[0]),
                           float(y[-1]))


# ---------------------------------------------------------------------------------------------
# SIMPACK profile files

_KEY = re.compile(r"^\s*([A-Za-z][\w.]*)\s*=\s*(.*?)\s*$")
_DEFAULTS = {"point.dist.min": 0.0, "shift.y": 0.0, "shift.z": 0.0, "rotate": 0.0,
             "bound.y.min": 1.0, "bound.y.max": 0.0, "bound.z.min": 1.0, "bound.z.max": 0.0,
             "mirror.y": 0.0, "mirror.z": 0.0, "inversion": 0.0, "units.len.f": 1.0,
             "units.ang.f": 1.0, "approx.smooth": 0.0}


def _strip_comment(line: str) -> str:
    out, quoted = [], False
    for ch in line:
        if ch == "'":
            quoted = not quoted
        elif ch == "!" and not quoted:
            break
        out.append(ch)
    return "".join(out).strip()


def _parse_simpack(text: str, name: str) -> tuple[dict[str, float], int | None, np.ndarray]:
    flags = dict(_DEFAULTS)
    kind_code, section, points = None, "", []
    for n, raw in enumerate(text.splitlines(), 1):
        line = _strip_comment(raw)
        if not line:
            continue
        low = line.lower()
        if low.endswith(".begin"):
            section = low[:-6]
            continue
        if low.endswith(".end"):
            section = ""
            continue
        if section == "point":
            try:
                vals = [float(v) for v in line.replace(",", " ").split()]
            except ValueError:
                raise ValueError(f"{name}, line {n}: not a profile point: "
                                 f"{raw.strip()!r}") from None
            if len(vals) not in (2, 3):
                raise ValueError(f"{name}, line {n}: a point has 2 or 3 numbers (y z [weight])")
            points.append(vals[:2])
            continue
        m = _KEY.match(line)
        if not m:
            continue
        key, value = m.group(1).lower(), m.group(2).strip()
        if section == "header" and key == "type":
            kind_code = int(float(value))
        elif section == "spline" and key in flags:
            try:
                flags[key] = float(value)
            except ValueError:
                raise ValueError(f"{name}, line {n}: {key} = {value!r} is not a number") from None
    if len(points) < 4:
        raise ValueError(f"{name}: fewer than 4 profile points in a point.begin ... point.end "
                         "block")
    return flags, kind_code, np.array(points)


def _apply_simpack_flags(pts: np.ndarray, f: dict[str, float]) -> np.ndarray:
    """Flags 1-7 of the module docstring, in SIMPACK's order: file units in, m out."""
    if f["point.dist.min"] > 0.0:
        keep = [0]
        for i in range(1, len(pts)):
            if math.dist(pts[i], pts[keep[-1]]) >= f["point.dist.min"]:
                keep.append(i)
        pts = pts[keep]
    pts = pts + np.array([f["shift.y"], f["shift.z"]])
    angle = f["rotate"] / f["units.ang.f"]
    if angle != 0.0:
        c, s = math.cos(angle), math.sin(angle)
        pts = np.column_stack((c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]))
    if f["bound.y.min"] < f["bound.y.max"]:
        pts = pts[(pts[:, 0] >= f["bound.y.min"]) & (pts[:, 0] <= f["bound.y.max"])]
    if f["bound.z.min"] < f["bound.z.max"]:
        pts = np.column_stack((pts[:, 0], np.clip(pts[:, 1], f["bound.z.min"], f["bound.z.max"])))
    if f["mirror.y"] == 1.0:
        pts = pts * np.array([-1.0, 1.0])
    if f["mirror.z"] == 1.0:
        pts = pts * np.array([1.0, -1.0])
    pts = pts / f["units.len.f"]
    if f["inversion"] == 1.0:
        pts = pts[::-1]
    return pts


def read_simpack(path: str | Path, smoothing: float | None = None) -> Profile:
    """Read a SIMPACK wheel (``.prw``) or rail (``.prr``) profile, applying its processing flags
    (module docstring). ``smoothing``: filter wavelength L in m (0 interpolates); None takes the
    file's ``approx.smooth`` when it is 0 and raises otherwise."""
    path = Path(path)
    flags, kind_code, pts = _parse_simpack(path.read_text(), path.name)
    for key in ("units.len.f", "units.ang.f"):
        if not flags[key] > 0.0:
            raise ValueError(f"{path.name}: {key} = {flags[key]!r} is out of range: allowed > 0")
    if kind_code not in (0, 1):
        suffix = path.suffix.lower()
        if suffix not in (".prr", ".prw"):
            raise ValueError(f"{path.name}: no header type (0 rail, 1 wheel) and no .prr/.prw "
                             "suffix")
        kind_code = 1 if suffix == ".prw" else 0
    if smoothing is None:
        if flags["approx.smooth"] != 0.0:
            raise ValueError(
                f"{path.name}: approx.smooth = {flags['approx.smooth']!r} is SIMPACK's own "
                "smoothing scale, which is not reproduced here: pass smoothing= (filter "
                "wavelength in m, 0 to interpolate the points)")
        smoothing = 0.0
    pts = _apply_simpack_flags(pts, flags)
    return Profile(pts[:, 0], pts[:, 1], ("rail", "wheel")[kind_code], smoothing, path.name)


def write_simpack(profile: Profile, path: str | Path, *, mirror_y: bool = False,
                  mirror_z: bool = False, inversion: bool = False, shift: tuple[float, float] =
                  (0.0, 0.0), rotate: float = 0.0, unit_factor: float = 1000.0,
                  comment: str = "") -> None:
    """Write ``profile`` as a SIMPACK profile file whose flags, applied by :func:`read_simpack`,
    give the profile back: the points are stored with the inverse transformation. ``shift`` in
    file units, ``rotate`` in rad, ``unit_factor`` file length units per m (1000: mm). The
    profile's own smoothing is not stored (``approx.smooth = 0``)."""
    if not (math.isfinite(unit_factor) and unit_factor > 0.0):
        raise ValueError(f"unit_factor={unit_factor!r} is out of range: allowed > 0")
    pts = np.column_stack((profile.y, profile.z))
    if inversion:
        pts = pts[::-1]
    pts = pts * unit_factor
    pts = pts * np.array([-1.0 if mirror_y else 1.0, -1.0 if mirror_z else 1.0])
    c, s = math.cos(-rotate), math.sin(-rotate)
    pts = np.column_stack((c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]))
    pts = pts - np.array(shift)
    kind_code = KINDS[::-1].index(profile.kind)   # rail 0, wheel 1

    def num(v: float) -> str:
        return f"{v:+.15e}"
    lines = [
        "! SIMPACK Rail-Wheel Profile, written by contact_core.geometry.write_simpack",
        "  header.begin",
        "    version       =  1",
        f"    type          =  {kind_code}                       ! 0=rail profile, 1=wheel profile",
        "  header.end",
        "  spline.begin",
        f"    approx.smooth  = {num(0.0)}",
        f"    comment        = '{comment.replace(chr(39), '')}'",
        f"    point.dist.min = {num(0.0)}",
        f"    shift.y        = {num(shift[0])}",
        f"    shift.z        = {num(shift[1])}",
        f"    rotate         = {num(rotate)}",
        f"    bound.y.min    = {num(1.0)}",
        f"    bound.y.max    = {num(0.0)}",
        f"    bound.z.min    = {num(1.0)}",
        f"    bound.z.max    = {num(0.0)}",
        f"    mirror.y       =  {int(mirror_y)}",
        f"    mirror.z       =  {int(mirror_z)}",
        f"    inversion      =  {int(inversion)}",
        f"    units.len.f    = {num(unit_factor)}",
        f"    units.ang.f    = {num(1.0)}",
        "    point.begin",
        *(f"{a:.16e}\t{b:.16e}" for a, b in pts),
        "    point.end",
        "  spline.end",
    ]
    Path(path).write_text("\n".join(lines) + "\n")


# ---------------------------------------------------------------------------------------------
# plain y-z tables

def read_yz_table(path: str | Path, kind: str, *, scale: float = 1e-3, mirror_y: bool = False,
                  mirror_z: bool = False, smoothing: float = 0.0) -> Profile:
    """Read a profile from a table of y, z columns (whitespace or commas; lines starting with
    ``#``, ``%`` or ``!`` are comments). ``scale`` converts the file's lengths to m (1e-3: mm);
    ``mirror_y``/``mirror_z`` negate a column to reach the canonical form; ``smoothing`` as in
    :class:`Profile`."""
    if not (math.isfinite(scale) and scale > 0.0):
        raise ValueError(f"scale={scale!r} is out of range: allowed > 0 (m per file unit)")
    path = Path(path)
    rows = []
    for n, raw in enumerate(path.read_text().splitlines(), 1):
        line = raw.strip()
        if not line or line[0] in "#%!":
            continue
        try:
            vals = [float(v) for v in line.replace(",", " ").split()]
        except ValueError:
            raise ValueError(f"{path.name}, line {n}: not a y z row: {line!r}") from None
        if len(vals) < 2:
            raise ValueError(f"{path.name}, line {n}: a row needs y and z")
        rows.append(vals[:2])
    if len(rows) < 4:
        raise ValueError(f"{path.name}: fewer than 4 rows")
    pts = np.array(rows) * scale
    y = -pts[:, 0] if mirror_y else pts[:, 0]
    z = -pts[:, 1] if mirror_z else pts[:, 1]
    return Profile(y, z, kind, smoothing, path.name)


def write_yz_table(profile: Profile, path: str | Path, *, scale: float = 1e-3,
                   mirror_y: bool = False, mirror_z: bool = False) -> None:
    """Write ``profile`` as a y–z table that :func:`read_yz_table` with the same arguments reads
    back (``scale`` m per file unit)."""
    if not (math.isfinite(scale) and scale > 0.0):
        raise ValueError(f"scale={scale!r} is out of range: allowed > 0 (m per file unit)")
    y = (-profile.y if mirror_y else profile.y) / scale
    z = (-profile.z if mirror_z else profile.z) / scale
    head = f"# {profile.kind} profile {profile.name}: y z in units of {scale} m"
    Path(path).write_text(head + "\n" + "\n".join(f"{a:.16e} {b:.16e}" for a, b in zip(y, z))
                          + "\n")


def read_profile(path: str | Path, kind: str | None = None, **options) -> Profile:
    """Read a profile by its suffix: ``.prw``/``.prr`` with :func:`read_simpack` (``options``:
    ``smoothing``), anything else as a y–z table with :func:`read_yz_table` (``kind`` required)."""
    path = Path(path)
    if path.suffix.lower() in (".prw", ".prr"):
        p = read_simpack(path, **options)
        if kind is not None and kind != p.kind:
            raise ValueError(f"{path.name} is a {p.kind} profile, not a {kind} profile")
        return p
    if kind is None:
        raise ValueError(f"{path.name}: kind='wheel' or 'rail' is required for a y-z table")
    return read_yz_table(path, kind, **options)


def shipped_profile(name: str) -> Profile:
    """A profile shipped with the package: ``"S1002"`` (new S1002 wheel) or ``"UIC60"`` (new UIC60
    rail, inclined 1:40 in the file), version 3 of the Manchester Contact Benchmark (Shackleton &
    Iwnicki, Vehicle System Dynamics 46, 2008)."""
    try:
        fname = SHIPPED[name]
    except KeyError:
        raise ValueError(f"name={name!r} is unknown: allowed {list(SHIPPED)}") from None
    return read_simpack(DATA_DIR / fname)
