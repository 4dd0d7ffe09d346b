"""Slip-velocity-dependent ("falling") friction: the law μ(s) of the effect ``falling_friction``.

Friction that drops as the local slip velocity s (m/s) grows is what makes a creep-force curve
fall beyond its adhesion peak (Polach 2005; Vollebregt, Six & Polach, *Challenges and progress
in the understanding and modelling of the wheel-rail creep forces*, VSD 59 (2021) 1026-1068).
The laws are CONTACT's (E. A. H. Vollebregt, CONTACT user guide, sec. "Slip velocity dependent
friction", frictional laws L = 2, 3, 4), written relative to the static coefficient μ_stat, which
stays the ``mu`` of the contact (a parameter or, with ``variable_friction``, an input):

    μ(s) = μ_stat ρ(s),   ρ(s) = k + (1 - k) [(1 - q) f(s/s_h1) + q f2(s/s_h2)],

k = μ_kin/μ_stat (``kinetic``), q the share of the falling part in a second term (``second``),
s_h1, s_h2 the slip velocities at which each term is halved (``s_half``, ``s_half2``), and

``"exponential"`` (CONTACT L=4)  f = f2 = exp(-ln2 · u),
``"rational"``    (CONTACT L=3)  f = 1/(1 + u),  f2 = 1/(1 + u²),
``"linear"``      (CONTACT L=2)  f = f2 = max(0, 1 - u/2).

ρ(0) = 1, ρ decreases to k, so |F| <= μ_stat N holds as with Coulomb friction. CONTACT's
absolute coefficients map as μ_kin = k μ_stat, μ_exp1 (μ_lin1, μ_rat1) = (1 - k)(1 - q) μ_stat,
μ_exp2 = (1 - k) q μ_stat (:meth:`FrictionLaw.from_contact`).

Polach's exponential law (O. Polach, *Creep forces in simulations of traction vehicles running
on adhesion limit*, Wear 258 (2005) 992-1000, eq. 14), μ = μ0 [(1 - A) e^(-B w) + A] with w the
magnitude of the slip velocity (m/s), is the exponential law with μ_stat = μ0, k = A,
s_h1 = ln 2 / B, q = 0 (:meth:`FrictionLaw.polach`; CONTACT user guide, eq. "polach_law").

Friction memory (CONTACT user guide, sec. "Friction memory"; Vollebregt 2012, the quasi-steady
creep forces with falling friction): the actual coefficient relaxes towards μ(s) over a sliding
distance d_c (``memory``, m), dμ/dt = -max(s, s_0)/d_c (μ - μ(s)), s_0 (``memory_speed``, m/s)
letting it recover in the adhesion area. In steady rolling a particle crosses an element of
length h in h/V, and the implicit Euler step of that equation is

    μ_i = θ μ_upstream + (1 - θ) μ(s_i),   θ = d_c / (d_c + (h/V) max(s_i, s_0)),

starting from μ_stat where the material enters the contact. ``memory = 0`` is the instantaneous
law. Only the methods that resolve the slip over the contact (FASTSIM and ``exact`` with
``falling="local"``) use it.

The rolling speed V (m/s) is an input of the contact with this effect: the slip velocity of a
creepage is its product with V. Methods that do not resolve the local slip use the friction at
the creep velocity w = V s_C (:func:`creep_velocity`: Polach 1999, 2005; Spiryagin, Polach &
Cole 2013): one coefficient for the whole contact.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, NamedTuple

#: The laws (CONTACT's L digit in brackets): exponential (4), rational (3), linear (2).
KINDS: tuple[str, ...] = ("exponential", "rational", "linear")
_LN2 = math.log(2.0)


@dataclass(frozen=True)
class FrictionLaw:
    """μ(s)/μ_stat of the effect ``falling_friction`` (module docstring). SI units: slip
    velocities in m/s, the memory distance in m.

    The default is the law of CONTACT's ``tractcurv`` example for the Eurosprinter locomotive
    (Vollebregt, CONTACT user guide, example "tractcurv", series 4: Polach's exponential law with
    A = 0.38, B = 0.7 s/m, as used with the modified FASTSIM of Spiryagin et al. 2013), without
    memory.
    """

    kind: str = "exponential"
    kinetic: float = 0.38
    s_half: float = _LN2 / 0.7
    second: float = 0.0
    s_half2: float = 1.0
    memory: float = 0.0
    memory_speed: float = 0.0

    #: Each parameter's allowed interval (lo, hi, lo open, hi open, what it is), also that of
    #: the FMU parameters of the law (:data:`contact_core.variables.VARIABLES`).
    RANGES: ClassVar[dict[str, tuple[float, float, bool, bool, str]]] = {
        "kinetic": (0.0, 1.0, False, False, "kinetic over static friction coefficient"),
        "s_half": (0.0, math.inf, True, True, "slip velocity halving the falling part, m/s"),
        "second": (0.0, 1.0, False, False, "share of the falling part in the second term"),
        "s_half2": (0.0, math.inf, True, True, "slip velocity halving the second term, m/s"),
        "memory": (0.0, math.inf, False, True, "friction memory distance d_c, m"),
        "memory_speed": (0.0, math.inf, False, True, "friction memory velocity s_0, m/s"),
    }

    def __post_init__(self) -> None:
        if not isinstance(self.kind, str) or self.kind not in KINDS:
            raise ValueError(f"kind={self.kind!r} is invalid: allowed "
                             + " or ".join(repr(k) for k in KINDS))
        for name, (lo, hi, lo_open, hi_open, what) in self.RANGES.items():
            v = getattr(self, name)
            ok = (isinstance(v, (int, float)) and not isinstance(v, bool) and not math.isnan(v)
                  and (lo < v if lo_open else lo <= v) and (v < hi if hi_open else v <= hi))
            if not ok:
                raise ValueError(f"{name}={v!r} is out of range: allowed {lo:g} "
                                 f"{'<' if lo_open else '<='} {name} {'<' if hi_open else '<='} "
                                 f"{hi:g} ({what})")
            object.__setattr__(self, name, float(v))

    @classmethod
    def polach(cls, A: float, B: float, **memory: float) -> "FrictionLaw":
        """Polach 2005's μ = μ0 [(1 - A) e^(-B w) + A] (B in s/m): k = A, s_h = ln 2 / B."""
        if not (isinstance(B, (int, float)) and 0.0 < B < math.inf):
            raise ValueError(f"B={B!r} is out of range: allowed 0 < B < inf (Polach's decay "
                             "rate, s/m)")
        return cls("exponential", A, _LN2 / B, **memory)

    @classmethod
    def from_contact(cls, kind: str, fstat: float, fkin: float, f1: float, s_h1: float,
                     f2: float = 0.0, s_h2: float = 1.0, memory: float = 0.0,
                     memory_speed: float = 0.0) -> "FrictionLaw":
        """CONTACT's absolute coefficients (FSTAT, FKIN, FEXP1/FLIN1/FRAT1, SABSH1, ...; slip
        velocities in m/s, MEMDST in m): FSTAT must be FKIN + f1 + f2 as in CONTACT."""
        if not (fstat > 0.0 and math.isclose(fkin + f1 + f2, fstat, rel_tol=1e-6)):
            raise ValueError(f"fstat={fstat!r}, fkin={fkin!r}, f1={f1!r}, f2={f2!r}: allowed "
                             "fstat = fkin + f1 + f2 > 0 (the static coefficient is mu(0))")
        falling = f1 + f2
        return cls(kind, fkin / fstat, s_h1, f2 / falling if falling > 0.0 else 0.0,
                   s_h2 if f2 > 0.0 else 1.0, memory, memory_speed)

    @property
    def B(self) -> float:
        """Polach's decay rate ln 2 / s_h1, s/m (exact for the exponential law)."""
        return _LN2 / self.s_half

    def params(self) -> tuple[float, ...]:
        """(kind index, k, (1 - k)(1 - q), s_h1, (1 - k) q, s_h2, d_c, s_0): the law as the
        compiled kernels take it (:func:`ratio_of`)."""
        fall = 1.0 - self.kinetic
        return (float(KINDS.index(self.kind)), self.kinetic, fall * (1.0 - self.second),
                self.s_half, fall * self.second, self.s_half2, self.memory, self.memory_speed)

    def ratio(self, s: float) -> float:
        """ρ(s) = μ(s)/μ_stat at the slip velocity |s| (m/s)."""
        return ratio_of(self.params(), abs(s))


