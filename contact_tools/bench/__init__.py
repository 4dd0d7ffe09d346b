"""What accuracy costs in time: the benchmark of every method and setting against a converged
reference (``python -m contact_tools.bench``).

Modules: :mod:`.cases` (the case set, from ``cases.toml``), :mod:`.reference` (exact solver on
fine grids, extrapolated, convergence check), :mod:`.settings` (the method/setting matrix),
:mod:`.timing` (in-process and FMU per-call timing), :mod:`.report` (statistics, Markdown, plot),
:mod:`.runner` (the pipeline, :func:`run`).
"""
from .cases import REGIMES, Case, load_spec, make_cases
from .reference import Reference, compute_references
from .runner import BenchResult, run
from .settings import Setting, default_settings

__all__ = ["BenchResult", "Case", "REGIMES", "Reference", "Setting", "compute_references",
           "default_settings", "load_spec", "make_cases", "run"]
