"""contact_core.geometry: profile files, placement, contact search, creepages and the table,
against closed forms (cone on a cylinder, circle on a circle, linearised wheelset kinematics,
the smoothing spline's transfer function, describing functions) and CONTACT's published data."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from scipy.optimize import fsolve, minimize

import contact_core as cc
from contact_core.geometry import (Profile, Track, Wheelset, WheelsetMotion, WheelsetOnTrack,
                                   benchmark_model, contact_search, creepages, read_profile,
                                   read_simpack, read_yz_table, shipped_profile, solve_wheel,
                                   write_simpack, write_yz_table)
from contact_core.geometry.profiles import DATA_DIR
from contact_core.geometry.table import COLUMNS, ContactTable, contact_table, load_table

from conftest import REFERENCE_DIR

pytestmark = pytest.mark.unit
R0 = 0.46


# ---------------------------------------------------------------------------------------------
# analytic profiles

def circle_rail(R: float = 0.3, half_width: float = 0.03, n: int = 241) -> Profile:
    """Rail crown: a circle of radius R, top at the origin (canonical, z down)."""
    y = np.linspace(-half_width, half_width, n)
    return Profile(y, R - np.sqrt(R * R - y * y), "rail", name="circle rail")


def cone_wheel(gamma: float, half_width: float = 0.05, n: int = 201) -> Profile:
    """Conical tread: radius r0 + z with z = −γ y (larger towards the flange side, y < 0)."""
    y = np.linspace(half_width, -half_width, n)
    return Profile(y, -gamma * y, "wheel", name="cone")


def circle_wheel(R: float, half_width: float = 0.04, n: int = 321) -> Profile:
    """Tread profile: a circle of radius R, convex towards the rail, top at the origin."""
    y = np.linspace(half_width, -half_width, n)
    return Profile(y, -(R - np.sqrt(R * R - y * y)), "wheel", name="circle wheel")


def aligned_model(wheel: Profile, rail: Profile, R_rail: float, gauge_height: float = 1e-3,
                  r0: float = R0) -> WheelsetOnTrack:
    """Track and wheelset whose wheel-profile origins sit right above the rail crowns' tops."""
    c = 0.7175 + math.sqrt(R_rail ** 2 - (R_rail - gauge_height) ** 2)  # gauge face → crown top
    track = Track(rail, gauge=1.435, gauge_height=gauge_height)
    wheelset = Wheelset(wheel, flange_back_distance=1.36, flange_back_position=0.68 - c,
                        nominal_radius=r0)
    return WheelsetOnTrack(track, wheelset)


def _raw_points(path) -> np.ndarray:
    """The points of a SIMPACK file as written (independent of the reader)."""
    rows, inside = [], False
    for line in open(path):
        s = line.strip()
        if s.startswith("point.begin"):
            inside = True
        elif s.startswith("point.end"):
            inside = False
        elif inside and s and not s.startswith("!"):
            rows.append([float(v) for v in s.split()[:2]])
    return np.array(rows)


# ---------------------------------------------------------------------------------------------
# profiles

def test_shipped_profiles_honour_their_files_flags():
    # S1002: mirror.y = 1 and inversion = 1, mm; UIC60: no flags (the files' headers)
    raw_w = _raw_points(DATA_DIR / "MBench_S1002_v3.prw")
    raw_r = _raw_points(DATA_DIR / "MBench_UIC60_v3.prr")
    w, r = shipped_profile("S1002"), shipped_profile("UIC60")
    assert w.kind == "wheel" and r.kind == "rail"
    np.testing.assert_allclose(w.y, -raw_w[::-1, 0] / 1000, rtol=0, atol=1e-15)
    np.testing.assert_allclose(w.z, raw_w[::-1, 1] / 1000, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.c_[r.y, r.z], raw_r / 1000, rtol=0, atol=1e-15)
    # canonical: the flange (the wheel's largest radius, 28 mm above the tread) on the
    # track-centre side y < 0; the wheel's points run from the field side to the flange
    assert w.y[0] > 0 > w.y[-1]
    assert w.y[np.argmax(w.z)] < -0.04 and 0.027 < w.z.max() < 0.029


