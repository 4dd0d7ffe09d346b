"""Build the WheelRailContact FMU (FMI 2.0 co-simulation) for a scene.

    build-fmu [--scene SCENE] [--method METHOD] [--out DIR] [--name NAME] [--set NAME=VALUE ...]
              [--wrapper {auto,native,pythonfmu}] [--geometry-input {curvatures,semi_axes}]
              [--contacts N]

(``python build_fmu.py ...`` in a checkout does the same.) ``--scene``: a shipped scene
(``contact_core.scenes()``) or the path of a scene ``.toml``; default ``full``. ``--method``: the
default of the FMU's ``method`` parameter (default: the scene's). ``--set``: start value of a
parameter, checked now with the checks the FMU makes at initialisation (``--set E=2.05e11``).
``--out``: output folder (default ``dist``). The FMU is ``DIR/WheelRailContact_<scene>_<method>.fmu``
unless ``--name`` is given. ``--geometry-input``, for a scene with ``varying_geometry``: the
geometry inputs are the curvatures A, B (``curvatures``, the default: the FMU solves Hertz's patch)
or the host's semi-axes a, b (``semi_axes``: a and b are then inputs, not outputs; the file name
ends in ``_semi_axes``). ``--contacts N``: one FMU of N independent contacts, evaluated together
at every step, each with its own inputs and outputs named ``c[k].<name>`` (k = 1 .. N) and the
parameters shared (:func:`.model_description.contact_variable`; the file name ends in
``_<N>contacts``).

The model description says ``providesDirectionalDerivative="true"`` when the Linux binary is
this project's wrapper (``fmi2GetDirectionalDerivative`` calls the slave); pythonfmu's binaries
have no directional derivatives (its Windows binary, which the archive carries as it is, answers
``fmi2Error``).

What goes in:

* ``binaries/linux64/WheelRailContact.so``: this project's FMI wrapper
  (``native/fmi2_python.c``) compiled with the system C compiler against this Python's shared
  libpython (``--wrapper native``). Without a compiler, Python headers or a shared libpython,
  pythonfmu's generic binary instead (``--wrapper pythonfmu``; ``auto``, the default, warns when it
  falls back). pythonfmu's Windows binary is added as it is.
* ``resources/_wheel_rail_contact_<digest>/``: the code the FMU runs, as one package named after
  the digest of its contents: ``contact_core`` whole (the runtime: its modules and data), the
  runtime modules of ``wheel_rail_fmu`` (``RUNTIME_MODULES``) and pythonfmu's Python side;
  ``resources/wheel_rail_contact_<digest>.py`` (:mod:`.entry`), the slave module that loads it
  (``resources/slavemodule.txt``).
* ``resources/wheel_rail_contact.json``: scene, effects, default method, parameter start values,
  GUID; ``resources/requirements.txt``: what the host's Python needs (numpy, scipy, numba).

Reproducible: the GUID is a hash of everything bundled and of the scene/method/parameters; the
archive has sorted entries, fixed timestamps and permissions; modelDescription.xml has no
generation date unless SOURCE_DATE_EPOCH is set. The same sources give the same bytes.
"""
from __future__ import annotations

import argparse
import hashlib
import importlib.metadata
import json
import math
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import uuid
import warnings
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import contact_core

from . import entry
from .model_description import (BUILD_CONFIG, BuildConfig, VarSpec, check_contacts,
                                variables_for)

GEOMETRY_INPUTS = contact_core.variables.GEOMETRY_INPUTS

MODEL_NAME = "WheelRailContact"
HERE = Path(__file__).resolve().parent
WRAPPER_SOURCE = HERE / "native" / "fmi2_python.c"
#: Modules of this package the FMU runs: the slave and what it imports at run time (the rest is
#: host-side: build, validation, host, native/; entry is copied in as the slave module).
RUNTIME_MODULES = ("__init__.py", "model_description.py", "runtime.py", "slave.py", "state.py")
#: Compiled caches (Python's bytecode, numba's index and data): never bundled, the FMU makes its
#: own.
_CACHE_SUFFIXES = {".pyc", ".pyo", ".nbi", ".nbc"}
WRAPPERS = ("auto", "native", "pythonfmu")


