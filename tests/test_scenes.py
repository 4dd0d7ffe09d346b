"""Scenes (contact_core/scenes/*.toml) and their effect sets, as issue 5 specifies them."""
from __future__ import annotations

import pytest

import contact_core as cc

pytestmark = pytest.mark.unit

#: Every effect of Coulomb friction (the default set; falling_friction is opt-in, issue 63).
ALL = set(cc.ALL_EFFECTS.names())
#: The issue's table: scene -> effects it needs.
EXPECTED = {
    "traction": {"longitudinal", "saturation"},
    "traction_falling": {"longitudinal", "saturation", "falling_friction"},
    "tangent_track": {"longitudinal", "lateral", "spin"},
    "curving": ALL,
    "full": ALL,
    "vehicle": ALL | {"varying_geometry"},
}


def test_shipped_scenes():
    assert set(EXPECTED) <= set(cc.scenes())
    assert cc.DEFAULT_SCENE == "full"
    assert cc.load_scene().name == "full"


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_scene_effects_and_method(name):
    s = cc.load_scene(name)
    assert s.name == name and s.description
    assert set(s.effects.names()) == EXPECTED[name]
    assert s.default_method in cc.methods()


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_core_computes_only_the_scene_effects(name, wheel_rail_case):
    """solve(effects=scene) gives zeros for unselected outputs and rejects their inputs."""
    from conftest import options_for
    s = cc.load_scene(name)
    eff = s.effects
    case = dict(wheel_rail_case, xi=1e-3 if eff.longitudinal else 0.0,
                eta=-4e-4 if eff.lateral else 0.0, phi=0.1 if eff.spin else 0.0)
    r = cc.solve(s.default_method, effects=eff, **case, **options_for(s.default_method))
    assert (r.Fx != 0.0) == eff.longitudinal
    assert (r.Fy != 0.0) == eff.lateral
    assert (r.Mz != 0.0) == eff.spin
    for var, on in (("eta", eff.lateral), ("phi", eff.spin)):
        if not on:
            with pytest.raises(ValueError, match=var):
                cc.solve(s.default_method, effects=eff, **{**case, var: 1e-3},
                         **options_for(s.default_method))


def test_scene_from_file_and_preferences(tmp_path):
    f = tmp_path / "braking.toml"
    f.write_text('description = "test"\neffects = ["longitudinal", "saturation"]\n'
                 'default_method = ["no_such_method", "linear"]\n')
    s = cc.load_scene(f)
    assert s.name == "braking" and s.default_method == "linear"
    assert cc.load_scene(str(f)) == s


@pytest.mark.parametrize("text, match", [
    ('effects = ["longitudinal", "grip"]', "grip"),
    ('effects = ["saturation"]', "at least one"),
    ('effects = ["longitudinal", "variable_friction"]', "variable_friction"),
    ('effects = ["longitudinal", "falling_friction"]', "falling_friction"),
    ('effects = ["longitudinal"]\ndefault_method = "nope"', "nope"),
    ('effects = ["longitudinal"]\ncolour = "red"', "colour"),
    ('effects = "longitudinal"', "effects"),
])
def test_bad_scene_files(tmp_path, text, match):
    f = tmp_path / "bad.toml"
    f.write_text(text + "\n")
    with pytest.raises(ValueError, match=match):
        cc.load_scene(f)


def test_unknown_scene_lists_allowed():
    with pytest.raises(ValueError, match="traction"):
        cc.load_scene("no_such_scene")
