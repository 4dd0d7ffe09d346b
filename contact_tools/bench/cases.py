"""The benchmark's case set, generated reproducibly from ``cases.toml`` (shipped with the package).

A :class:`Case` is one wheel–rail contact state. Its ellipse comes from Hertz for a wheel on a rail
(:func:`contact_core.hertz_geometry`): the rail crown radius is solved per semi-axis ratio a/b
(:func:`rail_radius_for`), so an FMU given the same radii and load sees the same ``a`` and ``b``
(the FMU computes the patch from Hertz at each step's N).

Levels are Kalker-normalised with the creep coefficients ``C11, C22, C23`` of the case's a/b and ν
(Kalker 1979, eqs 17 and 22; the Shen–Hedrick–Elkins form with spin)::

    tau_creep = G c² |(C11 ξ, C22 η)| / (μN)
    tau_spin  = G c³ C23 |φ| / (μN)
    tau       = √(tau_creep² + tau_spin²)                       c = √(ab)

For pure longitudinal, lateral or spin creepage ``tau`` is the linear-theory force over the
friction limit μN (Johnson–Vermeulen's normalised creepage). With lateral creepage and spin together
the linear lateral force is ``C22 η + C23 c φ``, which can cancel although the tractions do not
(the spin part is odd in x); the Euclidean sum above does not cancel and measures how far the
tractions are pushed towards μ p. Regimes (boundaries in the data
file): ``spin-dominated`` if tau_spin > tau_creep, else ``linear`` (tau below ``linear_below``),
``partial slip``, or ``near saturation`` (tau from ``saturation_from`` on, full sliding included).

Generation: for every a/b, μ, kind and stratum [lo, hi) of tau, one case with tau log-uniform in the
stratum, N log-uniform in the N range, random signs/angles, all from ``numpy.random.default_rng``
seeded from the file (and the form), so the set is identical on every run and machine.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import brentq

from contact_core.cache import cached
from contact_core.coefficients import creep_coefficients
from contact_core.hertz import hertz_geometry, wheel_rail_curvatures
from contact_core.material import shear_modulus

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

#: Regimes, in report order.
REGIMES: tuple[str, ...] = ("linear", "partial slip", "near saturation", "spin-dominated")
#: Kinds of creepage a case can have.
KINDS: tuple[str, ...] = ("longitudinal", "lateral", "spin", "creepage", "combined")
#: Forms of the case set defined in the data file (``[forms.<name>]``).
FORMS: tuple[str, ...] = ("short", "full", "smoke")


@dataclass(frozen=True)
class Case:
    """One contact state (SI units). ``a``, ``b`` come from Hertz for the radii and ``N``."""

    id: int
    kind: str
    a_over_b: float          # nominal ratio (from the data file); a/b of the patch equals it
    mu: float
    N: float
    xi: float
    eta: float
    phi: float
    a: float
    b: float
    G: float
    nu: float
    E: float
    R_wheel: float
    R_wheel_profile: float
    R_rail_profile: float
    tau: float
    tau_creep: float
    tau_spin: float
    regime: str

    @property
    def c(self) -> float:
        return math.sqrt(self.a * self.b)

    def solve_kwargs(self) -> dict[str, float]:
        """Keyword arguments of :func:`contact_core.solve` for this state."""
        return {"xi": self.xi, "eta": self.eta, "phi": self.phi, "N": self.N, "mu": self.mu,
                "a": self.a, "b": self.b, "G": self.G, "nu": self.nu}

    def fmu_parameters(self) -> dict[str, float]:
        """FMU parameters (start values) that reproduce this case's geometry and material (the
        FMU's finite form: a straight profile has radius 0)."""
        def finite(R: float) -> float:
            return 0.0 if math.isinf(R) else R
        return {"E": self.E, "nu": self.nu, "R_wheel": self.R_wheel,
                "R_wheel_profile": finite(self.R_wheel_profile),
                "R_rail_profile": finite(self.R_rail_profile)}


def load_spec(path: str | Path | None = None) -> dict[str, Any]:
    """The parsed data file (default: the packaged ``cases.toml``)."""
    if path is None:
        text = resources.files(__package__).joinpath("cases.toml").read_text(encoding="utf-8")
    else:
        text = Path(path).read_text(encoding="utf-8")
    return tomllib.loads(text)


@cached(64)
def rail_radius_for(a_over_b: float, R_wheel: float, R_wheel_profile: float, E: float,
                    nu: float) -> float:
    """Rail crown radius (m) that gives the Hertz patch the semi-axis ratio ``a_over_b``."""
    def ratio(log_r: float) -> float:
        A, B = wheel_rail_curvatures(R_wheel, R_wheel_profile, math.exp(log_r))
        g = hertz_geometry(A, B, E, nu)
        return math.log(g.ka / g.kb) - math.log(a_over_b)
    # a/b grows as the rail crown gets sharper (B up): bracket from 5 mm to 100 m.
    return math.exp(brentq(ratio, math.log(5e-3), math.log(1e2), xtol=1e-14, rtol=1e-14))


