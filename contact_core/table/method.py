"""The method ``"table"``: Kalker's exact theory, tabulated in advance and interpolated.

The idea is Kalker's USETAB (Kalker 1996, *Book of tables for the Hertzian creep-force law*), with
the values taken from this package's own exact solver (:mod:`contact_core.exact`) extrapolated to
the continuum, and with the spin moment. The parametrisation (:mod:`.grid`) uses the similarity
of the Hertzian problem, so one table serves every load, friction coefficient, size and shear
modulus; its axes are a/b, ν and the Kalker-reduced creepages, spin weighted by a function of
a/b (direction and a saturating map of the magnitude). The lookup (:mod:`.interp`) is a local
cubic interpolation; where a/b and ν repeat (a simulation) it runs on a slice of the table at
that a/b and ν, with the same result to the bit.

Domain: a/b and ν inside the table's axes (``data.load().axes``); elsewhere the state is solved
by the exact method (default options) with a :class:`TableDomainWarning`, and the result's
``method`` is ``"exact"`` (the FMU's ``method_used`` says so). Without the ``saturation`` effect
the tangential problem is linear: the result is Kalker's linear theory (the exact theory's
limit), reported as ``"table"``. Unselected outputs are 0.0. Signs as everywhere in contact_core
(Kalker's convention, ``Fx = -G c² C11 ξ`` for small ξ). The slip fraction is interpolated too.

How the table is built: ``python -m contact_core.table build`` (:mod:`.build`; the table's
``exact_table.json`` records the command); how accurate it is: ``python -m contact_core.table
check`` (:mod:`.check`, docs/table_accuracy.md).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .. import notices
from ..base import ContactMethod
from ..cache import cached
from ..coefficients import SPLINE
from ..exact import Exact
from ..hertz import held_spin_moment
from ..linear import LinearTheory
from ..result import make_result
from . import data
from .interp import kernels, with_psi_ghosts


#: a/b and ν are accepted within a few ulps outside their axes (a and b rescaled by a common
#: factor give an a/b that differs in its last digits; ν computed at run time, e.g. 0.1 + 0.2).
_EDGE_LO, _EDGE_HI = 1.0 - 1e-12, 1.0 + 1e-12
#: Kept per solver: the (a/b, ν) pairs met, at most ``_MAX_PAIRS`` (then forgotten with their
#: slices), and for at most ``_MAX_SLICES`` of them, from their second call on, the scales and a
#: 3-D slice (:func:`.interp._make_slice`, 1.5 MB for the shipped table).
_MAX_PAIRS, _MAX_SLICES = 64, 8


@cached(4)
def _kernel_arrays(folder: str | None) -> tuple[np.ndarray, np.ndarray]:
    """The table of ``folder`` as the kernels read it (:func:`.interp.with_psi_ghosts`, read-only)
    and its axes (start and step; ψ from the ghost node): one copy shared by every solver."""
    t = data.load(folder)
    values = with_psi_ghosts(t.values)
    values.setflags(write=False)
    lo = t.lo.copy()
    lo[3] -= t.h[3]                         # the ghost node before ψ = 0
    return values, np.array([lo, t.h])


class TableDomainWarning(RuntimeWarning):
    """a/b or ν outside the table: the exact method was used instead."""


class Table(ContactMethod):
    """Kalker's exact theory from a precomputed table (module docstring).

    Options
    -------
    folder : str or None
        Folder of another table built by ``python -m contact_core.table build --out FOLDER``
        (default None: the table shipped in the package).
    """

    name = "table"
    code = 5
    fallback = Exact.name
    default_options: dict = {"folder": None}

    def _check_options(self) -> None:
        folder = self.options["folder"]
        if folder is not None and not isinstance(folder, str):
            raise ValueError(f"folder={folder!r} is invalid: allowed None or a folder name")
        t = data.load(folder)
        self._values, self._axes = _kernel_arrays(folder)
        ax = t.axes
        self._spin_power = ax.spin_power
        self._ab_range = (ax.ab_lo, ax.ab_hi)
        self._nu_range = (ax.nu_lo, ax.nu_hi)
        self._lo_nu, self._hi_nu = ax.nu_lo * _EDGE_LO, ax.nu_hi * _EDGE_HI
        self._lookup_state, self._scales, self._make_slice, self._lookup_slice = kernels()
        self._seen: set[tuple[float, float]] = set()
        #: (a/b, ν) -> C11, C22, w C23 (:func:`.interp._scales`) and the slice
        self._slices: dict[tuple[float, float], tuple] = {}
        self._lo_ab, self._hi_ab = ax.ab_lo * _EDGE_LO, ax.ab_hi * _EDGE_HI
        self._fallback: Exact | None = None
        self._linear = LinearTheory(self.effects) if not self.effects.saturation else None

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        ab = a / b
        # a/b and ν rarely change in a simulation (a/b of a Hertz patch whose size follows N
        # takes two or three values in the last digits): a pair met twice gets a slice.
        kept = self._slices.get((ab, nu))
        if kept is None:
            if not (self._lo_ab <= ab <= self._hi_ab and self._lo_nu <= nu <= self._hi_nu):
                return self._outside(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
            if self._linear is not None:    # without saturation μ may be 0: k divides by μN
                return replace(self._linear.step(xi, eta, phi, N, mu, a, b, G, nu),
                               method=self.name)
        c = math.sqrt(a * b)
        k = G * a * b / (mu * N)
        if kept is None:
            # a/b and ν brought onto the table's range (an end, up to rounding)
            inside = min(self._ab_range[1], max(self._ab_range[0], ab))
            nu_in = min(self._nu_range[1], max(self._nu_range[0], nu))
            breaks, pieces = SPLINE
            fx, fy, mz, slip = self._lookup_state(self._values, self._axes, breaks, pieces,
                                                  self._spin_power, xi, eta, phi, c, k, inside,
                                                  nu_in)
            self._meet(ab, nu, inside, nu_in)
        else:
            s_xi, s_eta, s_phi, slab = kept
            fx, fy, mz, slip = self._lookup_slice(slab, self._axes, s_xi * xi * k,
                                                  s_eta * eta * k, s_phi * c * phi * k)
        mun = mu * N
        eff = self.effects
        # interpolation between nodes may cross Coulomb's bound on the moment (interp._finish
        # holds |F| to μN)
        return make_result(fx * mun if eff.longitudinal else 0.0,
                           fy * mun if eff.lateral else 0.0,
                           held_spin_moment(mz * mun * c, mun, a, b) if eff.spin else 0.0,
                           self.name, slip)

    def _meet(self, ab: float, nu: float, inside: float, nu_in: float) -> None:
        """Remember the pair (a/b, ν) (``inside``, ``nu_in``: a/b and ν brought onto the table's
        range); at its second call make its slice (see ``_MAX_PAIRS``)."""
        key = (ab, nu)
        if key not in self._seen:
            if len(self._seen) >= _MAX_PAIRS:
                self._seen.clear()
                self._slices.clear()
            self._seen.add(key)
        elif len(self._slices) < _MAX_SLICES:
            breaks, pieces = SPLINE
            s_xi, s_eta, s_phi, log_ab = self._scales(breaks, pieces, self._spin_power, inside,
                                                      nu_in)
            self._slices[key] = (s_xi, s_eta, s_phi,
                                 self._make_slice(self._values, self._axes, log_ab, nu_in))

    def _outside(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        notices.warn(f"table: a/b={a / b:g}, nu={nu:g} outside the table (a/b "
                     f"{self._ab_range[0]:g}..{self._ab_range[1]:g}, nu "
                     f"{self._nu_range[0]:g}..{self._nu_range[1]:g}): solved by the exact "
                     "method", TableDomainWarning, stacklevel=4)
        if self._fallback is None:
            self._fallback = Exact(self.effects)
        start = warm_start if getattr(warm_start, "method", None) == "exact" else None
        return self._fallback.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start=start)
