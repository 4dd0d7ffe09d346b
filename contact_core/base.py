"""Base class shared by all contact methods, and input validation.

Modelled on ``scipy.integrate.OdeSolver``: a method is a class constructed once with its options
(validated there), whose public :meth:`ContactMethod.step` validates one contact state and delegates
to the private :meth:`ContactMethod._step_impl`. ``contact_core.solve`` is the one entry point.
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any, ClassVar

from .effects import ALL_EFFECTS, Effects
from .result import ContactResult, make_result


def _bad(name: str, value: float, allowed: str) -> ValueError:
    return ValueError(f"{name}={value!r} is out of range: allowed {allowed}")


def check_inputs(xi: float, eta: float, phi: float, N: float, mu: float,
                 a: float, b: float, G: float, nu: float) -> None:
    """Raise ``ValueError`` naming the first invalid argument and its allowed range."""
    isfinite = math.isfinite
    if not isfinite(xi):
        raise _bad("xi", xi, "a finite number (longitudinal creepage, dimensionless)")
    if not isfinite(eta):
        raise _bad("eta", eta, "a finite number (lateral creepage, dimensionless)")
    if not isfinite(phi):
        raise _bad("phi", phi, "a finite number (spin, 1/m)")
    if not (isfinite(N) and N >= 0.0):
        raise _bad("N", N, "0 <= N < inf (normal load, N)")
    if not (isfinite(mu) and mu >= 0.0):
        raise _bad("mu", mu, "0 <= mu < inf (friction coefficient)")
    if not (isfinite(a) and a > 0.0):
        raise _bad("a", a, "0 < a < inf (semi-axis along rolling direction, m)")
    if not (isfinite(b) and b > 0.0):
        raise _bad("b", b, "0 < b < inf (lateral semi-axis, m)")
    if not (isfinite(G) and G > 0.0):
        raise _bad("G", G, "0 < G < inf (shear modulus, Pa)")
    if not (0.0 <= nu < 0.5):
        raise _bad("nu", nu, "0 <= nu < 0.5 (Poisson's ratio)")


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
    def check_warm_state(cls, warm_state: Any) -> None:
        """Check a ``ContactResult.warm_state`` of this method read from outside (e.g. a saved
        FMU state) before it is used; raise ``ValueError`` saying what is wrong. Methods without a
        warm start accept only None."""
        if warm_state is not None:
            raise ValueError(f"method {cls.name!r} keeps no warm state (got {warm_state!r:.80})")

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