def ratio_of(law: tuple, s: float) -> float:
    """ρ(s) of a law given as :meth:`FrictionLaw.params` (plain arithmetic: also compiled into
    the numba kernels); s >= 0, m/s (inf gives k)."""
    kind = law[0]
    u1 = s / law[3]
    if kind == 0.0:
        t1 = math.exp(-_LN2 * u1) if u1 < 1e300 else 0.0
    elif kind == 1.0:
        t1 = 1.0 / (1.0 + u1)
    else:
        t1 = max(0.0, 1.0 - 0.5 * u1)
    if law[4] == 0.0:
        return law[1] + law[2] * t1
    u2 = s / law[5]
    if kind == 0.0:
        t2 = math.exp(-_LN2 * u2) if u2 < 1e300 else 0.0
    elif kind == 1.0:
        t2 = 1.0 / (1.0 + u2 * u2) if u2 < 1e150 else 0.0
    else:
        t2 = max(0.0, 1.0 - 0.5 * u2)
    return law[1] + law[2] * t1 + law[4] * t2


def memory_step(up: float, rho: float, s: float, d_c: float, dt_per_v: float,
                s0: float) -> float:
    """μ/μ_stat of an element with friction memory (CONTACT user guide, sec. "Friction memory";
    module docstring): θ ``up`` + (1 - θ) ``rho``, θ = d_c/(d_c + (h/V) max(s, s_0)), from the
    upstream element's ``up``, the law's ``rho`` = ρ(s) at the slip velocity ``s`` (m/s), the
    memory distance ``d_c`` (m; 0: ``rho`` itself), ``dt_per_v`` = h/V (s) and ``s0`` = s_0
    (m/s). Plain arithmetic: also compiled into the numba kernels."""
    if d_c > 0.0:
        theta = d_c / (d_c + dt_per_v * max(s, s0))
        return theta * up + (1.0 - theta) * rho
    return rho


