"""Build the WheelRailContact FMU (FMI 2.0 co-simulation, pythonfmu) for a scene.

    python build_fmu.py [--scene SCENE] [--method METHOD] [--out DIR] [--set NAME=VALUE ...]

``--scene``: a shipped scene (``contact_core.scenes()``: traction, tangent_track, curving, full) or
the path of a scene ``.toml``; default ``full``. ``--method``: the default of the FMU's ``method``
parameter (default: the scene's). ``--set``: start value of a parameter (e.g. ``--set mu=0.25``).
``--out``: output folder (default ``dist``). The FMU is ``DIR/WheelRailContact.fmu`` for the
``full`` scene and ``DIR/WheelRailContact_<scene>.fmu`` otherwise (``--name`` overrides).

What goes in (``resources/``): the slave ``wheel_rail_contact.py``, the ``wheel_rail_fmu`` helper
package, a copy of ``contact_core`` (sources, data, scenes), ``requirements.txt`` (what the host's
Python needs: numpy, scipy, numba), and ``wheel_rail_contact.json``: the scene's effects, the
default method, parameter start values and the GUID. The slave reads that file when instantiated,
so the variables it declares (and pythonfmu writes to modelDescription.xml) are the scene's.

Reproducible: the GUID is a hash of everything bundled and of the scene/method/parameters; the
archive is rewritten with sorted entries, fixed timestamps and permissions; modelDescription.xml has
no generation date unless SOURCE_DATE_EPOCH is set. The same sources give the same bytes.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import shutil
import sys
import tempfile
import uuid
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent
FMU_SRC = ROOT / "fmu_src"
SLAVE_SCRIPT = FMU_SRC / "wheel_rail_contact.py"
MODEL_NAME = "WheelRailContact"
#: Runtime dependencies of contact_core inside the FMU (others in pyproject are for tools).
RUNTIME_DEPENDENCIES = ("numpy", "scipy", "numba")
_SKIP_DIRS = {"__pycache__", ".numba_cache"}
_SKIP_SUFFIXES = {".pyc", ".pyo", ".nbi", ".nbc"}

if str(FMU_SRC) not in sys.path:
    sys.path.insert(0, str(FMU_SRC))


def _copy_tree(src: Path, dst: Path) -> None:
    """Copy source files (no caches), in sorted order."""
    for f in sorted(src.rglob("*")):
        rel = f.relative_to(src)
        if f.is_dir() or any(p in _SKIP_DIRS for p in rel.parts) or f.suffix in _SKIP_SUFFIXES:
            continue
        (dst / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(f, dst / rel)


def requirements_text() -> str:
    """requirements.txt for the FMU's host Python: contact_core's runtime dependencies."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    keep = [d for d in deps
            if d.split(">")[0].split("=")[0].split("<")[0].strip().lower() in RUNTIME_DEPENDENCIES]
    return ("# Python packages the WheelRailContact FMU needs in the host's Python environment\n"
            "# (pythonfmu itself and contact_core are bundled in resources/).\n"
            + "\n".join(keep) + "\n")


def _digest(stage: Path, extra: dict) -> str:
    h = hashlib.sha256(json.dumps(extra, sort_keys=True).encode())
    h.update(SLAVE_SCRIPT.read_bytes())
    for f in sorted(p for p in stage.rglob("*") if p.is_file()):
        h.update(str(f.relative_to(stage).as_posix()).encode() + b"\0" + f.read_bytes())
    import pythonfmu
    h.update(f"pythonfmu {pythonfmu.__version__}".encode())
    h.update((Path(pythonfmu.__file__).parent / "resources/binaries/linux64/"
              "libpythonfmu-export.so").read_bytes())
    return h.hexdigest()


