"""The shipped table: a data-only file, versioned and checked before use.

``contact_core/data/exact_table.npz`` (numpy, read with ``allow_pickle=False``) holds the node
values (single precision, uncompressed: ``DTYPE``); ``exact_table.json`` next to it holds the
format version, the axes, the exact solver's options, the command that built it, the build time
and the SHA-256 of the ``.npz``. Loading checks the version, the hash, the shape against the
axes and that every value is finite.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..cache import cached
from .grid import Axes

#: 2: the spin axis is weighted (``grid.Axes.spin_power``); tables of version 1 are refused.
FORMAT_VERSION = 2
NAME = "exact_table"
#: Values per node: Fx/(μN s), Fy/(μN s), Mz/(μN c s), slip fraction.
N_VALUES = 4
#: Stored and held in single precision: its rounding (at most 1.2e-7 of μN on the shipped table)
#: is 1e-5 of the table's 1 % target, and it halves the array the lookups read from. Stored
#: uncompressed, which reads several times faster than compressed (docs/notes/table_build.md);
#: the wheel and the FMU are zip files and compress it anyway.
#: A double-precision table (older builds) is read and rounded the same way.
DTYPE = np.float32


@dataclass(frozen=True)
class TableData:
    axes: Axes
    values: np.ndarray          # (a/b rows, ghost row incl., n_ν, n_θ, n_ψ, n_s, 4), read-only
    lo: np.ndarray              # per axis: first node (ln(a/b), ν, θ, ψ, s)
    h: np.ndarray               # per axis: node step
    meta: dict[str, Any]


def data_dir() -> Path:
    return Path(str(resources.files("contact_core") / "data"))


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def write(values: np.ndarray, axes: Axes, meta: dict[str, Any], folder: Path) -> Path:
    """Write ``NAME.npz`` and ``NAME.json`` into ``folder``; returns the ``.npz`` path."""
    folder.mkdir(parents=True, exist_ok=True)
    npz = folder / f"{NAME}.npz"
    np.savez(npz, values=np.ascontiguousarray(values, dtype=DTYPE))
    meta = {**meta, "format_version": FORMAT_VERSION, "axes": axes.to_record(),
            "sha256": sha256(npz)}
    (folder / f"{NAME}.json").write_text(json.dumps(meta, indent=1) + "\n", encoding="utf-8")
    return npz


@cached(4)
def load(folder: str | None = None) -> TableData:
    """The table in ``folder`` (default: the package's data), checked; ``ValueError`` if it is
    missing, of another format version, altered (hash) or inconsistent."""
    base = Path(folder) if folder is not None else data_dir()
    npz, js = base / f"{NAME}.npz", base / f"{NAME}.json"
    if not (npz.is_file() and js.is_file()):
        raise ValueError(f"the exact-theory table is missing in {base}: build it with "
                         "`python -m contact_tools.table build`")
    meta = json.loads(js.read_text(encoding="utf-8"))
    if meta.get("format_version") != FORMAT_VERSION:
        raise ValueError(f"{js}: format_version={meta.get('format_version')!r}, this code "
                         f"reads {FORMAT_VERSION}")
    if meta.get("sha256") != sha256(npz):
        raise ValueError(f"{npz} does not match the SHA-256 recorded in {js}")
    axes = Axes(**meta["axes"])
    with np.load(npz, allow_pickle=False) as z:
        values = np.ascontiguousarray(z["values"], dtype=DTYPE)
    if values.shape != axes.shape + (N_VALUES,) or not np.isfinite(values).all():
        raise ValueError(f"{npz}: values of shape {values.shape} (want "
                         f"{axes.shape + (N_VALUES,)}), all finite")
    values.setflags(write=False)
    lo = np.array([np.log(axes.ab_lo) - axes.ghost_below * axes.ab_step(), axes.nu_lo, 0.0,
                   0.0, 0.0])
    n = np.array(axes.shape, dtype=float)
    span = np.array([0.0, axes.nu_hi - axes.nu_lo, np.pi, 0.5 * np.pi, 1.0])
    h = span / np.maximum(n - 1.0, 1.0)
    h[0] = axes.ab_step()
    return TableData(axes, values, lo, h, meta)
