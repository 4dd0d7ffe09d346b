"""Base class shared by all contact methods, and input validation.

Modelled on ``scipy.integrate.OdeSolver``: a method is a class constructed once with its options
(validated there), whose public :meth:`ContactMethod.step` validates one contact state and delegates
to the private :meth:`ContactMethod._step_impl`. ``contact_core.solve`` is the one entry point.
"""
from __future__ import annotations

import math
import numbers
import operator
from abc import ABC, abstractmethod
from dataclasses import replace
from typing import Any, ClassVar, Sequence

import numpy as np
from numba.extending import register_jitable

from . import jacobian as derivatives
from .coefficients import A_OVER_B_RANGE
from .effects import ALL_EFFECTS, Effects
from .friction import DEFAULT_LAW, FrictionLaw, Rolling, creep_velocity, ratio_of
from .jacobian import Jacobian
from .result import ContactResult, make_result
from .variables import out_of_range


def _bad(name: str, value: float, allowed: str) -> ValueError:
    return ValueError(f"{name}={value!r} is out of range: allowed {allowed}")


# ----------------------------------------------------------------------------------------------
# Method options: the validators every method uses in _check_options, with one wording
# ("name=value is invalid: allowed ..."). Each stores the normalised value back in ``options``.
# ----------------------------------------------------------------------------------------------

def _invalid(name: str, value: Any, allowed: str) -> ValueError:
    return ValueError(f"{name}={value!r} is invalid: allowed {allowed}")


def int_option(options: dict[str, Any], name: str, lo: int, hi: int, what: str = "") -> int:
    """An integer option ``lo <= value <= hi`` (bools refused; numpy integers accepted)."""
    v = options[name]
    try:
        n = operator.index(v)
    except TypeError:
        n = None
    if isinstance(v, bool) or n is None or not lo <= n <= hi:
        raise _invalid(name, v, f"an integer {lo} <= {name} <= {hi}" + (f" ({what})" if what
                                                                          else ""))
    options[name] = int(n)
    return int(n)


def float_option(options: dict[str, Any], name: str, lo: float, hi: float,
                 lo_open: bool = False, hi_open: bool = False) -> float:
    """A real option in the interval from ``lo`` to ``hi`` (open ends as given)."""
    v = options[name]
    ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
    if ok:
        ok = (lo < v if lo_open else lo <= v) and (v < hi if hi_open else v <= hi)
    if not ok:
        raise _invalid(name, v, f"a number {lo:g} {'<' if lo_open else '<='} {name} "
                                f"{'<' if hi_open else '<='} {hi:g}")
    options[name] = float(v)
    return float(v)


def choice_option(options: dict[str, Any], name: str, choices: Sequence[str]) -> str:
    """A string option, one of ``choices``."""
    v = options[name]
    if not isinstance(v, str) or v not in choices:
        raise _invalid(name, v, " or ".join(repr(c) for c in choices))
    return v


def bool_option(options: dict[str, Any], name: str) -> bool:
    """A boolean option (Python or numpy bool)."""
    v = options[name]
    if not isinstance(v, (bool, np.bool_)):
        raise _invalid(name, v, "True or False")
    options[name] = bool(v)
    return bool(v)


def check_inputs(xi: float, eta: float, phi: float, N: float, mu: float,
                 a: float, b: float, G: float, nu: float) -> None:
    """Raise ``ValueError`` naming the first invalid argument and its allowed range."""
    # Inline tests (this runs at every call); the ranges and messages of the contact's
    # variables are those of contact_core.variables.
    isfinite = math.isfinite
    if not isfinite(xi):
        raise out_of_range("xi", xi)
    if not isfinite(eta):
        raise out_of_range("eta", eta)
    if not isfinite(phi):
        raise out_of_range("phi", phi)
    if not (isfinite(N) and N >= 0.0):
        raise _bad("N", N, "0 <= N < inf (normal load, N)")
    if not (isfinite(mu) and mu >= 0.0):
        raise out_of_range("mu", mu)
    if not (isfinite(a) and a > 0.0):
        raise _bad("a", a, "0 < a < inf (semi-axis along rolling direction, m)")
    if not (isfinite(b) and b > 0.0):
        raise _bad("b", b, "0 < b < inf (lateral semi-axis, m)")
    if not (isfinite(G) and G > 0.0):
        raise _bad("G", G, "0 < G < inf (shear modulus, Pa)")
    if not (0.005 <= a / b <= 200.0):  # coefficients.A_OVER_B_RANGE, literal for speed
        raise ValueError(f"a={a!r}, b={b!r}: a/b={a / b!r} is out of range: allowed "
                         f"{A_OVER_B_RANGE[0]} <= a/b <= {A_OVER_B_RANGE[1]} (Kalker's "
                         "coefficients and their asymptotes)")
    if not (0.0 <= nu < 0.5):
        raise out_of_range("nu", nu)


