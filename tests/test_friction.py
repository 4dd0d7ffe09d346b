"""Falling friction (the effect ``falling_friction``, contact_core.friction) against independent
references: CONTACT's published friction laws and their conversion from Polach's (CONTACT user
guide, "Slip velocity dependent friction"), the static and the flat-law limits (Coulomb
friction), full sliding at the law's coefficient, Coulomb's law element by element, and
CONTACT's published ``tractcurv`` example: series 2 (exact theory, exponential falling friction
with memory, elastic interfacial layer) and series 4 (modified FASTSIM with slope reduction)."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import contact_core as cc
from contact_core.friction import FrictionLaw

from conftest import REFERENCE_DIR

pytestmark = pytest.mark.unit

FALLING = ("longitudinal", "lateral", "spin", "saturation", "falling_friction")
COULOMB = ("longitudinal", "lateral", "spin", "saturation")
CASE = dict(N=1e5, mu=0.3, a=6e-3, b=4e-3, G=8e10, nu=0.28)
#: every method that saturates, the discretised ones on small grids
SATURATING = {"johnson_vermeulen": {}, "polach": {}, "table": {},
              "fastsim": {}, "fastsim-creep": {"falling": "creep"},
              "exact": {"mx": 16, "my": 16, "extrapolate": False}}


def solve(name, effects=FALLING, **kw):
    opts = SATURATING.get(name, {})
    return cc.solve(name.split("-")[0], effects=effects, **(CASE | kw), **opts)


# ------------------------------------------------------------------------------- the laws

@pytest.mark.parametrize("kind", ["exponential", "rational", "linear"])
def test_each_law_halves_its_falling_part_at_s_half(kind):
    # CONTACT user guide: s_h is the slip velocity at which a term is halved; μ(0) = μ_stat,
    # μ -> μ_kin; the linear law reaches μ_kin at 2 s_h.
    law = FrictionLaw(kind, kinetic=0.4, s_half=1.5)
    assert law.ratio(0.0) == 1.0
    assert law.ratio(1.5) == pytest.approx(0.4 + 0.6 / 2, rel=1e-14)
    assert law.ratio(1e9) == pytest.approx(0.4, abs=1e-8)
    if kind == "linear":
        assert law.ratio(3.0) == pytest.approx(0.4, rel=1e-14)
    s = np.linspace(0.0, 10.0, 101)
    assert np.all(np.diff([law.ratio(v) for v in s]) <= 0.0)


def test_second_terms_as_contact():
    # CONTACT L=3: μ_rat2/(1 + (s/s_h2)²), halved at s_h2; L=4: exp(-ln2 s/s_h2)
    law = FrictionLaw("rational", kinetic=0.5, s_half=1e9, second=1.0, s_half2=2.0)
    assert law.ratio(2.0) == pytest.approx(0.75, rel=1e-12)
    assert law.ratio(4.0) == pytest.approx(0.5 + 0.5 / 5.0, rel=1e-12)


@pytest.mark.parametrize("w", [0.0, 0.1, 1.0, 7.0])
def test_polach_law_is_contacts_exponential_law(w):
    # Polach 2005: μ = μ0 [(1 - A) e^(-B w) + A]; CONTACT's conversion μ_kin = A μ0,
    # μ_exp1 = (1 - A) μ0, s_h1 = ln 2 / B
    mu0, A, B = 0.36, 0.38, 0.7
    law = FrictionLaw.polach(A, B)
    assert mu0 * law.ratio(w) == pytest.approx(mu0 * ((1 - A) * math.exp(-B * w) + A), rel=1e-14)
    assert law.B == pytest.approx(B, rel=1e-14)


def test_tractcurv_series_4_law_is_polachs():
    # CONTACT user guide, example tractcurv: series 4's FKIN 0.1368, FEXP1 0.2232, SABSH1 990
    # mm/s are Polach's law with μ_stat = 0.36, A = 0.38, B = 0.7 s/m
    law = FrictionLaw.from_contact("exponential", 0.36, 0.1368, 0.2232, 0.990)
    assert law.kinetic == pytest.approx(0.38, rel=1e-12)
    assert law.B == pytest.approx(0.7, rel=5e-4)     # SABSH1 printed to ±0.5 mm/s


@pytest.mark.parametrize("kw, word", [
    (dict(kind="cubic"), "kind"), (dict(kinetic=1.5), "kinetic"), (dict(kinetic=-0.1), "kinetic"),
    (dict(s_half=0.0), "s_half"), (dict(s_half=math.nan), "s_half"), (dict(second=2.0), "second"),
    (dict(memory=-1.0), "memory"), (dict(memory_speed=math.inf), "memory_speed"),
    (dict(kinetic="0.4"), "kinetic"),
])
def test_bad_law_parameters_are_named(kw, word):
    with pytest.raises(ValueError, match=rf"^{word}=.*allowed"):
        FrictionLaw(**kw)


def test_effect_inputs_and_their_errors():
    with pytest.raises(ValueError, match="'falling_friction' needs 'saturation'"):
        cc.solve("polach", xi=1e-3, eta=0.0, phi=0.0, effects=("longitudinal", "falling_friction"),
                 **CASE)
    with pytest.raises(ValueError, match="^friction=.*not selected"):
        cc.solve("polach", xi=1e-3, eta=0.0, phi=0.0, friction=FrictionLaw(), **CASE)
    with pytest.raises(ValueError, match="^V=20.0 is given but the effect 'falling_friction'"):
        cc.solve("polach", xi=1e-3, eta=0.0, phi=0.0, V=20.0, **CASE)
    with pytest.raises(ValueError, match="^friction=.*allowed a contact_core.FrictionLaw"):
        solve("polach", xi=1e-3, eta=0.0, phi=0.0, friction={"kinetic": 0.4})
    for bad in (math.nan, math.inf):
        with pytest.raises(ValueError, match=r"^V=.* is out of range: allowed a finite number"):
            solve("fastsim", xi=1e-3, eta=0.0, phi=0.0, V=bad)
    with pytest.raises(ValueError, match=r"^V='20' is not a number"):
        solve("exact", xi=1e-3, eta=0.0, phi=0.0, V="20")
    # the contact's own inputs are still named first
    with pytest.raises(ValueError, match=r"^xi=nan is out of range"):
        solve("polach", xi=math.nan, eta=0.0, phi=0.0, V=20.0)
    with pytest.raises(ValueError, match=r"^a=.* is out of range"):
        solve("fastsim", xi=1e-3, eta=0.0, phi=0.0, V=20.0, a=-1.0)


# ------------------------------------------------------------------ limits: Coulomb friction

@pytest.mark.parametrize("name", list(SATURATING))
def test_at_rest_the_law_is_static_friction(name):
    # V = 0: no slip velocity anywhere, μ = μ_stat: Coulomb friction, to the last bit
    for xi, eta, phi in ((2e-3, -1e-3, 0.5), (1e-2, 0.0, 0.0)):
        r = solve(name, xi=xi, eta=eta, phi=phi, V=0.0)
        c = solve(name, effects=COULOMB, xi=xi, eta=eta, phi=phi)
        assert (r.Fx, r.Fy, r.Mz) == (c.Fx, c.Fy, c.Mz)


@pytest.mark.parametrize("name", ["fastsim", "exact"])
def test_a_flat_law_is_coulomb_friction(name):
    # μ_kin = μ_stat: whatever the slip velocity, the local march and the outer iteration give
    # Coulomb's solution
    flat = FrictionLaw(kinetic=1.0)
    for xi, eta, phi in ((2e-3, -1e-3, 0.5), (1e-2, 3e-3, 0.0)):
        r = solve(name, xi=xi, eta=eta, phi=phi, V=30.0, friction=flat)
        c = solve(name, effects=COULOMB, xi=xi, eta=eta, phi=phi)
        np.testing.assert_allclose([r.Fx, r.Fy, r.Mz], [c.Fx, c.Fy, c.Mz], rtol=1e-9,
                                   atol=1e-9 * CASE["mu"] * CASE["N"])


@pytest.mark.parametrize("name", list(SATURATING))
@pytest.mark.parametrize("xi, V", [(0.05, 20.0), (0.2, 5.0), (1.0, 5.0)])
def test_full_sliding_at_the_friction_of_the_slip_velocity(name, xi, V):
    # Every element slides at nearly the rigid slip velocity V ξ: |F| -> μ(V ξ) N (Coulomb's law
    # with the law's coefficient), against the slip. The methods with one coefficient at the
    # creep velocity V ξ stay below it until the whole contact slides; the local ones above:
    # the elastic part of the slip makes their slip velocities smaller. Both vanish as ξ grows.
    ref = CASE["mu"] * CASE["N"] * FrictionLaw().ratio(V * xi)
    r = solve(name, xi=xi, eta=0.0, phi=0.0, V=V)
    assert -r.Fx / ref == pytest.approx(1.0, abs=3e-3 if xi < 1.0 else 1e-4)
    if name in ("fastsim", "exact"):
        assert -r.Fx / ref >= 1.0 - 1e-9
    else:
        assert -r.Fx / ref <= 1.0 + 1e-12


@pytest.mark.parametrize("name", ["fastsim", "exact", "polach"])
def test_symmetries_of_steady_rolling_with_falling_friction(name):
    # the law depends on |slip|: ξ -> -ξ flips Fx only, (η, φ) -> -(η, φ) flips Fy and Mz only
    kw = dict(xi=3e-3, eta=-2e-3, phi=0.8, V=20.0)
    r = solve(name, **kw)
    rx = solve(name, **(kw | dict(xi=-kw["xi"])))
    ry = solve(name, **(kw | dict(eta=-kw["eta"], phi=-kw["phi"])))
    tol = 1e-9 * CASE["mu"] * CASE["N"]
    assert abs(rx.Fx + r.Fx) < tol and abs(rx.Fy - r.Fy) < tol and abs(rx.Mz - r.Mz) < tol * 1e-2
    assert abs(ry.Fx - r.Fx) < tol and abs(ry.Fy + r.Fy) < tol and abs(ry.Mz + r.Mz) < tol * 1e-2


def test_exact_meets_coulombs_law_with_the_local_friction_element_by_element():
    # Kalker 1979 eq 5 with μ at each element's own slip velocity s = V |w|: slipping elements
    # on μ(s) p_n, against their slip; sticking ones within μ_stat p_n (no memory)
    V = 20.0
    r = solve("exact", xi=4e-3, eta=1e-3, phi=0.3, V=V, fields=True)
    f = r.fields
    law = FrictionLaw()
    p = np.hypot(f.px, f.py)
    w = np.hypot(f.sx, f.sy)
    slip = f.status == cc.exact.SLIP
    stick = f.status == cc.exact.STICK
    assert slip.sum() > 20 and stick.sum() > 20
    bound = CASE["mu"] * f.pn * np.vectorize(law.ratio)(V * w)
    scale = CASE["mu"] * f.pn.max()
    assert np.abs(p[slip] - bound[slip]).max() < 2e-4 * scale
    assert np.all(p[stick] <= CASE["mu"] * f.pn[stick] * (1 + 1e-9))
    assert np.all(f.px[slip] * f.sx[slip] + f.py[slip] * f.sy[slip] < 0.0)
    assert bound[slip].min() < 0.95 * (CASE["mu"] * f.pn[slip]).max()   # the law acts


def test_fastsim_and_exact_agree_under_the_same_local_law():
    # two independent discretisations of the local law (simplified theory's strip march and
    # the boundary elements with the outer iteration) on the falling branch and near the peak
    kw = dict(eta=0.0, phi=0.0, V=20.0)
    for xi in (2e-3, 5e-3, 2e-2):
        fs = solve("fastsim", xi=xi, **kw)
        ex = cc.solve("exact", xi=xi, effects=FALLING, **(CASE | kw))
        assert abs(fs.Fx - ex.Fx) < 0.03 * CASE["mu"] * CASE["N"]


# ------------------------------------------------------------- CONTACT's tractcurv example

def _series(series):
    with open(REFERENCE_DIR / "contact_tractcurv_example.csv", newline="") as f:
        return [r for r in csv.DictReader(f) if r["series"] == series]


# Eurosprinter (CONTACT tractcurv, Polach 2005), SI units; a, b from the file's Hertz solution
EURO = dict(N=106.7e3, a=6.304e-3, b=12.61e-3, G=82e9, nu=0.28)


def test_tractcurv_series_4_modified_fastsim_within_2_percent():
    # Series 4: CONTACT's modified FASTSIM (M=3, parabolic bound, 48x44 over 1.1x the ellipse:
    # our comparable strip grid 44x40, its discretisation scheme="kalker"), Spiryagin's slope
    # reduction k0 = 0.54, alpha = 0.02, beta = 0.62, and one coefficient at the creep velocity
    # V |xi| (falling="creep") of the exponential law FSTAT 0.36, FKIN 0.1368, FEXP1 0.2232,
    # SABSH1 990 mm/s, at V = 10 m/s
    rows = _series("4")
    assert len(rows) == 30
    r0 = rows[0]
    assert (r0["K0_MF"], r0["ALFAMF"], r0["BETAMF"]) == ("0.54", "0.02", "0.62")
    law = FrictionLaw.from_contact("exponential", 0.36, 0.1368, 0.2232, 0.990)
    solver = cc.make_solver("fastsim", FALLING, law, nx=44, ny=40, bound="parabolic",
                            scheme="kalker", flexibility="blended-contact", falling="creep",
                            k0=0.54, alpha_inf=0.02, beta=0.62)
    errors = []
    for r in rows:
        res = solver.step(float(r["CKSI"]), 0.0, 0.0, EURO["N"], 0.36, EURO["a"], EURO["b"],
                          EURO["G"], EURO["nu"], None, float(r["VELOC_mm_per_s"]) * 1e-3)
        errors.append(res.Fx / (0.36 * EURO["N"]) - float(r["FX_over_FSTAT_FN"]))
    assert max(map(abs, errors)) < 0.02
    # the slope reduction and the falling law both act: without either, 10-30 % off
    plain = cc.make_solver("fastsim", ("longitudinal", "saturation"), nx=44, ny=40,
                           scheme="kalker")
    f = plain.step(0.002, 0.0, 0.0, EURO["N"], 0.36, EURO["a"], EURO["b"], EURO["G"],
                   EURO["nu"]).Fx / (0.36 * EURO["N"])
    assert abs(f - float(rows[2]["FX_over_FSTAT_FN"])) > 0.1


def test_tractcurv_series_2_exact_with_layer_and_memory():
    # Series 2: CONTACT's exact steady rolling on 48x44 over 1.1x the ellipse, the exponential
    # law FSTAT 0.33, FKIN 0.14, FEXP1 0.19, SABSH1 1250 mm/s with memory (MEMDST 0.003 mm,
    # MEM_S0 1 mm/s) at V = 10 m/s, and an elastic interfacial layer GG3 = 8200 N/mm²,
    # LAYTHK = 1.25 mm (no plasticity): the same discretisation here (extrapolate=False) with
    # every element at its own slip velocity reproduces the published curve to its 4 digits
    rows = _series("2")
    assert len(rows) == 30 and {r["TAU_C0_N_per_mm2"] for r in rows} == {"0.0"}
    law = FrictionLaw.from_contact("exponential", 0.33, 0.14, 0.19, 1.25, memory=3e-6,
                                   memory_speed=1e-3)
    solver = cc.make_solver("exact", FALLING, law, mx=48, my=44, scale=1.1, extrapolate=False,
                            layer=1.25e-3 / 8.2e9)
    worst = 0.0
    for r in rows[::3]:
        res = solver.step(float(r["CKSI"]), 0.0, 0.0, EURO["N"], 0.33, EURO["a"], EURO["b"],
                          EURO["G"], EURO["nu"], None, 10.0)
        assert res.converged
        worst = max(worst, abs(res.Fx / (0.33 * EURO["N"]) - float(r["FX_over_FSTAT_FN"])))
    assert worst < 3e-4


def test_tractcurv_example_script_writes_both_series(tmp_path):
    from tractcurv_friction import main
    out = tmp_path / "tc.csv"
    assert main(["--out", str(out)]) == 0
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    assert {r["series"] for r in rows} == {"2", "4"} and len(rows) == 60
    for r in rows:
        assert abs(float(r["difference"])) < (3e-4 if r["series"] == "2" else 0.02)
    # --cases: other cases in the file's own columns (here: series 1, Coulomb friction)
    cases = tmp_path / "cases.csv"
    with open(REFERENCE_DIR / "contact_tractcurv_example.csv", newline="") as f:
        src = list(csv.DictReader(f))
    with open(cases, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(src[0]))
        w.writeheader()
        w.writerows([r for r in src if r["series"] == "1"][:6])
    assert main(["--cases", str(cases), "--out", str(out)]) == 0
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6 and all(abs(float(r["difference"])) < 5e-3 for r in rows)
