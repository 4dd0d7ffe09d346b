"""Effect sets: which parts of the rolling-contact problem a scene needs.

A vehicle-dynamics scene rarely needs the whole contact law. Traction on straight track needs the
longitudinal force and its saturation only; small-amplitude hunting needs the linear creep forces in
both directions and spin, but no saturation. An :class:`Effects` value names what is needed, and
every method computes only that:

``longitudinal``
    input ξ, output Fx.
``lateral``
    input η, output Fy.
``spin``
    input φ, output Mz (and φ's contribution to Fy when ``lateral`` is also selected).
``saturation``
    Coulomb friction bounds the tractions (|p| ≤ μ p_n). Without it every method returns its own
    unsaturated limit μ → ∞ (the linear range), which is cheaper, and μ is not used.
``variable_friction``
    μ is a time-varying input (FMU only: the core always takes μ per call).
``falling_friction``
    friction falls with the slip velocity (:mod:`contact_core.friction`): the rolling speed V
    (m/s) is an input and μ is the static coefficient of a :class:`~contact_core.friction.
    FrictionLaw`. Needs ``saturation``. Opt-in: not in the default set :data:`ALL_EFFECTS`
    (every effect of Coulomb friction), whose calls it leaves unchanged.
``varying_geometry``
    the patch geometry is an input at every step: the relative curvatures A, B of the two
    surfaces at the contact point (1/m), or the host's own semi-axes a, b (m), instead of the
    fixed radii ``R_wheel``, ``R_wheel_profile``, ``R_rail_profile`` (the evaluator and the FMU:
    :class:`~contact_core.wheel_rail.VaryingGeometryEvaluator`; ``solve`` always takes a, b per
    call). Methods given it expect a new a/b at every call and compute what depends on a/b per
    call instead of caching it (the same results). Opt-in, like ``falling_friction``.

Inputs of an effect that is not selected must be zero (a non-zero value is a ``ValueError``, never
silently dropped); outputs of an effect that is not selected are reported as 0.0.
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Iterable

from .cache import cached

EFFECT_NAMES: tuple[str, ...] = ("longitudinal", "lateral", "spin", "saturation", "variable_friction",
                                   "falling_friction", "varying_geometry")


@dataclass(frozen=True)
class Effects:
    """The set of effects a computation includes (by default every effect of Coulomb friction;
    ``falling_friction`` and ``varying_geometry`` are opt-in)."""

    longitudinal: bool = True
    lateral: bool = True
    spin: bool = True
    saturation: bool = True
    variable_friction: bool = True
    falling_friction: bool = False
    varying_geometry: bool = False

    def __post_init__(self) -> None:
        # solve() looks its solver up by the effects at every call: hashed once, not per call
        object.__setattr__(self, "_hash", hash(tuple(getattr(self, f.name) for f in fields(self))))

    def __hash__(self) -> int:
        return self._hash

    @classmethod
    def from_names(cls, names: Iterable[str]) -> "Effects":
        """Build from effect names; an unknown name is a ``ValueError`` listing the allowed ones."""
        names = tuple(names)
        unknown = [n for n in names if n not in EFFECT_NAMES]
        if unknown:
            raise ValueError(f"effects: unknown effect(s) {unknown}; allowed: {list(EFFECT_NAMES)}")
        chosen = set(names)
        if not chosen & {"longitudinal", "lateral", "spin"}:
            raise ValueError(
                "effects: select at least one of 'longitudinal', 'lateral', 'spin' "
                f"(got {sorted(chosen)})")
        return cls(**{n: (n in chosen) for n in EFFECT_NAMES})

    def names(self) -> tuple[str, ...]:
        """The selected effect names, in canonical order."""
        return tuple(f.name for f in fields(self) if getattr(self, f.name))


#: The default set: every effect of Coulomb friction (all but the opt-in ``falling_friction``
#: and ``varying_geometry``).
ALL_EFFECTS = Effects()


@cached(256)
def _from_hashable(spec: tuple[str, ...] | frozenset | str) -> Effects:
    if isinstance(spec, str):
        spec = (spec,)
    return Effects.from_names(sorted(spec) if isinstance(spec, frozenset) else spec)


def as_effects(spec: Effects | Iterable[str] | None) -> Effects:
    """Normalise ``None`` (all effects), an :class:`Effects`, or an iterable of names."""
    if spec is None:
        return ALL_EFFECTS
    if isinstance(spec, Effects):
        return spec
    if isinstance(spec, (tuple, frozenset, str)):
        return _from_hashable(spec)
    try:
        names = tuple(spec)
    except TypeError:
        raise ValueError(f"effects={spec!r} is invalid: allowed None, an Effects or effect names "
                         f"from {list(EFFECT_NAMES)}") from None
    return _from_hashable(names)