@pytest.mark.parametrize("flags", [
    dict(),
    dict(mirror_y=True),
    dict(mirror_z=True),
    dict(inversion=True),
    dict(mirror_y=True, inversion=True, unit_factor=1.0),
    dict(shift=(3.5, -1.25), rotate=0.025),
    dict(mirror_y=True, mirror_z=True, inversion=True, shift=(-2.0, 0.5), rotate=-0.04,
         unit_factor=1e4),
])
@pytest.mark.parametrize("name", ["S1002", "UIC60"])
def test_simpack_round_trip(tmp_path, name, flags):
    p = shipped_profile(name)
    path = tmp_path / ("x.prw" if p.kind == "wheel" else "x.prr")
    write_simpack(p, path, **flags)
    q = read_simpack(path)
    assert q.kind == p.kind
    np.testing.assert_allclose(q.y, p.y, rtol=0, atol=1e-14)
    np.testing.assert_allclose(q.z, p.z, rtol=0, atol=1e-14)


def test_simpack_flags_change_what_is_read(tmp_path):
    # the flags are applied, not merely carried: the stored points are transformed, and a file
    # whose flag is switched off reads as the untransformed points
    p = shipped_profile("S1002")
    path = tmp_path / "w.prw"
    write_simpack(p, path, mirror_y=True, inversion=True)
    raw = _raw_points(path)
    np.testing.assert_allclose(raw, np.c_[-p.y, p.z][::-1] * 1000, rtol=0, atol=1e-11)
    text = path.read_text()
    path.write_text(text.replace("mirror.y       =  1", "mirror.y       =  0"))
    q = read_simpack(path)                    # now the mirror image, in canonical order again
    np.testing.assert_allclose(np.sort(q.y), np.sort(-p.y), rtol=0, atol=1e-14)
    path.write_text(text.replace("units.len.f    = +1.000000000000000e+03",
                                 "units.len.f    = +1.000000000000000e+02"))
    np.testing.assert_allclose(read_simpack(path).y, 10 * p.y, rtol=1e-14)
    path.write_text(text.replace("approx.smooth  = +0.000000000000000e+00",
                                 "approx.smooth  = +5.000000000000000e-01"))
    with pytest.raises(ValueError, match="approx.smooth"):
        read_simpack(path)
    assert read_simpack(path, smoothing=0.002).smoothing == 0.002


@pytest.mark.parametrize("mirror_y, mirror_z", [(False, False), (True, False), (True, True)])
def test_yz_table_round_trip(tmp_path, mirror_y, mirror_z):
    p = shipped_profile("UIC60")
    path = tmp_path / "rail.txt"
    write_yz_table(p, path, scale=1e-3, mirror_y=mirror_y, mirror_z=mirror_z)
    q = read_profile(path, "rail", scale=1e-3, mirror_y=mirror_y, mirror_z=mirror_z)
    np.testing.assert_allclose(np.c_[q.y, q.z], np.c_[p.y, p.z], rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="kind"):
        read_profile(path)


def test_bad_profiles_are_clear_errors(tmp_path):
    with pytest.raises(ValueError, match="kind"):
        Profile([0, 1, 2, 3], [0, 0, 0, 0], "axle")
    with pytest.raises(ValueError, match=">= 4"):
        Profile([0, 1, 2], [0, 0, 0], "rail")
    with pytest.raises(ValueError, match="finite"):
        Profile([0, 1, 2, math.nan], [0, 0, 0, 0], "rail")
    with pytest.raises(ValueError, match="smoothing"):
        Profile([0, 1, 2, 3], [0, 0, 0, 0], "rail", smoothing=-1.0)
    bad = tmp_path / "bad.txt"
    bad.write_text("# y z\n0 0\n1 x\n")
    with pytest.raises(ValueError, match="line 3"):
        read_yz_table(bad, "rail")


def test_interpolation_of_a_circle():
    # exact points of a circle, 0.25 mm apart: the interpolating spline's height, slope and
    # curvature are those of the circle (Profile.function's z(y))
    R = 0.3
    f = circle_rail(R).function()
    y = np.linspace(-0.025, 0.025, 101)
    np.testing.assert_allclose(f.z(y), R - np.sqrt(R * R - y * y), rtol=0, atol=1e-10)
    np.testing.assert_allclose(f.slope(y), y / np.sqrt(R * R - y * y), rtol=0, atol=1e-7)
    np.testing.assert_allclose(f.curvature(y), 1.0 / R, rtol=1e-4)