def _rezip(src: Path, dst: Path) -> None:
    """Rewrite the archive deterministically: sorted entries, fixed date and permissions."""
    with zipfile.ZipFile(src) as zin:
        entries = {i.filename.replace("\\", "/"): zin.read(i) for i in zin.infolist()
                   if not i.is_dir()}
    order = sorted(entries, key=lambda n: (n != "modelDescription.xml", n))
    tmp = dst.with_suffix(".fmu.part")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as zout:
        for name in order:
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.create_system = 3
            info.external_attr = (0o755 if name.endswith((".so", ".dll")) else 0o644) << 16
            zout.writestr(info, entries[name])
    tmp.replace(dst)


def _parse_value(text: str):
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


def build(scene: str | Path = "full", method: str | None = None, out: str | Path = "dist",
          parameters: dict | None = None, name: str | None = None) -> Path:
    """Build the FMU for ``scene`` and return its path (see the module docstring)."""
    import contact_core
    from pythonfmu import FmuBuilder

    from wheel_rail_fmu.model_description import BUILD_CONFIG, BuildConfig, variables_for
    from wheel_rail_fmu.validation import validate

    sc = contact_core.load_scene(scene)
    method = method or sc.default_method
    if method not in contact_core.METHODS:
        raise ValueError(f"method={method!r} is unknown: allowed {list(contact_core.METHODS)}")
    parameters = dict(parameters or {})
    # Fail early on an unknown parameter name (the slave would fail the same way).
    variables_for(sc.effects.names(), method, contact_core.METHODS, parameters)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    dest = out / f"{name or (MODEL_NAME if sc.name == 'full' else f'{MODEL_NAME}_{sc.name}')}.fmu"

    with tempfile.TemporaryDirectory(prefix="wheel_rail_fmu_") as tmp:
        stage = Path(tmp) / "stage"
        _copy_tree(Path(contact_core.__file__).parent, stage / "contact_core")
        _copy_tree(FMU_SRC / "wheel_rail_fmu", stage / "wheel_rail_fmu")
        (stage / "requirements.txt").write_text(requirements_text())
        extra = {"scene": sc.name, "effects": sc.effects.names(), "method": method,
                 "parameters": parameters, "description": sc.description}
        guid = str(uuid.uuid5(uuid.NAMESPACE_URL, "urn:contact_core:WheelRailContact:"
                              + _digest(stage, extra)))
        cfg = BuildConfig(sc.name, sc.description, sc.effects.names(), method, guid, parameters)
        (stage / BUILD_CONFIG).write_text(cfg.to_json())

        raw = FmuBuilder.build_FMU(
            SLAVE_SCRIPT, dest=Path(tmp) / f"{MODEL_NAME}.fmu",
            project_files=[stage / "contact_core", stage / "wheel_rail_fmu",
                           stage / "requirements.txt", stage / BUILD_CONFIG],
            canGetAndSetFMUstate=True, canSerializeFMUstate=True)
        _rezip(Path(raw), dest)

    problems = validate(dest)
    if problems:
        raise RuntimeError(f"{dest} does not validate:\n  " + "\n  ".join(problems))
    return dest


def main(argv: list[str] | None = None) -> int:
    import contact_core
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default="full",
                   help=f"scene name {list(contact_core.scenes())} or path of a .toml file "
                        "(default: full)")
    p.add_argument("--method", default=None,
                   help=f"default method {list(contact_core.METHODS)} (default: the scene's)")
    p.add_argument("--out", default=str(ROOT / "dist"), help="output folder (default: dist)")
    p.add_argument("--name", default=None, help="file name of the FMU without .fmu")
    p.add_argument("--set", dest="params", action="append", default=[], metavar="NAME=VALUE",
                   help="start value of a parameter (repeatable)")
    a = p.parse_args(argv)
    params = {}
    for item in a.params:
        k, sep, v = item.partition("=")
        if not sep:
            p.error(f"--set {item!r}: expected NAME=VALUE")
        params[k.strip()] = _parse_value(v.strip())
    try:
        path = build(a.scene, a.method, a.out, params, a.name)
    except ValueError as e:
        p.error(str(e))
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
