"""The variables of one wheel–rail contact: one table for the evaluator, the FMU and its checks.

Each :class:`Variable` states its name, causality (input, output or parameter of a contact
evaluated step by step), type, SI unit, the effect that brings it (:mod:`.effects`; None:
always there), its default and its allowed range. :class:`~contact_core.WheelRailConfig` takes
its defaults and range checks from here, and the FMU (``wheel_rail_fmu.model_description``)
declares exactly :func:`scene_variables`, so a scene exposes only the variables of its effects.

The friction coefficient ``mu`` is an input with ``variable_friction``, a parameter with
``saturation`` alone, and absent without saturation (it does not enter the result). With
``falling_friction`` it is the static coefficient of the law whose parameters ``friction_*`` are,
and the rolling speed ``V`` is an input.

With ``varying_geometry`` the patch geometry is an input at every step and the fixed radii
``R_wheel``, ``R_wheel_profile``, ``R_rail_profile`` are absent: by default
(``geometry_input="curvatures"``) the relative curvatures ``A``, ``B`` of the two surfaces at the
contact point, from which the contact solves Hertz's patch (outputs ``a``, ``b``, ``p0``); with
``geometry_input="semi_axes"`` the semi-axes ``a``, ``b`` themselves, which are then inputs (for
a host that computes its own patch; ``p0`` stays an output). The outputs of the patch and
``method_used`` then depend on the geometry inputs too.
Sign convention of the outputs: Kalker 1979 sec. 2 (forces of the rail on the wheel).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .effects import Effects
from .friction import DEFAULT_LAW, KINDS, FrictionLaw

_INF = math.inf


@dataclass(frozen=True)
class Range:
    """An interval of allowed values; ``what`` names the quantity in error messages."""

    lo: float
    hi: float
    lo_open: bool
    hi_open: bool
    what: str

    def contains(self, value: float) -> bool:
        if math.isnan(value):
            return False
        above = self.lo < value if self.lo_open else self.lo <= value
        below = value < self.hi if self.hi_open else value <= self.hi
        return above and below

    def text(self, name: str) -> str:
        if self.lo == -_INF and self.hi == _INF:
            return f"a finite number ({self.what})"
        return (f"{self.lo:g} {'<' if self.lo_open else '<='} {name} "
                f"{'<' if self.hi_open else '<='} {self.hi:g} ({self.what})")


@dataclass(frozen=True)
class Variable:
    """One variable of a contact; ``depends``: for outputs, the inputs they depend on (None:
    all of them)."""

    name: str
    causality: str
    type: str
    unit: str | None
    description: str
    effect: str | None = None
    default: float | None = None
    range: Range | None = None
    depends: tuple[str, ...] | None = None


def _finite(what: str) -> Range:
    return Range(-_INF, _INF, True, True, what)


VARIABLES: tuple[Variable, ...] = (
    Variable("xi", "input", "Real", "1", "Longitudinal creepage: longitudinal rigid slip "
             "velocity / rolling speed", "longitudinal", 0.0,
             _finite("longitudinal creepage, dimensionless")),
    Variable("eta", "input", "Real", "1", "Lateral creepage: lateral rigid slip velocity / "
             "rolling speed", "lateral", 0.0, _finite("lateral creepage, dimensionless")),
    Variable("phi", "input", "Real", "1/m", "Spin creepage: rigid spin angular velocity / "
             "rolling speed", "spin", 0.0, _finite("spin, 1/m")),
    Variable("N", "input", "Real", "N", "Normal load; N <= 0 means the wheel is lifted: zero "
             "forces, moment and patch", None, 0.0,
             _finite("normal load, N; N <= 0 means the wheel is lifted")),
    Variable("mu", "input", "Real", "1", "Friction coefficient", "saturation", 0.3,
             Range(0.0, _INF, False, True, "friction coefficient")),
    Variable("V", "input", "Real", "m/s", "Rolling speed: the slip velocity is the creepage "
             "times |V| (0: static friction throughout)", "falling_friction", 0.0,
             _finite("rolling speed, m/s")),
    # varying_geometry; defaults: the curvatures of the default radii R_wheel and R_rail_profile
    Variable("A", "input", "Real", "1/m", "Relative curvature of wheel and rail along the "
             "rolling direction x at the contact point (gap h = A x^2 + B y^2)",
             "varying_geometry", 0.5 / 0.46,
             Range(0.0, _INF, True, True, "relative curvature along the rolling direction x, 1/m; "
                   "A <= 0 is not Hertzian")),
    Variable("B", "input", "Real", "1/m", "Relative curvature of wheel and rail across the "
             "rolling direction (y) at the contact point (gap h = A x^2 + B y^2)",
             "varying_geometry", 0.5 / 0.3,
             Range(0.0, _INF, True, True, "relative curvature along the lateral direction y, 1/m; "
                   "B <= 0 is not Hertzian")),
    Variable("Fx", "output", "Real", "N", "Longitudinal creep force of the rail on the wheel "
             "(Kalker's sign convention)", "longitudinal"),
    Variable("Fy", "output", "Real", "N", "Lateral creep force of the rail on the wheel "
             "(Kalker's sign convention)", "lateral"),
    Variable("Mz", "output", "Real", "N.m", "Spin moment about the contact normal", "spin"),
    Variable("a", "output", "Real", "m", "Hertz semi-axis along the rolling direction",
             depends=("N",)),
    Variable("b", "output", "Real", "m", "Hertz semi-axis across the rolling direction",
             depends=("N",)),
    Variable("p0", "output", "Real", "Pa", "Maximum Hertz pressure", depends=("N",)),
    Variable("slip_fraction", "output", "Real", "1", "Fraction of the contact area in slip, "
             "0..1"),
    # N: a loaded state may go to the method's fallback (table -> exact), a lifted one does not
    Variable("method_used", "output", "Integer", None, "Code of the method that computed the "
             "outputs", depends=("N",)),
    Variable("E", "parameter", "Real", "Pa", "Young's modulus of wheel and rail (same "
             "material)", None, 210e9, Range(0.0, _INF, True, True, "Young's modulus, Pa")),
    Variable("nu", "parameter", "Real", "1", "Poisson's ratio of wheel and rail", None, 0.28,
             Range(0.0, 0.5, False, True, "Poisson's ratio")),
    Variable("R_wheel", "parameter", "Real", "m", "Wheel rolling radius (longitudinal "
             "curvature)", None, 0.46, Range(0.0, _INF, True, True, "rolling radius, m")),
    Variable("R_wheel_profile", "parameter", "Real", "m", "Transverse radius of the wheel "
             "profile at the contact (negative: concave; 0: straight, i.e. a conical tread); "
             "1/R_wheel_profile + 1/R_rail_profile > 0", None, 0.0),
    Variable("R_rail_profile", "parameter", "Real", "m", "Rail crown radius at the contact "
             "(convex positive; 0: straight); 1/R_wheel_profile + 1/R_rail_profile > 0", None,
             0.3),
    # the law of contact_core.friction (mu is its static coefficient), its defaults
    Variable("friction_law", "parameter", "String", None, "Falling friction law: "
             "'exponential', 'rational' or 'linear' (CONTACT's L = 4, 3, 2)", "falling_friction",
             DEFAULT_LAW.kind),
    Variable("friction_kinetic_ratio", "parameter", "Real", "1", "Kinetic over static friction "
             "coefficient, the limit at large slip velocity (Polach's A)", "falling_friction",
             DEFAULT_LAW.kinetic, Range(*FrictionLaw.RANGES["kinetic"])),
    Variable("friction_slip_half", "parameter", "Real", "m/s", "Slip velocity at which the "
             "falling part of the friction is halved (exponential law: ln 2 / Polach's B)",
             "falling_friction", DEFAULT_LAW.s_half, Range(*FrictionLaw.RANGES["s_half"])),
)
#: Variables by name.
BY_NAME = {v.name: v for v in VARIABLES}
#: Defaults by name (inputs and parameters).
DEFAULTS = {v.name: v.default for v in VARIABLES if v.default is not None}


def out_of_range(name: str, value: float) -> ValueError:
    """The error for ``value`` outside the range of the variable ``name``."""
    return ValueError(f"{name}={value!r} is out of range: allowed "
                      f"{BY_NAME[name].range.text(name)}")


def check(name: str, value: float) -> float:
    """``value`` if it is in the range of the variable ``name``, else :func:`out_of_range`."""
    if not BY_NAME[name].range.contains(value):
        raise out_of_range(name, value)
    return value


def friction_law(kind: str, kinetic_ratio: float, slip_half: float) -> FrictionLaw:
    """The law of the parameters ``friction_law``, ``friction_kinetic_ratio`` and
    ``friction_slip_half`` (effect ``falling_friction``); ``ValueError`` names the parameter."""
    if not isinstance(kind, str) or kind not in KINDS:
        raise ValueError(f"friction_law={kind!r} is invalid: allowed "
                         + " or ".join(repr(k) for k in KINDS))
    return FrictionLaw(kind, check("friction_kinetic_ratio", kinetic_ratio),
                       check("friction_slip_half", slip_half))


#: How the geometry comes in with ``varying_geometry`` (module docstring); the first is the default.
GEOMETRY_INPUTS = ("curvatures", "semi_axes")
#: The parameters of a fixed geometry (absent with ``varying_geometry``).
FIXED_GEOMETRY = ("R_wheel", "R_wheel_profile", "R_rail_profile")
#: The semi-axes as inputs (``geometry_input="semi_axes"``): their ranges, and start values
#: (about the Hertz patch of the default curvatures under 100 kN).
SEMI_AXES = {"a": (Range(0.0, _INF, True, True, "semi-axis along the rolling direction x, m"),
                   7e-3),
             "b": (Range(0.0, _INF, True, True, "semi-axis along the lateral direction y, m"),
                   5.4e-3)}


def geometry_names(geometry_input: str) -> tuple[str, str]:
    """The two geometry inputs of ``geometry_input`` (``GEOMETRY_INPUTS``), or ``ValueError``."""
    if geometry_input == "curvatures":
        return ("A", "B")
    if geometry_input == "semi_axes":
        return ("a", "b")
    raise ValueError(f"geometry_input={geometry_input!r} is invalid: allowed "
                     + " or ".join(map(repr, GEOMETRY_INPUTS)))


def _varying_geometry(v: Variable, geometry: tuple[str, str]) -> Variable | None:
    """``v`` as a contact with ``varying_geometry`` and the geometry inputs ``geometry`` has it
    (module docstring), None if it has not."""
    if v.name in FIXED_GEOMETRY or (v.name in ("A", "B") and v.name not in geometry):
        return None
    if v.name in geometry and v.causality == "output":        # a, b as inputs
        rng, start = SEMI_AXES[v.name]
        return replace(v, causality="input", default=start, range=rng, depends=None,
                       description=v.description + " (computed by the host)")
    if v.causality == "output" and v.depends is not None:      # the patch and method_used
        return replace(v, depends=v.depends + geometry)
    return v


def scene_variables(effects: Effects,
                    geometry_input: str = GEOMETRY_INPUTS[0]) -> tuple[Variable, ...]:
    """The variables of a contact computing ``effects`` (see the module docstring for mu and
    the geometry; ``geometry_input`` matters only with ``varying_geometry``)."""
    geometry = geometry_names(geometry_input)
    out = []
    for v in VARIABLES:
        if effects.varying_geometry:
            v = _varying_geometry(v, geometry)
            if v is None:
                continue
        if v.name == "mu":
            if effects.variable_friction:
                out.append(replace(v, description=v.description + " (time-varying)"))
            elif effects.saturation:
                out.append(replace(v, causality="parameter"))
        elif v.effect is None or getattr(effects, v.effect):
            out.append(v)
    return tuple(out)
