"""Kalker's exact steady-rolling theory (method "exact") against independent references.

References: Kalker's coefficient table (Kalker 1990, Table E.3, shipped CSV), CONTACT's public
example ``tractcurv`` and CONTACT's results with spin (tests/data), Hertz's pressure, full sliding
(|F| = μN), the symmetries of the problem, and the behaviour on the hard cases of Kalker's thesis
(Kalker 1967: pure spin). Grids are modest (12×12 to 40×40) except the 48×44 tractcurv comparison.
"""
from __future__ import annotations

import csv
import math
import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest

import contact_core as cc
from conftest import REFERENCE_DIR
from contact_core.effects import Effects
from contact_core.exact import EXTERIOR, SLIP, STICK, ExactSolverWarning

pytestmark = pytest.mark.unit

TABLE = Path(cc.__file__).parent / "data" / "kalker_coefficients.csv"
G, NU = 8e10, 0.25


def _table(ab: float, nu: float = 0.25) -> tuple[float, float, float, float]:
    with open(TABLE) as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        for r in rows:
            if float(r["a_over_b"]) == ab and float(r["nu"]) == nu:
                return tuple(float(r[k]) for k in ("C11", "C22", "C23", "C33"))
    raise KeyError(ab)


def _patch(ab: float, c: float = 6e-3) -> tuple[float, float]:
    b = c / math.sqrt(ab)
    return ab * b, b


def _coefficients(ab: float, m: int | None) -> np.ndarray:
    """(C11, C22, C23, C33) from tiny creepage / spin (φ c = 1e-6), μ = 0.3, on one m×m grid
    (``m=None``: the default setting, extrapolated)."""
    a, b = _patch(ab)
    c = math.sqrt(a * b)
    kw = dict(N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU)
    if m is not None:
        kw.update(mx=m, my=m, extrapolate=False)
    rx = cc.solve("exact", xi=1e-6, eta=0.0, phi=0.0, **kw)
    ry = cc.solve("exact", xi=0.0, eta=1e-6, phi=0.0, **kw)
    rs = cc.solve("exact", xi=0.0, eta=0.0, phi=1e-6 / c, **kw)
    assert rx.converged and ry.converged and rs.converged
    return np.array([-rx.Fx / (G * c * c * 1e-6), -ry.Fy / (G * c * c * 1e-6),
                     -rs.Fy / (G * c * c * 1e-6), -rs.Mz / (G * c ** 3 * 1e-6)])


_COEF_CACHE: dict = {}


def _rel_err(ab: float, m: int | None) -> np.ndarray:
    key = (ab, m)
    if key not in _COEF_CACHE:
        _COEF_CACHE[key] = _coefficients(ab, m) / np.array(_table(ab)) - 1.0
    return _COEF_CACHE[key]


# ---------------------------------------------------------------------------- normal problem

@pytest.mark.parametrize("ab", [1.0, 0.5, 3.0])
def test_normal_pressure_matches_hertz(ab):
    a, b = _patch(ab)
    N = 1e5
    r = cc.solve("exact", xi=1e-4, eta=0.0, phi=0.0, N=N, mu=0.3, a=a, b=b, G=G, nu=NU,
                 mx=40, my=40, fields=True)
    f = r.fields
    dA = (f.x[1] - f.x[0]) * (f.y[1] - f.y[0])
    assert f.pn.sum() * dA == pytest.approx(N, rel=1e-12)          # total N exact
    p0 = 3 * N / (2 * math.pi * a * b)                             # Hertz
    assert f.pn.max() == pytest.approx(p0, rel=0.02)
    assert (f.pn >= 0).all()


