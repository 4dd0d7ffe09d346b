"""The contract every registered method meets (``contact_core.ContactMethod``'s docstring lists what
a method implements): each test here runs over ``contact_core.METHODS``, so a new method gets them
all by being registered.

What the contract holds, with its references: the symmetries of steady rolling (Kalker 1967 sec.
4.2; Kalker 1979 sec. 2: Fx is odd in ξ, Fy and Mz are even; (η, φ) -> (-η, -φ) flips Fy and Mz
and keeps Fx); forces against the slip, bounded by Coulomb's μN and reaching it at full sliding;
linear theory as the small-creepage limit (Kalker 1979 eq 18); Hertzian similarity (Kalker 1979
sec. 2: the answer does not depend on the units, nor on the scale of lengths, loads and spin);
zero forces for a lifted or resting contact; only the selected effects computed
(``contact_core.effects``); every finite input either solved or refused with a ``ValueError``
naming the argument (property-based, hypothesis); the warm state's record read back; the traction
fields scaled with the inputs.

What a method does differently by design is declared below, per method, with its source
(:data:`DECLARED`); a registered method without a declaration is held to the strict defaults of
:class:`Declared`.

Profiles of the property tests (``HYPOTHESIS_PROFILE``): ``ci`` (default; sized so that the suite
stays short) and ``deep`` (at least 1e5 examples per property: ``HYPOTHESIS_PROFILE=deep pytest
tests/test_method_contract.py``).
"""
from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass, field, replace

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import contact_core as cc
from contact_core.hertz import coulomb_spin_moment

pytestmark = pytest.mark.unit

