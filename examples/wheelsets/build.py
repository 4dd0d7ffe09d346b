"""Build the reference wheelset FMUs (pythonfmu) and, optionally, contact FMUs.

    python -m wheelsets.build [--out DIR] [--contact SCENE:METHOD ...] [--profiles]
                                                                           (from examples/)

Writes ``TangentTrackWheelset.fmu``, ``CurvingWheelset.fmu`` and ``DrivenWheelsetFMU.fmu`` (default
DIR: dist/wheelsets). With ``--contact`` it also builds contact FMUs with ``wheel_rail_fmu.build``
(one per ``SCENE:METHOD``, named ``WheelRailContact_<scene>_<method>.fmu``), so a run has
everything in one folder. Each wheelset FMU's slave module is ``fmu_entries/<name>.py``, which
imports its class from this package; the FMU bundles the package's modules the models need
(:data:`FMU_MODULES`: the equations and the FMI plumbing), as the package ``wheelsets``. The
FMUs are built by pythonfmu and then given the contact FMU's FMI wrapper
(``wheel_rail_fmu.build.use_native_wrapper``): pythonfmu 0.7's binary releases a reference to the
slave module's namespace at every fmi2Instantiate and fails after a few instances per process.

With ``--profiles`` it also builds the real-profile wheelsets (:func:`build_profile_wheelsets`:
``TangentTrackProfileWheelset.fmu``, ``CurvingProfileWheelset.fmu``), which run on the
contact-geometry table of new S1002 wheels on new UIC60 rails 1:40 and four contact patches. Each
bundles, as one package named after the digest of its contents (``profile_entry.py``), the
modules of this package it needs (:data:`PROFILE_FMU_MODULES`), a copy of ``contact_core``
without the exact theory's table (:data:`CORE_EXCLUDED`; the wheelset evaluates geometry and
kinematics, never a contact) and the table as data (``ContactTable.save``, read with
``allow_pickle=False``) with its description (JSON).
"""
from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
#: The modules of this package an FMU needs at run time.
FMU_MODULES = ("__init__.py", "wheelset_dynamics.py", "wheelset_fmu_common.py",
               "tangent_track.py", "curving.py", "driven_wheel.py", "slip_control.py")
#: FMU name (its class, and the stem of its slave module in fmu_entries/).
FMU_NAMES = ("TangentTrackWheelset", "CurvingWheelset", "DrivenWheelsetFMU")
#: The modules of this package the real-profile wheelset FMUs need at run time.
PROFILE_FMU_MODULES = ("__init__.py", "wheelset_dynamics.py", "wheelset_fmu_common.py",
                       "profile_runtime.py", "profile_dynamics.py", "profile_fmus.py")
#: The real-profile wheelset FMUs (their classes in profile_fmus.py).
PROFILE_FMU_NAMES = ("TangentTrackProfileWheelset", "CurvingProfileWheelset")
#: Files of contact_core the real-profile wheelset FMUs leave out (the exact theory's table).
CORE_EXCLUDED = ("exact_table.npz", "exact_table.json")
#: Lateral range and step of the real-profile wheelsets' contact-geometry table, m.
PROFILE_TABLE_Y_MAX, PROFILE_TABLE_STEP = 0.012, 2e-5


def build_wheelsets(out: Path) -> dict[str, Path]:
    """Build the three wheelset FMUs into ``out``; name -> path."""
    from pythonfmu import FmuBuilder

    from wheel_rail_fmu.build import use_native_wrapper
    out.mkdir(parents=True, exist_ok=True)
    paths = {}
    with tempfile.TemporaryDirectory(prefix="wheelsets_") as tmp:
        package = Path(tmp) / "wheelsets"
        package.mkdir()
        for name in FMU_MODULES:
            shutil.copyfile(HERE / name, package / name)
        for name in FMU_NAMES:
            path = FmuBuilder.build_FMU(HERE / "fmu_entries" / f"{name}.py", dest=out,
                                        project_files=[package])
            use_native_wrapper(path)
            paths[name] = Path(path)
    return paths


