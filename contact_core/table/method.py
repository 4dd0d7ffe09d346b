"""The method ``"table"``: Kalker's exact theory, tabulated in advance and interpolated.

The idea is Kalker's USETAB (Kalker 1996, *Book of tables for the Hertzian creep-force law*), with
the values taken from this package's own exact solver (:mod:`contact_core.exact`) extrapolated to
the continuum, and with the spin moment. The parametrisation (:mod:`.grid`) uses the similarity
of the Hertzian problem, so one table serves every load, friction coefficient, size and shear
modulus; its axes are a/b, ν and the Kalker-reduced creepages (direction and a saturating map of
the magnitude). The lookup (:mod:`.interp`) is a local cubic interpolation.

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
import warnings
from dataclasses import replace

import numpy as np

from ..base import ContactMethod
from ..coefficients import creep_coefficients
from ..exact import Exact
from ..linear import LinearTheory
from ..result import make_result
from . import data
from .interp import kernel


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
    default_options: dict = {"folder": None}

    def _check_options(self) -> None:
        folder = self.options["folder"]
        if folder is not None and not isinstance(folder, str):
            raise ValueError(f"folder={folder!r} is invalid: allowed None or a folder name")
        t = data.load(folder)
        self._values, self._lo, self._h = t.values, t.lo, t.h
        ax = t.axes
        self._ab_range = (ax.ab_lo, ax.ab_hi)
        self._nu_range = (ax.nu_lo, ax.nu_hi)
        self._kern = kernel()
        self._out = np.empty(data.N_VALUES)
        self._fallback: Exact | None = None
        self._linear = LinearTheory(self.effects) if not self.effects.saturation else None

    def _step_impl(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        ab = a / b
        if not (self._ab_range[0] <= ab <= self._ab_range[1]
                and self._nu_range[0] <= nu <= self._nu_range[1]):
            return self._outside(xi, eta, phi, N, mu, a, b, G, nu, warm_start)
        eff = self.effects
        if self._linear is not None:
            return replace(self._linear.step(xi, eta, phi, N, mu, a, b, G, nu), method=self.name)
        c11, c22, c23, _ = creep_coefficients(ab, nu)
        c = math.sqrt(a * b)
        k = G * a * b / (mu * N)
        out = self._out
        self._kern(self._values, self._lo, self._h, c11 * xi * k, c22 * eta * k,
                   c23 * c * phi * k, math.log(ab), nu, out)
        fx, fy = float(out[0]), float(out[1])
        f = math.hypot(fx, fy)
        if f > 1.0:            # Coulomb's bound, which interpolation between nodes may cross
            fx, fy = fx / f, fy / f
        mun = mu * N
        return make_result(fx * mun if eff.longitudinal else 0.0,
                           fy * mun if eff.lateral else 0.0,
                           float(out[2]) * mun * c if eff.spin else 0.0, self.name,
                           float(out[3]))

    def _outside(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        warnings.warn(f"table: a/b={a / b:g}, nu={nu:g} outside the table (a/b "
                      f"{self._ab_range[0]:g}..{self._ab_range[1]:g}, nu "
                      f"{self._nu_range[0]:g}..{self._nu_range[1]:g}): solved by the exact "
                      "method", TableDomainWarning, stacklevel=4)
        if self._fallback is None:
            self._fallback = Exact(self.effects)
        start = warm_start if getattr(warm_start, "method", None) == "exact" else None
        return self._fallback.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start=start)
