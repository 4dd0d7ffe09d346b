"""The library's caches of derived data: one policy, one place to clear them.

Policy: every cache is bounded and keyed by value. Functions whose results are worth keeping
(influence tables, normal solutions, grids, kernel tables, Kalker's coefficients per a/b and ν)
are decorated with :func:`cached`, a ``functools.lru_cache`` of a stated size that evicts the
least recently used entry; the one cache on the per-call path of :func:`contact_core.solve`
(solver objects by method, effects and options) is a plain dict that is emptied when it reaches
its size, because an LRU's bookkeeping would cost a tenth of a linear-theory call. Cached results
are shared: callers must not modify returned arrays.

:func:`clear_caches` empties every cache (cold-start benchmarks, or to free the memory).
numba's compiled kernels are cached on disk next to their modules (``cache=True``);
:func:`compiled_with_data` guards the kernels that carry data of their own.
"""
from __future__ import annotations

import functools
from typing import Callable, Sequence, TypeVar

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


def compiled_with_data(fn: F, samples: Sequence[tuple], rtol: float = 1e-12,
                       nogil: bool = True, signature: str | None = None) -> F:
    """``fn`` compiled by numba with its on-disk cache, checked against ``fn`` itself.

    For a kernel whose data are module-level arrays: numba freezes global arrays into the
    compiled code as constants (no array arguments to pass, which would cost a tenth of a µs
    each per call), but keys its disk cache on the source file only, so a cache compiled from
    other data (an edited data file, a new scipy) would be used as it is. The compiled function
    is therefore compared with the interpreted one on ``samples`` (argument tuples) and compiled
    afresh (which rewrites the cache) where any value differs by more than ``rtol``.
    ``signature`` (numba's, e.g. ``"float64(float64)"``): compiled for those types only, so that
    other arguments are converted (an int) or refused with a ``TypeError`` (a string) instead
    of compiling another version.
    """
    import numba
    jit = numba.njit(signature, cache=True, nogil=nogil, error_model="numpy") if signature \
        else numba.njit(cache=True, nogil=nogil, error_model="numpy")
    kernel = jit(fn)

    def stale() -> bool:
        for args in samples:
            for got, want in zip(kernel(*args), fn(*args)):
                if not abs(got - want) <= rtol * abs(want):
                    return True
        return False

    if stale():
        kernel.recompile()
    return kernel
