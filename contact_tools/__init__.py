"""The project's tooling, in the repository beside the runtime (installed by the ``bench`` extra).

It measures and builds what the runtime ships and never runs inside it: the layers point one way,
``contact_core`` (the runtime) <- ``wheel_rail_fmu`` (the FMU) <- ``contact_tools`` (this), as
the import-linter contract in ``pyproject.toml`` enforces.

* :mod:`.bench`: what accuracy costs in time, every method against a converged exact reference
  (``python -m contact_tools.bench``), and the hard-input sweep (``python -m contact_tools.bench
  hard``);
* :mod:`.table`: the build of the shipped exact-theory table and its held-out check
  (``python -m contact_tools.table build|check``);
* :mod:`.sweep`: where independent solves run (a Dask ``distributed`` cluster);
* :mod:`.fastsim_vs_contact`: FASTSIM against CONTACT's FASTSIM, both against the converged exact
  theory (``python -m contact_tools.fastsim_vs_contact``);
* speed and resource benchmarks, one module each, ``python -m contact_tools.bench_<name>``
  (``make bench`` runs them; ``trivial_fmu/`` holds the baseline FMUs of the FMU benchmarks).
"""
