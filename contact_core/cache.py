"""The library's caches of derived data: one policy, one place to clear them.

Policy: every cache is bounded and keyed by value. Functions whose results are worth keeping
(influence tables, normal solutions, grids, kernel tables, Kalker's coefficients per a/b and ν)
are decorated with :func:`cached`, a ``functools.lru_cache`` of a stated size that evicts the
least recently used entry; the one cache on the per-call path of :func:`contact_core.solve`
(solver objects by method, effects and options) is a plain dict that is emptied when it reaches
its size, because an LRU's bookkeeping would cost a tenth of a linear-theory call. Cached results
are shared: callers must not modify returned arrays.

:func:`clear_caches` empties every cache (cold-start benchmarks, or to free the memory).
"""
from __future__ import annotations

import functools
from typing import Callable, TypeVar

F = TypeVar("F", bound=Callable)
_CLEARERS: list[Callable[[], None]] = []


def cached(maxsize: int) -> Callable[[F], F]:
    """``functools.lru_cache(maxsize)``, registered with :func:`clear_caches`."""
    def decorate(fn: F) -> F:
        wrapped = functools.lru_cache(maxsize=maxsize)(fn)
        _CLEARERS.append(wrapped.cache_clear)
        return wrapped
    return decorate


def register(clear: Callable[[], None]) -> None:
    """Register the ``clear`` function of a cache that is not a :func:`cached` function."""
    _CLEARERS.append(clear)


def clear_caches() -> None:
    """Empty every cache of ``contact_core``."""
    for clear in _CLEARERS:
        clear()
