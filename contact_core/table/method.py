"""The method ``"table"``: Kalker's exact theory, tabulated in advance and interpolated.

The idea is Kalker's USETAB (Kalker 1996, *Book of tables for the Hertzian creep-force law*), with
the values taken from this package's own exact solver (:mod:`contact_core.exact`) extrapolated to
the continuum, and with the spin moment. The parametrisation (:mod:`.grid`) uses the similarity
of the Hertzian problem, so one table serves every load, friction coefficient, size and shear
modulus; its axes are a/b, ν and the Kalker-reduced creepages, spin weighted by a function of
a/b (direction and a saturating map of the magnitude). The lookup (:mod:`.interp`) is a local
cubic interpolation; where a/b and ν repeat (a simulation) it runs on a slice of the table at
that a/b and ν, and where only ν repeats (a geometry that changes at every step, the effect
``varying_geometry``) on the table at that ν, with the same result to the bit.

Domain: a/b and ν inside the table's axes (``data.load().axes``); elsewhere the state is solved
by the exact method (default options) with a :class:`TableDomainWarning`, and the result's
``method`` is ``"exact"`` (the FMU's ``method_used`` says so). Without the ``saturation`` effect
the tangential problem is linear: the result is Kalker's linear theory (the exact theory's
limit), reported as ``"table"``. Unselected outputs are 0.0. Signs as everywhere in contact_core
(Kalker's convention, ``Fx = -G c² C11 ξ`` for small ξ). The slip fraction is interpolated too.

How the table is built: ``python -m contact_tools.table build`` (the tooling's
:mod:`contact_tools.table.build`; the table's ``exact_table.json`` records the command); how
accurate it is: ``python -m contact_tools.table check`` (docs/table_accuracy.md).
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
from .interp import check_frozen, kernels, with_psi_ghosts


#: a/b and ν are accepted within a few ulps outside their axes (a and b rescaled by a common
#: factor give an a/b that differs in its last digits; ν computed at run time, e.g. 0.1 + 0.2).
_EDGE_LO, _EDGE_HI = 1.0 - 1e-12, 1.0 + 1e-12
#: Kept per solver: the (a/b, ν) pairs met, at most ``_MAX_PAIRS`` (then forgotten with their
#: slices), and for at most ``_MAX_SLICES`` of them, from their second call on, the scales and a
#: 3-D slice (:func:`.interp._make_slice`, 1.5 MB for the shipped table). With the effect
#: ``varying_geometry`` (a new a/b at every call, ν fixed) the ν met instead, and for at most
#: ``_MAX_ROWS`` of them, from their second call on, the table at that ν (:func:`_rows_at`,
#: 15 MB for the shipped table, shared by the solvers of a process).
_MAX_PAIRS, _MAX_SLICES, _MAX_ROWS = 64, 8, 2


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


@cached(2)
def _rows_at(folder: str | None, nu: float) -> np.ndarray:
    """The table of ``folder`` interpolated at ν (:func:`.interp._nu_rows`, read-only): one copy
    shared by every solver (several contacts of a vehicle in one process)."""
    values, axes = _kernel_arrays(folder)
    rows = kernels()[4](values, axes, nu)
    check_frozen()
    rows.setflags(write=False)
    return rows


class TableDomainWarning(RuntimeWarning):
    """a/b or ν outside the table: the exact method was used instead."""


class Table(ContactMethod):
    """Kalker's exact theory from a precomputed table (module docstring).

    Options
    -------
    folder : str or None
        Folder of another table built by ``python -m contact_tools.table build --out FOLDER``
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
        (self._lookup_state, self._scales, self._make_slice, self._lookup_slice, _,
         self._lookup_rows) = kernels()
        self._varying = self.effects.varying_geometry
        #: the pairs (a/b, ν) met, or with varying_geometry the ν
        self._seen: set = set()
        #: (a/b, ν) -> C11, C22, w C23 (:func:`.interp._scales`) and the slice
        self._slices: dict[tuple[float, float], tuple] = {}
        #: ν -> the table at ν (brought onto the table's range) and the lookup's axes
        #: (varying_geometry)
        self._rows: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self._lo_ab, self._hi_ab = ax.ab_lo * _EDGE_LO, ax.ab_hi * _EDGE_HI
        self._fallback: Exact | None = None
        self._linear = LinearTheory(self.effects) if not self.effects.saturation else None

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        ab = a / b
        # a/b and ν rarely change in a simulation of a fixed geometry (a/b of a Hertz patch whose
        # size follows N takes two or three values in the last digits): a pair met twice gets a
        # slice. With varying_geometry a/b changes at every call and ν does not: a ν met twice
        # gets the table at it, and pairs are not kept.
        if self._varying:
            rows = self._rows.get(nu)       # (ν inside the table, with saturation)
            kept = None
        else:
            rows = None
            kept = self._slices.get((ab, nu))
        if kept is None and (rows is None or not self._lo_ab <= ab <= self._hi_ab):
            if not (self._lo_ab <= ab <= self._hi_ab and self._lo_nu <= nu <= self._hi_nu):
                return self._outside(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
            if self._linear is not None:    # without saturation μ may be 0: k divides by μN
                return replace(self._linear.step(xi, eta, phi, N, mu, a, b, G, nu),
                               method=self.name)
        c = math.sqrt(a * b)
        k = G * a * b / (mu * N)
        if kept is not None:
            s_xi, s_eta, s_phi, slab = kept
            fx, fy, mz, slip = self._lookup_slice(slab, self._axes, s_xi * xi * k,
                                                  s_eta * eta * k, s_phi * c * phi * k)
        else:
            # a/b and ν brought onto the table's range (an end, up to rounding)
            lo, hi = self._ab_range
            inside = ab if lo <= ab <= hi else min(hi, max(lo, ab))
            if rows is not None:
                fx, fy, mz, slip = self._lookup_rows(rows[0], rows[1], xi, eta, phi, c, k,
                                                     inside)
            else:
                breaks, pieces = SPLINE
                nu_in = min(self._nu_range[1], max(self._nu_range[0], nu))
                fx, fy, mz, slip = self._lookup_state(self._values, self._axes, breaks, pieces,
                                                      self._spin_power, xi, eta, phi, c, k,
                                                      inside, nu_in)
                self._meet(ab, nu, inside, nu_in)
        mun = mu * N
        eff = self.effects
        # interpolation between nodes may cross Coulomb's bound on the moment (interp._finish
        # holds |F| to μN)
        return make_result(fx * mun if eff.longitudinal else 0.0,
                           fy * mun if eff.lateral else 0.0,
                           held_spin_moment(mz * mun * c, mun, a, b) if eff.spin else 0.0,
                           self.name, slip)

    def _meet(self, ab: float, nu: float, inside: float, nu_in: float) -> None:
        """Remember the pair (a/b, ν), or with varying_geometry ν (``inside``, ``nu_in``: a/b and
        ν brought onto the table's range); at its second call make its slice, or the table at ν
        (see ``_MAX_PAIRS``)."""
        key = nu if self._varying else (ab, nu)
        if key not in self._seen:
            if len(self._seen) >= _MAX_PAIRS:
                self._seen.clear()
                self._slices.clear()
                self._rows.clear()
            self._seen.add(key)
        elif self._varying:
            if len(self._rows) < _MAX_ROWS:
                # the axes with the arguments the rows' lookup takes from them
                axes = np.vstack([self._axes, [self._spin_power, nu_in, 0.0, 0.0, 0.0]])
                self._rows[nu] = (_rows_at(self.options["folder"], nu_in), axes)
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