_INPUT_NAMES = ("xi", "eta", "phi", "N", "mu", "a", "b", "G", "nu")


def _not_a_number(values: tuple) -> ValueError | None:
    """For a call that failed: a ``ValueError`` naming the first input that is not a real scalar
    (None, a string, an array, a complex number, an integer beyond the float range), else None
    (the failure was about the values, and its own error names them)."""
    for name, v in zip(_INPUT_NAMES, values):
        ok = isinstance(v, numbers.Real) and not isinstance(v, bool) and np.ndim(v) == 0
        if ok:
            try:
                float(v)
            except OverflowError:
                ok = False
        if not ok:
            text = repr(v)
            text = text if len(text) <= 60 else text[:57] + "..."
            return ValueError(f"{name}={text} is not a number: allowed a real scalar "
                              f"({type(v).__name__} given)")
    return None


@register_jitable
def _moderate(xi: float, eta: float, phi: float, N: float, mu: float, a: float, b: float,
              G: float, nu: float, saturates: bool) -> bool:
    """Inputs a method computes directly in SI units: semi-axes 1e-8..1e3 m, G 1e-3..1e15 Pa,
    N and μN (N without saturation) 1e-12..1e12 N, |σ| <= 1e6 (max(a, b) >= √(ab) bounding the
    spin term). Every product and square of the methods' SI arithmetic then stays far inside the
    float range; with ν and a/b in range these bounds imply every check of check_inputs. NaN
    fails every comparison. Literal numbers: this runs at every call. Also compiled into the
    methods' fused kernels (numba's ``register_jitable``: a plain Python function when called
    from Python)."""
    if (1e-8 <= a <= 1e3 and 1e-8 <= b <= 1e3 and 1e-3 <= G <= 1e15 and 1e-12 <= N <= 1e12
            and 0.0 <= nu < 0.5 and 0.005 <= a / b <= 200.0
            and 0.0 <= mu <= 1.7976931348623157e308):
        mun = mu * N if saturates else N
        if 1e-12 <= mun <= 1e12:
            s = ((xi if xi >= 0.0 else -xi) + (eta if eta >= 0.0 else -eta)
                 + (phi if phi >= 0.0 else -phi) * (a if a > b else b)) * (G * a * b / mun)
            return s <= 1e6 and (s >= 1e-60 or s == 0.0)
    return False


def _onto_bound(fx: float, fy: float, bound: float) -> tuple[float, float]:
    """(fx, fy) moved towards 0 by ulps until |F| <= bound (a rounding guard; nothing else)."""
    while math.hypot(fx, fy) > bound:
        fx = math.nextafter(fx, 0.0)
        fy = math.nextafter(fy, 0.0)
    return fx, fy


def _speed(V: Any) -> float:
    """|V| of the rolling speed V (m/s), or a ``ValueError`` naming it."""
    if type(V) is float and -math.inf < V < math.inf:    # the common call, at no cost
        return V if V >= 0.0 else -V
    if isinstance(V, numbers.Real) and not isinstance(V, bool) and np.ndim(V) == 0:
        try:
            v = float(V)
        except OverflowError:
            v = math.inf
        if math.isfinite(v):
            return abs(v)
        raise out_of_range("V", V)
    raise ValueError(f"V={V!r} is not a number: allowed a real scalar ({type(V).__name__} "
                     "given)")


def refuse_speed(V: Any) -> None:
    """A rolling speed V given without the effect 'falling_friction': a ``ValueError`` unless
    it is 0 (then unused)."""
    if V:
        raise ValueError(f"V={V!r} is given but the effect 'falling_friction' is not "
                         "selected: allowed None or 0, or select the effect")


