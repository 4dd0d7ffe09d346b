"""``python -m contact_tools.bench [--full] [--jobs N] [--out DIR] [--docs DIR] [--no-fmu]``
and ``python -m contact_tools.bench hard [--cases N] [--exact-cases M]`` (:mod:`.hard`).

What accuracy costs in time: every method and setting against a converged exact reference, with
per-call times in-process and through the FMU. Writes ``OUT/accuracy_vs_time.md`` and ``.png``
(and copies in ``--docs``, e.g. ``docs/reports``). The short form (default, ``make run``: 120 cases) takes about a
minute on two cores; ``--full`` is the definitive sweep (400 cases, finer reference grids, more
settings; about ten minutes).
"""
from __future__ import annotations

import argparse
import os
import sys

from .runner import run


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["hard"]:
        from .hard import main as hard
        return hard(argv[1:])
    p = argparse.ArgumentParser(prog="python -m contact_tools.bench",
                                description=__doc__.split("\n\n")[1].strip())
    p.add_argument("--full", action="store_true", help="the full sweep (default: the short form)")
    p.add_argument("--form", default=None, help=argparse.SUPPRESS)  # short/full/smoke
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help="Dask LocalCluster processes for the reference sweep (default: all cores)")
    p.add_argument("--scheduler", default=None,
                   help="address of a Dask scheduler to run the reference sweep on instead")
    p.add_argument("--out", default="out", help="output folder (default: out)")
    p.add_argument("--docs", default=None, help="also copy the table and plot here (e.g. docs/reports)")
    p.add_argument("--no-fmu", action="store_true", help="skip the FMU timing")
    p.add_argument("--repeats", type=int, default=None,
                   help="timing repeats per case (default 3 short, 5 full)")
    p.add_argument("--build-dir", default="build/bench_fmu",
                   help="where the FMU is built and cached (default: build/bench_fmu)")
    p.add_argument("--reference-cache", default="build/bench_reference",
                   help="folder where the reference's grid solutions are kept between runs "
                   "(default: build/bench_reference; 'none': not kept)")
    p.add_argument("--no-progress", action="store_true", help="no progress bars")
    a = p.parse_args(argv)
    form = a.form or ("full" if a.full else "short")
    cli = " ".join(["", *(argv if argv is not None else sys.argv[1:])])
    run(form, jobs=max(1, a.jobs), scheduler=a.scheduler, fmu=not a.no_fmu, repeats=a.repeats,
        out=a.out, docs=a.docs, build_dir=a.build_dir, progress=not a.no_progress, cli=cli.rstrip(),
        reference_cache=None if a.reference_cache.lower() == "none" else a.reference_cache)
    return 0


if __name__ == "__main__":
    sys.exit(main())
