"""The slave module of a WheelRailContact FMU: it loads the code the FMU bundles, under its own name.

The build copies this file into the FMU as ``resources/wheel_rail_contact_<digest>.py`` (named in
``resources/slavemodule.txt``) and the code it runs as the package
``resources/_wheel_rail_contact_<digest>/`` (``contact_core``, the runtime part of
``wheel_rail_fmu`` and pythonfmu's Python side). ``<digest>`` is :func:`bundle_digest` of that
package, so

* each FMU runs the code it bundles, whatever the host has imported: nothing is imported by a
  shared name (no ``contact_core`` in ``sys.modules`` is used), and two FMUs share modules only
  when their code is the same byte for byte;
* compiled code is reused across processes: the package is run from a verified copy in a stable
  folder, :func:`cache_root` (``$CONTACT_CORE_FMU_CACHE``, else ``$XDG_CACHE_HOME/contact_core/fmu``,
  else ``~/.cache/contact_core/fmu``), one sub-folder per digest, where numba's on-disk cache
  (``cache=True``) and Python's bytecode then live next to the sources. Deleting the folder is
  always safe (it is rebuilt on the next start, and compiled again). Each start marks its
  sub-folder as used (its modification time) and removes the sub-folders no FMU has used for
  :data:`MAX_IDLE_DAYS` days, so the folder does not grow with every version ever run. An FMU's
  own extraction folder cannot serve: hosts extract to a new temporary folder each time and
  delete it. The sources are checked against the digest at every start; the compiled caches are
  trusted as Python and numba trust theirs, so the folder must be writable by its user only (it
  is created with mode 0700).

If the cache folder cannot be written, the package runs from a private temporary copy (compiled
anew in each process) and :data:`NOTICES` says why (the bundle package keeps them as
``LOAD_NOTICES``; each slave instance logs them as warnings).

Only the standard library is used here: nothing else can be imported before the bundle is.
"""
from __future__ import annotations

import atexit
import hashlib
import importlib
import importlib.util
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

#: File-name prefix of the slave module; the bundle package is the same name with a leading "_".
PREFIX = "wheel_rail_contact_"
#: Environment variable that moves the folder of verified bundle copies.
CACHE_ENV = "CONTACT_CORE_FMU_CACHE"
#: Messages for the slave to log (e.g. why the cache folder was not used).
NOTICES: list[str] = []
#: A verified copy no FMU has started from for this long is removed by the next start.
MAX_IDLE_DAYS = 30
_SKIP = "__pycache__"


def bundle_digest(root: Path) -> str:
    """SHA-256 (first 20 hex digits) of the files under ``root``, caches excluded."""
    h = hashlib.sha256()
    for f in sorted(p for p in root.rglob("*") if p.is_file() and _SKIP not in p.parts):
        h.update(f.relative_to(root).as_posix().encode() + b"\0")
        h.update(f.read_bytes())
        h.update(b"\0")
    return h.hexdigest()[:20]


def cache_root() -> Path:
    """Folder of the verified bundle copies (see the module docstring)."""
    if os.environ.get(CACHE_ENV):
        return Path(os.environ[CACHE_ENV])
    base = os.environ.get("XDG_CACHE_HOME") or os.environ.get("LOCALAPPDATA")
    return (Path(base) if base else Path.home() / ".cache") / "contact_core" / "fmu"


def _copy(src: Path, parent: Path, name: str, digest: str) -> Path:
    """Copy the bundle ``src`` to ``parent/name`` and check it; returns the copy."""
    dst = parent / name
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns(_SKIP))
    if bundle_digest(dst) != digest:
        raise OSError(f"the copy of the bundle in {dst} does not match its digest {digest}")
    return dst


def _home(src: Path, name: str, digest: str) -> Path:
    """The folder to import the bundle ``name`` from: its verified copy in :func:`cache_root`."""
    root = cache_root()
    home = root / name
    try:
        if (home / name).is_dir():
            _touch(home)          # before the check: a start removing idle copies now keeps it
            if bundle_digest(home / name) == digest:
                _remove_idle(root, home)
                return home
        root.mkdir(mode=0o700, parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f"{name}.", dir=root))
        _copy(src, tmp, name, digest)
        if home.exists():   # an incomplete or altered copy: replace it
            shutil.rmtree(home, ignore_errors=True)
        try:
            os.rename(tmp, home)  # atomic; fails if another process has just put its copy there
        except OSError:
            shutil.rmtree(tmp, ignore_errors=True)
        if bundle_digest(home / name) != digest:
            raise OSError(f"{home} does not hold the bundle {digest}")
        _remove_idle(root, home)
        return home
    except OSError as e:
        tmp = Path(tempfile.mkdtemp(prefix=f"{name}."))
        atexit.register(shutil.rmtree, tmp, True)
        _copy(src, tmp, name, digest)
        NOTICES.append(f"the FMU's code runs from the temporary folder {tmp} and is compiled "
                       f"again in every process: the cache folder {root} is not usable ({e}); "
                       f"set {CACHE_ENV} to a writable folder")
        return tmp


def _touch(home: Path) -> None:
    """Mark the copy ``home`` as used now (its modification time; best effort)."""
    try:
        os.utime(home)
    except OSError:
        pass


def _remove_idle(root: Path, home: Path) -> None:
    """Remove the bundle copies in ``root`` other than ``home`` (and copies left incomplete by a
    failed start) that no start has touched for :data:`MAX_IDLE_DAYS` days. Each is renamed
    before it is deleted, so a start that touched it meanwhile fails its digest check and copies
    the bundle anew. Best effort: errors are ignored."""
    limit = time.time() - MAX_IDLE_DAYS * 86400.0
    try:
        for p in root.iterdir():
            if (not p.name.startswith("_" + PREFIX) or p == home or not p.is_dir()
                    or p.stat().st_mtime >= limit):
                continue
            if ".removing." not in p.name:        # (a rename keeps the folder's own time)
                p = p.rename(p.with_name(f"{p.name}.removing.{os.getpid()}"))
            shutil.rmtree(p, ignore_errors=True)
    except OSError:
        pass


def load_slave_class(resources: Path, module_name: str) -> type:
    """Import the bundle next to the slave module ``module_name`` and return its slave class."""
    if not module_name.startswith(PREFIX):
        raise ImportError(f"{module_name!r} is not a WheelRailContact slave module name")
    name = "_" + module_name
    if name not in sys.modules:
        src = resources / name
        digest = module_name[len(PREFIX):]
        if bundle_digest(src) != digest:
            raise ImportError(f"the code in {src} does not match the FMU's digest {digest}: "
                              "the FMU was altered after it was built")
        home = _home(src, name, digest)
        spec = importlib.util.spec_from_file_location(
            name, home / name / "__init__.py", submodule_search_locations=[str(home / name)])
        package = importlib.util.module_from_spec(spec)
        package.LOAD_NOTICES = tuple(NOTICES)
        sys.modules[name] = package
        try:
            spec.loader.exec_module(package)
        except BaseException:
            del sys.modules[name]
            raise
    return importlib.import_module(f"{name}.wheel_rail_fmu.slave").WheelRailContact


# Loaded as an FMU's slave module (a top-level module), not as wheel_rail_fmu.entry of a checkout.
if not __package__:
    WheelRailContact = load_slave_class(Path(__file__).resolve().parent, __name__)