@pytest.mark.parametrize("ratio", [1 / 3, 1.0, 3.0])
def test_smoothing_spline_filters_as_stated(ratio):
    # Vollebregt 2022 (CONTACT user guide): λ = (L/2π)^4 with w_i = δs_i is a low-pass filter
    # whose continuous transfer function for wavelength Λ is 1/(1 + (L/Λ)^4): one half at L = Λ
    wave, amp = 0.010, 1e-5
    y = np.arange(-0.06, 0.06 + 1e-9, 1e-4)
    p = Profile(y, amp * np.sin(2 * np.pi * y / wave), "rail", smoothing=ratio * wave)
    s = np.linspace(0.03, 0.09, 601)             # inside, away from the ends
    y_s, z = p.curve(s).T
    # least-squares amplitude of the sine in the smoothed curve
    gain = np.linalg.lstsq(np.c_[np.sin(2 * np.pi * y_s / wave), np.cos(2 * np.pi * y_s / wave)],
                           z, rcond=None)[0][0] / amp
    assert gain == pytest.approx(1.0 / (1.0 + ratio ** 4), rel=0.02, abs=2e-3)


# ---------------------------------------------------------------------------------------------
# placement: the benchmark against CONTACT's published contact points

def _reference_rows() -> list[dict[str, float]]:
    with open(REFERENCE_DIR / "mbench_a22_left_contact.csv", newline="") as f:
        return [{k: float(v) for k, v in r.items()}
                for r in csv.DictReader(line for line in f if not line.startswith("#"))]


def test_benchmark_placement_matches_contact():
    # CONTACT places the left rail profile (its y towards the track centre) at
    # y_track = −c + y_rail and the left wheel profile at y_track = y_ws − b + y_wheel: its
    # published points give c and b (0.1 µm resolution of the CSV)
    m = benchmark_model()
    for r in _reference_rows():
        assert r["ycp_rail_mm"] - r["ycp_tr_mm"] == pytest.approx(m.rail_offset * 1e3, abs=2e-4)
    r = _reference_rows()[0]                     # unyawed: the wheel's offset too
    assert r["y_ws_mm"] + r["ycp_w_mm"] - r["ycp_tr_mm"] == pytest.approx(
        m.wheelset.wheel_offset * 1e3, abs=2e-4)
    assert abs(m.rail_top) < 1e-7                # the highest point of the profile is its origin
    # gauge: 1435 mm between the gauge faces 14 mm below the top of the rails
    y, z = m.rail_profile.curve(np.linspace(0.0, m.rail_profile.arc_length[-1], 200001)).T
    gauge_side = np.flatnonzero((z <= 0.014 + m.rail_top) & (y < 0.0))[0]
    assert m.rail_offset + y[gauge_side] == pytest.approx(0.7175, abs=1e-6)


def test_rail_inclination_turns_the_crown_towards_the_centre():
    # an upright circular crown inclined by α: at the crown's former top the surface is inclined
    # by α, so the contact angle there is −α on the right rail and +α on the left
    alpha = math.atan(1 / 40)
    m = WheelsetOnTrack(Track(circle_rail(), 1.435, 1e-3, alpha),
                        Wheelset(cone_wheel(0.05), 1.36, -0.07, R0))
    # the former top (0, 0) stays at the origin; the circle's centre turns to (R sin α, R cos α)
    assert float(m.rail.slope(0.0)) == pytest.approx(-math.tan(alpha), rel=1e-6)
    assert m.rail_top == pytest.approx(-0.3 * (1 - math.cos(alpha)), rel=1e-6)
    # a cone of slope γ touches where the placed crown is inclined by −atan γ, which on the
    # rail's own (upright) profile is where it is inclined by α − atan γ: y_rail = R sin(α − atan γ)
    (p,) = contact_search(m, 0.0, roll=0.0).right.points
    assert p.delta == pytest.approx(-math.atan(0.05), abs=1e-7)
    assert p.y_rail == pytest.approx(0.3 * math.sin(alpha - math.atan(0.05)), abs=1e-7)


# ---------------------------------------------------------------------------------------------
# contact search: closed forms

@pytest.mark.parametrize("y", [-0.003, 0.0, 0.002, 0.005])
def test_cone_on_cylinder(y):
    # straight generator (slope γ) on a circular crown R: the contact is where the crown is
    # inclined as the cone, δ = ∓atan γ, at R sin δ from the crown's top; r = r0 − γ y_w;
    # A = cos δ / (2r) (Meusnier), B = 1/(2R) (the cone is straight across)
    gamma, R = 0.05, 0.3
    m = aligned_model(cone_wheel(gamma), circle_rail(R), R)
    c, b = m.rail_offset, m.wheelset.wheel_offset
    res = contact_search(m, y, roll=0.0)         # the lower wheel touches, the other is clear
    for side, sig in (("left", -1.0), ("right", 1.0)):
        (p,) = res.wheel(side).points
        delta = -sig * math.atan(gamma)
        Y = sig * (c + R * math.sin(sig * delta))
        y_w = sig * (Y - y) - b
        r = R0 - gamma * y_w
        assert p.delta == pytest.approx(delta, abs=1e-7)
        assert p.y == pytest.approx(Y, abs=1e-7)
        assert p.z == pytest.approx(R * (1 - math.cos(delta)), abs=1e-9)
        assert p.radius == pytest.approx(r, abs=1e-9)
        assert p.A == pytest.approx(math.cos(delta) / (2 * r), rel=1e-6)
        assert p.B == pytest.approx(1 / (2 * R), rel=1e-4)