@pytest.mark.parametrize("mx, my, ab", [(20, 20, 0.5), (21, 19, 0.7), (16, 23, 3.0)])
def test_folded_normal_solver_equals_fft_solver(mx, my, ab):
    # the quarter-folded dense Polonsky-Keer iteration (small grids) and the full-grid FFT one
    # solve the same discrete problem (even and odd grids)
    from contact_core.exact import normal
    out = []
    for dense_max in (10 ** 9, 0):
        p, it, err = normal.normalised_pressure(mx, my, 1.1, ab, "numerical", dense_max=dense_max)
        assert err < 1e-12 and it < 100
        out.append(p)
    assert ((out[0] > 0) == (out[1] > 0)).all()
    assert np.abs(out[0] - out[1]).max() < 1e-10 * out[1].max()


# ------------------------------------------------------------- Kalker's creep coefficients

@pytest.mark.parametrize("ab", [0.2, 0.5, 1.0, 2.0, 5.0])
def test_creep_coefficients_c11_c22_c23_converge_to_kalker(ab):
    coarse, fine = _rel_err(ab, 20), _rel_err(ab, 40)
    assert np.abs(fine[:3]).max() < 0.03, fine
    # the error shrinks with refinement (max over C11, C22, C23)
    assert np.abs(fine[:3]).max() < np.abs(coarse[:3]).max(), (coarse, fine)


@pytest.mark.parametrize("ab", [0.2, 0.5])
def test_spin_moment_coefficient_c33_small_ab(ab):
    assert abs(_rel_err(ab, 40)[3]) < 0.05
    assert abs(_rel_err(ab, 40)[3]) < abs(_rel_err(ab, 20)[3])


def _c33(ab: float, m: int, my: int | None = None) -> float:
    """C33 from a tiny spin (φ c = 1e-6, all stick) on an m×m grid (m×my with ``my``)."""
    a, b = _patch(ab)
    c = math.sqrt(a * b)
    r = cc.solve("exact", xi=0.0, eta=0.0, phi=1e-6 / c, N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU,
                 mx=m, my=m if my is None else my, extrapolate=False)
    assert r.converged
    return -r.Mz / (G * c ** 3 * 1e-6)


@pytest.mark.slow
def test_spin_moment_coefficient_c33_round_contact_richardson():
    # At a/b = 1 the plain grid values approach Kalker's C33 slowly and, on coarse grids, not
    # monotonically (elements entering/leaving the circle): +20 % (20x20), +8.1 % (40), +5.2 %
    # (80), +3.8 % (160). On the nested sequence 32/64/128 the error halves with h: the order
    # is estimated from the three grids (measured p = 1.10; 40/80/160 gives 0.99) and must lie
    # in a plausible band for a first-order (staircase-boundary) error, then Richardson's
    # extrapolation (measured +2.2 %, 40/80/160: +2.3 %) is within 5 % of Kalker's value.
    c33 = _table(1.0)[3]
    c1, c2, c3 = (_c33(1.0, m) for m in (32, 64, 128))
    err = [abs(v / c33 - 1.0) for v in (c1, c2, c3)]
    assert err[0] > err[1] > err[2]                 # the error shrinks with refinement
    ratio = (c1 - c2) / (c2 - c3)
    p = math.log2(ratio)
    assert 0.7 < p < 1.5, p
    extrapolated = c3 + (c3 - c2) / (ratio - 1.0)   # = c3 + (c3 - c2)/(2^p - 1)
    assert abs(extrapolated / c33 - 1.0) < 0.05, (c1, c2, c3, p, extrapolated)


@pytest.mark.xfail(strict=True, reason=(
    "at a/b = 5 the exact theory's C33 lies well below the tabulated 0.779 (nu = 0.25): on square "
    "elements (mx = 5 my) 80x16 0.751, 160x32 0.683, 320x64 0.644, falling at order 0.6-0.8, "
    "first-order limit of the first two 0.615 (-21 %); at nu = 0.28, 400x80 gives 0.607 against "
    "0.733 (-17 %). C11, C22, C23 agree with the table within 1 % (tests above); see "
    "contact_core/coefficients.py"))
