"""Scenes: which effects of the contact law a simulation needs, read from small TOML files.

A scene names the effects it calls for (see :mod:`contact_core.effects`) and a default method.
The shipped scenes live in ``contact_core/scenes/*.toml``:

``traction``
    straight track, traction/braking: ``longitudinal`` + ``saturation``.
``traction_falling``
    the same with ``falling_friction``: the adhesion curve's falling branch beyond its peak
    (wheel slip, slip control, wheel-slide protection); default method ``polach``.
``tangent_track``
    small-amplitude hunting: ``longitudinal``, ``lateral``, ``spin`` (linear range, no saturation).
``curving``
    every effect.
``full``
    every effect; the default scene.
``vehicle``
    every effect of ``full`` and ``varying_geometry``: the patch geometry is an input at every
    step (the curvatures A, B at the contact point, or with ``build-fmu --geometry-input
    semi_axes`` the host's own semi-axes a, b), for a vehicle model whose contact point moves
    over the wheel and rail profiles.

File format (every key but ``effects`` optional)::

    description = "Straight track, traction/braking"
    effects = ["longitudinal", "saturation"]
    default_method = "johnson_vermeulen"        # or a preference list: ["fastsim", "linear"]

``default_method`` may list several methods in order of preference; the first one registered in
:data:`contact_core.METHODS` when the scene is loaded is used, so a scene can prefer a method that
another part of the library adds later. ``variable_friction`` (μ is a time-varying input) needs
``saturation``: without saturation μ does not enter the result. ``varying_geometry`` goes with any
other effects (it changes where the geometry comes from, not what is computed).

    >>> import contact_core as cc
    >>> s = cc.load_scene("traction")
    >>> s.effects.names()
    ('longitudinal', 'saturation')
    >>> r = cc.solve(s.default_method, xi=1e-3, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=6e-3, b=4e-3,
    ...              G=8e10, nu=0.28, effects=s.effects)
"""
from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from .effects import Effects

#: The scene used when none is named.
DEFAULT_SCENE = "full"

_KEYS = {"name", "description", "effects", "default_method"}


@dataclass(frozen=True)
class Scene:
    """A named set of effects and the method to use by default."""

    name: str
    description: str
    effects: Effects
    default_method: str


def _scene_dir():
    return resources.files(__package__).joinpath("scenes")


def scenes() -> tuple[str, ...]:
    """Names of the shipped scenes (sorted)."""
    return tuple(sorted(p.name[:-5] for p in _scene_dir().iterdir() if p.name.endswith(".toml")))


def _registered_methods() -> tuple[str, ...]:
    from .api import methods  # late import: the registry may grow after this module is imported
    return methods()


def parse_scene(text: str, name: str) -> Scene:
    """Build a :class:`Scene` from TOML text; ``ValueError`` names the offending key."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10: the same parser as the tomli package
        import tomli as tomllib
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"scene {name!r}: invalid TOML: {e}") from None
    unknown = sorted(set(data) - _KEYS)
    if unknown:
        raise ValueError(f"scene {name!r}: unknown key(s) {unknown}; allowed: {sorted(_KEYS)}")
    name = data.get("name", name)
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"scene name={name!r} is invalid: allowed a Python identifier")
    effects_spec = data.get("effects")
    if not isinstance(effects_spec, list) or not all(isinstance(e, str) for e in effects_spec):
        raise ValueError(f"scene {name!r}: effects={effects_spec!r} is invalid: allowed a list of "
                         "effect names")
    try:
        effects = Effects.from_names(effects_spec)
    except ValueError as e:
        raise ValueError(f"scene {name!r}: {e}") from None
    for needs in ("variable_friction", "falling_friction"):
        if getattr(effects, needs) and not effects.saturation:
            raise ValueError(f"scene {name!r}: effect {needs!r} needs 'saturation' (without "
                             "saturation the friction coefficient does not enter the result)")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise ValueError(f"scene {name!r}: description must be a string")
    pref = data.get("default_method", "johnson_vermeulen")
    pref = [pref] if isinstance(pref, str) else pref
    if not isinstance(pref, list) or not pref or not all(isinstance(m, str) for m in pref):
        raise ValueError(f"scene {name!r}: default_method={data.get('default_method')!r} is "
                         "invalid: allowed a method name or a non-empty list of them")
    registered = _registered_methods()
    chosen = next((m for m in pref if m in registered), None)
    if chosen is None:
        raise ValueError(f"scene {name!r}: none of default_method={pref} is registered: "
                         f"allowed {list(registered)}")
    return Scene(name, description, effects, chosen)


def load_scene(scene: str | Path = DEFAULT_SCENE) -> Scene:
    """Load a shipped scene by name (see :func:`scenes`) or a scene file by path (``*.toml``)."""
    if isinstance(scene, Scene):
        return scene
    text_name = str(scene)
    if isinstance(scene, Path) or text_name.endswith(".toml"):
        path = Path(scene)
        if not path.is_file():
            raise ValueError(f"scene file {str(path)!r} does not exist")
        return parse_scene(path.read_text(encoding="utf-8"), path.stem)
    if text_name not in scenes():
        raise ValueError(f"scene={text_name!r} is unknown: allowed {list(scenes())} "
                         "or the path of a .toml file")
    return parse_scene(_scene_dir().joinpath(f"{text_name}.toml").read_text(encoding="utf-8"),
                       text_name)
