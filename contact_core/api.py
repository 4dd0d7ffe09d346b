"""The single entry point ``solve`` and the registry of methods (cf. ``scipy.integrate.solve_ivp``)."""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Iterable

from .base import ContactMethod, refuse_speed
from .cache import register
from .effects import Effects, as_effects
from .exact import Exact
from .fastsim import Fastsim
from .friction import FrictionLaw
from .johnson_vermeulen import JohnsonVermeulen
from .linear import LinearTheory
from .polach import Polach
from .result import ContactResult
from .table import Table

#: Registered methods, cheapest to dearest.
METHODS: dict[str, type[ContactMethod]] = {
    cls.name: cls for cls in (LinearTheory, JohnsonVermeulen, Polach, Fastsim, Table, Exact)
}

_solvers: dict[tuple, ContactMethod] = {}  # see contact_core.cache: emptied when full
register(_solvers.clear)


def methods() -> tuple[str, ...]:
    """Names of the registered methods, cheapest to dearest."""
    return tuple(METHODS)


def make_solver(method: str, effects: Effects | Iterable[str] | None = None,
                friction: FrictionLaw | None = None, **options: Any) -> ContactMethod:
    """Construct a method object once, to call its ``step`` many times (e.g. from the FMU).
    ``friction``: the law of the effect 'falling_friction' (None: ``FrictionLaw()``); with that
    effect ``step`` takes the rolling speed ``V`` (m/s) after ``warm_start``."""
    try:
        cls = METHODS[method]
    except (KeyError, TypeError):
        raise ValueError(f"method={method!r} is unknown: allowed {list(METHODS)}") from None
    return cls(as_effects(effects), friction, **options)


def _cached_solver(method: str, effects: Any, friction: Any,
                   options: dict[str, Any]) -> ContactMethod:
    if not isinstance(effects, (Effects, tuple, frozenset, str, type(None))):
        effects = as_effects(effects)  # a list, set or generator of names: not a cache key
    try:
        # with the types: True == 1 == 1.0, but an option may accept one and refuse the others
        key = (method, effects, tuple((k, type(v), v) for k, v in options.items()), friction)
        solver = _solvers.get(key)
    except TypeError:  # unhashable option value: no caching
        return make_solver(method, effects, friction, **options)
    if solver is None:
        solver = make_solver(method, effects, friction, **options)
        if len(_solvers) > 512:
            _solvers.clear()
        _solvers[key] = solver
    return solver


def solve(method: str, *, xi: float, eta: float, phi: float, N: float, mu: float, a: float,
          b: float, G: float, nu: float, effects: Effects | Iterable[str] | None = None,
          warm_start: ContactResult | None = None, V: float | None = None,
          friction: FrictionLaw | None = None, jacobian: bool = False,
          **options: Any) -> ContactResult:
    """Creep forces and spin moment of one wheel–rail contact.

    Parameters
    ----------
    method : str
        One of :func:`methods`: ``"linear"``, ``"johnson_vermeulen"``, ...
    xi, eta : float
        Longitudinal and lateral creepage (dimensionless; Kalker 1979, eq 2: rigid slip / V).
    phi : float
        Spin creepage, 1/m.
    N : float
        Normal load, N (>= 0; N = 0 gives zero forces: wheel lifted).
    mu : float
        Coefficient of friction (>= 0).
    a, b : float
        Contact-ellipse semi-axes, m: ``a`` along the rolling direction x, ``b`` lateral.
    G : float
        Combined shear modulus, Pa.
    nu : float
        Combined Poisson's ratio, 0 <= nu < 0.5.
    effects : Effects or iterable of str, optional
        Effects to compute (see :mod:`contact_core.effects`); all by default.
    warm_start : ContactResult, optional
        A previous result of the same method near this state; iterative methods start from it.
    V : float, optional
        Rolling speed, m/s, with the effect ``falling_friction`` (the slip velocity is the
        creepage times |V|; None or 0: static friction). Without that effect it must be None or 0.
    friction : FrictionLaw, optional
        The law of the effect ``falling_friction`` (:mod:`contact_core.friction`; None: the
        default ``FrictionLaw()``), ``mu`` being its static coefficient.
    jacobian : bool, optional
        Also the derivatives of the outputs with respect to the inputs, as the result's
        ``jacobian`` (:class:`contact_core.jacobian.Jacobian`: analytic for ``linear``,
        ``johnson_vermeulen`` and ``table``, else central differences of the method).
    **options
        Passed to the method (e.g. ``variant=`` for Johnson–Vermeulen); unknown ones are an error.

    Returns
    -------
    ContactResult
        ``Fx, Fy`` in N, ``Mz`` in N·m, forces of the rail on the wheel (Kalker's convention:
        ``Fx = -G c² C11 ξ`` for small ξ, c = √(ab)).
    """
    try:  # the common call: hashable effects, no options, no friction law
        solver = _solvers[method, effects, (), None] if not (options or friction) else None
    except (KeyError, TypeError):
        solver = None
    if solver is None:
        solver = _cached_solver(method, effects, friction, options)
    if jacobian:
        if V and solver.friction is None:
            refuse_speed(V)
        r = (solver.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
             if solver.friction is None else
             solver.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start, 0.0 if V is None else V))
        return replace(r, jacobian=solver.jacobian(xi, eta, phi, N, mu, a, b, G, nu,
                                                   warm_start, V, result=r))
    if V is None:
        return solver.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
    if solver.friction is None:
        refuse_speed(V)
        return solver.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
    return solver.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start, V)
