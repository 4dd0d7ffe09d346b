"""Build the reference wheelset FMUs (pythonfmu) into ``dist/wheelsets/``.

    python examples/wheelsets/build.py [--out DIR] [--contact SCENE:METHOD ...]

Writes ``TangentTrackWheelset.fmu``, ``CurvingWheelset.fmu`` and ``DrivenWheelsetFMU.fmu``. With
``--contact`` it also builds contact FMUs with ``wheel_rail_fmu.build`` (one per
``SCENE:METHOD``, named ``WheelRailContact_<scene>_<method>.fmu``), so a run has everything in one
folder. Each wheelset FMU bundles its script, ``wheelset_dynamics.py`` (the equations) and
``wheelset_fmu_common.py`` (FMI plumbing). Run it in its own process (as ``make`` and the tests do):
pythonfmu imports the scripts by module name while building.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
COMMON = [HERE / "wheelset_dynamics.py", HERE / "wheelset_fmu_common.py"]

#: script -> extra project files
MODELS = {
    "tangent_track.py": [],
    "curving.py": [HERE / "tangent_track.py"],
    "driven_wheel.py": [],
}
FMU_NAMES = {"tangent_track.py": "TangentTrackWheelset", "curving.py": "CurvingWheelset",
             "driven_wheel.py": "DrivenWheelsetFMU"}


def build_wheelsets(out: Path) -> dict[str, Path]:
    from pythonfmu import FmuBuilder
    out.mkdir(parents=True, exist_ok=True)
    paths = {}
    for script, extra in MODELS.items():
        path = FmuBuilder.build_FMU(HERE / script, dest=out, project_files=COMMON + extra)
        paths[FMU_NAMES[script]] = Path(path)
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