class WrapperUnavailable(RuntimeError):
    """This project's FMI wrapper cannot be compiled here; the message says why."""


# ----------------------------------------------------------------------------------------------
# Parameters
# ----------------------------------------------------------------------------------------------

def _coerce(spec: VarSpec, value) -> object:
    """A start value of ``spec``'s type from a Python value or command-line text."""
    text = value if isinstance(value, str) else None
    try:
        if spec.type == "Real":
            if isinstance(value, bool):
                raise ValueError
            v = float(value)
            if not math.isfinite(v):
                raise ValueError
            return v
        if spec.type == "Integer":
            if isinstance(value, bool) or (isinstance(value, float) and not value.is_integer()):
                raise ValueError
            return int(value)
        if spec.type == "Boolean":
            if isinstance(value, bool):
                return value
            if text is not None and text.lower() in ("true", "false", "1", "0"):
                return text.lower() in ("true", "1")
            raise ValueError
        return str(value)
    except (TypeError, ValueError):
        allowed = {"Real": "a finite number", "Integer": "an integer",
                   "Boolean": "true or false"}[spec.type]
        raise ValueError(f"{spec.name}={value!r} is invalid: allowed {allowed} ({spec.type} "
                         f"parameter: {spec.description})") from None


def resolve_parameters(scene: contact_core.Scene, method: str | None,
                       parameters: dict | None) -> tuple[str, dict]:
    """The default method and the typed start values of a build, checked as the FMU checks
    them at initialisation; ``ValueError`` names the offending option or parameter."""
    parameters = dict(parameters or {})
    if "method" in parameters:
        if method is not None and parameters["method"] != method:
            raise ValueError(f"method given twice, as {method!r} and as --set method="
                             f"{parameters['method']!r}: give it once")
        method = parameters.pop("method")
    method = method or scene.default_method
    if method not in contact_core.METHODS:
        raise ValueError(f"method={method!r} is unknown: allowed {list(contact_core.METHODS)}")
    eff = scene.effects
    specs = {v.name: v for v in variables_for(eff.names(), method, contact_core.METHODS)}
    allowed = sorted(n for n, v in specs.items() if v.causality == "parameter")
    if "mu" in parameters and "mu" not in allowed:
        why = ("an input (effect 'variable_friction'): the host sets it at every step"
               if eff.variable_friction else "not used (the scene has no 'saturation' effect)")
        raise ValueError(f"mu is {why} in scene {scene.name!r}; a scene with 'saturation' and "
                         "without 'variable_friction' (e.g. traction) has mu as a parameter")
    unknown = sorted(set(parameters) - set(allowed))
    if unknown:
        raise ValueError(f"unknown parameter(s) {unknown} in scene {scene.name!r}: allowed "
                         f"{allowed}")
    typed = {name: _coerce(specs[name], value) for name, value in parameters.items()}
    # Options of every method, not only the default one: the host may choose another.
    start = {n: typed.get(n, v.start) for n, v in specs.items() if v.causality == "parameter"}
    for mname, cls in contact_core.METHODS.items():
        options = {opt: start[v.name] for v in specs.values() if v.option is not None
                   for owner, opt in [v.option] if owner in (mname, "*")
                   and opt in cls.default_options}
        contact_core.make_solver(mname, eff, **options)
    return method, typed


# ----------------------------------------------------------------------------------------------
# The FMI wrapper
# ----------------------------------------------------------------------------------------------

