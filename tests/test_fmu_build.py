"""Building the WheelRailContact FMU: validation, the variables of each scene, reproducibility,
names, build-time checks of start values, the README's build commands, what the archive holds.
References: fmpy's validator, the scene table of the user guide (docs/guide/scenes_and_effects.md),
the FMI 2.0 standard."""
from __future__ import annotations

import math
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

import contact_core as cc
from conftest import SCENES
from wheel_rail_fmu.build import build, main
from wheel_rail_fmu.host import FmuInstance
from wheel_rail_fmu.validation import validate

pytestmark = pytest.mark.fmu_build

ROOT = Path(__file__).resolve().parents[1]
DIAGNOSTICS = {"a", "b", "p0", "slip_fraction", "method_used"}
#: The user guide's scene table, docs/guide/scenes_and_effects.md: scene -> (inputs, outputs).
EXPECTED = {
    "traction": ({"xi", "N"}, {"Fx"} | DIAGNOSTICS),
    "tangent_track": ({"xi", "eta", "phi", "N"}, {"Fx", "Fy", "Mz"} | DIAGNOSTICS),
    "curving": ({"xi", "eta", "phi", "N", "mu"}, {"Fx", "Fy", "Mz"} | DIAGNOSTICS),
    "full": ({"xi", "eta", "phi", "N", "mu"}, {"Fx", "Fy", "Mz"} | DIAGNOSTICS),
}
UNITS = {"xi": "1", "eta": "1", "phi": "1/m", "N": "N", "mu": "1", "Fx": "N", "Fy": "N",
         "Mz": "N.m", "a": "m", "b": "m", "p0": "Pa", "slip_fraction": "1", "E": "Pa",
         "nu": "1", "R_wheel": "m", "R_wheel_profile": "m", "R_rail_profile": "m"}


@pytest.mark.parametrize("scene", SCENES)
def test_scene_fmu_validates(fmus, scene):
    assert validate_fmu(str(fmus[scene])) == []
    assert validate(fmus[scene]) == []


@pytest.mark.parametrize("scene", SCENES)
def test_scene_fmu_exposes_exactly_its_variables(fmus, scene):
    md = read_model_description(str(fmus[scene]))
    by = {}
    for v in md.modelVariables:
        by.setdefault(v.causality, set()).add(v.name)
    inputs, outputs = EXPECTED[scene]
    assert by["input"] == inputs
    assert by["output"] == outputs
    params = by["parameter"]
    assert {"method", "invalid_input", "E", "nu", "R_wheel", "R_wheel_profile",
            "R_rail_profile"} <= params
    # what the FMU cannot use is not exposed: traction fields, the exact solver's switches
    assert not {"fields", "half", "predictor"} & params
    eff = cc.load_scene(scene).effects
    assert ("mu" in params) == (eff.saturation and not eff.variable_friction)
    # grid sizes and tolerances: every numeric option of every registered method
    for m, cls in cc.METHODS.items():
        for opt, default in cls.default_options.items():
            if type(default) in (int, float):
                assert opt in params or f"{m}_{opt}" in params, (m, opt)
    units = {v.name: v.unit for v in md.modelVariables}
    for name, unit in UNITS.items():
        if name in units:
            assert units[name] == unit, name
    start = {v.name: v.start for v in md.modelVariables}
    assert start["method"] == cc.load_scene(scene).default_method
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    assert not md.coSimulation.needsExecutionTool


@pytest.mark.parametrize("scene", SCENES)
def test_start_values_are_finite(fmus, scene):
    """OMSimulator refuses infinite values: a straight profile is R = 0 (WheelRailConfig)."""
    md = read_model_description(str(fmus[scene]))
    for v in md.modelVariables:
        if v.type == "Real" and v.start is not None:
            assert math.isfinite(float(v.start)), v.name
    assert {v.name: float(v.start) for v in md.modelVariables
            if v.name == "R_wheel_profile"} == {"R_wheel_profile": 0.0}


def test_start_values_are_the_instance_values(fmus):
    """A host that applies the XML's start values sets what the instance starts with, to the
    last bit (1/6, the exact solver's spin_shift, included)."""
    md = read_model_description(str(fmus["full"]))
    starts = {v.name: float(v.start) for v in md.modelVariables
              if v.type == "Real" and v.start is not None}
    assert "spin_shift" in starts
    with FmuInstance(fmus["full"], initialize=False) as inst:
        inst.fmu.setupExperiment(startTime=0.0)
        inst.fmu.enterInitializationMode()
        assert {name: inst.get(name)[0] for name in starts} == starts


def test_build_is_reproducible(fmus, tmp_path):
    again = build("full", out=tmp_path)
    assert again.read_bytes() == fmus["full"].read_bytes()


@pytest.mark.slow
def test_default_name_carries_scene_and_method(tmp_path):
    a = build("traction", "linear", tmp_path)
    b = build("traction", "fastsim", tmp_path)
    c = build("traction", "linear", tmp_path, name="Mine")
    assert [a.name, b.name, c.name] == ["WheelRailContact_traction_linear.fmu",
                                        "WheelRailContact_traction_fastsim.fmu", "Mine.fmu"]
    starts = [{v.name: v.start for v in read_model_description(str(p)).modelVariables}["method"]
              for p in (a, b, c)]
    assert starts == ["linear", "fastsim", "linear"]