def test_yawed_cone_contact_is_the_minimum_over_the_wheel_surface():
    # the contact locus against a brute-force search: the smallest vertical distance between the
    # rail and every point (y_w, t) of the wheel's surface of revolution
    gamma, R, yaw, y = 0.05, 0.3, 0.02, 0.002
    m = aligned_model(cone_wheel(gamma), circle_rail(R), R)
    b, c = m.wheelset.wheel_offset, m.rail_offset
    res = contact_search(m, y, yaw, roll=0.0)
    (p,) = res.right.points

    def gap(v):
        y_w, t = v
        r = R0 - gamma * y_w
        px, py, pz = r * math.sin(t), b + y_w, r * math.cos(t)
        X, Y = math.cos(yaw) * px - math.sin(yaw) * py, y + math.sin(yaw) * px + math.cos(yaw) * py
        Z = res.position.z - R0 + pz
        return R - math.sqrt(R * R - (Y - c) ** 2) - Z
    best = minimize(gap, [0.0, 0.0], method="Nelder-Mead",
                    options=dict(xatol=1e-12, fatol=1e-16, maxiter=20000))
    y_w, t = best.x
    r = R0 - gamma * y_w
    assert p.y_wheel == pytest.approx(y_w, abs=2e-6)
    assert p.x == pytest.approx(math.cos(yaw) * r * math.sin(t) - math.sin(yaw) * (b + y_w),
                                abs=2e-6)
    assert p.gap == pytest.approx(best.fun, abs=1e-10)


def test_circle_on_circle_gives_the_hertz_ellipse():
    # circular tread R_w on a circular crown R_r, both tops aligned: δ = 0, A = 1/(2 r0),
    # B = (1/R_w + 1/R_r)/2; the loaded wheel's patch is Hertz's (Johnson 1985, sec. 4.2)
    R_w, R_r, N, E, nu = 0.5, 0.3, 60e3, 210e9, 0.28
    m = aligned_model(circle_wheel(R_w), circle_rail(R_r), R_r)
    res = contact_search(m, 0.0)
    assert res.position.roll == pytest.approx(0.0, abs=1e-12)
    for side in ("left", "right"):
        (p,) = res.wheel(side).points
        assert p.delta == pytest.approx(0.0, abs=1e-8)
        assert p.A == pytest.approx(1 / (2 * R0), rel=1e-9)
        assert p.B == pytest.approx(0.5 * (1 / R_w + 1 / R_r), rel=1e-4)
    sol = solve_wheel(m, "right", y=0.0, yaw=0.0, roll=0.0, load=N,
                      motion=WheelsetMotion(10.0), mu=0.3, E=E, nu=nu, method="linear")
    (patch,) = sol.patches
    ref = cc.hertz_from_radii(N, R0, R_w, R_r, E, nu)
    assert patch.N == pytest.approx(N, rel=1e-9)
    assert patch.hertz.a == pytest.approx(ref.a, rel=2e-4)
    assert patch.hertz.b == pytest.approx(ref.b, rel=2e-4)
    # the wheelset sinks by Hertz's approach below the height at which it touches
    touch = contact_search(m, 0.0).position.z
    assert sol.position.z - touch == pytest.approx(ref.approach, rel=1e-6)
    # the overlap of the parabolic gap: width 2 (approach / B)^1/2
    assert patch.point.width == pytest.approx(2 * math.sqrt(ref.approach / patch.point.B),
                                              rel=2e-3)