def ratio_and_slope_of(law: tuple, s: float) -> tuple[float, float]:
    """(ρ(s), dρ/ds) of a law given as :meth:`FrictionLaw.params`, s >= 0 in m/s (the slope in
    s/m; the linear law's kink at 2 s_h takes the slope of the side s lies on)."""
    kind = law[0]
    rho = law[1]
    slope = 0.0
    for share, s_h, second in ((law[2], law[3], False), (law[4], law[5], True)):
        if share == 0.0:
            continue
        u = s / s_h
        if kind == 0.0:
            t = math.exp(-_LN2 * u) if u < 1e300 else 0.0
            rho += share * t
            slope -= share * _LN2 / s_h * t
        elif kind == 1.0:
            if second:
                q = 1.0 / (1.0 + u * u) if u < 1e150 else 0.0
                rho += share * q
                slope -= share * 2.0 * u * q * q / s_h
            else:
                q = 1.0 / (1.0 + u)
                rho += share * q
                slope -= share * q * q / s_h
        elif u < 2.0:
            rho += share * (1.0 - 0.5 * u)
            slope -= share * 0.5 / s_h
    return rho, slope


#: The default law (CONTACT's tractcurv example, series 4).
DEFAULT_LAW = FrictionLaw()


class Rolling(NamedTuple):
    """What a local falling-friction solve takes per call, in the units of that solve: the
    rolling speed ``V`` (slip velocity = V × slip per rolling speed) and the friction memory
    distance ``memory`` (d_c; ``ContactMethod._similar`` scales both)."""

    V: float
    memory: float


def lateral_creep_with_spin(eta: float, phi: float, a: float) -> float:
    """Polach's lateral creepage with the spin's share, s_yC = η + φ a where that is larger
    than |η|, else η (O. Polach, *A fast wheel-rail forces calculation computer code*, VSD 33
    suppl. (1999) 728-739; the same in Polach 2005)."""
    eta_c = eta + phi * a
    return eta if abs(eta_c) < abs(eta) else eta_c


def creep_velocity(V: float, xi: float, eta: float, phi: float, a: float) -> float:
    """Polach's creep velocity w = |V| s_C (m/s), s_C = |(ξ, s_yC)|
    (:func:`lateral_creep_with_spin`). The friction of the methods that take one coefficient for
    the contact (the effect's "creep" mode) is μ(w)."""
    return abs(V) * math.hypot(xi, lateral_creep_with_spin(eta, phi, a))