def test_default_build_carries_this_projects_wrapper(fmus):
    import pythonfmu
    generic = (Path(pythonfmu.__file__).parent
               / "resources/binaries/linux64/libpythonfmu-export.so").read_bytes()
    with zipfile.ZipFile(fmus["traction"]) as z:
        assert z.read("binaries/linux64/WheelRailContact.so") != generic


def test_archive_holds_runtime_code_only(fmus):
    with zipfile.ZipFile(fmus["full"]) as z:
        names = z.namelist()
        code = {n: z.read(n).decode() for n in names if n.endswith(".py")}
    bundle = {n.split("/")[1] for n in names if n.startswith("resources/_wheel_rail_contact_")}
    assert len(bundle) == 1
    fmu_modules = {Path(n).name for n in names if "/wheel_rail_fmu/" in n}
    assert fmu_modules == {"__init__.py", "model_description.py", "runtime.py", "slave.py",
                           "state.py"}
    assert not [n for n in names if "/bench/" in n]
    assert not [n for n, text in code.items() if re.search(r"^\s*(import|from) fmpy", text, re.M)]
    # nothing is importable by a shared name: the only top-level module is the digest-named one
    top = {n.split("/")[1] for n in names if n.startswith("resources/") and n.count("/") == 1}
    (entry,) = [n for n in top if n.endswith(".py")]
    assert entry == f"{next(iter(bundle))[1:]}.py"


# ---------------------------------------------------------------------------------------------
# Command line: names, checks of --set, contradictions, the README's commands
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_cli_builds_scene_with_method(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--scene", "traction",
                          "--method", "linear", "--out", str(tmp_path)],
                         capture_output=True, text=True, check=True).stdout.strip()
    path = Path(out)
    assert path == tmp_path / "WheelRailContact_traction_linear.fmu" and path.is_file()
    assert {v.name: v.start for v in read_model_description(str(path)).modelVariables}[
        "method"] == "linear"


BAD_CLI = [
    (["--set", "E=-1"], "E=-1.0 is out of range: allowed 0 < E < inf"),
    (["--set", "nu=0.5"], "nu=0.5 is out of range: allowed 0 <= nu < 0.5"),
    (["--set", "nx=abc"], "nx='abc' is invalid: allowed an integer"),
    (["--set", "nx=2.5"], "nx='2.5' is invalid: allowed an integer"),
    (["--set", "mx=2"], "mx=2 is invalid: allowed an integer 4 <= mx <= 400"),  # exact's
    (["--set", "tol=abc"], "tol='abc' is invalid: allowed a finite number"),
    (["--set", "variant=nope"], "variant='nope' is invalid: allowed"),
    (["--set", "invalid_input=ignore"], "invalid_input='ignore' is invalid: allowed 'discard' or 'error'"),
    (["--set", "mu=0.25"], "mu is an input (effect 'variable_friction')"),
    (["--scene", "tangent_track", "--set", "mu=0.25"], "mu is not used"),
    (["--scene", "traction", "--set", "mu=-0.1"], "mu=-0.1 is out of range"),
    (["--set", "method=exact", "--method", "fastsim"], "method given twice"),
    (["--set", "R_wheel_profile=-0.2"], "allowed 0 < B"),
    (["--set", "nope=1"], "unknown parameter(s) ['nope']"),
    (["--set", "E"], "expected NAME=VALUE"),
    (["--set", "E=1e11", "--set", "E=2e11"], "--set E is given twice"),
    (["--method", "nope"], "method='nope' is unknown"),
]


@pytest.mark.parametrize("args, message", BAD_CLI)
def test_cli_checks_every_option_before_building(tmp_path, capsys, args, message):
    with pytest.raises(SystemExit) as e:
        main([*args, "--out", str(tmp_path)])
    assert e.value.code == 2
    assert message in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


@pytest.mark.slow
def test_readme_build_commands_run_as_written(tmp_path):
    text = (ROOT / "README.md").read_text()
    block = text.split("### Build it for a scene", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    venv_bin = str(Path(sys.executable).parent) + "/"
    script = block.replace(".venv/bin/", venv_bin)
    assert script != block
    subprocess.run(["bash", "-e", "-c", script], cwd=tmp_path, check=True, capture_output=True)
    made = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*.fmu"))
    assert made == ["dist/WheelRailContact_full_table.fmu",
                    "dist/WheelRailContact_traction_exact.fmu",
                    "dist/WheelRailContact_wet_curve_fastsim.fmu", "fmus/TractionWet.fmu"]
    start = {v.name: v.start for v in
             read_model_description(str(tmp_path / "fmus/TractionWet.fmu")).modelVariables}
    assert (float(start["mu"]), float(start["E"])) == (0.25, 2.05e11)