def compile_wrapper(dest: Path) -> None:
    """Compile :data:`WRAPPER_SOURCE` into the shared library ``dest`` for this Python."""
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        raise WrapperUnavailable("no C compiler (cc or gcc) on PATH")
    if not sys.platform.startswith("linux"):
        raise WrapperUnavailable(f"the wrapper is built on Linux only (this is {sys.platform})")
    libdir = Path(sysconfig.get_config_var("LIBDIR") or "")
    libpython = libdir / (sysconfig.get_config_var("INSTSONAME") or "")
    if not sysconfig.get_config_var("Py_ENABLE_SHARED") or not libpython.is_file():
        raise WrapperUnavailable(f"this Python has no shared libpython ({libpython})")
    include = Path(sysconfig.get_paths()["include"])
    if not (include / "Python.h").is_file():
        raise WrapperUnavailable(f"no Python headers in {include}")
    try:
        import fmpy
    except ImportError:
        raise WrapperUnavailable("the FMI 2.0 headers come with fmpy, which is not installed "
                                 "(pip install 'contact-core[host]')") from None
    headers = Path(fmpy.__file__).parent / "c-code"
    python = sys.executable.replace("\\", "\\\\").replace('"', '\\"')
    cmd = [cc, "-shared", "-fPIC", "-O2", "-std=gnu11", "-fvisibility=hidden", "-Wall",
           f"-I{headers}", f"-I{include}", f'-DWRC_PYTHON_EXECUTABLE="{python}"', "-o", str(dest),
           str(WRAPPER_SOURCE), str(libpython), f"-Wl,-rpath,{libdir}", "-Wl,--no-undefined",
           "-ldl", "-lpthread"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise WrapperUnavailable(f"{' '.join(cmd)} failed:\n{done.stderr}")


def use_native_wrapper(fmu: str | Path) -> bool:
    """Replace the Linux binary of a pythonfmu-built FMU with this project's wrapper, which runs
    the same slave (pythonfmu's Python interface and packaging) without pythonfmu 0.7's defects
    (see the module docstring of ``native/fmi2_python.c``). Returns False, leaving the FMU as it
    is, where the wrapper cannot be compiled."""
    fmu = Path(fmu)
    with zipfile.ZipFile(fmu) as z:
        files = {i.filename: z.read(i) for i in z.infolist() if not i.is_dir()}
    names = [n for n in files if n.startswith("binaries/linux64/") and n.endswith(".so")]
    if len(names) != 1:
        raise ValueError(f"{fmu} has {len(names)} Linux binaries: expected one")
    with tempfile.TemporaryDirectory() as tmp:
        so = Path(tmp) / "wrapper.so"
        try:
            compile_wrapper(so)
        except WrapperUnavailable as e:
            warnings.warn(f"{fmu.name} keeps pythonfmu's binary: {e}", RuntimeWarning,
                          stacklevel=2)
            return False
        files[names[0]] = so.read_bytes()
    _write_archive(files, fmu)
    return True


def _binaries(stage: Path, wrapper: str) -> tuple[dict[str, bytes], bool]:
    """Archive name -> bytes of the binaries (see the module docstring), and whether the Linux
    binary is this project's wrapper (else pythonfmu's generic one)."""
    import pythonfmu
    generic = Path(pythonfmu.__file__).parent / "resources" / "binaries"
    out = {f"binaries/{f.parent.name}/{MODEL_NAME}{f.suffix}": f.read_bytes()
           for f in sorted(generic.glob("*/*")) if f.suffix in (".so", ".dll", ".dylib")}
    if wrapper != "pythonfmu":
        so = stage / f"{MODEL_NAME}.so"
        try:
            compile_wrapper(so)
            out[f"binaries/linux64/{MODEL_NAME}.so"] = so.read_bytes()
            return out, True
        except WrapperUnavailable as e:
            if wrapper == "native":
                raise
            warnings.warn(f"using pythonfmu's generic binary: {e}", RuntimeWarning, stacklevel=3)
    return out, False


# ----------------------------------------------------------------------------------------------
# The archive
# ----------------------------------------------------------------------------------------------

def _copy_tree(src: Path, dst: Path, only: tuple[str, ...] | None = None) -> None:
    """Copy the files of ``src`` (only those named in ``only``, if given), no compiled caches, in
    sorted order."""
    for f in sorted(src.rglob("*")):
        rel = f.relative_to(src)
        if (f.is_dir() or f.suffix in _CACHE_SUFFIXES
                or (only is not None and rel.as_posix() not in only)):
            continue
        (dst / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(f, dst / rel)


def requirements_text() -> str:
    """requirements.txt for the FMU's host Python: contact_core's own dependencies."""
    deps = [r for r in importlib.metadata.requires("contact-core") or () if "extra ==" not in r]
    return ("# Python packages the WheelRailContact FMU needs in the host's Python environment\n"
            "# (contact_core and pythonfmu's Python side are bundled in resources/).\n"
            + "\n".join(deps) + "\n")


def _stage_bundle(resources: Path, core: Path) -> str:
    """Write the bundle package (with the contact_core sources in ``core``) and the slave module
    into ``resources``; returns the module name (``wheel_rail_contact_<digest>``)."""
    import pythonfmu
    tmp = resources / "_bundle"
    tmp.mkdir(parents=True)
    (tmp / "__init__.py").write_text('"""The code a WheelRailContact FMU runs (see '
                                     'wheel_rail_fmu.entry)."""\n')
    _copy_tree(core, tmp / "contact_core")
    _copy_tree(HERE, tmp / "wheel_rail_fmu", only=RUNTIME_MODULES)
    _copy_tree(Path(pythonfmu.__file__).parent, tmp / "pythonfmu",
               only=tuple(p.name for p in Path(pythonfmu.__file__).parent.glob("*.py")))
    module = entry.PREFIX + entry.bundle_digest(tmp)
    tmp.rename(resources / f"_{module}")
    shutil.copyfile(Path(entry.__file__), resources / f"{module}.py")
    (resources / "slavemodule.txt").write_text(module)
    return module


def _write_archive(files: dict[str, bytes], dest: Path) -> None:
    """Deterministic zip: modelDescription.xml first, then sorted, fixed date and permissions."""
    order = sorted(files, key=lambda n: (n != "modelDescription.xml", n))
    tmp = dest.with_suffix(".fmu.part")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for name in order:
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.create_system = 3
            info.external_attr = (0o755 if name.endswith((".so", ".dll")) else 0o644) << 16
            z.writestr(info, files[name])
    tmp.replace(dest)


def build(scene: str | Path = "full", method: str | None = None, out: str | Path = "dist",
          parameters: dict | None = None, name: str | None = None,
          wrapper: str = "auto", core: str | Path | None = None,
          geometry_input: str = GEOMETRY_INPUTS[0], contacts: int = 1) -> Path:
    """Build the FMU for ``scene`` and return its path (see the module docstring).

    ``core``: the ``contact_core`` sources to bundle (default: the installed package; another
    version of it, e.g. to compare releases in one co-simulation). ``geometry_input``: with
    ``varying_geometry``, "curvatures" (inputs A, B) or "semi_axes" (inputs a, b).
    ``contacts``: the number of contacts (``c[k].<name>`` variables when more than one).
    """
    from .validation import validate

    if wrapper not in WRAPPERS:
        raise ValueError(f"wrapper={wrapper!r} is unknown: allowed {list(WRAPPERS)}")
    check_contacts(contacts)
    sc = contact_core.load_scene(scene)
    method, parameters = resolve_parameters(sc, method, parameters)
    contact_core.variables.geometry_names(geometry_input)     # a ValueError naming it
    varying = sc.effects.varying_geometry
    if geometry_input != GEOMETRY_INPUTS[0] and not varying:
        raise ValueError(f"geometry_input={geometry_input!r} needs a scene with the effect "
                         f"'varying_geometry' (scene {sc.name!r} has a fixed geometry)")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    suffix = ("_semi_axes" if geometry_input == "semi_axes" else "") \
        + (f"_{contacts}contacts" if contacts > 1 else "")
    dest = out / f"{name or f'{MODEL_NAME}_{sc.name}_{method}{suffix}'}.fmu"

    with tempfile.TemporaryDirectory(prefix="wheel_rail_fmu_") as tmp:
        stage = Path(tmp)
        resources = stage / "resources"
        module = _stage_bundle(resources, Path(core or Path(contact_core.__file__).parent))
        (resources / "requirements.txt").write_text(requirements_text())
        files, native = _binaries(stage, wrapper)
        identity = {"scene": sc.name, "effects": sc.effects.names(), "method": method,
                    "parameters": parameters, "description": sc.description, "module": module,
                    "entry": hashlib.sha256((resources / f"{module}.py").read_bytes()).hexdigest(),
                    "binaries": {k: hashlib.sha256(v).hexdigest() for k, v in files.items()}}
        if varying:
            identity["geometry_input"] = geometry_input
        if contacts > 1:
            identity["contacts"] = contacts
        guid = str(uuid.uuid5(uuid.NAMESPACE_URL, "urn:contact_core:WheelRailContact:"
                              + json.dumps(identity, sort_keys=True)))
        cfg = BuildConfig(sc.name, sc.description, sc.effects.names(), method, guid, parameters,
                          geometry_input, contacts)
        (resources / BUILD_CONFIG).write_text(cfg.to_json())

        # The model description comes from the slave as the host will load it, after the
        # checks of the host's initialisation.
        cls = entry.load_slave_class(resources, module)
        slave = cls(instance_name="build", resources=str(resources), fmi_error_status=True)
        slave.enter_initialization_mode()
        try:
            slave.exit_initialization_mode()
        except Exception as e:  # the slave's FmiStatusError: an invalid start value
            if getattr(e, "fmi_status", None) is None:
                raise
            raise ValueError(str(e)) from None
        xml = slave.to_xml()
        # the slave's get_directional_derivative is called by this project's wrapper only
        xml.find("CoSimulation").set("providesDirectionalDerivative",
                                     "true" if native else "false")
        ElementTree.indent(xml)
        files["modelDescription.xml"] = ElementTree.tostring(xml, encoding="UTF-8",
                                                             xml_declaration=True) + b"\n"
        for f in sorted(resources.rglob("*")):
            if f.is_file() and "__pycache__" not in f.parts:
                files[f.relative_to(stage).as_posix()] = f.read_bytes()
        _write_archive(files, dest)

    problems = validate(dest)
    if problems:
        raise RuntimeError(f"{dest} does not validate:\n  " + "\n  ".join(problems))
    return dest


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="build-fmu", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default="full",
                   help=f"scene name {list(contact_core.scenes())} or path of a .toml file "
                        "(default: full)")
    p.add_argument("--method", default=None,
                   help=f"default method {list(contact_core.METHODS)} (default: the scene's)")
    p.add_argument("--out", default="dist", help="output folder (default: dist)")
    p.add_argument("--name", default=None,
                   help="file name of the FMU without .fmu (default: WheelRailContact_<scene>_"
                        "<method>)")
    p.add_argument("--set", dest="params", action="append", default=[], metavar="NAME=VALUE",
                   help="start value of a parameter (repeatable)")
    p.add_argument("--wrapper", choices=WRAPPERS, default="auto",
                   help="FMI binary: this project's (native), pythonfmu's generic one, or native "
                        "where it can be compiled (auto, default)")
    p.add_argument("--geometry-input", choices=GEOMETRY_INPUTS, default=GEOMETRY_INPUTS[0],
                   help="with a scene of effect varying_geometry: inputs A, B (curvatures, "
                        "default) or the host's semi-axes a, b (semi_axes)")
    p.add_argument("--contacts", type=int, default=1, metavar="N",
                   help="the number of independent contacts of the FMU, variables c[k].<name> "
                        "for k = 1 .. N when N > 1 (default 1)")
    a = p.parse_args(argv)
    params = {}
    for item in a.params:
        k, sep, v = item.partition("=")
        if not sep or not k.strip():
            p.error(f"--set {item!r}: expected NAME=VALUE")
        if k.strip() in params:
            p.error(f"--set {k.strip()} is given twice")
        params[k.strip()] = v.strip()
    try:
        path = build(a.scene, a.method, a.out, params, a.name, a.wrapper,
                     geometry_input=a.geometry_input, contacts=a.contacts)
    except (ValueError, WrapperUnavailable) as e:
        p.error(str(e))
    print(path)
    return 0
