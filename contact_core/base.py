"""Base class shared by all contact methods, and input validation.

Modelled on ``scipy.integrate.OdeSolver``: a method is a class constructed once with its options
(validated there), whose public :meth:`ContactMethod.step` validates one contact state and delegates
to the private :meth:`ContactMethod._step_impl`. ``contact_core.solve`` is the one entry point.
"""
from __future__ import annotations

import math
import operator
from abc import ABC, abstractmethod
from typing import Any, ClassVar, Sequence

import numpy as np

from .effects import ALL_EFFECTS, Effects
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
    if not (0.0 <= nu < 0.5):
        raise out_of_range("nu", nu)


class ContactMethod(ABC):
    """A rolling-contact method: construct once with options, then call :meth:`step` per state.

    Subclasses set ``name`` (registry key), ``code`` (integer id, reported by the FMU as
    ``method_used``) and ``default_options`` (every accepted option with its default), may override
    :meth:`_check_options`, and implement :meth:`_step_impl`.
    """

    name: ClassVar[str] = ""
    code: ClassVar[int] = 0
    default_options: ClassVar[dict[str, Any]] = {}

    def __init__(self, effects: Effects = ALL_EFFECTS, **options: Any) -> None:
        unknown = sorted(set(options) - set(self.default_options))
        if unknown:
            raise ValueError(f"method {self.name!r}: unknown option(s) {unknown}; "
                             f"allowed: {sorted(self.default_options)}")
        self.effects = effects
        self.options = {**self.default_options, **options}
        self._check_options()

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
        check_inputs(xi, eta, phi, N, mu, a, b, G, nu)
        eff = self.effects
        if (xi and not eff.longitudinal) or (eta and not eff.lateral) or (phi and not eff.spin):
            off = [n for n, v, on in (("xi", xi, eff.longitudinal), ("eta", eta, eff.lateral),
                                      ("phi", phi, eff.spin)) if v and not on]
            raise ValueError(f"{off[0]} is non-zero but its effect is not selected "
                             f"(effects={list(eff.names())}); pass 0.0 or select the effect")
        if N == 0.0 or (mu == 0.0 and eff.saturation):
            # Wheel lifted (no load) or frictionless contact: no tangential force.
            return make_result(0.0, 0.0, 0.0, self.name, 1.0 if N else 0.0)
        return self._step_impl(xi, eta, phi, N, mu, a, b, G, nu, warm_start)

    @abstractmethod
    def _step_impl(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
                   b: float, G: float, nu: float,
                   warm_start: ContactResult | None) -> ContactResult:
        """Compute one validated contact state with N > 0."""