def test_spin_moment_coefficient_c33_elongated_contact():
    # Kalker 1990, Table E.3, a/b = 5: C33 from a tiny spin on square elements, the two grids'
    # first-order (staircase-boundary) limit within 5 % of the table.
    c33 = [_c33(5.0, 5 * my, my) for my in (16, 32)]
    assert 2 * c33[1] - c33[0] == pytest.approx(_table(5.0)[3], rel=0.05), c33


def _reciprocity_gap(ab: float, **opts) -> float:
    """(C32 - C23)/C23 with C32 = Mz per η·c and C23 = -Fy per φ·c (all stick)."""
    a, b = _patch(ab)
    c = math.sqrt(a * b)
    kw = dict(N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU, tol=1e-10, **opts)
    ry = cc.solve("exact", xi=0.0, eta=1e-6, phi=0.0, **kw)
    rs = cc.solve("exact", xi=0.0, eta=0.0, phi=1e-6 / c, **kw)
    return (ry.Mz / c + rs.Fy) / -rs.Fy


@pytest.mark.parametrize("ab", [0.2, 1.0, 5.0])
def test_reciprocity_c32_equals_minus_c23_in_the_limit(ab):
    # C32 = -C23 (Kalker 1967, sec. 6.1). The spin term of the rigid slip is sampled a sixth of
    # an element downstream (CONTACT's), which moves Fy(φ) by a first-order amount: on plain
    # grids the gap halves with the element size (measured -5.9, -2.8, -1.4 % at a/b = 1), and
    # the default setting (extrapolated to h -> 0) closes it.
    gaps = [_reciprocity_gap(ab, mx=m, my=m, extrapolate=False) for m in (16, 32, 64)]
    assert all(abs(g) < 0.15 for g in gaps), gaps
    for coarse, fine in zip(gaps, gaps[1:]):
        assert 1.8 < coarse / fine < 2.2, gaps
    assert abs(_reciprocity_gap(ab)) < 0.005


@pytest.mark.parametrize("ab", sorted({float(r["a_over_b"]) for r in csv.DictReader(
    line for line in TABLE.read_text().splitlines() if not line.startswith("#"))}))
def test_default_setting_matches_kalker_c11_c22_within_1_percent(ab):
    # Issue 17: the default setting (52×52, extrapolated) reproduces Kalker's linear theory in
    # the linear range, pure ξ and pure η, over the whole table a/b = 0.1 .. 10.
    err = _rel_err(ab, None)
    assert np.abs(err[:2]).max() < 0.01, err


# ----------------------------------------------------------------------- CONTACT tractcurv