def test_search_is_mirror_symmetric():
    m = benchmark_model()
    for y, yaw in ((0.003, 0.004), (0.0062, 0.0)):
        a, b = contact_search(m, y, yaw), contact_search(m, -y, -yaw)
        assert b.position.roll == pytest.approx(-a.position.roll, abs=1e-10)
        assert b.position.z == pytest.approx(a.position.z, abs=1e-10)
        for p, q in zip(a.right.points, b.left.points):
            assert (p.slot, p.y_wheel, p.radius) == pytest.approx((q.slot, q.y_wheel, q.radius),
                                                                  abs=1e-9)
            assert (p.delta, p.y, p.x) == pytest.approx((-q.delta, -q.y, q.x), abs=1e-9)


# ---------------------------------------------------------------------------------------------
# creepages

def test_creepages_of_a_cone_wheelset_match_the_linearised_kinematics():
    # Wickens (2003), as in the reference wheelset models: ξ_L = −ξ_R = λy/r + b0ψ̇/V,
    # η = ẏ/V − ψ, φ_L,R = ±λ/r + ψ̇/V (Kalker's signs, track frame x along, y right, z down),
    # r the centred rolling radius (free rolling there: Ω = −V/r); the exact kinematics differ by
    # O(λ²) = 2.5e-3 relative (sin δ, cos δ against λ) and O(ξ) (the rolling speed), and η by
    # O(λ²)(|ẏ|/V + |ψ|) and by ψ̇x/V with the contact's lead x ≈ b0ψ
    lam, R = 0.05, 0.3
    m = aligned_model(cone_wheel(lam), circle_rail(R), R)
    r = R0 + lam * R * math.sin(math.atan(lam))  # the crown meets the cone R sin δ off its top
    y, yaw, V, ydot, yawdot = 0.002, 0.001, 20.0, 0.05, 0.05
    res = contact_search(m, y, yaw, roll=0.0)
    motion = WheelsetMotion(V, pitch_rate=-V / r, lateral_velocity=ydot, yaw_rate=yawdot)
    L = {s: creepages(res.position, res.wheel(s).points[0], motion, R0) for s in ("left", "right")}
    b0 = 0.5 * (res.right.points[0].y - res.left.points[0].y)
    assert L["left"].xi == pytest.approx(lam * y / r + b0 * yawdot / V, rel=3e-3)
    assert L["right"].xi == pytest.approx(-lam * y / r - b0 * yawdot / V, rel=3e-3)
    for s, sign in (("left", 1.0), ("right", -1.0)):
        assert L[s].eta == pytest.approx(ydot / V - yaw, abs=lam ** 2 * (ydot / V + yaw)
                                         + b0 * yawdot * yaw / V)
        assert L[s].phi == pytest.approx(sign * lam / r + yawdot / V, rel=3e-3)


def test_benchmark_creepages_map_to_contacts():
    # CONTACT prints rail relative to wheel: the negatives of ours; its ξ, η, φ at y = 0.5 mm
    # (case 2; at CONTACT's own height, so that only geometry and kinematics enter)
    m = benchmark_model()
    r = _reference_rows()[1]
    res = contact_search(m, r["y_ws_mm"] * 1e-3, r["yaw_ws"], r["roll_ws"], r["z_ws_mm"] * 1e-3)
    (p,) = res.left.points
    c = creepages(res.position, p, WheelsetMotion(r["vx_ws_mm_s"] * 1e-3, r["vpitch_ws"]), R0)
    assert -c.xi == pytest.approx(r["cksi"], rel=0.01)
    assert -c.eta == pytest.approx(r["ceta"], rel=0.01)
    assert -c.phi * 1e-3 == pytest.approx(r["cphi_per_mm"], rel=0.01)
    assert c.speed * 1e3 == pytest.approx(r["veloc_mm_s"], abs=1.0)


# ---------------------------------------------------------------------------------------------
# the contact-geometry table

def _synthetic_table(dr) -> ContactTable:
    y = np.linspace(-0.01, 0.01, 2001)
    data = np.zeros((y.size, len(COLUMNS)))
    data[:, COLUMNS.index("right.radius_contact")] = R0 + 0.5 * dr(y)
    data[:, COLUMNS.index("left.radius_contact")] = R0 - 0.5 * dr(y)
    return ContactTable(y, data, 50e3, 210e9, 0.28)


def test_equivalent_conicity_is_the_describing_function():
    # Δr = 2γy + k y³: the first harmonic of Δr(A sin τ) gives γ_e = γ + 3kA²/8
    gamma, k = 0.15, 2e4
    t = _synthetic_table(lambda y: 2 * gamma * y + k * y ** 3)
    amp = np.array([0.5e-3, 2e-3, 5e-3, 9e-3])
    np.testing.assert_allclose(t.equivalent_conicity(amp), gamma + 3 * k * amp ** 2 / 8,
                               rtol=1e-6)
    with pytest.raises(ValueError, match="amplitudes"):
        t.equivalent_conicity([0.02])