def regime_of(tau: float, tau_creep: float, tau_spin: float, bounds: dict[str, float]) -> str:
    """The regime of a state (see the module docstring)."""
    if tau_spin > tau_creep:
        return "spin-dominated"
    if tau < bounds["linear_below"]:
        return "linear"
    if tau < bounds["saturation_from"]:
        return "partial slip"
    return "near saturation"


def _levels(G: float, c: float, C: tuple[float, ...], mu: float, N: float, xi: float, eta: float,
            phi: float) -> tuple[float, float, float]:
    C11, C22, C23 = C[0], C[1], C[2]
    k = G * c * c / (mu * N)
    tau_creep = k * math.hypot(C11 * xi, C22 * eta)
    tau_spin = k * C23 * c * abs(phi)
    tau = math.hypot(tau_creep, tau_spin)
    return tau, tau_creep, tau_spin


def make_cases(form: str = "short", spec: dict[str, Any] | None = None,
               seed: int | None = None) -> list[Case]:
    """The case set of ``form`` (a ``[forms.<form>]`` table of the data file)."""
    spec = load_spec() if spec is None else spec
    if form not in spec.get("forms", {}):
        raise ValueError(f"form={form!r} is unknown: allowed {sorted(spec.get('forms', {}))}")
    f = spec["forms"][form]
    geo, mat, bounds = spec["geometry"], spec["material"], spec["regimes"]
    seed = spec["seed"] if seed is None else seed
    # One stream per form, so adding a form never changes another's cases.
    rng = np.random.default_rng([seed, sum(map(ord, form))])
    E, nu = float(mat["E"]), float(mat["nu"])
    G = shear_modulus(E, nu)
    R_wheel, R_wp = float(geo["R_wheel"]), float(geo["R_wheel_profile"])
    ratios = [float(r) for r in f.get("a_over_b", geo["a_over_b"])]
    mus = [float(m) for m in f.get("mu", spec["friction"]["mu"])]
    kinds = list(f["kinds"])
    unknown = sorted(set(kinds) - set(KINDS))
    if unknown:
        raise ValueError(f"form {form!r}: unknown kind(s) {unknown}; allowed {list(KINDS)}")
    edges = [float(e) for e in f["strata"]]
    sr_lo, sr_hi = (float(v) for v in f.get("spin_ratio", (0.2, 2.0)))
    n_lo, n_hi = (float(v) for v in f.get("N", geo["N"]))

    cases: list[Case] = []
    for ab in ratios:
        R_rail = rail_radius_for(ab, R_wheel, R_wp, E, nu)
        g = hertz_geometry(*wheel_rail_curvatures(R_wheel, R_wp, R_rail), E, nu)
        C = creep_coefficients(g.ka / g.kb, nu)
        for mu in mus:
            for kind in kinds:
                for lo, hi in zip(edges[:-1], edges[1:]):
                    target = math.exp(rng.uniform(math.log(lo), math.log(hi)))
                    N = math.exp(rng.uniform(math.log(n_lo), math.log(n_hi)))
                    s = N ** (1.0 / 3.0)       # HertzGeometry.patch's arithmetic, as the FMU's
                    a, b = g.ka * s, g.kb * s
                    c = math.sqrt(a * b)
                    angle = rng.uniform(0.0, 2.0 * math.pi)
                    sign = rng.choice((-1.0, 1.0), size=3)
                    ratio = math.exp(rng.uniform(math.log(sr_lo), math.log(sr_hi)))
                    # Unit-level direction in normalised creepage (C11 ξ, C22 η, C23 c φ) ...
                    if kind == "longitudinal":
                        u = (sign[0], 0.0, 0.0)
                    elif kind == "lateral":
                        u = (0.0, sign[1], 0.0)
                    elif kind == "spin":
                        u = (0.0, 0.0, sign[2])
                    elif kind == "creepage":
                        u = (math.cos(angle), math.sin(angle), 0.0)
                    else:  # combined
                        u = (math.cos(angle), math.sin(angle), sign[2] * ratio)
                    # ... scaled so that tau hits the drawn level.
                    k = G * c * c / (mu * N)
                    norm = math.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
                    scale = target / (k * norm)
                    xi = float(scale * u[0] / C[0])
                    eta = float(scale * u[1] / C[1])
                    phi = float(scale * u[2] / (C[2] * c))
                    tau, tc, ts = _levels(G, c, C, mu, N, xi, eta, phi)
                    cases.append(Case(
                        id=len(cases), kind=kind, a_over_b=ab, mu=mu, N=N, xi=xi, eta=eta,
                        phi=phi, a=a, b=b, G=G, nu=nu, E=E, R_wheel=R_wheel,
                        R_wheel_profile=R_wp, R_rail_profile=R_rail, tau=tau, tau_creep=tc,
                        tau_spin=ts, regime=regime_of(tau, tc, ts, bounds)))
    return cases


def describe(cases: list[Case]) -> str:
    """One line: the count, and how the cases split over a/b, kinds and regimes."""
    def count(key):
        out: dict[Any, int] = {}
        for c in cases:
            out[key(c)] = out.get(key(c), 0) + 1
        return ", ".join(f"{k}: {v}" for k, v in out.items())
    return (f"{len(cases)} cases (a/b {count(lambda c: c.a_over_b)}; "
            f"regimes {count(lambda c: c.regime)}; kinds {count(lambda c: c.kind)})")
