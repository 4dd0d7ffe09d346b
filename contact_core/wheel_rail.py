"""One wheel–rail contact evaluated step after step: material fixed, load varying, geometry
fixed (:class:`WheelRailConfig`) or given at every step (:class:`VaryingGeometryConfig`).

This is what the FMU (``fmu_src/``) wraps. A :class:`WheelRailConfig` fixes the method, the effects,
the material and the radii; :class:`WheelRailEvaluator` validates it once, solves the
load-independent Hertz problem once (:func:`~contact_core.hertz.hertz_geometry`: the ellipse's
eccentricity depends on the curvatures only) and constructs the method object once
(:func:`~contact_core.api.make_solver`). Each :meth:`WheelRailEvaluator.evaluate` then costs one
``N^{1/3}`` scaling of the patch plus one ``solver.step``: no root-finding, no file access, no
objects but the method's result.

Wheel lifted: ``N <= 0`` gives zero forces, moment, patch and pressure (the contact is open; a
negative load is what a vehicle model produces when the wheel leaves the rail), instead of the
``ValueError`` of :func:`contact_core.solve` for ``N < 0``. Every other input must be finite even
then. NaN or infinite inputs raise ``ValueError`` naming the input.

Warm start: the evaluator keeps its last result with ``N > 0`` (``WheelRailEvaluator.last``) and
passes it as ``warm_start`` to the next step, so iterative methods start from the previous solution.
Closed-form methods ignore it. Outputs therefore equal the chain
``r_k = solve(..., warm_start=r_{k-1})`` over the loaded steps.

Geometry at every step (the effect ``varying_geometry``: a contact point that moves over curved
profiles): :class:`VaryingGeometryConfig` has no radii, and :class:`VaryingGeometryEvaluator`
takes at every call (:meth:`VaryingGeometryEvaluator.evaluate`) the relative curvatures A, B
(Hertz's patch from the tabulated load-independent solution, :func:`~contact_core.hertz.
tabulated_patch`, compiled) or, with ``geometry_input="semi_axes"``, the caller's own semi-axes
a, b. Its methods are made with the effect, so
they compute what depends on a/b per call (the same results as ``solve``). Geometry that is not
finite, or impossible (A <= 0 or B <= 0: not Hertzian; A/B outside ``CURVATURE_RATIO_RANGE``; a
semi-axis <= 0), is a ``ValueError`` naming the input and its range, and the evaluator keeps its
state. With ``N <= 0`` (lifted) the geometry must be finite and is otherwise not used (a
contact search that found no contact may pass anything finite).

Derivatives: each evaluator's ``jacobian`` (same arguments as ``evaluate``) gives those of its
outputs with respect to its inputs, the method's (:mod:`contact_core.jacobian`) chained through
the patch; several contacts evaluated together: :mod:`contact_core.contacts`.

    >>> import contact_core as cc
    >>> ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method="johnson_vermeulen"))
    >>> r = ev.evaluate(xi=1e-3, eta=0.0, phi=0.0, N=100e3, mu=0.3)
    >>> ev.a > 0 and r.Fx < 0
    True
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Iterable, Mapping

import numpy as np
from numba.extending import register_jitable

from .api import METHODS, make_solver
from .base import _speed, check_inputs, refuse_speed
from .effects import ALL_EFFECTS, Effects, as_effects
from .friction import FrictionLaw
from .hertz import (CURVATURE_RATIO_RANGE, HertzPatch, hertz_geometry, max_pressure,
                    patch_kernel, tabulated_patch_derivatives, wheel_rail_curvatures)
from .jacobian import Jacobian
from .material import contact_modulus
from .material import shear_modulus
from .result import ContactResult, make_result
from .variables import (BY_NAME, DEFAULTS, GEOMETRY_INPUTS, SEMI_AXES, check, geometry_names,
                        out_of_range)

#: The patch of a lifted wheel (N <= 0).
LIFTED_PATCH = HertzPatch(0.0, 0.0, 0.0, 0.0)
_INF = math.inf
_THIRD = 1.0 / 3.0


class _Config:
    """What both configurations share: the options kept as sorted (name, value) pairs (hashable
    and order-independent), the effects as :class:`Effects`, the check of the method."""

    def __post_init__(self) -> None:
        items = self.options.items() if isinstance(self.options, Mapping) else self.options
        object.__setattr__(self, "options", tuple(sorted(items)))
        object.__setattr__(self, "effects", as_effects(self.effects))

    def _check_method(self) -> None:
        if self.method not in METHODS:
            raise ValueError(f"method={self.method!r} is unknown: allowed {list(METHODS)}")


@dataclass(frozen=True)
class WheelRailConfig(_Config):
    """Fixed data of one wheel–rail contact (SI units).

    Attributes
    ----------
    method : str
        A registered method (:func:`contact_core.methods`).
    effects : Effects
        The effects to compute (a :class:`~contact_core.scene.Scene`'s ``effects``).
    mu : float
        Friction coefficient used when :meth:`WheelRailEvaluator.evaluate` gets none.
    E, nu : float
        Young's modulus (Pa) and Poisson's ratio of wheel and rail (same material).
    R_wheel : float
        Rolling radius, m.
    R_wheel_profile : float
        Transverse radius of the wheel profile, m (negative: concave/hollow; 0 or inf: straight,
        i.e. a conical tread; 0 is the finite form FMI hosts need).
    R_rail_profile : float
        Rail-crown radius, m (convex positive; 0 or inf: straight).
    options : mapping
        Options of the method (its ``default_options`` keys), e.g. ``{"variant": "original"}``.
    friction : FrictionLaw or None
        The law of the effect ``falling_friction`` (None: ``FrictionLaw()``; ``mu`` is its
        static coefficient); :meth:`WheelRailEvaluator.evaluate` then takes the rolling speed.

    Defaults and allowed ranges: :data:`contact_core.variables.VARIABLES`.
    """

    method: str = "johnson_vermeulen"
    effects: Effects = ALL_EFFECTS
    mu: float = DEFAULTS["mu"]
    E: float = DEFAULTS["E"]
    nu: float = DEFAULTS["nu"]
    R_wheel: float = DEFAULTS["R_wheel"]
    R_wheel_profile: float = DEFAULTS["R_wheel_profile"]
    R_rail_profile: float = DEFAULTS["R_rail_profile"]
    options: Mapping[str, Any] | tuple[tuple[str, Any], ...] = ()
    friction: FrictionLaw | None = None

    def check(self) -> None:
        """Raise ``ValueError`` naming the first invalid parameter and its allowed range."""
        self._check_method()
        if self.effects.varying_geometry:
            raise ValueError("effects: 'varying_geometry' takes the geometry at every step, "
                             "WheelRailConfig's radii are fixed: use VaryingGeometryConfig")
        for name in ("mu", "E", "nu", "R_wheel"):
            check(name, getattr(self, name))
        A, B = self.curvatures()
        if not (math.isfinite(B) and B > 0.0):
            raise ValueError(
                f"R_wheel_profile={self.R_wheel_profile!r}, R_rail_profile={self.R_rail_profile!r} "
                f"give a transverse relative curvature B={B!r} 1/m: allowed 0 < B < inf, i.e. "
                "1/R_wheel_profile + 1/R_rail_profile > 0 (a concave wheel profile must be flatter "
                "than the rail crown)")

    def curvatures(self) -> tuple[float, float]:
        """Relative curvatures (A, B), 1/m (:func:`~contact_core.hertz.wheel_rail_curvatures`;
        a profile radius of 0 is a straight profile)."""
        def radius(R: float) -> float:
            return _INF if R == 0.0 else R
        return wheel_rail_curvatures(self.R_wheel, radius(self.R_wheel_profile),
                                     radius(self.R_rail_profile))


class _Evaluator:
    """What both evaluators share (module docstring): the method object made once, the
    material, ``inputs`` (the names of the arguments, :func:`contact_inputs`), the warm start
    ``last``, a loaded step's bookkeeping, the lifted wheel, the frame of the Jacobian and the
    check of outputs from outside."""

    def __init__(self, config: WheelRailConfig | VaryingGeometryConfig) -> None:
        self.config = config
        self.solver = make_solver(config.method, config.effects, config.friction,
                                  **dict(config.options))
        self.G = shear_modulus(config.E, config.nu)
        self.nu = config.nu
        self.mu = config.mu
        self.inputs = contact_inputs(config)
        self.method_code = self._code = METHODS[config.method].code
        self._name = self.solver.name
        self._codes = {name: cls.code for name, cls in METHODS.items()}
        self._lifted = make_result(0.0, 0.0, 0.0, config.method, 0.0)
        self.a = self.b = self.p0 = 0.0
        self.last: ContactResult | None = None

    def _step(self, xi: float, eta: float, phi: float, N: float, mu: float, a: float, b: float,
              p0: float, V: float | None) -> ContactResult:
        """The method's step on the patch ``a``, ``b`` (peak pressure ``p0``), kept as the warm
        start, with the patch and the code of the method that gave it."""
        result = (self.solver.step(xi, eta, phi, N, mu, a, b, self.G, self.nu, self.last)
                  if V is None else
                  self.solver.step(xi, eta, phi, N, mu, a, b, self.G, self.nu, self.last, V))
        if not math.isfinite(result.Fx + result.Fy + result.Mz):  # a method's bug, never ours
            raise FloatingPointError(
                f"method {result.method!r} returned non-finite forces (Fx={result.Fx!r}, "
                f"Fy={result.Fy!r}, Mz={result.Mz!r}) for xi={xi!r}, eta={eta!r}, "
                f"phi={phi!r}, N={N!r}, mu={mu!r}, a={a!r}, b={b!r}")
        self.last = result
        self.a = a
        self.b = b
        self.p0 = p0
        self.method_code = (self._code if result.method is self._name
                            else self._codes[result.method])
        return result

    def _lift(self) -> ContactResult:
        """The step of a lifted wheel (its inputs checked): no patch, the configured method."""
        self.a = self.b = self.p0 = 0.0
        self.method_code = self._code
        return self._lifted

    def _check_lifted(self, N: float, xi: float, eta: float, phi: float, mu: float,
                      V: float | None, geometry: Iterable[tuple[str, float]] = ()) -> None:
        """The checks of an unloaded step's inputs (``ValueError`` naming one): ``N`` a lifted
        wheel's (-inf < N <= 0), the others finite, the geometry's (name, value) pairs any
        finite value."""
        if not -_INF < N <= 0.0:
            raise out_of_range("N", N)
        check_inputs(xi, eta, phi, 0.0, mu, 1.0, 1.0, self.G, self.nu)
        if V is not None:
            _speed(V)
        for name, v in geometry:
            if not math.isfinite(v):
                raise ValueError(f"{name}={v!r} is out of range: allowed a finite number "
                                 "(any finite value while the wheel is lifted, N <= 0)")

    def _zero_jacobian(self, outputs: tuple[str, ...]) -> Jacobian:
        """The Jacobian of a lifted wheel."""
        return Jacobian(outputs, self.inputs, np.zeros((len(outputs), len(self.inputs))), "zero")

    def _chain(self, outputs: tuple[str, ...], patch: np.ndarray, xi: float, eta: float,
               phi: float, N: float, mu: float, a: float, b: float, V: float | None) -> Jacobian:
        """The Jacobian of ``outputs`` from the method's (by ξ, η, φ, N, μ, a, b[, V], from
        the warm start) at the patch ``a``, ``b`` and the patch's derivatives ``patch`` (rows
        a, b, p0 by :attr:`inputs`): ∂F/∂x = ∂F/∂x|_(a, b) + ∂F/∂a ∂a/∂x + ∂F/∂b ∂b/∂x."""
        core = self.solver.jacobian(xi, eta, phi, N, mu, a, b, self.G, self.nu, self.last, V)
        m = core.matrix                     # rows Fx, Fy, Mz, slip fraction
        ia, ib = core.inputs.index("a"), core.inputs.index("b")
        law = np.outer(m[:, ia], patch[0]) + np.outer(m[:, ib], patch[1])
        for j, name in enumerate(self.inputs):
            if name in core.inputs and name not in ("a", "b"):   # a, b: the caller's semi-axes
                law[:, j] += m[:, core.inputs.index(name)]
        rows = {"Fx": law[0], "Fy": law[1], "Mz": law[2], "slip_fraction": law[3],
                "a": patch[0], "b": patch[1], "p0": patch[2]}
        return Jacobian(outputs, self.inputs, np.array([rows[o] for o in outputs]),
                        f"{core.how}; the patch's analytic", core.steps)

    def _check_outputs(self, what: str, patch: tuple[float, float, float],
                       want: tuple[float, float, float], N: float, mu: float, Fx: float,
                       Fy: float, slip_fraction: float) -> None:
        """``check_outputs`` once the patch the outputs must have is known (``want``, of the
        inputs ``what``): the patch (a, b, p0), ``slip_fraction`` in [0, 1], zero forces when
        lifted, and |(Fx, Fy)| <= μN for a saturating method (Coulomb's law, Kalker 1979 eq 5,
        which every method's step keeps)."""
        for name, value, expected in zip(("a", "b", "p0"), patch, want):
            if not math.isclose(value, expected, rel_tol=1e-12):
                raise ValueError(f"{name}={value!r} is not the Hertz patch of {what}: allowed "
                                 f"{name}={expected!r}")
        if not 0.0 <= slip_fraction <= 1.0:
            raise ValueError(f"slip_fraction={slip_fraction!r} is out of range: allowed "
                             "0 <= slip_fraction <= 1")
        force = math.hypot(Fx, Fy)
        if N <= 0.0:
            if force != 0.0:
                raise ValueError(f"Fx={Fx!r}, Fy={Fy!r} with N={N!r}: allowed zero forces for "
                                 "a lifted wheel (N <= 0)")
        elif self.config.effects.saturation and self.solver.saturates and not force <= mu * N:
            raise ValueError(f"Fx={Fx!r}, Fy={Fy!r}: |(Fx, Fy)| = {force!r} N is out of range: "
                             f"allowed at most mu*N = {mu * N!r} N (mu={mu!r}, N={N!r})")


#: The outputs of an evaluator's Jacobian: forces, moment, the patch, the slip fraction.
EVALUATOR_OUTPUTS = ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction")
#: ... with the caller's semi-axes as inputs (``geometry_input="semi_axes"``).
SEMI_AXES_OUTPUTS = ("Fx", "Fy", "Mz", "p0", "slip_fraction")


class WheelRailEvaluator(_Evaluator):
    """Evaluate one contact per simulation step; see the module docstring.

    Attributes after :meth:`evaluate`: ``a``, ``b``, ``p0`` (the step's Hertz semi-axes, m, and
    maximum pressure, Pa; 0 when lifted), ``last`` (last loaded
    :class:`~contact_core.result.ContactResult`: the warm start) and ``method_code`` (``code`` of
    the method that produced the step's result).
    """

    def __init__(self, config: WheelRailConfig) -> None:
        config.check()
        A, B = config.curvatures()
        try:
            self.geometry = hertz_geometry(A, B, config.E, config.nu)
        except ValueError as e:  # the curvature ratio: name the radii it comes from
            raise ValueError(f"R_wheel, R_wheel_profile, R_rail_profile: {e} (the relative "
                             f"curvatures A={A!r}, B={B!r} 1/m)") from None
        super().__init__(config)
        self._ka, self._kb = self.geometry.ka, self.geometry.kb

    def evaluate(self, xi: float, eta: float, phi: float, N: float,
                 mu: float | None = None, V: float | None = None) -> ContactResult:
        """Forces of one step: creepages ``xi, eta`` (1), spin ``phi`` (1/m), load ``N`` (N),
        friction ``mu`` (the configuration's when None), rolling speed ``V`` (m/s; with the
        effect ``falling_friction``, None: 0, static friction). ``N <= 0``: zero forces (wheel
        lifted).

        Also sets ``self.a``, ``self.b`` (m) and ``self.p0`` (Pa) of the step's Hertz patch.
        """
        if mu is None:
            mu = self.mu
        if V is not None and self.solver.friction is None:
            refuse_speed(V)
            V = None
        if 0.0 < N < _INF:
            # HertzGeometry.patch(N) without building a HertzPatch per step (same arithmetic).
            s = N ** _THIRD
            a = self._ka * s
            b = self._kb * s
            return self._step(xi, eta, phi, N, mu, a, b, max_pressure(N, a, b), V)
        self._check_lifted(N, xi, eta, phi, mu, V)
        return self._lift()

    def jacobian(self, xi: float, eta: float, phi: float, N: float, mu: float | None = None,
                 V: float | None = None) -> Jacobian:
        """The derivatives of :meth:`evaluate`'s outputs (Fx, Fy, Mz, a, b, p0, slip fraction)
        with respect to its inputs (ξ, η, φ, N, μ and, with the effect 'falling_friction', V)
        at these inputs, in SI units; the evaluator's state is not changed. The method's
        (:meth:`~contact_core.base.ContactMethod.jacobian`, from the warm start ``last``)
        chained through Hertz's patch of the load: a, b ∝ N^{1/3}, so ∂a/∂N = a/(3N), and
        p0 = 3N/(2πab) ∝ N^{1/3} (Kalker 1979 sec. 2, eq 3). Lifted (N <= 0): zero."""
        if mu is None:
            mu = self.mu
        if V is not None and self.solver.friction is None:
            refuse_speed(V)
            V = None
        if not 0.0 < N < _INF:
            self._check_lifted(N, xi, eta, phi, mu, V)
            return self._zero_jacobian(EVALUATOR_OUTPUTS)
        s = N ** _THIRD
        a, b = self._ka * s, self._kb * s
        p0 = max_pressure(N, a, b)
        patch = np.zeros((3, len(self.inputs)))
        patch[:, 3] = (a / (3.0 * N), b / (3.0 * N), p0 / (3.0 * N))
        return self._chain(EVALUATOR_OUTPUTS, patch, xi, eta, phi, N, mu, a, b, V)

    def check_outputs(self, N: float, mu: float, Fx: float, Fy: float, a: float, b: float,
                      p0: float, slip_fraction: float) -> None:
        """Raise ``ValueError`` naming the first output that :meth:`evaluate` cannot have given
        at load ``N`` (N) and friction ``mu``: for outputs that come back from outside (a saved
        FMU state), which are untrusted.

        The patch ``a``, ``b`` (m) and ``p0`` (Pa) must be Hertz's for ``N``, and zero with
        zero forces when ``N <= 0`` (wheel lifted). ``slip_fraction`` must be in [0, 1], and
        for a saturating method the force must satisfy |(Fx, Fy)| <= μN (Coulomb's law, Kalker
        1979 eq 5, which every method's step keeps). The moment is not checked, because a
        discretised method's grid pressure may exceed the continuum's bound on it.
        """
        if not (-_INF < N < _INF):
            raise out_of_range("N", N)
        want = self.geometry.patch(N) if N > 0.0 else LIFTED_PATCH
        self._check_outputs(f"N={N!r}", (a, b, p0), (want.a, want.b, want.p0), N, mu, Fx, Fy,
                            slip_fraction)


#: The default effects of a contact whose geometry is an input: every effect of ``ALL_EFFECTS``.
VARYING_GEOMETRY_EFFECTS = Effects(varying_geometry=True)


@dataclass(frozen=True)
class VaryingGeometryConfig(_Config):
    """Fixed data of one wheel–rail contact whose geometry is an input at every step (the effect
    ``varying_geometry``; SI units): the method, the effects, the friction coefficient used
    when a call gets none, Young's modulus ``E`` (Pa) and Poisson's ratio ``nu`` of both
    bodies, the method's ``options``, the law of the effect ``falling_friction`` (``friction``:
    None for ``FrictionLaw()``; :meth:`VaryingGeometryEvaluator.evaluate` then takes the
    rolling speed ``V``), and what the geometry at a call is, ``geometry_input``
    (:data:`contact_core.variables.GEOMETRY_INPUTS`): "curvatures", the relative curvatures
    A, B of the two surfaces at the contact point, of which the evaluator solves Hertz's patch,
    or "semi_axes", the semi-axes a, b of a patch the caller computes. Defaults and ranges:
    :data:`contact_core.variables.VARIABLES`."""

    method: str = "johnson_vermeulen"
    effects: Effects = VARYING_GEOMETRY_EFFECTS
    mu: float = DEFAULTS["mu"]
    E: float = DEFAULTS["E"]
    nu: float = DEFAULTS["nu"]
    options: Mapping[str, Any] | tuple[tuple[str, Any], ...] = ()
    geometry_input: str = GEOMETRY_INPUTS[0]
    friction: FrictionLaw | None = None

    def check(self) -> None:
        """Raise ``ValueError`` naming the first invalid parameter and its allowed range."""
        self._check_method()
        if not self.effects.varying_geometry:
            raise ValueError("effects: VaryingGeometryConfig needs the effect 'varying_geometry' "
                             "(a fixed geometry: WheelRailConfig)")
        geometry_names(self.geometry_input)
        for name in ("mu", "E", "nu"):
            check(name, getattr(self, name))


def contact_inputs(config: WheelRailConfig | VaryingGeometryConfig) -> tuple[str, ...]:
    """The inputs of one contact of ``config``, in the order of the evaluator's arguments:
    ξ, η, φ, N, μ, the geometry inputs with ``varying_geometry`` (A, B or a, b), and the
    rolling speed V with ``falling_friction``."""
    names = ("xi", "eta", "phi", "N", "mu")
    if isinstance(config, VaryingGeometryConfig):
        names += geometry_names(config.geometry_input)
    if config.effects.falling_friction:
        names += ("V",)
    return names


@register_jitable
def _semi_axes_patch(N: float, a: float, b: float, e_star: float) -> tuple[float, float, float]:
    """The patch of semi-axes ``a``, ``b`` (m) under ``N``: Hertz's peak pressure 3N/(2πab)
    (Kalker 1979 eq 3); (nan, nan, nan) for a semi-axis that is not finite and positive (also
    compiled into the kernel of :mod:`.contacts`)."""
    if 0.0 < a < _INF and 0.0 < b < _INF:
        return a, b, max_pressure(N, a, b)
    return math.nan, math.nan, math.nan


class VaryingGeometryEvaluator(_Evaluator):
    """Evaluate one contact per simulation step with its geometry given at every step (module
    docstring). Attributes after a call: ``a``, ``b``, ``p0`` (the step's semi-axes, m, and
    peak pressure, Pa; 0 when lifted), ``last`` (the last loaded result: the warm start) and
    ``method_code``."""

    def __init__(self, config: VaryingGeometryConfig) -> None:
        config.check()
        super().__init__(config)
        self._e_star = contact_modulus(config.E, config.nu)
        #: the names of the geometry inputs, and their patch: Hertz's of the curvatures, or the
        #: caller's semi-axes with Hertz's pressure
        self.geometry = geometry_names(config.geometry_input)
        self._curvatures = self.geometry == ("A", "B")
        self._patch = patch_kernel() if self._curvatures else _semi_axes_patch

    def evaluate(self, xi: float, eta: float, phi: float, N: float, mu: float | None, gx: float,
                 gy: float, V: float | None = None) -> ContactResult:
        """Forces of one step from the creepages ``xi, eta`` (1), spin ``phi`` (1/m), load ``N``
        (N), friction ``mu`` (None: the configuration's) and the geometry along the rolling
        direction x and across it, ``gx, gy``: the relative curvatures A, B (1/m) of the two
        surfaces at the contact point (gap h = A x² + B y²), or with ``geometry_input=
        "semi_axes"`` the semi-axes a, b (m) of the caller's patch (e.g. a non-Hertzian or
        multi-Hertzian contact model's); the rolling speed ``V`` (m/s) with the effect
        ``falling_friction`` (None: 0, static friction). Sets ``a``, ``b``, ``p0``: Hertz's
        patch of the curvatures, or the caller's with Hertz's peak pressure 3N/(2πab)."""
        if mu is None:
            mu = self.mu
        if V is not None and self.solver.friction is None:
            refuse_speed(V)
            V = None
        if 0.0 < N < _INF:
            a, b, p0 = self._patch(N, gx, gy, self._e_star)
            if a != a:          # nan: no patch for this geometry
                raise self._geometry_error(gx, gy)
            return self._step(xi, eta, phi, N, mu, a, b, p0, V)
        self._check_lifted(N, xi, eta, phi, mu, V, zip(self.geometry, (gx, gy)))
        return self._lift()

    def jacobian(self, xi: float, eta: float, phi: float, N: float, mu: float | None,
                 gx: float, gy: float, V: float | None = None) -> Jacobian:
        """The derivatives of :meth:`evaluate`'s outputs (Fx, Fy, Mz, a, b, p0, slip fraction;
        without a, b with ``geometry_input="semi_axes"``, where they are inputs) with respect
        to its inputs (ξ, η, φ, N, μ, the geometry and, with the effect 'falling_friction',
        V) at these inputs, in SI units; the evaluator's state is not changed. The method's
        (:meth:`~contact_core.base.ContactMethod.jacobian`, from the warm start ``last``)
        chained through the patch: Hertz's of the curvatures A, B, the tabulated solution
        differentiated (:func:`~contact_core.hertz.tabulated_patch_derivatives`), or the
        caller's a, b with p0 = 3N/(2πab). Lifted (N <= 0): zero."""
        if mu is None:
            mu = self.mu
        if V is not None and self.solver.friction is None:
            refuse_speed(V)
            V = None
        outputs = EVALUATOR_OUTPUTS if self._curvatures else SEMI_AXES_OUTPUTS
        if not 0.0 < N < _INF:
            self._check_lifted(N, xi, eta, phi, mu, V, zip(self.geometry, (gx, gy)))
            return self._zero_jacobian(outputs)
        a, b, p0 = self._patch(N, gx, gy, self._e_star)
        if a != a:
            raise self._geometry_error(gx, gy)
        patch = np.zeros((3, len(self.inputs)))
        if self._curvatures:
            a, b, p0, d = tabulated_patch_derivatives(N, gx, gy, self._e_star)
            patch[:, [3, 5, 6]] = d
        else:
            patch[0, 5] = patch[1, 6] = 1.0
            patch[2, [3, 5, 6]] = (p0 / N, -p0 / a, -p0 / b)
        return self._chain(outputs, patch, xi, eta, phi, N, mu, a, b, V)

    def _geometry_error(self, gx: float, gy: float) -> ValueError:
        """The error for a geometry without a patch: the first input outside its range, else
        (curvatures) their ratio."""
        for name, v in zip(self.geometry, (gx, gy)):
            rng = BY_NAME[name].range if self._curvatures else SEMI_AXES[name][0]
            if not rng.contains(v):
                return ValueError(f"{name}={v!r} is out of range: allowed {rng.text(name)}")
        lo, hi = CURVATURE_RATIO_RANGE
        return ValueError(f"A={gx!r}, B={gy!r}: A/B={gx / gy!r} is out of range: allowed "
                          f"{lo:g} <= A/B <= {hi:g} (the Hertz ellipses supported, semi-axis "
                          "ratios about 0.015 to 68)")

    def check_outputs(self, N: float, mu: float, Fx: float, Fy: float, a: float, b: float,
                      p0: float, slip_fraction: float, gx: float, gy: float) -> None:
        """Raise ``ValueError`` naming the first output that :meth:`evaluate` cannot have given
        with the geometry ``gx, gy`` (outputs from outside, e.g. a saved FMU state): the patch
        ``a``, ``b``, ``p0`` must be the one :meth:`evaluate` gives for ``N``, ``gx``, ``gy``
        (the caller's a, b with ``geometry_input="semi_axes"``), a zero one when lifted
        (N <= 0); then as ``WheelRailEvaluator.check_outputs``."""
        if not (-_INF < N < _INF):
            raise out_of_range("N", N)
        if N > 0.0:
            want = self._patch(N, gx, gy, self._e_star)
            if want[0] != want[0]:
                raise self._geometry_error(gx, gy)
            if not self._curvatures:        # the ratio the method would have refused
                check_inputs(0.0, 0.0, 0.0, N, 0.0, gx, gy, self.G, self.nu)
        else:
            want = (0.0, 0.0, 0.0)
        if not self._curvatures:            # a, b are the caller's
            want = (a, b, want[2]) if N > 0.0 else (a, b, 0.0)
        what = ", ".join(f"{n}={v!r}" for n, v in zip(("N",) + self.geometry, (N, gx, gy)))
        self._check_outputs(what, (a, b, p0), want, N, mu, Fx, Fy, slip_fraction)