def _falling_law(effects: Effects, friction: Any) -> FrictionLaw | None:
    """The friction law of a method for ``effects`` (None without 'falling_friction')."""
    if not effects.falling_friction:
        if friction is not None:
            raise ValueError(f"friction={friction!r} is given but the effect 'falling_friction' "
                             "is not selected: allowed None, or select the effect")
        return None
    if not effects.saturation:
        raise ValueError("effects: 'falling_friction' needs 'saturation' (without it friction "
                         "does not enter the result)")
    if friction is None:
        return DEFAULT_LAW
    if not isinstance(friction, FrictionLaw):
        raise ValueError(f"friction={friction!r} is invalid: allowed a "
                         "contact_core.FrictionLaw or None (the default law)")
    return friction


# Similarity units (ContactMethod._similar).
_P0 = 3.0 / (2.0 * math.pi)         # p0 = _P0 N/(ab) (hertz.max_pressure; Kalker 1979 eq 3)
_LOG_P0 = math.log(_P0)
_N_CANON = 2.0 * math.pi / 3.0      # the load of the canonical problem: p0 = 1 with a b = 1
_LOG_S_MAX, _LOG_S_MIN = math.log(1e100), math.log(1e-100)


class ContactMethod(ABC):
    """A rolling-contact method: construct once with options, then call :meth:`step` per state.

    The base class of every method of :data:`contact_core.METHODS`, as ``scipy.integrate.OdeSolver``
    is of ``solve_ivp``'s: the public :meth:`step` checks the inputs, handles the lifted and
    frictionless contact, the effects not selected, the units of inputs far from wheel–rail
    values (:meth:`_similar`), the falling-friction effect and Coulomb's bound to the last bit,
    and calls the private :meth:`_step_impl` of the subclass with validated SI inputs.

    Parameters
    ----------
    effects : Effects
        The effects to compute (:mod:`contact_core.effects`); all of Coulomb friction by default.
    friction : FrictionLaw, optional
        The law of the effect ``falling_friction`` (None: the default law, with the effect).
    **options
        The method's options; an option not in ``default_options`` is a ``ValueError``.

    Notes
    -----
    **Implementing a new method.** A subclass sets or implements:

    ``name`` : str
        The registry key (``contact_core.solve(name, ...)``), also the ``method`` of its results.
    ``code`` : int
        A small integer not used by another method, the FMU's ``method_used`` output.
    ``default_options`` : dict
        Every option it accepts, with its default. The FMU exposes the numeric, boolean and
        string ones as parameters (:mod:`wheel_rail_fmu.model_description`); ``option_units``
        gives the SI unit of those that have one.
    :meth:`_check_options`
        Validates ``self.options`` (already completed with the defaults) with the validators
        :func:`int_option`, :func:`float_option`, :func:`choice_option`, :func:`bool_option`,
        whose ``ValueError`` names the option and its allowed values; it may store derived
        values on ``self``. A method with a local falling-friction law sets
        ``self._falling_local`` here.
    :meth:`_step_impl`
        ``(xi, eta, phi, N, mu, a, b, G, nu, warm_start)`` → :class:`ContactResult`, for
        validated inputs with ``N > 0`` in SI units (and ``rolling`` after ``warm_start`` when
        ``_falling_local``). It computes only ``self.effects``: the outputs of unselected
        effects are 0.0, and without ``saturation`` (``self._saturates`` False) it returns its
        own unsaturated, μ → ∞ limit. It builds its result with :func:`.result.make_result`
        (or ``ContactResult``); ``step`` holds ``hypot(Fx, Fy) <= mu * N`` afterwards.
    ``saturates`` : bool
        False only for a method that never saturates (linear theory): its forces are then linear
        in the creepages whatever the effects, and μ does not enter.
    ``fallback`` : str or None
        The registered method that solves the states outside this one's domain (the table's
        a/b and ν: ``exact``); such results carry the fallback's ``name``.
    ``fields`` (optional)
        A method that returns traction fields (an option ``fields``) gives them an instance
        method ``scaled(length, pressure, bound, traction, slip)``, the fields in other units:
        :meth:`_similar` solves inputs far from wheel–rail values in the units of Hertzian
        similarity and scales the fields back with it.
    :meth:`warm_state_from_record` (optional)
        A method that keeps a warm start (``ContactResult.warm_state``, read back from
        ``warm_start`` at the next call) gives the state a ``to_record()`` (a dict of numbers,
        strings and float arrays: the FMU's saved states hold it as data) and overrides this
        class method to read one back, checked.
    :meth:`_jacobian_impl` (optional)
        The analytic derivatives of its outputs at a state it solved directly (:meth:`jacobian`,
        ``solve(..., jacobian=True)``); without it, central differences of :meth:`step` with
        the relative step of ``contact_core.jacobian.RELATIVE_STEPS``.
    effects
        Besides ``saturation``, a method sees the effects only through its inputs:
        ``falling_friction`` either passes one coefficient at the creep velocity as ``mu``
        (:meth:`_step_falling`) or, with ``_falling_local``, the rolling speed to
        :meth:`_step_impl`; with ``varying_geometry`` (``self.effects.varying_geometry``) a new
        a/b comes at every call, so a method computes per call what it would cache per a/b,
        with the same results.

    It is registered by adding the class to :data:`contact_core.METHODS` (``contact_core.api``).

    **The contract it is held to.** ``tests/test_method_contract.py`` runs every registered
    method through the same tests, so a new method gets them by being registered: results
    finite and, with saturation, |F| <= μN in floating point; forces against the slip and
    reaching μN at full sliding; the symmetries of steady rolling (ξ -> -ξ flips Fx only,
    (η, φ) -> (-η, -φ) flips Fy and Mz only); linear theory as the small-creepage limit; SI and
    other consistent units alike, and Hertzian similarity at any scale; zero forces for a lifted
    or resting contact; only the selected effects computed, the others' inputs refused; every
    finite input either solved or refused with a ``ValueError`` naming the argument and its
    range; the warm state's record read back; the fields scaled. What a method does differently
    by design is declared there per method with its source (the ``DECLARED`` table: linear
    theory never saturates; FASTSIM's default scheme makes its linear limit (1 + 1/nx) times
    linear theory's; the discretised methods meet the linear limit within their grids' error;
    Polach's combined linear limit lies along the creepage; Johnson–Vermeulen's force at full
    sliding keeps the direction of its linear force; the closed forms and FASTSIM take Kalker's
    tabulated C33, the exact theory and the table their own), never as a wider tolerance for all.
    """

    name: ClassVar[str] = ""
    code: ClassVar[int] = 0
    default_options: ClassVar[dict[str, Any]] = {}
    #: False for a method that never saturates (linear theory): its forces are linear in the
    #: creepages whatever the effects.
    saturates: ClassVar[bool] = True
    #: The method that solves the states outside this one's domain (None: no such states); its
    #: results then carry that method's ``name``.
    fallback: ClassVar[str | None] = None
    #: SI units of the real options that have one (the others are dimensionless).
    option_units: ClassVar[dict[str, str]] = {}

    def __init__(self, effects: Effects = ALL_EFFECTS, friction: FrictionLaw | None = None,
                 **options: Any) -> None:
        unknown = sorted(set(options) - set(self.default_options))
        if unknown:
            raise ValueError(f"method {self.name!r}: unknown option(s) {unknown}; "
                             f"allowed: {sorted(self.default_options)}")
        self.effects = effects
        self.options = {**self.default_options, **options}
        self._saturates = effects.saturation and self.saturates
        # every creepage input selected: the fast path of step need not check for ignored ones
        self._all_inputs = effects.longitudinal and effects.lateral and effects.spin
        #: The law of the effect 'falling_friction' (None without it).
        self.friction = _falling_law(effects, friction)
        #: Set by a method's _check_options when it bounds each traction by the friction at its
        #: own slip velocity (its _step_impl then takes ``rolling``); else the effect takes one
        #: coefficient at the creep velocity (_step_falling).
        self._falling_local = False
        self._check_options()
        if self.friction is not None:
            # the Coulomb path (step) stays as it is; this instance's step takes V
            self._law = self.friction.params()
            self.step = self._step_falling

    def _check_options(self) -> None:
        """Validate ``self.options``; raise ``ValueError`` naming the option and its range."""

    @classmethod
    def warm_state_from_record(cls, record: dict[str, Any] | None) -> Any:
        """The ``ContactResult.warm_state`` written as ``record`` (its ``to_record()``: a dict of
        numbers, strings and float arrays), checked before use (e.g. from a saved FMU state);
        ``ValueError`` says what is wrong. Methods without a warm start accept only None."""
        if record is not None:
            raise ValueError(f"method {cls.name!r} keeps no warm state")
        return None

    def step(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float, b: float,
             G: float, nu: float, warm_start: ContactResult | None = None) -> ContactResult:
        """Solve one contact state (SI units; see ``contact_core.solve`` for the arguments)."""
        try:
            if not (self._all_inputs and _moderate(xi, eta, phi, N, mu, a, b, G, nu,
                                                   self._saturates)):
                check_inputs(xi, eta, phi, N, mu, a, b, G, nu)
                self._refuse_unselected(xi, eta, phi)
                if N == 0.0 or (mu == 0.0 and self._saturates):
                    # Wheel lifted (no load) or frictionless contact: no tangential force.
                    return make_result(0.0, 0.0, 0.0, self.name, 1.0 if N else 0.0)
                # with every input selected, _moderate was already False above
                if self._all_inputs or not _moderate(xi, eta, phi, N, mu, a, b, G, nu,
                                                     self._saturates):
                    return self._similar(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
            r = self._step_impl(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
            if self._saturates and math.hypot(r.Fx, r.Fy) > mu * N:
                return self._held(r, mu * N)
            return r
        except (TypeError, ValueError, OverflowError):  # (no cost unless raised)
            named = _not_a_number((xi, eta, phi, N, mu, a, b, G, nu))
            if named is None:
                raise
            raise named from None

    def _refuse_unselected(self, xi: float, eta: float, phi: float) -> None:
        """A ``ValueError`` for a non-zero creepage whose effect is not selected."""
        eff = self.effects
        if (xi and not eff.longitudinal) or (eta and not eff.lateral) or (phi and not eff.spin):
            off = [n for n, v, on in (("xi", xi, eff.longitudinal), ("eta", eta, eff.lateral),
                                      ("phi", phi, eff.spin)) if v and not on]
            raise ValueError(f"{off[0]} is non-zero but its effect is not selected "
                             f"(effects={list(eff.names())}); pass 0.0 or select the effect")

    def _step_falling(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                      b: float, G: float, nu: float, warm_start: ContactResult | None = None,
                      V: float = 0.0) -> ContactResult:
        """:meth:`step` with the effect 'falling_friction' (it replaces ``step`` on such an
        instance): ``V`` is the rolling speed, m/s (its sign does not matter; 0: static
        friction throughout), ``mu`` the static coefficient of ``self.friction``.

        A method without a local law (``_falling_local`` False) solves its Coulomb problem with
        one coefficient μ(w), w = |V| s_C the creep velocity (:func:`.friction.creep_velocity`;
        Polach 2005, Spiryagin et al. 2013); a local one gets the rolling speed in its
        ``_step_impl``. Without saturation (linear theory) friction does not enter."""
        speed = _speed(V)
        if not self._saturates:
            return type(self).step(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start)
        if self._falling_local:
            return self._step_local(xi, eta, phi, N, mu, a, b, G, nu, warm_start, speed)
        try:
            mu_c = mu * ratio_of(self._law, creep_velocity(speed, xi, eta, phi, a))
        except (TypeError, ValueError, OverflowError):
            mu_c = mu          # not numbers: step names the argument
        if not math.isfinite(mu_c):
            mu_c = mu          # a non-finite input: step names it
        return type(self).step(self, xi, eta, phi, N, mu_c, a, b, G, nu, warm_start)

    def _step_local(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                    b: float, G: float, nu: float, warm_start: ContactResult | None,
                    speed: float) -> ContactResult:
        """:meth:`step`'s checks and scaling around a ``_step_impl`` that takes the rolling
        speed and the friction memory distance (:class:`.friction.Rolling`)."""
        try:
            check_inputs(xi, eta, phi, N, mu, a, b, G, nu)
            self._refuse_unselected(xi, eta, phi)
            if N == 0.0 or mu == 0.0:
                return make_result(0.0, 0.0, 0.0, self.name, 1.0 if N else 0.0)
            if not _moderate(xi, eta, phi, N, mu, a, b, G, nu, True):
                return self._similar(xi, eta, phi, N, mu, a, b, G, nu, warm_start, speed)
            r = self._step_impl(xi, eta, phi, N, mu, a, b, G, nu, warm_start,
                                Rolling(speed, self.friction.memory))
            if math.hypot(r.Fx, r.Fy) > mu * N:
                return self._held(r, mu * N)
            return r
        except (TypeError, ValueError, OverflowError):
            named = _not_a_number((xi, eta, phi, N, mu, a, b, G, nu))
            if named is None:
                raise
            raise named from None

    def jacobian(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                 b: float, G: float, nu: float, warm_start: ContactResult | None = None,
                 V: float | None = None, result: ContactResult | None = None) -> Jacobian:
        """The derivatives of :meth:`step`'s outputs (Fx, Fy, Mz, slip fraction) with respect to
        ξ, η, φ, N, μ, a, b (and V with the effect 'falling_friction') at this state
        (:mod:`contact_core.jacobian`): the method's own (:meth:`_jacobian_impl`) where it has
        them, else central differences of :meth:`step`. ``result``: this state's result, if the
        caller has it (else solved here, from ``warm_start``)."""
        falling = self.friction is not None
        if result is None:
            result = (self.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start) if not falling
                      else self.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start,
                                     0.0 if V is None else V))
        if N == 0.0:
            return derivatives.zero(falling)
        matrix = None
        if (not falling and result.method == self.name
                and _moderate(xi, eta, phi, N, mu, a, b, G, nu, self._saturates)):
            matrix = self._jacobian_impl(xi, eta, phi, N, mu, a, b, G, nu, result)
        if matrix is None:
            return derivatives.method_differences(self, xi, eta, phi, N, mu, a, b, G, nu,
                                                  result, V)
        eff = self.effects
        for j, on in enumerate((eff.longitudinal, eff.lateral, eff.spin)):
            if not on:
                matrix[:, j] = 0.0
        return Jacobian(derivatives.OUTPUTS, derivatives.INPUTS, matrix, "analytic")

    def _jacobian_impl(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                       b: float, G: float, nu: float, result: ContactResult) -> Any:
        """The analytic derivatives (:data:`contact_core.jacobian.OUTPUTS` by
        :data:`~contact_core.jacobian.INPUTS`, a numpy array) at a state this method solved
        directly (in SI units, Coulomb friction), or None: central differences then."""
        return None

    @staticmethod
    def _held(r: ContactResult, bound: float) -> ContactResult:
        """``r`` with |F| <= μN (``bound``) in floating point, as users check it: a force formed
        as μN times a unit direction, or scaled down onto the bound, can land an ulp above it."""
        fx, fy = _onto_bound(r.Fx, r.Fy, bound)
        return replace(r, Fx=fx, Fy=fy)

    def _similar(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                 b: float, G: float, nu: float, warm_start: Any,
                 speed: float | None = None) -> ContactResult:
        """The state solved in the units of Hertzian similarity, for every finite input.

        F/(μN) and Mz/(μN c) (without saturation F/N and Mz/(N c)) depend only on a/b, ν and the
        normalised creepages σ = (ξ, η, φ c) G/(μ p0) (G/p0), c = √(ab), p0 = 3N/(2πab) (Kalker
        1967 ch. 2; Kalker 1979 sec. 2: the Hertzian problem scales with p0 and the semi-axes).
        The method solves the canonical problem with these σ: a = a/b, b = 1, G = 1, μ = 1,
        p0 = 1 (N = 2π(a/b)/3), and the result is scaled back. σ is formed in logarithms
        (no overflow or underflow on the way) and brought into [1e-100, 1e100], its direction
        kept: beyond |σ| = 1e100 the adhesion zone is below 1e-100 of the contact (full sliding
        in double precision), so a saturating solve is the same at 1e100; below 1e-100 no
        element slips, and without saturation always, the forces are linear in σ, so they are
        scaled back by the same factor. A result beyond the float range (an unsaturated force,
        or μN itself) is a ValueError naming the inputs.

        With a local falling-friction law (``speed``, the rolling speed in m/s) the slip
        velocities V w are kept (w, the slip per rolling speed, scales with σ: V by its inverse)
        and so is the memory's θ = d_c/(d_c + (h/V) s) (h/V per unit slip velocity scales with
        the lengths and σ: d_c likewise).
        """
        sat = self._saturates
        log_c = 0.5 * (math.log(a) + math.log(b))
        # log of G/(μ p0)
        log_k = math.log(G) + math.log(a) + math.log(b) - _LOG_P0 - math.log(N) \
            - (math.log(mu) if sat else 0.0)
        logs = [math.log(abs(v)) + extra + log_k if v else -math.inf
                for v, extra in ((xi, 0.0), (eta, 0.0), (phi, log_c))]
        top = max(logs)
        shift = 0.0
        if top > _LOG_S_MAX:
            shift = _LOG_S_MAX - top
        elif -math.inf < top < _LOG_S_MIN:
            shift = _LOG_S_MIN - top
        sig = [math.copysign(math.exp(lg + shift), v) if v else 0.0
               for lg, v in zip(logs, (xi, eta, phi))]
        # canonical contact a = a/b, b = 1 (the same a/b to the last bit), p0 = 1: N = 2π(a/b)/3
        r_ab = a / b
        c_canon = math.sqrt(r_ab)
        n_canon = _N_CANON * r_ab
        if speed is None:
            r = self._step_impl(sig[0], sig[1], sig[2] / c_canon, n_canon, 1.0, r_ab, 1.0, 1.0,
                                nu, warm_start)
        else:
            # σ = creepage e^(log_k + shift); canonical lengths are SI / b. Held below 1e100
            # (the friction then is the kinetic one, the memory at most θ -> 1): no inf * 0.
            up = log_k + shift
            rolling = Rolling(math.exp(min(math.log(speed) - up, 230.0)) if speed > 0.0 else 0.0,
                              math.exp(min(math.log(self.friction.memory) + up - math.log(b),
                                           230.0)) if self.friction.memory > 0.0 else 0.0)
            r = self._step_impl(sig[0], sig[1], sig[2] / c_canon, n_canon, 1.0, r_ab, 1.0, 1.0,
                                nu, warm_start, rolling)
        # back to SI: forces per (μ)N, moment per (μ)N c; linear regime: undo the scale-up
        f_scale = (mu * N if sat else N) / n_canon
        down = 1.0
        try:
            down = math.exp(-shift) if (shift > 0.0 or not sat) else 1.0
            m_scale = f_scale * math.exp(log_c) / c_canon
            out = [v * down * sc for v, sc in ((r.Fx, f_scale), (r.Fy, f_scale), (r.Mz, m_scale))]
        except OverflowError:
            out = [math.inf] * 3
        if not (math.isfinite(f_scale) and all(math.isfinite(v) for v in out)):
            if sat:
                raise ValueError(f"mu={mu!r}, N={N!r}, a={a!r}, b={b!r}: the force bound mu*N "
                                 "or the spin moment's scale mu*N*sqrt(ab) overflows: allowed "
                                 "inputs for which these are below 1.8e308")
            why = ("linear theory does not saturate" if not self.saturates else
                   "with the effect 'saturation' it is bounded by mu*N")
            raise ValueError(f"xi={xi!r}, eta={eta!r}, phi={phi!r}: the unsaturated force "
                             "overflows: allowed creepages whose force is below 1.8e308 N "
                             f"({why})")
        if sat:
            # rounding, most of all for tiny loads (subnormal μN has few significant digits)
            out[0], out[1] = _onto_bound(out[0], out[1], mu * N)
        fields = r.fields
        if fields is not None:  # traction maps in SI units (a method's fields.scaled)
            try:
                p0 = math.exp(_LOG_P0 + math.log(N) - math.log(a) - math.log(b))
                friction = mu * p0
                traction = (friction if sat else p0) * down
                slip = math.exp(-(log_k + shift))
            except OverflowError:
                p0 = friction = traction = slip = math.inf
            fields = fields.scaled(b, p0, friction, traction, slip)
        return replace(r, Fx=out[0], Fy=out[1], Mz=out[2], fields=fields)

    @abstractmethod
    def _step_impl(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                   b: float, G: float, nu: float,
                   warm_start: ContactResult | None) -> ContactResult:
        """Compute one validated contact state with N > 0. A method with a local falling-friction
        law (``_falling_local``) also takes ``rolling`` (:class:`.friction.Rolling`) after
        ``warm_start``."""
