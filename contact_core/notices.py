"""Where the core's warnings go: Python's :mod:`warnings`, or a sink of the calling thread.

The core warns through :func:`warn` (a coefficient held beyond Kalker's table, the table handing
a state to the exact method, an exact solve that stopped at ``maxit``). A caller whose messages
belong elsewhere sets ``local.sink``, a callable ``sink(category, message)``, around its calls and
back to None after them: the FMU does, because its warnings belong to the FMI logger and not to
its host's warning filters or stderr. The sink is thread-local, so hosts that call from other
threads keep Python's warnings, and setting it is an attribute store (no cost to speak of per
call, unlike ``warnings.catch_warnings``, which also changes process-wide state).
"""
from __future__ import annotations

import threading
import warnings

#: ``local.sink``: None (Python's warnings) or ``sink(category, message)`` for this thread.
local = threading.local()


def warn(message: str, category: type[Warning], stacklevel: int = 1) -> None:
    """``warnings.warn(message, category)`` at ``stacklevel`` above the caller, or the thread's
    sink (:data:`local`) when one is set."""
    sink = getattr(local, "sink", None)
    if sink is None:
        warnings.warn(message, category, stacklevel=stacklevel + 1)
    else:
        sink(category, message)
