"""Where independent solves run: a Dask ``distributed`` cluster, as a ``concurrent.futures``
executor.

The sweeps that outgrow one machine (the benchmark's reference solves, the table build) submit
their tasks to :func:`executor`: a ``LocalCluster`` of worker processes on this machine by
default, or the existing cluster whose scheduler listens at ``scheduler`` (e.g.
``tcp://10.0.0.5:8786``; start one with ``dask scheduler`` and ``dask worker ADDRESS`` on each
machine, every worker with contact_core installed). The futures work with
``concurrent.futures.as_completed``.
"""
from __future__ import annotations

import os
from contextlib import contextmanager
from typing import Iterator


@contextmanager
def executor(scheduler: str | None = None, workers: int | None = None) -> Iterator:
    """A Dask executor (``Client.get_executor()``): a ``LocalCluster`` of ``workers`` processes
    (default: every core) with one thread each, or the cluster at ``scheduler``."""
    from distributed import Client, LocalCluster

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                               processes=True, dashboard_address=":0")
    client = Client(scheduler if scheduler is not None else cluster)
    try:
        yield client.get_executor(pure=False)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