@pytest.fixture(scope="module")
def cone_table():
    lam, R = 0.05, 0.3
    m = aligned_model(cone_wheel(lam), circle_rail(R), R)
    return m, contact_table(m, y_max=0.006, step=2e-4)


def test_cone_table_rolling_radius_difference(cone_table):
    # rigid contact of two cones on circular crowns, solved independently: both generators, rolled
    # with the wheelset, tangent to their crowns; Δr = r_R − r_L at the tangent points
    m, table = cone_table
    lam, R, b, c = 0.05, 0.3, m.wheelset.wheel_offset, m.rail_offset

    def tangency(y, z, roll, sig):
        # the lowest generator, r(Y) = r0 − λ(σY − b), rolled with the wheelset: a line in the
        # track's y-z plane through P0 (at Y = σb) with direction v per unit Y; its distance from
        # the crown's centre and the Y of the foot of the perpendicular
        cr, sr, slope = math.cos(roll), math.sin(roll), -lam * sig
        Y0 = sig * b
        p0 = np.array([y + cr * Y0 - sr * R0, z - R0 + sr * Y0 + cr * R0])
        v = np.array([cr - sr * slope, sr + cr * slope])
        centre = np.array([sig * c, R])
        t = (centre - p0) @ v / (v @ v)
        return np.linalg.norm(p0 + t * v - centre), Y0 + t

    for y in (0.001, 0.0032, 0.006):
        (z, roll), info, ier, _ = fsolve(
            lambda v: [tangency(y, v[0], v[1], s)[0] - R for s in (-1.0, 1.0)], [0.0, 0.0],
            xtol=1e-12, full_output=True)
        assert ier == 1 and np.abs(info["fvec"]).max() < 1e-15
        radii = {sig: R0 - lam * (sig * tangency(y, z, roll, sig)[1] - b) for sig in (-1.0, 1.0)}
        assert table.rolling_radius_difference(y) == pytest.approx(radii[1.0] - radii[-1.0],
                                                                   abs=2e-8)
        assert table.column("roll", y) == pytest.approx(roll, abs=1e-8)


def test_table_matches_the_search_between_its_nodes(tmp_path):
    m = benchmark_model()
    contact_table(m, y_max=0.0045, step=1e-4, load=10e3).save(tmp_path / "t.npz")
    table = load_table(tmp_path / "t.npz")
    for y in (0.00137, 0.00281, -0.00363):
        res = contact_search(m, y)
        patches = table.patches(y)
        for side in ("left", "right"):
            (p,) = res.wheel(side).points
            t = patches[side, p.slot]
            assert t.present == 1.0 and t.weight == pytest.approx(1.0)
            assert t.delta == pytest.approx(p.delta, abs=2e-4)
            assert t.radius == pytest.approx(p.radius, abs=2e-7)
            assert t.y == pytest.approx(p.y, abs=2e-5)
            assert t.B == pytest.approx(p.B, rel=0.02)


def test_benchmark_table_flange_contact(tmp_path):
    # the flange takes the right wheel's load between y = 4.6 and 5.5 mm (two-point contact, the
    # flange patch's share rising from 0 to 1) and the rigid contact jumps onto the flange face
    # between 6.0 and 6.5 mm, where CONTACT's solved heights jump (z_ws -0.20 -> -3.05 mm)
    m = benchmark_model()
    table = contact_table(m, y_max=0.007, step=1e-4, load=10e3, E=2 * 82e9 * 1.28)
    ys = table.y[(table.y >= 0.0045) & (table.y <= 0.0056)]
    w = table.column("right.1.weight", ys)
    assert w[0] == 0.0 and w[-1] == pytest.approx(1.0)
    assert np.all(np.diff(w) >= -1e-12) and np.all((w >= 0) & (w <= 1))
    both = table.column("right.0.weight", ys) + w
    np.testing.assert_allclose(both[table.column("right.0.present", ys) > 0.5], 1.0)
    ref = {r["case"]: r for r in _reference_rows()}
    assert ref[13]["z_ws_mm"] > -1.0 and ref[14]["z_ws_mm"] < -3.0
    assert ref[13]["y_ws_mm"] * 1e-3 < table.flange_contact() <= ref[14]["y_ws_mm"] * 1e-3
    assert 0.0 < table.flange_onset() < table.flange_contact()