settings.register_profile("ci", max_examples=150, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("deep", max_examples=100_000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


# ----------------------------------------------------------------------------------------------
# Per-method declarations
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Declared:
    """What one method declares about itself for the contract (defaults: a closed form that
    meets every point exactly)."""

    #: Options of the property tests (the discretised methods on small grids: the properties do
    #: not depend on the grid).
    options: dict = field(default_factory=dict)
    #: Options of the sample-state tests (conftest.options_for: 16-20 elements per axis).
    coarse_options: dict = field(default_factory=dict)
    #: Relative distance to linear theory at a normalised creepage of 1e-6 (``options``).
    linear_limit: float = 1e-5
    #: Relative distance to linear theory at creepage 1e-9 on the coarse options.
    coarse_linear_limit: float = 1e-6
    #: Its spin moment is held to Coulomb's bound μ∫p_n r dA of the continuum's pressure (the
    #: discretised methods hold it to their grids' pressures, a little above the continuum's).
    moment_held: bool = True
    #: Direction of the full-sliding force: "slip" (against the rigid slip (ξ, η)) or
    #: "linear force" (against the linear force (C11 ξ, C22 η)).
    sliding_direction: str = "slip"
    #: Linear limit under combined (ξ, η): "kalker" (linear theory's force) or "along creepage"
    #: (Kalker's magnitude |(C11 ξ, C22 η)| along (ξ, η)).
    combined_linear_limit: str = "kalker"
    #: Whose C33 the small-spin moment takes: "kalker" (Kalker 1990, Table E.3) or "exact" (the
    #: converged exact theory's, up to 30 % lower at a/b = 5: contact_core.coefficients).
    c33: str = "kalker"
    #: Why, with the sources.
    why: str = ""


DECLARED: dict[str, Declared] = {
    "linear": Declared(
        linear_limit=1e-9,
        why="Kalker's linear theory (Kalker 1979 eq 17) is the limit itself; it never saturates "
            "(ContactMethod.saturates False): its forces grow without bound and μ is not used."),
    "johnson_vermeulen": Declared(
        sliding_direction="linear force",
        why="Kalker 1979 eq 22 keeps the force along the linear force (C11 ξ, C22 η) up to full "
            "sliding; the spin moment is linear theory's scaled (Shen, Hedrick & Elkins 1983), "
            "held to Coulomb's bound."),
    "polach": Declared(
        coarse_linear_limit=0.06, combined_linear_limit="along creepage",
        why="Polach 1999: the force has Kalker's magnitude G ab |(C11 ξ, C22 η)| along the "
            "creepage (ξ, η) (contact_core.polach); the spin moment as Johnson-Vermeulen's. Its "
            "sample-state tolerance is the discretised methods' (its own tests hold it to "
            "Kalker's coefficients)."),
    "fastsim": Declared(
        options={"nx": 10, "ny": 10}, coarse_options={"nx": 20, "ny": 20}, linear_limit=0.15,
        coarse_linear_limit=0.06, moment_held=False,
        why="Kalker's simplified theory on a strip grid: the default scheme makes the linear "
            "limit (1 + 1/nx) times linear theory's (Kalker 1982; contact_core.fastsim), 10 % "
            "on 10×10 besides the grid's error; the bound is the grid's pressure; L4 is fitted "
            "to Kalker's C33."),
    "table": Declared(
        linear_limit=0.02, coarse_linear_limit=0.06, c33="exact",
        why="The exact theory tabulated: its nodes are exact 48×48 extrapolated (C11, C22 "
            "-0.2..+1.6 % of Kalker's: contact_core.exact.solver); C33 is the exact theory's; "
            "outside its a/b and ν the fallback 'exact' answers."),
    "exact": Declared(
        options={"mx": 8, "my": 8, "extrapolate": False}, coarse_options={"mx": 16, "my": 16},
        linear_limit=0.05, coarse_linear_limit=0.06, moment_held=False, c33="exact",
        why="Boundary elements: within its grid's discretisation error of linear theory (16×16 "
            "at most 3.4 % over a/b 0.05..20 and ν 0..0.44); the bound is the grid's pressure; "
            "C33 is the exact theory's (Kalker's table lies above it for a/b > 1)."),
}

METHODS = cc.methods()
#: The exact method's linear-limit grid (16×16: within its declared 5 % of linear theory).
LINEAR_OPTIONS = {"exact": {"mx": 16, "my": 16, "extrapolate": False}}


def declared(method: str) -> Declared:
    return DECLARED.get(method, Declared())


def saturating() -> list[str]:
    return [m for m in METHODS if cc.METHODS[m].saturates]


ARGS = ("xi", "eta", "phi", "N", "mu", "a", "b", "G", "nu")
#: Small slack for rounding in the moment's bound (relative to it); the force bound has none.
ROUND = 1e-9


def solve(method, options=None, **kw):
    """``cc.solve`` with the method's property-test options (or ``options``), warnings off
    (extrapolated coefficients, unconverged sweeps)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return cc.solve(method, **kw, **(declared(method).options if options is None else options))


def forces_ok(method, r, kw):
    """Finite; with saturation |F| <= μN; slip fraction in [0, 1]; the moment held where the
    method declares it."""
    assert all(math.isfinite(v) for v in (r.Fx, r.Fy, r.Mz)), (method, kw, r)
    assert 0.0 <= r.slip_fraction <= 1.0
    if cc.METHODS[method].saturates:
        assert math.hypot(r.Fx, r.Fy) <= kw["mu"] * kw["N"], (method, kw, r)
    if declared(method).moment_held and cc.METHODS[method].saturates:
        # held to Coulomb's bound on the moment; the discretised methods' pressures are their
        # grids', up to 0.8 % above the continuum's bound on 8×8 (measured), so not checked here
        bound = coulomb_spin_moment(kw["mu"] * kw["N"], kw["a"], kw["b"])
        assert abs(r.Mz) <= bound * (1 + ROUND), (method, kw, r)


# ----------------------------------------------------------------------------------------------
# Registration
# ----------------------------------------------------------------------------------------------

def test_registry():
    assert METHODS[:2] == ("linear", "johnson_vermeulen")
    assert set(cc.METHODS) == set(METHODS)
    assert sorted(cls.code for cls in cc.METHODS.values()) == list(range(1, len(METHODS) + 1))


@pytest.mark.parametrize("method", METHODS)
def test_a_method_declares_its_name_options_and_fallback(method, wheel_rail_case):
    """The class attributes ContactMethod's contract asks for: its registry name, its options
    with their defaults (accepted as they are; an unknown one refused by name), a fallback that is
    itself registered, and results that carry the name (or the fallback's)."""
    cls = cc.METHODS[method]
    assert cls.name == method and isinstance(cls.code, int)
    assert isinstance(cls.default_options, dict)
    cc.make_solver(method, **cls.default_options)
    with pytest.raises(ValueError, match=r"unknown option\(s\) \['no_such_option'\]"):
        cc.make_solver(method, no_such_option=1)
    assert cls.fallback is None or cls.fallback in cc.METHODS
    r = cc.solve(method, xi=1e-3, eta=-2e-4, phi=0.1, **wheel_rail_case,
                 **declared(method).coarse_options)
    assert r.method in (method, cls.fallback)


# ----------------------------------------------------------------------------------------------
# Sample states: signs, symmetries, units, linear limit, zero, errors, effects
# ----------------------------------------------------------------------------------------------

CASES = [  # (xi, eta, phi): linear range, partial slip, near saturation, spin-dominated
    (2e-4, 0.0, 0.0), (1e-3, -5e-4, 0.0), (3e-3, 2e-3, 0.4), (0.0, 1e-4, 2.0), (-1e-3, 2e-4, -0.3),
]


def _solve(method, case, **kw):
    return cc.solve(method, **(case | kw), **declared(method).coarse_options)


def _close(r, s, case, rtol=1e-9):
    scale = case["mu"] * case["N"]
    np.testing.assert_allclose([r.Fx, r.Fy], [s.Fx, s.Fy], rtol=rtol, atol=rtol * scale)
    np.testing.assert_allclose(r.Mz, s.Mz, rtol=rtol, atol=rtol * scale * math.sqrt(case["a"] * case["b"]))


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("xi, eta, phi", CASES)
def test_symmetries_at_sample_states(method, wheel_rail_case, xi, eta, phi):
    c = wheel_rail_case
    r = _solve(method, c, xi=xi, eta=eta, phi=phi)
    r_xi = _solve(method, c, xi=-xi, eta=eta, phi=phi)
    r_lat = _solve(method, c, xi=xi, eta=-eta, phi=-phi)
    assert all(math.isfinite(v) for v in (r.Fx, r.Fy, r.Mz))
    _close(cc.ContactResult(-r_xi.Fx, r_xi.Fy, r_xi.Mz, method), r, c)  # Fx odd, Fy Mz even in ξ
    if eta == 0.0 and phi == 0.0:
        return
    _close(cc.ContactResult(r_lat.Fx, -r_lat.Fy, -r_lat.Mz, method), r, c)


@pytest.mark.parametrize("method", METHODS)
def test_units_si_and_millimetres_give_the_same_forces(method, wheel_rail_case):
    # Same physical case with lengths in mm and G in N/mm² (= MPa): forces in N agree, the
    # moment comes out in N·mm, the spin is entered in 1/mm.
    c = wheel_rail_case
    xi, eta, phi = 1e-3, -4e-4, 0.5
    si = _solve(method, c, xi=xi, eta=eta, phi=phi)
    mm = cc.solve(method, xi=xi, eta=eta, phi=phi / 1e3, N=c["N"], mu=c["mu"], a=c["a"] * 1e3,
                  b=c["b"] * 1e3, G=c["G"] / 1e6, nu=c["nu"], **declared(method).coarse_options)
    _close(cc.ContactResult(mm.Fx, mm.Fy, mm.Mz / 1e3, method), si, c)


@pytest.mark.parametrize("method", METHODS)
def test_small_creepage_agrees_with_linear_theory(method, wheel_rail_case):
    # All methods share linear theory as their small-creepage limit (Kalker 1979, eq 18). The
    # discretised methods run here on coarse grids (16-20 elements per axis), within a few percent;
    # their own tests check the convergence to Kalker's coefficients.
    c = wheel_rail_case
    tol = declared(method).coarse_linear_limit
    for inp in (dict(xi=1e-9, eta=0.0, phi=0.0), dict(xi=0.0, eta=1e-9, phi=0.0)):
        r, lin = _solve(method, c, **inp), cc.solve("linear", **(c | inp))
        assert r.Fx == pytest.approx(lin.Fx, rel=tol, abs=1e-14)
        assert r.Fy == pytest.approx(lin.Fy, rel=tol, abs=1e-14)


@pytest.mark.parametrize("method", METHODS)
def test_small_spin_moment_opposes_the_spin(method, wheel_rail_case):
    """Mz = -G c⁴ C33 φ at small spin (Kalker 1979 eq 17), C33 > 0 whichever C33 the method
    declares; the methods that take Kalker's tabulated C33 without a grid give linear theory's
    moment (those with the exact theory's C33 or a grid differ from it by design:
    :data:`DECLARED`)."""
    c = wheel_rail_case
    for phi in (1e-6, -1e-6):
        r, lin = _solve(method, c, xi=0.0, eta=0.0, phi=phi), cc.solve("linear", **(c | dict(
            xi=0.0, eta=0.0, phi=phi)))
        assert r.Mz * phi < 0.0 and lin.Mz * phi < 0.0
        d = declared(method)
        if d.c33 == "kalker" and not d.coarse_options:
            assert r.Mz == pytest.approx(lin.Mz, rel=d.coarse_linear_limit)


@pytest.mark.parametrize("method", METHODS)
def test_zero_load_and_zero_creepage_give_zero_forces(method, wheel_rail_case):
    c = wheel_rail_case
    lifted = _solve(method, c | dict(N=0.0), xi=1e-3, eta=1e-3, phi=1.0)
    assert (lifted.Fx, lifted.Fy, lifted.Mz) == (0.0, 0.0, 0.0)
    rest = _solve(method, c, xi=0.0, eta=0.0, phi=0.0)
    assert (rest.Fx, rest.Fy, rest.Mz) == (0.0, 0.0, 0.0)


BAD = [("xi", math.nan), ("eta", math.inf), ("phi", -math.inf), ("N", -1.0), ("N", math.nan),
       ("mu", -0.1), ("mu", math.inf), ("a", 0.0), ("a", -1e-3), ("b", math.nan), ("G", 0.0),
       ("G", math.inf), ("nu", 0.5), ("nu", -0.01), ("nu", math.nan)]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name, value", BAD)
def test_bad_input_is_a_value_error_naming_the_argument(method, wheel_rail_case, name, value):
    case = wheel_rail_case | dict(xi=1e-3, eta=0.0, phi=0.0) | {name: value}
    with pytest.raises(ValueError, match=rf"^{name}=.*allowed"):
        _solve(method, case)


@pytest.mark.parametrize("method", METHODS)
def test_effect_subsets_compute_only_their_outputs(method, wheel_rail_case):
    c = wheel_rail_case
    full = _solve(method, c, xi=1e-3, eta=0.0, phi=0.0)
    lon = _solve(method, c, xi=1e-3, eta=0.0, phi=0.0, effects=("longitudinal", "saturation"))
    assert (lon.Fy, lon.Mz) == (0.0, 0.0)
    # With the omitted inputs truly zero, the longitudinal-only solve is the full solve.
    assert lon.Fx == pytest.approx(full.Fx, rel=1e-9)
    with pytest.raises(ValueError, match="eta is non-zero"):
        _solve(method, c, xi=1e-3, eta=1e-4, phi=0.0, effects=("longitudinal",))
    with pytest.raises(ValueError, match="unknown effect"):
        _solve(method, c, xi=1e-3, eta=0.0, phi=0.0, effects=("traction",))
    # any iterable of names, as the signature says: a list, a set, a generator
    for spec in (["longitudinal", "saturation"], {"longitudinal", "saturation"},
                 (e for e in ("longitudinal", "saturation"))):
        assert _solve(method, c, xi=1e-3, eta=0.0, phi=0.0, effects=spec).Fx == lon.Fx


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("scene", sorted(cc.scenes()))
def test_every_scene_computes_only_its_effects(method, scene, wheel_rail_case):
    """Each shipped scene's effects with every method (not only its default one): the outputs of
    the selected creepage effects non-zero, the others 0.0 and their inputs refused by name."""
    eff = cc.load_scene(scene).effects
    case = dict(wheel_rail_case, xi=1e-3 if eff.longitudinal else 0.0,
                eta=-4e-4 if eff.lateral else 0.0, phi=0.1 if eff.spin else 0.0)
    r = _solve(method, case, effects=eff)
    assert (r.Fx != 0.0) == eff.longitudinal
    assert (r.Fy != 0.0) == eff.lateral
    assert (r.Mz != 0.0) == eff.spin
    for var, on in (("xi", eff.longitudinal), ("eta", eff.lateral), ("phi", eff.spin)):
        if not on:
            with pytest.raises(ValueError, match=f"^{var} is non-zero"):
                _solve(method, {**case, var: 1e-3}, effects=eff)


@pytest.mark.parametrize("method", METHODS)
def test_without_saturation_the_linear_range_is_not_bounded(method, wheel_rail_case):
    # Effect 'saturation' absent = the μ -> ∞ limit: forces keep growing past μN.
    c = wheel_rail_case
    eff = ("longitudinal", "lateral", "spin")
    r = _solve(method, c, xi=0.02, eta=0.0, phi=0.0, effects=eff)
    assert abs(r.Fx) > 2 * c["mu"] * c["N"]


@pytest.mark.parametrize("method", METHODS)
def test_varying_geometry_gives_the_same_forces(method):
    """With the effect ``varying_geometry`` a method computes per call what it caches per a/b
    otherwise (ContactMethod's contract): the same forces, to the bit, along a geometry that
    changes at every call (the table's per-ν rows from their third call at that ν)."""
    eff = cc.ALL_EFFECTS.names() + ("varying_geometry",)
    opts = declared(method).coarse_options
    varying, fixed = cc.make_solver(method, eff, **opts), cc.make_solver(method, **opts)
    for k in range(5):
        p = cc.hertz(1e5 * (1 + 0.1 * k), 1.09 * (1 + 0.2 * k), 1.67, 210e9, 0.28)
        args = (1e-3, -4e-4, 0.2, 1e5 * (1 + 0.1 * k), 0.3, p.a, p.b, 8.1e10, 0.28)
        r, ref = varying.step(*args), fixed.step(*args)
        assert (r.Fx, r.Fy, r.Mz, r.slip_fraction) == (ref.Fx, ref.Fy, ref.Mz, ref.slip_fraction)


@pytest.mark.parametrize("method", METHODS)
def test_falling_friction_is_bounded_by_static_friction(method, wheel_rail_case):
    """With the effect ``falling_friction`` friction only falls from its static value
    (contact_core.friction: ρ <= 1), so |F| <= μ_stat N at every rolling speed; a method that
    does not saturate is unchanged by it."""
    c = wheel_rail_case
    eff = ("longitudinal", "lateral", "spin", "saturation", "falling_friction")
    for V in (0.0, 5.0, 40.0):
        for xi, eta, phi in ((1e-3, -5e-4, 0.1), (2e-2, 0.0, 0.0)):
            r = _solve(method, c, xi=xi, eta=eta, phi=phi, effects=eff, V=V)
            if cc.METHODS[method].saturates:
                assert math.hypot(r.Fx, r.Fy) <= c["mu"] * c["N"]
            else:
                ref = _solve(method, c, xi=xi, eta=eta, phi=phi)
                assert (r.Fx, r.Fy, r.Mz) == (ref.Fx, ref.Fy, ref.Mz)


@pytest.mark.parametrize("method", METHODS)
def test_the_warm_state_is_read_back_from_its_record(method, wheel_rail_case):
    """A result's ``warm_state`` is saved as data (its ``to_record()``, as FMU states hold it)
    and read back by the method's ``warm_state_from_record``: the next warm-started call gives
    the same result from either. A method without a warm state accepts only None."""
    cls = cc.METHODS[method]
    opts = declared(method).coarse_options
    r = _solve(method, wheel_rail_case, xi=1e-3, eta=-5e-4, phi=0.2)
    assert cls.warm_state_from_record(None) is None
    if r.warm_state is None:
        with pytest.raises(ValueError):
            cls.warm_state_from_record({"x": 1.0})
        return
    record = r.warm_state.to_record()
    assert all(isinstance(v, (int, float, bool, str, np.ndarray)) for v in record.values())
    again = replace(r, warm_state=cls.warm_state_from_record(record))
    kw = wheel_rail_case | dict(xi=1.01e-3, eta=-5e-4, phi=0.2)
    a = cc.solve(method, warm_start=r, **kw, **opts)
    b = cc.solve(method, warm_start=again, **kw, **opts)
    assert (a.Fx, a.Fy, a.Mz) == (b.Fx, b.Fy, b.Mz)


# ----------------------------------------------------------------------------------------------
# Every finite input (property-based): the whole double range
# ----------------------------------------------------------------------------------------------

anything = st.floats(allow_nan=False, allow_infinity=False)
positive = st.floats(min_value=0.0, exclude_min=True, allow_infinity=False)
nonnegative = st.floats(min_value=0.0, allow_infinity=False)


@pytest.mark.parametrize("method", METHODS)
@given(xi=anything, eta=anything, phi=anything, N=nonnegative, mu=nonnegative, a=positive,
       b=positive, G=positive, nu=st.floats(min_value=0.0, max_value=0.5, exclude_max=True))
def test_every_finite_input_gives_a_bounded_answer_or_names_the_argument(
        method, xi, eta, phi, N, mu, a, b, G, nu):
    kw = dict(xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=a, b=b, G=G, nu=nu)
    try:
        r = solve(method, **kw)
    except ValueError as e:
        assert any(f"{n}=" in str(e) for n in ARGS), str(e)
        assert "allowed" in str(e)
        return
    forces_ok(method, r, kw)


NOT_NUMBERS = [None, "0.001", np.array([1e-3, 2e-3]), 1e-3 + 0j, 10 ** 400]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name", ["xi", "N", "G"])
@pytest.mark.parametrize("bad", NOT_NUMBERS, ids=["None", "str", "array", "complex", "huge int"])
def test_an_input_that_is_not_a_number_is_named(method, name, bad):
    kw = dict(xi=1e-3, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=6e-3, b=4e-3, G=8e10, nu=0.28)
    with pytest.raises(ValueError, match=f"^{name}=.* is not a number: allowed a real scalar"):
        solve(method, **{**kw, name: bad})


# ----------------------------------------------------------------------------------------------
# The physical range (property-based)
# ----------------------------------------------------------------------------------------------

def physical(draw_creepage=st.floats(-1.0, 1.0)):
    """Hertzian contacts of wheels and rails: a/b 0.05..20, c 0.1..50 mm, steel-like G, loads of
    1 N to 500 kN, μ 0.01..1; creepages up to full sliding."""
    return dict(
        xi=draw_creepage, eta=draw_creepage, phi=st.floats(-500.0, 500.0),
        N=st.floats(1.0, 5e5), mu=st.floats(0.01, 1.0), ab=st.floats(0.05, 20.0),
        c=st.floats(1e-4, 5e-2), G=st.floats(2e10, 1e11), nu=st.floats(0.0, 0.49))


def _case(xi, eta, phi, N, mu, ab, c, G, nu, method=None):
    if method == "table":
        # a/b and ν mapped into the table's domain (a/b 0.1..10, ν 0.25..0.30; outside it the
        # table is the exact method, tested as such), monotonically, so no example is lost
        ab = min(10.0, max(0.1, 0.1 * 100.0 ** (math.log(ab / 0.05) / math.log(400.0))))
        nu = 0.25 + 0.05 * nu / 0.49
    return dict(xi=xi, eta=eta, phi=phi, N=N, mu=mu, a=c * math.sqrt(ab), b=c / math.sqrt(ab),
                G=G, nu=nu)


def _sigma_scale(kw):
    """G/(μ p0): normalised creepage per unit creepage."""
    p0 = 1.5 * kw["N"] / (math.pi * kw["a"] * kw["b"])
    return kw["G"] / (kw["mu"] * p0)


@pytest.mark.parametrize("method", METHODS)
@given(**physical())
def test_physical_inputs_are_bounded_and_oppose_the_slip(method, xi, eta, phi, N, mu, ab, c,
                                                          G, nu):
    kw = _case(xi, eta, phi, N, mu, ab, c, G, nu, method)
    r = solve(method, **kw)
    forces_ok(method, r, kw)
    if phi == 0.0:  # without spin the force opposes the rigid slip (ξ, η)
        assert r.Fx * xi + r.Fy * eta <= ROUND * mu * N * (abs(xi) + abs(eta))


@pytest.mark.parametrize("method", METHODS)
@given(**physical())
def test_symmetries_of_steady_rolling(method, xi, eta, phi, N, mu, ab, c, G, nu):
    """ξ -> -ξ flips Fx only; (η, φ) -> (-η, -φ) flips Fy and Mz only."""
    kw = _case(xi, eta, phi, N, mu, ab, c, G, nu, method)
    r = solve(method, **kw)
    rx = solve(method, **(kw | dict(xi=-xi)))
    ry = solve(method, **(kw | dict(eta=-eta, phi=-phi)))
    tol_f = 1e-9 * mu * N + 1e-12 * (abs(r.Fx) + abs(r.Fy))
    tol_m = tol_f * math.sqrt(kw["a"] * kw["b"]) + 1e-12 * abs(r.Mz)
    assert abs(rx.Fx + r.Fx) <= tol_f and abs(rx.Fy - r.Fy) <= tol_f
    assert abs(rx.Mz - r.Mz) <= tol_m
    assert abs(ry.Fx - r.Fx) <= tol_f and abs(ry.Fy + r.Fy) <= tol_f
    assert abs(ry.Mz + r.Mz) <= tol_m


@pytest.mark.parametrize("method", METHODS)
@given(**physical(st.floats(-1.0, 1.0)), kind=st.sampled_from(["xi", "eta", "both"]))
def test_small_creepage_limit_is_linear_theory(method, xi, eta, phi, N, mu, ab, c, G, nu,
                                               kind):
    """Agreement with linear theory at σ = 1e-6, within the method's declared linear limit."""
    xi, eta = (xi, 0.0) if kind == "xi" else (0.0, eta) if kind == "eta" else (xi, eta)
    kw = _case(xi, eta, 0.0, N, mu, ab, c, G, nu, method)
    size = math.hypot(xi, eta)
    assume(size > 1e-6)
    f = 1e-6 / (size * _sigma_scale(kw))          # normalised creepage 1e-6
    kw |= dict(xi=xi * f, eta=eta * f)
    d = declared(method)
    r = solve(method, LINEAR_OPTIONS.get(method, d.options), **kw)
    lin = solve("linear", **kw)
    scale = math.hypot(lin.Fx, lin.Fy)
    if d.combined_linear_limit == "along creepage" and kind == "both":
        assert math.hypot(r.Fx, r.Fy) == pytest.approx(scale, rel=d.linear_limit)
        assert (r.Fx * xi + r.Fy * eta) / (scale * size) == pytest.approx(-1.0, abs=1e-9)
        return
    assert math.hypot(r.Fx - lin.Fx, r.Fy - lin.Fy) <= d.linear_limit * scale


@pytest.mark.parametrize("method", saturating())
@given(N=st.floats(1.0, 5e5), mu=st.floats(0.01, 1.0), ab=st.floats(0.05, 20.0),
       c=st.floats(1e-4, 5e-2), nu=st.floats(0.0, 0.49),
       s1=st.floats(1e-4, 1e4), s2=st.floats(1e-4, 1e4), sign=st.sampled_from([-1.0, 1.0]))
def test_longitudinal_force_grows_with_xi_up_to_mu_n(method, N, mu, ab, c, nu, s1, s2, sign):
    """|Fx| is monotonic in ξ (pure longitudinal creepage), and at full sliding it is μN."""
    kw = _case(0.0, 0.0, 0.0, N, mu, ab, c, 8e10, nu, method)
    k = _sigma_scale(kw)
    lo, hi = sorted((s1, s2))
    f_lo = solve(method, **(kw | dict(xi=sign * lo / k))).Fx
    f_hi = solve(method, **(kw | dict(xi=sign * hi / k))).Fx
    assert abs(f_lo) <= abs(f_hi) + 1e-6 * mu * N
    assert -sign * f_lo >= 0.0 and -sign * f_hi >= 0.0       # opposes ξ
    sliding = solve(method, **(kw | dict(xi=sign * 1e12 / k))).Fx
    assert abs(sliding) == pytest.approx(mu * N, rel=1e-6)


@pytest.mark.parametrize("method", saturating())
def test_saturated_force_is_within_mu_n_to_the_last_bit(method):
    """Coulomb's bound as a user checks it, ``hypot(Fx, Fy) <= mu * N`` in floating point, on
    seeded states around saturation (|σ| from 0.3 to 30 times the onset of full sliding, every
    direction, spin). A force formed as μN times a unit direction lands an ulp above μN in about
    one call in seven of Johnson–Vermeulen's without a final guard."""
    rng = np.random.default_rng(20261127)
    n = 40 if method == "exact" else 2000
    for _ in range(n):
        kw = _case(0.0, 0.0, 0.0, 10.0 ** rng.uniform(0, 6), rng.uniform(0.05, 1.0),
                   math.exp(rng.uniform(math.log(0.05), math.log(20.0))),
                   10.0 ** rng.uniform(-3.5, -2.0), 8e10, 0.28, method)
        size = 3.0 * 10.0 ** rng.uniform(-1, 1) / _sigma_scale(kw)
        t = rng.uniform(0.0, 2.0 * math.pi)
        kw |= dict(xi=size * math.cos(t), eta=size * math.sin(t),
                   phi=rng.normal() * size / math.sqrt(kw["a"] * kw["b"]))
        r = solve(method, **kw)
        assert math.hypot(r.Fx, r.Fy) <= kw["mu"] * kw["N"], (method, kw, r)


@pytest.mark.parametrize("method", saturating())
@given(**physical(), big=st.floats(1e4, 1e300))
def test_full_sliding_reaches_mu_n(method, xi, eta, phi, N, mu, ab, c, G, nu, big):
    """Creepage (ξ, η) beyond any stick zone: |F| = μN, whatever its size, against (ξ, η): along
    it where every element slides in the rigid-slip direction (FASTSIM, exact); Johnson–Vermeulen
    keeps the direction of its linear force, (C11 ξ, C22 η)."""
    kw = _case(xi, eta, 0.0, N, mu, ab, c, G, nu, method)
    size = math.hypot(xi, eta)
    assume(size > 1e-3)
    f = big / (size * _sigma_scale(kw))
    assume(math.isfinite(xi * f) and math.isfinite(eta * f))
    r = solve(method, **(kw | dict(xi=xi * f, eta=eta * f)))
    assert math.hypot(r.Fx, r.Fy) == pytest.approx(mu * N, rel=1e-3)
    cos = (r.Fx * xi + r.Fy * eta) / (mu * N * size)
    if declared(method).sliding_direction == "linear force":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # C33 extrapolated beyond a/b = 10: not used here
            c11, c22, _, _ = cc.creep_coefficients(ab, nu)
        lin = (c11 * xi, c22 * eta)
        assert cos == pytest.approx(-(c11 * xi * xi + c22 * eta * eta)
                                    / (math.hypot(*lin) * size), abs=1e-6)
    else:
        assert cos == pytest.approx(-1.0, abs=1e-3)


@pytest.mark.parametrize("method", METHODS)
@given(**physical(), scale=st.sampled_from([1e-100, 1e-30, 1e30, 1e100]))
def test_extreme_scales_are_the_physical_problem_scaled(method, xi, eta, phi, N, mu, ab, c, G,
                                                        nu, scale):
    """Hertzian similarity (Kalker 1979 sec. 2): lengths × λ, load × λ² (same pressure), spin
    / λ leave the creepages' effect unchanged, so F × λ² and Mz × λ³ — at scales where the
    SI arithmetic would overflow or underflow, the method must give exactly that."""
    kw = _case(xi, eta, phi, N, mu, ab, c, G, nu, method)
    big = dict(kw, a=kw["a"] * scale, b=kw["b"] * scale, N=N * scale * scale, phi=phi / scale)
    r = solve(method, **kw)
    expected = max(abs(r.Fx) * scale ** 2, abs(r.Fy) * scale ** 2, mu * N * scale ** 2,
                   abs(r.Mz) * scale ** 3)
    if math.isinf(expected):                # beyond the float range: refused, never inf
        with pytest.raises(ValueError, match="overflows"):
            solve(method, **big)
        return
    assume(expected < 1e306)                # too close to the float limit to call either way
    rs = solve(method, **big)
    tol = 1e-9 * (mu * N + abs(r.Fx) + abs(r.Fy))
    assert abs(rs.Fx / scale ** 2 - r.Fx) <= tol and abs(rs.Fy / scale ** 2 - r.Fy) <= tol
    assert abs(rs.Mz / scale ** 3 - r.Mz) <= tol * math.sqrt(kw["a"] * kw["b"]) + 1e-9 * abs(r.Mz)


@pytest.mark.parametrize("method", [m for m in METHODS
                                    if "fields" in cc.METHODS[m].default_options])
@pytest.mark.parametrize("scale", [1e-100, 1e100])
def test_extreme_scales_keep_the_traction_maps(method, scale):
    """The same similarity for the fields (``fields.scaled``): coordinates × λ, pressures,
    tractions and slips unchanged (areas × λ²)."""
    kw = _case(1e-3, -4e-4, 0.3, 1e5, 0.3, 1.5, 5e-3, 8e10, 0.28)
    big = dict(kw, a=kw["a"] * scale, b=kw["b"] * scale, N=kw["N"] * scale * scale,
               phi=kw["phi"] / scale)
    f = solve(method, {**declared(method).options, "fields": True}, **kw).fields
    g = solve(method, {**declared(method).options, "fields": True}, **big).fields
    length = {"x", "y"}
    for name in f.__dataclass_fields__:
        a, b = getattr(f, name), getattr(g, name)
        want = a * scale if name in length else a * scale ** 2 if name == "area" else a
        if a.dtype.kind in "biu":
            assert (b == want).all(), name
        else:
            assert abs(b - want).max() <= 1e-12 * abs(want).max(), name
