"""An elastic interfacial layer between wheel and rail (the option ``layer`` of ``exact``).

A third-body layer (oxides, wear debris, friction modifier, sand) sheared elastically adds the
displacement u = (h/G3) p to the bodies' displacement difference (CONTACT's material model M=4,
E. A. H. Vollebregt, CONTACT user guide, "Interfacial layer of contaminants", after K. Hou,
J. Kalousek & E. Magel, *Rheological model of solid layer in rolling contact*, Wear 211 (1997)
134-140; without its plasticity, TAU_C0 <= 0): a local flexibility f = h/G3 (m/Pa), which in
steady rolling lowers the initial slope of the creep-force curve (Vollebregt, *Numerical
modeling of measured railway creep versus creep-force curves with CONTACT*, Wear 314 (2014)
87-95). In the sweeps' units (tractions per G, lengths per dx; :mod:`.kernels`) it adds
f G/dx to the self-influence K(0,0)/π of the x and y tables; every other coefficient, and the
normal problem, are the half-space's.
"""
from __future__ import annotations

import numpy as np

from ..cache import cached
from .kernels import FOLD_MAX_BYTES, folded_tables, kernel_tables


@cached(8)
def layer_kernel_tables(mx: int, my: int, ratio: float, nu: float,
                        extra: float) -> tuple[np.ndarray, ...]:
    """:func:`.kernels.kernel_tables` with ``extra`` = f G/dx added to the self-influence of
    Kxx and Kyy (entry [my - 1, mx] of the flipped tables)."""
    kxx, kxy, kyy = kernel_tables(mx, my, ratio, nu)
    kxx = kxx.copy()
    kyy = kyy.copy()
    kxx[my - 1, mx] += extra
    kyy[my - 1, mx] += extra
    return kxx, kxy, kyy


@cached(8)
def layer_folded_tables(mx: int, my: int, ratio: float, nu: float,
                        extra: float) -> tuple[np.ndarray, ...] | None:
    """:func:`.kernels.folded_tables` of :func:`layer_kernel_tables` (None when too large)."""
    npair = (my + 1) // 2
    if 4 * npair * npair * 2 * mx * 8 > FOLD_MAX_BYTES:
        return None
    return folded_tables(*layer_kernel_tables(mx, my, ratio, nu, extra), mx, my)
