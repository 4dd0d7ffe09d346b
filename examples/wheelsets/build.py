"""Build the reference wheelset FMUs (pythonfmu) and, optionally, contact FMUs.

    python -m wheelsets.build [--out DIR] [--contact SCENE:METHOD ...]     (from examples/)

Writes ``TangentTrackWheelset.fmu``, ``CurvingWheelset.fmu`` and ``DrivenWheelsetFMU.fmu`` (default
DIR: dist/wheelsets). With ``--contact`` it also builds contact FMUs with ``wheel_rail_fmu.build``
(one per ``SCENE:METHOD``, named ``WheelRailContact_<scene>_<method>.fmu``), so a run has
everything in one folder. Each wheelset FMU's slave module is ``fmu_entries/<name>.py``, which
imports its class from this package; the FMU bundles the package's modules the models need
(:data:`FMU_MODULES`: the equations and the FMI plumbing), as the package ``wheelsets``. The
FMUs are built by pythonfmu and then given the contact FMU's FMI wrapper
(``wheel_rail_fmu.build.use_native_wrapper``): pythonfmu 0.7's binary releases a reference to the
slave module's namespace at every fmi2Instantiate and fails after a few instances per process.
"""
from __future__ import annotations

import argparse
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
    a = ap.parse_args(argv)
    out = Path(a.out)
    for name, path in build_wheelsets(out).items():
        print(path)
    for item in a.contact:
        scene, _, method = item.partition(":")
        print(build_contact(scene, method, out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