def _tractcurv():
    with open(REFERENCE_DIR / "contact_tractcurv_example.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["series"] == "1"]
    return rows


def test_tractcurv_creep_curve_matches_contact():
    rows = _tractcurv()
    r0 = rows[0]
    a, b = float(r0["AA_mm"]) * 1e-3, float(r0["BB_mm"]) * 1e-3
    N, mu = float(r0["FN_N"]), float(r0["FSTAT"])
    Gc, nu = float(r0["G_N_per_mm2"]) * 1e6, float(r0["POISS"])
    assert (int(r0["MX"]), int(r0["MY"]), float(r0["SCALE"])) == (48, 44, 1.1)
    solver = cc.make_solver("exact", mx=48, my=44, scale=1.1, fields=True, extrapolate=False)
    checked = 0
    for r in rows:
        xi = float(r["CKSI"])
        if xi > 0.0033:
            continue
        res = solver.step(xi, 0.0, 0.0, N, mu, a, b, Gc, nu)
        # CONTACT: forces on the upper body, positive creepage gives negative force (same as ours)
        assert res.Fx / (mu * N) == pytest.approx(float(r["FX_over_FSTAT_FN"]), abs=0.005)
        if xi == 1e-5:
            assert res.Fx == pytest.approx(float(r["FX_N"]), rel=0.005)
            assert res.fields.pn.max() == pytest.approx(float(r["PMAX_N_per_mm2"]) * 1e6,
                                                        rel=0.005)
            assert int((res.fields.status != EXTERIOR).sum()) == int(r["NCON"])
        checked += 1
    assert checked == 9


def test_fixed_grid_with_spin_equals_contact():
    # CONTACT's exact steady rolling with spin and creepage on the same grids (12x12 to 32x32 over
    # 1.1x the ellipse), in partial slip and near full sliding: the default spin sampling is
    # CONTACT's (a sixth of an element downstream), so the forces agree to the solvers'
    # tolerances (measured: 4e-7 of μN). A quarter element misses them by 0.16-1.75 % of μN.
    with open(REFERENCE_DIR / "contact_exact_spin.csv", newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert len(rows) == 24 and {r["kind"] for r in rows} == {"spin", "combined"}
    for r in rows:
        v = {k: float(x) for k, x in r.items() if k != "kind"}
        m = int(v["m"])
        kw = dict(xi=v["xi"], eta=v["eta"], phi=v["phi_per_m"], N=v["N_N"], mu=v["mu"],
                  a=v["a_m"], b=v["b_m"], G=v["G_Pa"], nu=v["nu"], mx=m, my=m, extrapolate=False)
        muN, c = v["mu"] * v["N_N"], math.sqrt(v["a_m"] * v["b_m"])
        res = cc.solve("exact", **kw)
        assert res.converged
        assert abs(res.Fx - v["contact_Fx_N"]) < 1e-5 * muN
        assert abs(res.Fy - v["contact_Fy_N"]) < 1e-5 * muN
        assert abs(res.Mz - v["contact_Mz_Nm"]) < 1e-5 * muN * c
        assert res.slip_fraction == pytest.approx(v["slip_fraction"], abs=5e-4)
        quarter = cc.solve("exact", spin_shift=0.25, **kw)
        off = math.hypot(quarter.Fx - v["contact_Fx_N"], quarter.Fy - v["contact_Fy_N"])
        assert off > 1e-3 * muN


# --------------------------------------------------------------------------- full sliding

@pytest.mark.parametrize("xi, eta", [(0.3, 0.0), (0.0, -0.3), (0.2, 0.25), (-0.3, 0.1)])
def test_full_sliding(xi, eta):
    a, b = _patch(0.7)
    N, mu = 1e5, 0.3
    r = cc.solve("exact", xi=xi, eta=eta, phi=0.0, N=N, mu=mu, a=a, b=b, G=G, nu=NU,
                 mx=20, my=20)
    assert r.converged and r.slip_fraction == 1.0
    F = np.hypot(r.Fx, r.Fy)
    assert F == pytest.approx(mu * N, rel=0.005)
    cos = -(r.Fx * xi + r.Fy * eta) / (F * math.hypot(xi, eta))
    assert cos > math.cos(0.005)


# ------------------------------------------------------------------------------ hard cases

@pytest.mark.parametrize("opts", [{"mx": 16, "my": 16, "extrapolate": False},
                                  {"mx": 32, "my": 32}], ids=["16x16", "32x32-extrapolated"])
@pytest.mark.parametrize("ab", [0.2, 1.0, 2.0, 5.0])
def test_pure_spin_sweep_smooth(ab, opts):
    # Kalker's thesis program failed on pure spin near the peak for a/b = 5 and 2 (Kalker 1967).
    a, b = _patch(ab)
    c = math.sqrt(a * b)
    N, mu = 1e5, 0.3
    c23 = _table(ab)[2]
    phi_ref = mu * N / (G * c ** 3 * c23)      # spin at which linear theory reaches μN
    solver = cc.make_solver("exact", **opts)
    F = []
    for psi in np.logspace(-2, 2, 81):
        r = solver.step(0.0, 0.0, psi * phi_ref, N, mu, a, b, G, NU)
        assert r.converged
        assert np.isfinite([r.Fx, r.Fy, r.Mz]).all()
        F.append(r.Fy / (mu * N))
    F = np.array(F)
    assert (F < 0).all() and (np.abs(F) <= 1.0).all()
    d1 = np.diff(F)
    assert np.count_nonzero(np.diff(np.sign(d1))) == 1      # rises, peaks once, decays
    assert np.abs(np.diff(F, 2)).max() < 0.1                 # no waviness
    assert abs(F[-1]) < 0.1 * abs(F).max()                   # decays towards full spin sliding


@pytest.mark.parametrize("ab", [0.05, 20.0])
@pytest.mark.parametrize("case", [(1e-3, 0, 0), (0, 1e-3, 0), (0, 0, 1.0), (5e-4, -5e-4, -2.0)])
def test_extreme_ellipses_converge_bounded(ab, case):
    a, b = _patch(ab)
    N, mu = 1e5, 0.3
    xi, eta, phi = case
    phi = phi / math.sqrt(a * b) * 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("error", ExactSolverWarning)
        r = cc.solve("exact", xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=a, b=b, G=G, nu=NU,
                     mx=20, my=20, fields=True)
    assert r.converged
    _check_fields(r, mu)
    assert math.hypot(r.Fx, r.Fy) <= mu * N * (1 + 1e-9)


def test_tiny_creepage_linear():
    a, b = _patch(1.0)
    c = math.sqrt(a * b)
    r = cc.solve("exact", xi=1e-9, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU,
                 mx=20, my=20)
    assert r.converged and r.slip_fraction == 0.0
    assert -r.Fx / (G * c * c * 1e-9) == pytest.approx(_table(1.0)[0], rel=0.05)


def _check_fields(r, mu):
    f = r.fields
    arrays = (f.pn, f.px, f.py, f.sx, f.sy)
    assert all(np.isfinite(v).all() for v in arrays)
    pt = np.hypot(f.px, f.py)
    assert (pt <= mu * f.pn * (1 + 1e-9)).all()
    ext = f.status == EXTERIOR
    assert (f.pn[ext] == 0).all() and (pt[ext] == 0).all()
    slip = f.status == SLIP
    assert np.allclose(pt[slip], mu * f.pn[slip], rtol=1e-9)
    # slipping elements: traction opposite to the slip
    s = np.hypot(f.sx, f.sy)
    ok = slip & (s > 1e-6 * s.max())
    cosang = -(f.px * f.sx + f.py * f.sy)[ok] / (pt[ok] * s[ok])
    assert (cosang > 1 - 1e-4).all()


@pytest.mark.parametrize("sx", [1, -1])
@pytest.mark.parametrize("sy", [1, -1])
@pytest.mark.parametrize("sp", [1, -1])
def test_combined_all_signs(sx, sy, sp):
    a, b = _patch(0.6)
    c = math.sqrt(a * b)
    N, mu = 1e5, 0.3
    r = cc.solve("exact", xi=sx * 6e-4, eta=sy * 4e-4, phi=sp * 0.3 / c * 1e-3, N=N, mu=mu,
                 a=a, b=b, G=G, nu=NU, mx=20, my=20, fields=True)
    assert r.converged and 0 < r.slip_fraction < 1
    _check_fields(r, mu)
    assert np.sign(r.Fx) == -sx                 # force opposes the longitudinal creepage


# ----------------------------------------------------------------------------- symmetries

@pytest.mark.parametrize("xi, eta, phi", [(6e-4, 3e-4, 20.0), (1.5e-3, -1e-3, -60.0),
                                          (2e-4, 1e-4, 100.0)])
def test_symmetries(xi, eta, phi):
    a, b = _patch(0.8)
    kw = dict(N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU, mx=20, my=20)
    r = cc.solve("exact", xi=xi, eta=eta, phi=phi, **kw)
    rx = cc.solve("exact", xi=-xi, eta=eta, phi=phi, **kw)          # Fx odd, Fy, Mz even in ξ
    ry = cc.solve("exact", xi=xi, eta=-eta, phi=-phi, **kw)         # flips Fy and Mz
    rel = 1e-9
    assert rx.Fx == pytest.approx(-r.Fx, rel=rel)
    assert rx.Fy == pytest.approx(r.Fy, rel=rel)
    assert rx.Mz == pytest.approx(r.Mz, rel=rel)
    assert ry.Fx == pytest.approx(r.Fx, rel=rel)
    assert ry.Fy == pytest.approx(-r.Fy, rel=rel)
    assert ry.Mz == pytest.approx(-r.Mz, rel=rel)


def test_longitudinal_only_equals_full_solve():
    a, b = _patch(0.5)
    kw = dict(xi=1.2e-3, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=0.28,
              mx=20, my=20)
    full = cc.solve("exact", **kw)
    lon = cc.solve("exact", effects=("longitudinal", "saturation"), **kw)
    assert lon.Fx == pytest.approx(full.Fx, rel=1e-9)
    assert lon.Fy == 0.0 and lon.Mz == 0.0
    assert abs(full.Fy) < 1e-9 * abs(full.Fx)       # y-mirror: Y odd in y


def test_without_saturation_is_linear_in_creepage():
    a, b = _patch(1.0)
    eff = Effects(saturation=False)
    kw = dict(eta=0.0, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU, mx=16, my=16,
              effects=eff, tol=1e-10)
    r1 = cc.solve("exact", xi=1e-3, **kw)
    r2 = cc.solve("exact", xi=2e-1, **kw)
    assert r1.slip_fraction == 0.0 and r1.converged
    assert r2.Fx == pytest.approx(200 * r1.Fx, rel=1e-6)     # no saturation: μ → ∞
    # agrees with the saturated solve at tiny creepage
    r3 = cc.solve("exact", xi=1e-6, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=NU,
                  mx=16, my=16, tol=1e-10)
    assert r1.Fx == pytest.approx(1000 * r3.Fx, rel=1e-5)


# ---------------------------------------------------------------------- API, warm start

def test_warm_start_is_faster_and_same(wheel_rail_case):
    # a co-simulation step: creepages and load change by 0.1 %
    solver = cc.make_solver("exact", mx=24, my=24, extrapolate=False)
    k = wheel_rail_case
    cold = solver.step(1.0e-3, 5e-4, 0.2, k["N"], k["mu"], k["a"], k["b"], k["G"], k["nu"])
    step = (1.001e-3, 5.005e-4, 0.2002, k["N"] * 1.001, k["mu"], k["a"], k["b"], k["G"], k["nu"])
    near = solver.step(*step)
    warm = solver.step(*step, warm_start=cold)
    assert warm.iterations * 2 <= near.iterations
    # both stop at the default tol = 1e-5 (rms traction update): forces agree to ~1e-6
    assert warm.Fx == pytest.approx(near.Fx, rel=1e-5)
    assert warm.Fy == pytest.approx(near.Fy, rel=1e-5)
    state = pickle.loads(pickle.dumps(cold.warm_state))
    assert all(isinstance(v, (int, float, bool, np.ndarray)) for v in state.to_record().values())
    # an incompatible state (other grid) is ignored: cold start
    other = cc.make_solver("exact", mx=16, my=16).step(1.0e-3, 5e-4, 0.2, k["N"], k["mu"],
                                                        k["a"], k["b"], k["G"], k["nu"])
    r = solver.step(1.0e-3, 5e-4, 0.2, k["N"], k["mu"], k["a"], k["b"], k["G"], k["nu"],
                    warm_start=other)
    assert r.Fx == pytest.approx(cold.Fx, rel=1e-6)


def test_isolated_warm_start_scales_the_previous_solution(wheel_rail_case):
    # Without a secant, the start is the previous solution scaled by the projection s of the
    # new normalised creepages on the old ones. Two exact properties of the discrete problem
    # make that start the solution itself, so one sweep (the convergence test) suffices:
    k = wheel_rail_case
    args = (k["N"], k["mu"], k["a"], k["b"], k["G"], k["nu"])
    # (1) without saturation (μ -> ∞, every element sticks) the problem is linear in the
    #     creepages (Kalker's linear theory), so p(s σ) = s p(σ);
    lin = cc.make_solver("exact", mx=16, my=16, extrapolate=False,
                         effects=("longitudinal", "lateral", "spin"))
    r1 = lin.step(1e-3, 5e-4, 0.2, *args)
    cold = lin.step(2.5e-3, 1.25e-3, 0.5, *args)
    warm = lin.step(2.5e-3, 1.25e-3, 0.5, *args, warm_start=r1)
    assert warm.iterations == 1 and cold.iterations > 5
    for f in ("Fx", "Fy", "Mz"):
        assert getattr(warm, f) == pytest.approx(getattr(cold, f), rel=1e-6)
    # (2) with Coulomb friction the problem is odd: p(-σ) = -p(σ) (s = -1), in partial slip
    sat = cc.make_solver("exact", mx=16, my=16, extrapolate=False)
    r1 = sat.step(1e-3, 5e-4, 0.2, *args)
    assert 0.2 < r1.slip_fraction < 0.9
    cold = sat.step(-1e-3, -5e-4, -0.2, *args)
    warm = sat.step(-1e-3, -5e-4, -0.2, *args, warm_start=r1)
    assert warm.iterations == 1 and cold.iterations > 5
    for f in ("Fx", "Fy", "Mz"):
        assert getattr(warm, f) == pytest.approx(getattr(cold, f), rel=1e-6)
        assert getattr(warm, f) == pytest.approx(-getattr(r1, f), rel=1e-6)


def test_not_converged_warns(wheel_rail_case):
    k = wheel_rail_case
    with pytest.warns(ExactSolverWarning):
        r = cc.solve("exact", xi=1e-3, eta=0.0, phi=0.0, maxit=2, mx=16, my=16,
                     extrapolate=False, **k)
    assert not r.converged and r.iterations == 2 and r.residual > 1e-5


@pytest.mark.parametrize("opt", [{"mx": 2}, {"my": 1000}, {"mx": 10.5}, {"scale": 1.0},
                                 {"scale": 5}, {"tol": 0}, {"maxit": 0}, {"normal": "fem"},
                                 {"fields": 1}, {"extrapolate": "yes"}, {"mx": 12}, {"bogus": 1},
                                 {"spin_shift": -0.1}, {"spin_shift": 0.6}])
def test_option_validation(opt):
    with pytest.raises(ValueError, match=next(iter(opt))):
        cc.make_solver("exact", **opt)


def test_registered_and_hertz_option(wheel_rail_case):
    assert "exact" in cc.methods() and cc.METHODS["exact"].code == 4
    k = wheel_rail_case
    r1 = cc.solve("exact", xi=1e-3, eta=0.0, phi=0.0, mx=24, my=24, **k)
    r2 = cc.solve("exact", xi=1e-3, eta=0.0, phi=0.0, mx=24, my=24, normal="hertz", **k)
    assert r1.method == "exact" and r2.converged
    assert r2.Fx == pytest.approx(r1.Fx, rel=0.02)
    s = cc.STICK if hasattr(cc, "STICK") else STICK
    assert s == 1


# ------------------------------------------------- half grid (η = φ = 0), secant warm start

@pytest.mark.parametrize("mx, my", [(20, 20), (21, 19), (16, 9)])
def test_half_grid_equals_full_grid(mx, my):
    # η = φ = 0: solved on the rows y >= 0 with folded kernels; the iterates are the full
    # grid's (same sums, weighted), so the results agree to rounding, odd my included
    a, b = _patch(0.5)
    kw = dict(xi=1.2e-3, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=a, b=b, G=G, nu=0.28, mx=mx, my=my,
              fields=True, effects=("longitudinal", "saturation"), extrapolate=False)
    half = cc.solve("exact", **kw)
    full = cc.solve("exact", **kw, half=False)
    assert half.converged and full.converged and 0 < full.slip_fraction < 1
    assert half.iterations == full.iterations
    assert half.Fx == pytest.approx(full.Fx, rel=1e-9)
    hf, ff = half.fields, full.fields
    scale = np.abs(ff.px).max()
    np.testing.assert_allclose(hf.px, ff.px, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(hf.py, ff.py, rtol=0, atol=1e-9 * scale)
    np.testing.assert_array_equal(hf.status, ff.status)
    assert np.abs(ff.py).max() > 1e-4 * scale                   # the ν-coupled Y is there
    # exact mirror symmetry of the returned fields: X even, Y odd in y
    np.testing.assert_array_equal(hf.px, hf.px[::-1])
    np.testing.assert_array_equal(hf.py, -hf.py[::-1])
    _check_fields(half, 0.3)
    # warm start from a non-symmetric solution (η != 0) still converges to the same
    s = cc.make_solver("exact", mx=mx, my=my, extrapolate=False)
    prev = s.step(1.2e-3, 3e-4, 0.0, 1e5, 0.3, a, b, G, 0.28)
    warm = s.step(1.2e-3, 0.0, 0.0, 1e5, 0.3, a, b, G, 0.28, warm_start=prev)
    assert warm.Fx == pytest.approx(full.Fx, rel=1e-5) and warm.Fy == 0.0


def test_secant_warm_start_sequence(wheel_rail_case):
    # a ramp of the creepages: the warm state holds the last two solutions and extrapolates
    k = wheel_rail_case

    def ramp(predictor):
        solver = cc.make_solver("exact", mx=24, my=24, predictor=predictor, extrapolate=False)
        r = solver.step(1.0e-3, 5e-4, 0.2, k["N"], k["mu"], k["a"], k["b"], k["G"], k["nu"])
        its = []
        for i in range(1, 6):
            f = 1.0 + 2e-3 * i
            r = solver.step(1.0e-3 * f, 5e-4 * f, 0.2 * f, k["N"], k["mu"], k["a"], k["b"],
                            k["G"], k["nu"], warm_start=r)
            its.append(r.iterations)
        return r, its

    r_sec, its_sec = ramp("secant")
    r_plain, its_plain = ramp("scale")
    assert its_sec[0] == its_plain[0]              # first warm start: no secant yet
    assert sum(its_sec[1:]) * 1.5 <= sum(its_plain[1:])
    assert r_sec.converged and r_sec.Fx == pytest.approx(r_plain.Fx, rel=1e-5)
    assert r_sec.Fy == pytest.approx(r_plain.Fy, rel=1e-5)
    state = pickle.loads(pickle.dumps(r_sec.warm_state))
    assert state.previous is not None
    record = state.to_record()  # data only: numbers and float arrays
    assert all(isinstance(v, (int, float, bool, np.ndarray)) for v in record.values())
    assert "prev_px" in record
    again = cc.METHODS["exact"].warm_state_from_record(record)
    np.testing.assert_array_equal(again.previous[0], state.previous[0])


def test_clear_caches_empties_every_cache():
    """contact_core.clear_caches: the public way to start cold (benchmarks, memory); the solver
    gives the same result afterwards."""
    from contact_core.exact import contact_grid, kernel_tables
    a, b = _patch(1.0)
    kw = dict(xi=1e-3, eta=2e-4, phi=0.1, N=1e5, mu=0.3, a=a, b=b, G=G, nu=0.28, mx=12, my=12,
              extrapolate=False)
    before = cc.solve("exact", **kw)
    assert contact_grid.cache_info().currsize > 0 and kernel_tables.cache_info().currsize > 0
    cc.clear_caches()
    assert contact_grid.cache_info().currsize == 0 and kernel_tables.cache_info().currsize == 0
    after = cc.solve("exact", **kw)
    assert (after.Fx, after.Fy, after.Mz) == (before.Fx, before.Fy, before.Mz)
