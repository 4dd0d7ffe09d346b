"""What the example scripts that co-simulate the wheelset FMUs share (``examples/run_*.py``,
``examples/adhesion.py``): their command line and the note on the machine their timings come
from."""
from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

#: The repository (examples/wheelsets/ is two levels below it).
ROOT = Path(__file__).resolve().parent.parent.parent


def command_line(doc: str, argv: list[str] | None = None) -> tuple[Path, Path, bool]:
    """``(out, dist, build)`` of the command line ``[--out DIR] [--dist DIR] [--no-build]`` of a
    script whose docstring is ``doc``: the folder of its results (created), the folder of the
    FMUs, and whether to build them."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "out"))
    ap.add_argument("--dist", default=str(ROOT / "dist" / "wheelsets"))
    ap.add_argument("--no-build", action="store_true")
    a = ap.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    return out, Path(a.dist), not a.no_build


def machine_note(also: str = "") -> str:
    """A report's closing note on the machine its timings come from (``also`` ends it)."""
    return (f"\n(machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
            f"shared with other jobs: timings are indicative{also}.)")
