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
accurate it is: ``python -m contact_tools.table check`` (docs/reports/table_accuracy.md).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .. import notices
from ..base import ContactMethod
from ..cache import cached
from ..coefficients import SPLINE, creep_coefficient_slopes, creep_coefficients
from ..exact import Exact
from ..hertz import held_spin_moment, held_spin_moment_derivatives
from ..linear import LinearTheory, linear_jacobian
from ..result import make_result
from . import data
from .grid import spin_weight
from .interp import check_frozen, gradient_kernel, kernels, step_rows_kernel, with_psi_ghosts


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
        if self._varying and self._all_inputs and self.effects.saturation:
            # a new a/b at every call: one compiled call from the rows at ν (the same results)
            self._fused = step_rows_kernel()
            self.step = self._step_fused

    def _step_fused(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start=None):
        """:meth:`step` by :func:`.interp._step_rows` where it applies (the rows at ν exist,
        the inputs are floats inside ``base._moderate``, a/b inside the table), else the
        general path."""
        try:
            rows = self._rows.get(nu)
            done = 0 if rows is None else None
        except TypeError:                   # ν unhashable: the general path names it
            done = 0
        if done is None:
            try:
                done, fx, fy, mz, slip = self._fused(rows[0], rows[1], xi, eta, phi, N, mu, a,
                                                     b, G, nu)
            except (TypeError, ValueError, OverflowError):   # not floats
                done = 0
            if done == 1:
                return make_result(fx, fy, mz, self.name, slip)
            if done:                        # Coulomb's bounds, as _step_impl and step hold them
                mun = mu * N
                r = make_result(fx, fy, held_spin_moment(mz, mun, a, b), self.name, slip)
                return self._held(r, mu * N) if math.hypot(fx, fy) > mu * N else r
        return ContactMethod.step(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start)

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
                self._rows[nu] = self.rows_at(nu)
        elif len(self._slices) < _MAX_SLICES:
            breaks, pieces = SPLINE
            s_xi, s_eta, s_phi, log_ab = self._scales(breaks, pieces, self._spin_power, inside,
                                                      nu_in)
            self._slices[key] = (s_xi, s_eta, s_phi,
                                 self._make_slice(self._values, self._axes, log_ab, nu_in))

    def _jacobian_impl(self, xi, eta, phi, N, mu, a, b, G, nu, result):
        """The derivatives of the interpolant (:mod:`contact_core.jacobian`): the Lagrange
        weights differentiated along θ, ψ, s and ln(a/b) (:func:`.interp._gradient`), chained
        through the polar coordinates (θ, ψ, s) of the table's coordinates v = (C11 ξ, C22 η,
        w C23 c φ) G ab/(μN) (:mod:`.grid`; Kalker's coefficients' and the spin weight's slopes
        in a/b), the symmetries that bring v into the tabulated quarter, the bound |F| <= μN
        (where it holds |F| the derivative of F/|F|) and Coulomb's bound on the moment. At zero
        creepage: the slopes stored at s = 0 along the three axes of v (the linear range), the
        slip fraction's taken as 0 (it grows like |v|). On the spin axis (ξ = η = 0) the
        derivative along θ at ψ = 0 and π/2. Without saturation: linear theory's. a/b within
        the edges' tolerance outside the table is taken at the edge (no slope in a/b)."""
        if self._linear is not None:
            return linear_jacobian(xi, eta, phi, a, b, G, nu)
        ab = a / b
        if not (self._lo_ab <= ab <= self._hi_ab and self._lo_nu <= nu <= self._hi_nu):
            return None
        lo, hi = self._ab_range
        inside = ab if lo <= ab <= hi else min(hi, max(lo, ab))
        nu_in = min(self._nu_range[1], max(self._nu_range[0], nu))
        x = math.log(inside)
        c11, c22, c23, _ = creep_coefficients(inside, nu_in)
        w = spin_weight(inside, self._spin_power)
        c = math.sqrt(a * b)
        k = G * a * b / (mu * N)
        u = np.array([c11 * xi * k, c22 * eta * k, w * c23 * c * phi * k])
        if inside == ab:
            l11, l22, l23, _ = creep_coefficient_slopes(inside, nu_in)
            lw = -self._spin_power / (1.0 + inside * inside)     # d ln w/d ln(a/b)
            d_log_ab = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 1.0 / a, -1.0 / b])
        else:
            l11 = l22 = l23 = lw = 0.0
            d_log_ab = np.zeros(7)
        # ∂v/∂(ξ, η, φ, N, μ, a, b): v ∝ k, k ∝ ab/(μN); v2 also ∝ c
        U = np.zeros((3, 7))
        U[0, 0], U[1, 1], U[2, 2] = c11 * k, c22 * k, w * c23 * c * k
        U[:, 3] = -u / N
        U[:, 4] = -u / mu
        U[:, 5] = u * (np.array([1.0 + l11, 1.0 + l22, 1.5 + l23 + lw])) / a
        U[:, 6] = u * (np.array([1.0 - l11, 1.0 - l22, 1.5 - l23 - lw])) / b
        f, df_du, df_dl = self._interpolant_derivatives(u, x, nu_in)
        Df = df_du @ U + np.outer(df_dl, d_log_ab)      # (fx, fy, mz/c, slip) by the inputs
        fx, fy = f[0], f[1]
        norm = math.hypot(fx, fy)
        if norm > 1.0:                                  # interp._finish: F/|F|
            n = np.array([fx, fy]) / norm
            Df[:2] = (Df[:2] - np.outer(n, n @ Df[:2])) / norm
            f[:2] = n
        mun = mu * N
        d_mun = np.array([0.0, 0.0, 0.0, mu, N, 0.0, 0.0])
        d_c = np.array([0.0, 0.0, 0.0, 0.0, 0.0, c / (2.0 * a), c / (2.0 * b)])
        J = np.zeros((4, 7))
        eff = self.effects
        if eff.longitudinal:
            J[0] = mun * Df[0] + f[0] * d_mun
        if eff.lateral:
            J[1] = mun * Df[1] + f[1] * d_mun
        if eff.spin:
            J[2] = mun * c * Df[2] + f[2] * c * d_mun + mun * f[2] * d_c
            _, h_mz, h_mun, h_a, h_b = held_spin_moment_derivatives(f[2] * mun * c, mun, a, b)
            J[2] = h_mz * J[2] + h_mun * d_mun
            J[2, 5] += h_a
            J[2, 6] += h_b
        J[3] = Df[3]
        return J

    def _interpolant_derivatives(self, u: np.ndarray, log_ab: float,
                                 nu: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The interpolant f = (Fx/(μN), Fy/(μN), Mz/(μN c), slip fraction) at the table's
        coordinates ``u`` before :func:`.interp._finish`'s bound, its derivatives by u (4 x 3)
        and by ln(a/b) (4) (:meth:`_jacobian_impl`). On a boundary of the interpolant's cells
        (a node of θ, ψ, s or ln(a/b): e.g. φ = 0, η = 0, ξ = 0, a/b = 1; the spin axis; zero
        creepage), where its slope jumps, the mean of the slopes on either side (the limit of
        central differences), each taken 1e-9 |u| away."""
        f, df_du, df_dl = self._one_sided(u, log_ab, nu)
        nodes = self._on_nodes(u, log_ab)
        if nodes[0]:
            d = 1e-9 * max(float(np.linalg.norm(u)), 1e-6)
            for j in range(3):
                side = np.zeros(3)
                side[j] = d
                df_du[:, j] = 0.5 * (self._one_sided(u + side, log_ab, nu)[1][:, j]
                                     + self._one_sided(u - side, log_ab, nu)[1][:, j])
        if nodes[1]:
            d = 1e-9 * self._axes[1, 0]
            df_dl = 0.5 * (self._one_sided(u, log_ab + d, nu)[2]
                           + self._one_sided(u, log_ab - d, nu)[2])
        return f, df_du, df_dl

    def _on_nodes(self, u: np.ndarray, log_ab: float) -> tuple[bool, bool]:
        """Whether the table's coordinates ``u`` lie on a boundary of the interpolant's cells
        in u (zero creepage, the spin axis, a node of θ, ψ or s), and ln(a/b) on a node."""
        lo, h = self._axes
        def at_node(x: float, axis: int) -> bool:
            t = (x - lo[axis]) / h[axis]
            return abs(t - round(t)) < 1e-9
        q = np.abs(u)
        r = float(np.linalg.norm(q))
        if r == 0.0 or math.hypot(q[0], q[1]) == 0.0:
            return True, at_node(log_ab, 0)
        theta = math.acos(min(1.0, max(-1.0, (u[2] if u[1] >= 0.0 else -u[2]) / r)))
        psi = math.atan2(q[1], q[0])
        return (at_node(theta, 2) or at_node(psi, 3) or at_node(r / (1.0 + r), 4),
                at_node(log_ab, 0))

    def _one_sided(self, u: np.ndarray, log_ab: float,
                   nu: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`_interpolant_derivatives` from the cell that :func:`.interp._lookup` takes
        at ``u`` (the slopes of its Lagrange weights)."""
        grad = gradient_kernel()
        values, axes = self._values, self._axes
        sx = math.copysign(1.0, u[0])
        sy = -1.0 if u[1] < 0.0 else 1.0
        q = np.array([abs(u[0]), sy * u[1], sy * u[2]])          # in the tabulated quarter
        sign = np.array([sx, sy, sy])
        r = float(np.linalg.norm(q))
        dq = np.zeros((4, 3))
        dl = np.zeros(4)
        f = np.zeros(4)
        half_pi = 0.5 * math.pi
        if r == 0.0:        # the slopes at s = 0 along the axes: (θ, ψ) = (π/2, 0), (π/2, π/2), 0
            for j, (theta, psi) in enumerate(((half_pi, 0.0), (half_pi, half_pi), (0.0, 0.0))):
                dq[:3, j] = grad(values, axes, theta, psi, 0.0, log_ab, nu)[:3, 0]
        else:
            theta = math.acos(min(1.0, max(-1.0, q[2] / r)))
            psi = math.atan2(q[1], q[0])
            s = r / (1.0 + r)
            g = grad(values, axes, theta, psi, s, log_ab, nu)
            ds = q / (r * (1.0 + r) ** 2)
            rho = math.hypot(q[0], q[1])
            if rho > 0.0:
                dtheta = np.array([q[0] * q[2] / (r * r * rho), q[1] * q[2] / (r * r * rho),
                                   -rho / (r * r)])
                dpsi = np.array([-q[1] / (rho * rho), q[0] / (rho * rho), 0.0])
                dg = np.outer(g[:, 1], dtheta) + np.outer(g[:, 2], dpsi) \
                    + np.outer(g[:, 3], ds)
            else:           # on the spin axis: along θ at ψ = 0 (for ξ) and ψ = π/2 (for η)
                side = 1.0 if theta == 0.0 else -1.0
                dg = np.outer(g[:, 3], ds)
                dg[:, 0] += grad(values, axes, theta, 0.0, s, log_ab, nu)[:, 1] * side / r
                dg[:, 1] += grad(values, axes, theta, half_pi, s, log_ab, nu)[:, 1] * side / r
            f[:3] = s * g[:3, 0]
            f[3] = g[3, 0]
            dq[:3] = np.outer(g[:3, 0], ds) + s * dg[:3]
            dq[3] = dg[3] if 0.0 <= g[3, 0] <= 1.0 else 0.0
            dl[:3] = s * g[:3, 4]
            dl[3] = g[3, 4] if 0.0 <= g[3, 0] <= 1.0 else 0.0
        out_sign = np.array([sx, sy, sy, 1.0])
        return f * out_sign, out_sign[:, None] * dq * sign[None, :], dl * out_sign

    def rows_at(self, nu: float) -> tuple[np.ndarray, np.ndarray] | None:
        """The table interpolated at ν (:func:`_rows_at`: shared, read-only) and the axes with
        what :func:`.interp._lookup_rows` and :func:`.interp._step_rows` take from them (the spin
        power, ν brought onto the table's range, the a/b range and the a/b accepted), or None
        for ν outside the table."""
        if not self._lo_nu <= nu <= self._hi_nu:
            return None
        nu_in = min(self._nu_range[1], max(self._nu_range[0], nu))
        axes = np.vstack([self._axes, [self._spin_power, nu_in, *self._ab_range, 0.0],
                          [self._lo_ab, self._hi_ab, 0.0, 0.0, 0.0]])
        return _rows_at(self.options["folder"], nu_in), axes

    def _outside(self, xi, eta, phi, N, mu, a, b, G, nu, warm_start):
        notices.warn(f"table: a/b={a / b:g}, nu={nu:g} outside the table (a/b "
                     f"{self._ab_range[0]:g}..{self._ab_range[1]:g}, nu "
                     f"{self._nu_range[0]:g}..{self._nu_range[1]:g}): solved by the exact "
                     "method", TableDomainWarning, stacklevel=4)
        if self._fallback is None:
            self._fallback = Exact(self.effects)
        start = warm_start if getattr(warm_start, "method", None) == "exact" else None
        return self._fallback.step(xi, eta, phi, N, mu, a, b, G, nu, warm_start=start)