def _stage_profile_bundle(parent: Path, model) -> Path:
    """The bundle package of the real-profile wheelset FMUs in ``parent`` (module docstring),
    named after its digest; ``model``: the ``contact_core.geometry.WheelsetOnTrack``."""
    import contact_core
    from contact_core.geometry import contact_table

    from wheel_rail_fmu.entry import bundle_digest

    from .profile_runtime import TABLE_FILE, TABLE_INFO
    stage = parent / "bundle"
    (stage / "wheelsets").mkdir(parents=True)
    (stage / "__init__.py").write_text('"""A real-profile wheelset FMU\'s code and data '
                                       '(wheelsets.build)."""\n', encoding="utf-8")
    for name in PROFILE_FMU_MODULES:
        shutil.copyfile(HERE / name, stage / "wheelsets" / name)
    shutil.copytree(Path(contact_core.__file__).parent, stage / "contact_core",
                    ignore=shutil.ignore_patterns("__pycache__", *CORE_EXCLUDED))
    table = contact_table(model, PROFILE_TABLE_Y_MAX, PROFILE_TABLE_STEP)
    table.save(stage / TABLE_FILE)
    track, ws = model.track, model.wheelset
    info = {"nominal_radius": ws.nominal_radius, "wheel": ws.wheel.name, "rail": track.rail.name,
            "gauge": track.gauge, "gauge_height": track.gauge_height,
            "inclination": track.inclination,
            "flange_back_distance": ws.flange_back_distance,
            "flange_back_position": ws.flange_back_position,
            "table": {"y_max": PROFILE_TABLE_Y_MAX, "step": PROFILE_TABLE_STEP,
                      "load": table.load, "E": table.E, "nu": table.nu}}
    (stage / TABLE_INFO).write_text(json.dumps(info, indent=1, sort_keys=True) + "\n",
                                    encoding="utf-8")
    bundle = parent / f"_wheelset_profiles_{bundle_digest(stage)}"
    stage.rename(bundle)
    return bundle


def build_profile_wheelsets(out: Path, model=None) -> dict[str, Path]:
    """Build the real-profile wheelset FMUs into ``out`` (name -> path), for ``model`` (a
    ``contact_core.geometry.WheelsetOnTrack``; default the benchmark's S1002 wheels on UIC60
    rails 1:40, ``benchmark_model``)."""
    from pythonfmu import FmuBuilder

    from contact_core.geometry import benchmark_model

    from wheel_rail_fmu.build import use_native_wrapper
    out.mkdir(parents=True, exist_ok=True)
    paths = {}
    with tempfile.TemporaryDirectory(prefix="profile_wheelsets_") as tmp:
        bundle = _stage_profile_bundle(Path(tmp), model or benchmark_model())
        digest = bundle.name.rpartition("_")[2]
        try:
            for name in PROFILE_FMU_NAMES:
                script = Path(tmp) / f"{name}_{digest}.py"
                shutil.copyfile(HERE / "profile_entry.py", script)
                path = FmuBuilder.build_FMU(script, dest=out, project_files=[bundle])
                use_native_wrapper(path)
                paths[name] = Path(path)
        finally:
            # pythonfmu imported the bundle from this temporary folder: forget it, so that an
            # FMU loaded later in this process imports its own copy
            for key in [k for k in sys.modules if k.startswith(bundle.name)
                        or k.endswith(f"_{digest}")]:
                del sys.modules[key]
            sys.path[:] = [p for p in sys.path if p != tmp]
    return paths


def contact_fmu_name(scene: str, method: str) -> str:
    return f"WheelRailContact_{scene}_{method}"


def build_contact(scene: str, method: str, out: Path) -> Path:
    """Build a contact FMU (:func:`wheel_rail_fmu.build.build`)."""
    from wheel_rail_fmu.build import build
    return build(scene, method, out, name=contact_fmu_name(scene, method))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "dist" / "wheelsets"))
    ap.add_argument("--contact", action="append", default=[], metavar="SCENE:METHOD")
    ap.add_argument("--profiles", action="store_true",
                    help="also build the real-profile wheelsets (S1002 on UIC60 1:40)")
    a = ap.parse_args(argv)
    out = Path(a.out)
    for name, path in build_wheelsets(out).items():
        print(path)
    if a.profiles:
        for path in build_profile_wheelsets(out).values():
            print(path)
    for item in a.contact:
        scene, _, method = item.partition(":")
        print(build_contact(scene, method, out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
