"""What a whole vehicle's contacts cost in one FMU (``build-fmu --contacts N``), in fmpy and
libcosim.

    python -m contact_tools.bench_multi [--steps N] [--repeat R] [--out DIR] [--skip-libcosim]

A vehicle of 8 wheels has 8 contact patches, 16 with two-point contact. Each contact follows the
trajectory of ``bench_geometry`` (a contact point moving over curved profiles: creepages, spin,
load, friction and the curvatures A, B change at every step), shifted in phase per contact, so
every step has new inputs and a new a/b for every contact. Measured in one run, each case the
least over chunks of 250 steps of R interleaved rounds (the ratios are the result; the µs depend
on the machine):

1. through fmpy's ``FMU2Slave``, µs per ``setReal(all inputs) + doStep + getReal(all Real
   outputs)``: the ``vehicle`` scene's FMU (method ``table``) with 1, 8 and 16 contacts, 16 of
   which 8 lifted (N <= 0), and 16 with Johnson–Vermeulen (the evaluators' Python path, not
   the table's compiled one), against trivial pythonfmu FMUs with the same interfaces
   (``trivial_fmu/trivial_geometry.py``, ``trivial_fmu/trivial_contacts.py``), which copy
   inputs to outputs. Two ways of calling: "lists", ``FMU2Slave.setReal(vrs, values)`` and
   ``getReal(vrs)`` with Python lists, which fmpy converts value by value into ctypes arrays
   at every call (its cost grows with the number of values, about as much per value as the
   whole law costs per contact); "arrays", fmpy's ``fmi2SetReal``, ``fmi2DoStep`` and
   ``fmi2GetReal`` with arrays made once, the step's inputs copied into them (what a C host
   such as libcosim, or a master keeping its values in arrays, does);
2. through libcosim (DNV's engine, libcosimpy): µs per ``execution.step()`` of an execution
   holding the one FMU, the 1- and 16-contact table FMUs against the trivial ones: "new", every
   input overridden with the step's values before the step (libcosimpy converts them value by
   value, which dominates); "held", the inputs overridden once, which libcosim sets again at
   every step (the FMU computes every step: the engine's own cost per step).

Targets (issue 62): 8 contacts at most 2x one single-contact step; 16 contacts at most 100 µs
per communication step in fmpy.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

from wheel_rail_fmu.build import build

from .bench_geometry import TRIVIAL as TRIVIAL_SINGLE, trajectory
from .fmu_timing import CHUNK, TimedInstance, interleaved_best

TRIVIAL_MULTI = Path(__file__).resolve().parent / "trivial_fmu" / "trivial_contacts.py"
INPUTS = ("xi", "eta", "phi", "N", "mu", "A", "B")
#: Steps of phase between contacts along the trajectory.
SHIFT = 397


def contact_columns(steps: int, contacts: int, lifted: int = 0) -> dict[str, list[float]]:
    """Every contact's inputs per step by name (c[1] .. c[N], each of ``INPUTS``); the last
    ``lifted`` contacts have N = -1 (lifted)."""
    tr = trajectory(steps + SHIFT * contacts)
    columns = {}
    for k in range(contacts):
        for n in INPUTS:
            lift = n == "N" and k >= contacts - lifted
            columns[n if contacts == 1 else f"c[{k + 1}].{n}"] = (
                [-1.0] * steps if lift else tr[n][SHIFT * k:SHIFT * k + steps])
    return columns


def build_all(out: Path) -> dict[str, Path]:
    """The FMUs of the benchmark (module docstring)."""
    from pythonfmu import FmuBuilder
    fmus = {"trivial 1": Path(FmuBuilder.build_FMU(TRIVIAL_SINGLE, dest=out / "trivial1"))}
    for n in (8, 16):
        folder = out / f"trivial{n}"
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "contacts.txt").write_text(str(n))
        fmus[f"trivial {n}"] = Path(FmuBuilder.build_FMU(
            TRIVIAL_MULTI, dest=folder, project_files=[folder / "contacts.txt"]))
    for n in (1, 8, 16):
        fmus[f"table {n}"] = build("vehicle", "table", out / "vehicle", contacts=n)
    return fmus


def per_step_fmpy(fmus: dict[str, Path], steps: int, repeat: int) -> dict[str, float]:
    """Section 1: µs per step through fmpy by case ("<case>" with lists, "<case>, arrays")."""
    cases = {"trivial 1": (fmus["trivial 1"], None, 1, 0),
             "trivial 8": (fmus["trivial 8"], None, 8, 0),
             "trivial 16": (fmus["trivial 16"], None, 16, 0),
             "table 1": (fmus["table 1"], None, 1, 0),
             "table 8": (fmus["table 8"], None, 8, 0),
             "table 16": (fmus["table 16"], None, 16, 0),
             "table 16, 8 lifted": (fmus["table 16"], None, 16, 8),
             "table 16, all lifted": (fmus["table 16"], None, 16, 16),
             "johnson_vermeulen 16": (fmus["table 16"], {"method": "johnson_vermeulen"}, 16, 0)}
    sessions = {k: TimedInstance(path, start, contact_columns(steps, n, lifted))
                for k, (path, start, n, lifted) in cases.items()}
    runs = {}
    for k, s in sessions.items():
        runs[k] = s.run
        runs[f"{k}, arrays"] = s.run_arrays
    try:
        return interleaved_best(runs, repeat)
    finally:
        for s in sessions.values():
            s.free()


def per_step_libcosim(fmus: dict[str, Path], steps: int, repeat: int) -> dict[str, float]:
    """Section 2: µs per ``execution.step()`` of a libcosim execution holding one FMU, its
    inputs overridden before each step."""
    from fmpy import read_model_description
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    runs = {}
    for key, n in (("trivial 1", 1), ("trivial 16", 16), ("table 1", 1), ("table 16", 16)):
        execution = CosimExecution.from_step_size(step_size=int(1e6))
        manipulator = CosimManipulator.create_override()
        execution.add_manipulator(manipulator=manipulator)
        index = execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmus[key]),
                                                          instance_name="contacts"))
        vr = {v.name: v.valueReference
              for v in read_model_description(str(fmus[key])).modelVariables}
        columns = contact_columns(steps, n)
        vin = [vr[name] for name in columns]
        rows = [list(row) for row in zip(*columns.values())]
        set_values = manipulator.slave_real_values
        step = execution.step

        def new(rows=rows, vin=vin, set_values=set_values, step=step, index=index) -> float:
            best = math.inf
            for i in range(0, len(rows), CHUNK):
                chunk = rows[i:i + CHUNK]
                t0 = time.perf_counter()
                for row in chunk:
                    set_values(index, vin, row)
                    if not step():
                        raise RuntimeError("libcosim stopped the run")
                best = min(best, (time.perf_counter() - t0) / len(chunk))
            return best * 1e6

        def held(rows=rows, vin=vin, set_values=set_values, step=step, index=index) -> float:
            set_values(index, vin, rows[0])
            best = math.inf
            for _ in range(0, len(rows), CHUNK):
                t0 = time.perf_counter()
                for _ in range(CHUNK):
                    if not step():
                        raise RuntimeError("libcosim stopped the run")
                best = min(best, (time.perf_counter() - t0) / CHUNK)
            return best * 1e6
        runs[key] = (execution, manipulator, new)
        runs[f"{key}, held"] = (execution, manipulator, held)
    try:
        return interleaved_best({k: r[2] for k, r in runs.items()}, repeat)
    finally:
        runs.clear()


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=2500, help="steps per round")
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--skip-libcosim", action="store_true")
    p.add_argument("--out", default=None, help="where to build the FMUs (default: a temp dir)")
    a = p.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_multi_") as tmp:
        fmus = build_all(Path(a.out or tmp))
        t = per_step_fmpy(fmus, a.steps, a.repeat)
        lc = None if a.skip_libcosim else per_step_libcosim(fmus, a.steps, a.repeat)
    print(f"1. fmpy, µs per setReal(all inputs) + doStep + getReal(all Real outputs), least over "
          f"chunks of {CHUNK} of {a.repeat} interleaved rounds of {a.steps} steps (scene "
          "vehicle, new inputs and a/b at every step); lists: FMU2Slave's setReal/getReal, "
          "arrays: fmi2SetReal/fmi2GetReal with arrays made once\n")
    print(f"{'FMU':<40}{'lists':>9}{'x trivial':>10}{'arrays':>9}{'x trivial':>10}"
          f"{'x its trivial':>15}")
    for key, label, trivial in (
            ("trivial 1", "trivial, 1 contact", "trivial 1"),
            ("trivial 8", "trivial, 8 contacts", "trivial 8"),
            ("trivial 16", "trivial, 16 contacts", "trivial 16"),
            ("table 1", "table, 1 contact", "trivial 1"),
            ("table 8", "table, 8 contacts", "trivial 8"),
            ("table 16", "table, 16 contacts", "trivial 16"),
            ("table 16, 8 lifted", "table, 16 contacts, 8 lifted", "trivial 16"),
            ("table 16, all lifted", "table, 16 contacts, all lifted", "trivial 16"),
            ("johnson_vermeulen 16", "johnson_vermeulen, 16 contacts", "trivial 16")):
        arr = f"{key}, arrays"
        print(f"{label:<40}{t[key]:>9.2f}{t[key] / t['trivial 1']:>10.2f}{t[arr]:>9.2f}"
              f"{t[arr] / t['trivial 1, arrays']:>10.2f}{t[arr] / t[f'{trivial}, arrays']:>15.2f}")
    print(f"\n8 contacts / 1 contact (table): lists {t['table 8'] / t['table 1']:.2f}, arrays "
          f"{t['table 8, arrays'] / t['table 1, arrays']:.2f} (target <= 2); 16 contacts: "
          f"lists {t['table 16']:.1f} µs, arrays {t['table 16, arrays']:.1f} µs per "
          "communication step (target <= 100)")
    if lc is not None:
        print(f"\n2. libcosim, µs per execution.step(), least over chunks of {CHUNK} of "
              f"{a.repeat} interleaved rounds of {a.steps} steps; new: every input overridden "
              "before each step, held: overridden once, set again by libcosim at every step\n")
        print(f"{'FMU':<40}{'new':>9}{'x trivial':>10}{'held':>9}{'x trivial':>10}"
              f"{'x its trivial':>15}")
        for key, label, trivial in (("trivial 1", "trivial, 1 contact", "trivial 1"),
                                    ("trivial 16", "trivial, 16 contacts", "trivial 16"),
                                    ("table 1", "table, 1 contact", "trivial 1"),
                                    ("table 16", "table, 16 contacts", "trivial 16")):
            h = f"{key}, held"
            print(f"{label:<40}{lc[key]:>9.2f}{lc[key] / lc['trivial 1']:>10.2f}{lc[h]:>9.2f}"
                  f"{lc[h] / lc['trivial 1, held']:>10.2f}"
                  f"{lc[h] / lc[f'{trivial}, held']:>15.2f}")
        print(f"\n16 contacts in libcosim: new {lc['table 16']:.1f} µs, held "
              f"{lc['table 16, held']:.1f} µs per communication step")
    return 0


if __name__ == "__main__":
    sys.exit(main())
