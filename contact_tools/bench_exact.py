"""Benchmark of the exact solver: ms per solve, cold and warm-started (not a test).

Eurosprinter case of CONTACT's tractcurv example (a = 6.304 mm, b = 12.61 mm, N = 106.7 kN,
G = 82 GPa, ν = 0.28, μ = 0.33). Case types: longitudinal ξ = 1.2 ‰; lateral η = 1 ‰;
spin φ = 0.2 /m (φ·√(ab) = 1.8 ‰); combined ξ = 1 ‰, η = 0.5 ‰, φ = 0.1 /m.
"Cold" = no warm start, normal solution cached (it depends only on the grid and a/b, the
situation of a co-simulation); "+normal" also solves the normal problem (influence tables of the
grid cached); "new a/b" also recomputes the influence tables and the folded normal operator
(they depend on dy/dx, i.e. on a/b). "Warm start against Δ": cold ms over warm ms, where
the normalised creepages change by the relative amount Δ, for a single warm start from a cold
solution (scale predictor) and per step of a ten-step ramp warm-started step by step (secant
predictor; at Δ = 0.1 % also without it). Δ decides the speed-up: the warm solve starts with an
error of order Δ and needs ln(error/tol)/ln(1/ρ) sweeps against ln(1/tol)/ln(1/ρ) cold (ρ the
sweep's contraction), so the ratio falls as Δ grows, whatever ρ is. "Co-simulation replay": the
left-wheel contact inputs of the reference wheelset models (examples/wheelsets; hunting above and
below the critical speed, a curve entry), recorded with FASTSIM contacts; the most demanding
stretch of each run (the steps of largest median change) is solved by the exact method through
the FMU's evaluator (contact_core.WheelRailEvaluator: warm start from the previous step) and
cold at every step; on 20×20 also the sweeps from the best first-order start (the exact tangent
about the previous solution, :class:`_FirstOrderStart`): what any predictor built from the
previous solution and its first derivatives could save at most, whatever it costs.
"Longitudinal only": effects (longitudinal, saturation), η = φ = 0, solved on the half grid
(y-mirror symmetry) against the full grid. Each timing is the minimum over repeats (the machine
is shared). Numba compile/cache-load time reported separately.
"""
from __future__ import annotations

import dataclasses
import math
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

import contact_core as cc
from contact_core.exact import (EXTERIOR, SLIP, STICK, contact_grid, kernel_tables, slip_field,
                                traction_differences)
from contact_core.exact.normal import normalised_pressure
from contact_core.material import shear_modulus

# the reference wheelset models: the repository's examples/wheelsets (examples, not installed)
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
from wheelsets.linear_model import LinearWheelset  # noqa: E402
from wheelsets.systems import lateral_time_constant, recommended_step  # noqa: E402
from wheelsets.wheelset_dynamics import LateralParams, LateralState, LateralWheelset  # noqa: E402

A, B, N, G, NU, MU = 6.304e-3, 12.61e-3, 106.7e3, 82e9, 0.28, 0.33
CASES = {"longitudinal": (1.2e-3, 0.0, 0.0), "lateral": (0.0, 1e-3, 0.0),
         "spin": (0.0, 0.0, 0.2e3 * 1e-3), "combined": (1e-3, 5e-4, 0.1)}


def _best(fn, repeat: int) -> tuple[float, object]:
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best * 1e3, out


STEPS = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2)


def _warm_vs_step(solvers: dict, xi: float, eta: float, phi: float, repeat: int) -> dict:
    """Per relative creepage change Δ: (ms, sweeps) of one warm start from the cold solution at
    creepages (1 - Δ), and mean (ms, sweeps) per step of ten warm-started steps of +Δ each
    (secant predictor); at Δ = 0.1 % also the ten steps without the secant (scaling only).
    ``solvers``: the same grid with option ``predictor`` "secant" and "scale"."""
    args = (xi, eta, phi, N, MU, A, B, G, NU)
    solver = solvers["secant"]
    out = {}
    for d in STEPS:
        prev = solver.step(xi * (1 - d), eta * (1 - d), phi * (1 - d), N, MU, A, B, G, NU)
        ms_iso, r = _best(lambda: solver.step(*args, warm_start=prev), repeat)
        seq = []
        for predictor in (("secant", "scale") if d == 1e-3 else ("secant",)):
            solver = solvers[predictor]
            best = math.inf
            for _ in range(3):
                rk = solver.step(*args)
                t, its = 0.0, 0
                for k in range(1, 11):
                    f = 1.0 + k * d
                    t0 = time.perf_counter()
                    rk = solver.step(xi * f, eta * f, phi * f, N, MU, A, B, G, NU, warm_start=rk)
                    t += time.perf_counter() - t0
                    its += rk.iterations
                best = min(best, t)
            seq.append((best * 1e3 / 10, its / 10))
        solver = solvers["secant"]
        out[d] = ((ms_iso, r.iterations), seq)
    return out


def _record(V: float, h: float, T: float, y0: float, R: float = math.inf,
            L: float = 0.0) -> np.ndarray:
    """(ξ, η, φ, N, a, b) of the left contact at every step of a lateral wheelset run
    (FASTSIM)."""
    ws = LateralWheelset(LateralParams(V=V, R=R, L_transition=L), LateralState(y=y0))
    evs = {s: cc.WheelRailEvaluator(cc.WheelRailConfig(method="fastsim")) for s in "LR"}
    rows = []
    for _ in range(int(round(T / h))):
        c = ws.creepages()
        f = {s: evs[s].evaluate(c["xi_" + s], c["eta_" + s], c["phi_" + s], c["N_" + s],
                                evs[s].mu) for s in "LR"}
        rows.append((c["xi_L"], c["eta_L"], c["phi_L"], c["N_L"], evs["L"].a, evs["L"].b))
        ws.step(h, f["L"].Fx, f["L"].Fy, f["L"].Mz, f["R"].Fx, f["R"].Fy, f["R"].Mz)
    return np.array(rows)


def _replay(rows: np.ndarray, mx: int, my: int) -> dict:
    """Mean ms and sweeps per step of the exact evaluator, cold and warm-started."""
    out = {}
    for warm in (False, True):
        ev = cc.WheelRailEvaluator(cc.WheelRailConfig(method="exact",
                                                      options={"mx": mx, "my": my,
                                                               "extrapolate": False}))
        t, its = 0.0, 0
        for xi, eta, phi, n, _, _ in rows:
            if not warm:
                ev.last = None
            t0 = time.perf_counter()
            r = ev.evaluate(xi, eta, phi, n, ev.mu)
            t += time.perf_counter() - t0
            its += r.iterations
        out[warm] = (t * 1e3 / len(rows), its / len(rows))
    return out


class _FirstOrderStart:
    """The best first-order start of a step, as a bound for the secant predictor.

    Not a usable predictor: it needs a dense solve with the 2n × 2n Jacobian (n contact
    elements; ~5 ms for n = 264 on 20×20, more than a cold solve). Discrete steady-rolling
    equations (Kalker 1990, *Three-Dimensional Elastic Bodies in Rolling Contact*, ch. 5; Kalker
    1979 sec. 4) in the solver's normalised tractions v = p/(μ p0): true slip w = c(σ) + M v,
    with c the rigid slip (σ1 - σ3 y/√(ab), σ2 + σ3 x/√(ab)) and M the slip of unit tractions;
    stick elements w = 0, slipping ones v = -g w/|w| (g = p_n/p0). Holding the stick/slip
    partition of the previous solution v_k, a first-order expansion in δσ gives the linear
    system stick rows: M δv = -δc; slip rows: δv + (g/|w|)(I - e eᵀ)(M δv + δc) = 0,
    e = w/|w|; the start is v_k + δv, clipped to the friction bound.
    """

    def __init__(self, solver, solution, a: float, b: float) -> None:
        """Operator of the grid of ``solution`` (any solution with fields at this a/b)."""
        o = solver.options
        mx, my = o["mx"], o["my"]
        grid = contact_grid(mx, my, o["scale"], a / b, o["normal"])
        kxx, kxy, kyy = kernel_tables(mx, my, mx / my * b / a, solution.warm_state.nu)  # dy/dx
        self.a_over_b = a / b
        self.shape = (my, mx)
        self.iy, self.ix = np.nonzero(grid.contact)
        n = len(self.iy)
        self.xh = solution.fields.x[self.ix] / math.sqrt(a * b)    # independent of N at fixed a/b
        self.yh = solution.fields.y[self.iy] / math.sqrt(a * b)
        self.g = grid.pn[self.iy, self.ix]
        zero = np.zeros(self.shape)
        stick = np.where(grid.contact, STICK, EXTERIOR).astype(np.int8)
        self.M = np.empty((2 * n, 2 * n))
        for j in range(2 * n):
            t = np.zeros((2,) + self.shape)
            t[j // n][self.iy[j % n], self.ix[j % n]] = 1.0
            qx, qy = traction_differences(t[0], t[1])
            wx, wy = slip_field(t[0], t[1], qx, qy, stick, zero, zero, kxx, kxy, kyy,
                                grid.c_lo, grid.c_hi, grid.e_lo, grid.e_hi)
            self.M[:, j] = np.concatenate([wx[self.iy, self.ix], wy[self.iy, self.ix]])

    def rigid(self, sigma: np.ndarray) -> np.ndarray:
        return np.concatenate([sigma[0] - sigma[2] * self.yh, sigma[1] + sigma[2] * self.xh])

    def start(self, prev, sigma: np.ndarray) -> SimpleNamespace:
        """Warm state holding the first-order start at σ from ``prev`` (solved with fields)."""
        n = len(self.iy)
        st = prev.warm_state
        v = np.concatenate([st.px[self.iy, self.ix], st.py[self.iy, self.ix]])
        c = self.rigid(st.sigma)
        dc = self.rigid(sigma) - c
        w = self.M @ v + c
        J, rhs = self.M.copy(), -dc
        i = np.flatnonzero(prev.fields.status[self.iy, self.ix] == SLIP)
        wx, wy = w[i], w[n + i]
        nw = np.hypot(wx, wy)
        f, ex, ey = self.g[i] / nw, wx / nw, wy / nw
        for r, (cx, cy) in ((i, (1.0 - ex * ex, -ex * ey)), (n + i, (-ex * ey, 1.0 - ey * ey))):
            J[r] = f[:, None] * (cx[:, None] * self.M[i] + cy[:, None] * self.M[n + i])
            J[r, r] += 1.0
            rhs[r] = -f * (cx * dc[i] + cy * dc[n + i])
        v = v + np.linalg.solve(J, rhs)
        mag = np.hypot(v[:n], v[n:])
        v *= np.tile(np.where(mag > self.g, self.g / np.where(mag > 0.0, mag, 1.0), 1.0), 2)
        t = np.zeros((2,) + self.shape)
        t[0][self.iy, self.ix] = v[:n]
        t[1][self.iy, self.ix] = v[n:]
        # σ equal to the stored one: the solver's scale predictor is then the identity
        return SimpleNamespace(warm_state=dataclasses.replace(st, px=t[0], py=t[1], sigma=sigma))


def _first_order_sweeps(rows: np.ndarray, mx: int, my: int) -> float:
    """Mean sweeps per step when every step starts from :class:`_FirstOrderStart` about the
    previous step's solution (solved to 1e-12, with its stick/slip partition)."""
    cfg = cc.WheelRailConfig()                      # the replay's evaluator's material
    G_, nu_, mu_ = shear_modulus(cfg.E, cfg.nu), cfg.nu, cfg.mu
    tight = cc.make_solver("exact", mx=mx, my=my, tol=1e-12, maxit=100000, fields=True,
                           extrapolate=False)
    solver = cc.make_solver("exact", mx=mx, my=my, extrapolate=False)
    bound = None
    prev, its = None, []
    for xi, eta, phi, n, a, b in rows:
        args = (xi, eta, phi, n, mu_, a, b, G_, nu_)
        r = tight.step(*args, warm_start=prev)
        # a new a/b is a new grid: no start from the previous step (as in the solver)
        if prev is not None and prev.warm_state.a_over_b == a / b:
            if bound is None or bound.a_over_b != a / b:
                bound = _FirstOrderStart(solver, r, a, b)
            its.append(solver.step(*args, warm_start=bound.start(prev, r.warm_state.sigma))
                       .iterations)
        prev = r
    return float(np.mean(its))


def replay_table() -> None:
    vc = LinearWheelset(k_y=LateralParams.k_y, k_psi=LateralParams.k_psi).critical_speed()
    scenes = [("hunting 1.1 Vc", dict(V=1.1 * vc, h=1e-3, T=2.0, y0=1e-3)),
              ("hunting 0.9 Vc", dict(V=0.9 * vc, h=recommended_step(
                  lateral_time_constant(0.9 * vc)), T=2.0, y0=3e-3)),
              ("curve R 300 m", dict(V=20.0, h=1e-3, T=2.0, y0=0.0, R=300.0, L=20.0))]
    print("co-simulation replay: the left contact's inputs of a wheelset run; exact solver cold "
          "at every step vs warm-started from the previous step (secant); mean per step")
    print("replayed: the scene's most demanding stretch, the 300 (20x20) or 60 (48x44) steps "
          "of largest median Δσ/σ, from the time 'from';")
    print("Δσ/σ: median relative change per step of (ξ, η, φ√(ab)) over those steps")
    print("bound (20x20): sweeps from the best first-order start (exact tangent about the "
          "previous solution; a dense solve costlier than a cold solve) and cold sweeps / those")
    print(f"{'scene':15s} {'step':>6s} {'from':>5s} {'grid':7s} {'Δσ/σ':>7s} | {'cold ms':>8s} "
          f"{'sw':>5s} | {'warm ms':>8s} {'sw':>5s} | {'x cold':>6s} | {'bound sw':>8s} {'x cold':>6s}")
    for name, kw in scenes:
        rows = _record(**kw)
        c = np.sqrt(rows[:, 4] * rows[:, 5])
        sig = np.column_stack([rows[:, 0], rows[:, 1], rows[:, 2] * c])
        step = np.linalg.norm(np.diff(sig, axis=0), axis=1) / np.linalg.norm(sig[1:], axis=1)
        for (mx, my), n in (((20, 20), 300), ((48, 44), 60)):
            # the scene's most demanding stretch: the n steps of largest median change
            k = int(np.argmax(np.median(np.lib.stride_tricks.sliding_window_view(step, n - 1),
                                        axis=1)))
            rel = float(np.median(step[k:k + n - 1]))
            window = rows[k:k + n]
            o = _replay(window, mx, my)
            (tc, ic), (tw, iw) = o[False], o[True]
            extra = ""
            if mx == 20:
                sw = _first_order_sweeps(window, mx, my)
                extra = f" | {sw:8.1f} {ic / sw:6.2f}"
            print(f"{name:15s} {kw['h'] * 1e3:4.0f}ms {k * kw['h']:4.2f}s {mx}x{my:<4d} "
                  f"{rel:7.1e} | {tc:8.2f} {ic:5.1f} | {tw:8.2f} {iw:5.1f} | {tc / tw:6.2f}{extra}",
                  flush=True)


def main() -> int:
    t = time.perf_counter()
    cc.solve("exact", xi=1e-3, eta=1e-4, phi=0.1, N=N, mu=MU, a=A, b=B, G=G, nu=NU, mx=8, my=8,
             extrapolate=False)
    print(f"first call (numba compile or cache load, influence tables): "
          f"{(time.perf_counter() - t) * 1e3:.0f} ms")
    rows, warm = [], []
    for mx, my in ((20, 20), (32, 32), (48, 44)):
        solver = cc.make_solver("exact", mx=mx, my=my, extrapolate=False)
        solvers = {"secant": solver, "scale": cc.make_solver("exact", mx=mx, my=my,
                                                              extrapolate=False,
                                                              predictor="scale")}
        repeat = 15 if mx <= 32 else 7
        for name, (xi, eta, phi) in CASES.items():
            args = (xi, eta, phi, N, MU, A, B, G, NU)
            solver.step(*args)                       # influence tables, normal solution cached
            ms_cold, r = _best(lambda: solver.step(*args), repeat)

            def cold_normal():
                normalised_pressure.cache_clear()
                contact_grid.cache_clear()
                return solver.step(*args)
            ms_cn, _ = _best(cold_normal, max(3, repeat // 3))

            def cold_all():
                # a new a/b: also the influence and kernel tables, the folded normal operator
                cc.clear_caches()
                return solver.step(*args)
            ms_all, _ = _best(cold_all, max(3, repeat // 3))
            rows.append((f"{mx}x{my}", name, ms_cold, ms_cn, ms_all, r.iterations,
                         r.Fx / (MU * N), r.Fy / (MU * N)))
            warm.append((f"{mx}x{my}", name, ms_cold, r.iterations,
                         _warm_vs_step(solvers, xi, eta, phi, repeat)))
    print(f"{'grid':7s} {'case':13s} {'cold ms':>8s} {'+normal':>8s} {'new a/b':>8s} "
          f"{'sweeps':>6s} |  Fx/μN    Fy/μN")
    for g, name, c, cn, ca, it, fx, fy in rows:
        print(f"{g:7s} {name:13s} {c:8.2f} {cn:8.2f} {ca:8.2f} {it:6d} | {fx:+.4f} {fy:+.4f}")
    print()
    print("warm start against the relative creepage change Δ: cold ms / warm ms (warm sweeps)")
    print("  single: one warm start from the cold solution at creepages (1 - Δ) (scale predictor)")
    print("  ramp:   ten steps of +Δ, each warm-started from the previous result (secant); "
          "'ramp, no secant' at Δ = 0.1 %")
    head = "".join(f" {100 * d:>13.2g}%" for d in STEPS)
    print(f"{'grid':7s} {'case':13s} {'cold sw':>7s} {'':7s}|{head} | ramp, no secant")
    for g, name, c, it, res in warm:
        for k, label in ((0, "single"), (1, "ramp")):
            cells = []
            for d in STEPS:
                ms, sw = res[d][0] if k == 0 else res[d][1][0]
                cells.append(f" {c / ms:7.2f} ({sw:4.1f})")
            extra = ""
            if k == 1:
                ms, sw = res[1e-3][1][1]
                extra = f" {c / ms:7.2f} ({sw:4.1f})"
            lead = f"{g:7s} {name:13s} {it:7d}" if k == 0 else f"{'':7s} {'':13s} {'':7s}"
            print(f"{lead} {label:6s}|{''.join(cells)} |{extra}")
    print()
    replay_table()
    print()
    print("longitudinal only (effects longitudinal + saturation, η = φ = 0): ms per cold solve "
          "(cached normal)")
    print(f"{'grid':7s} {'full grid':>10s} {'half grid':>10s} {'speed-up':>9s} {'rel. dFx':>9s}")
    for mx, my in ((20, 20), (32, 32), (48, 44), (41, 39)):
        args = (1.2e-3, 0.0, 0.0, N, MU, A, B, G, NU)
        repeat = 15 if mx <= 32 else 7
        out = []
        for half in (False, True):
            solver = cc.make_solver("exact", mx=mx, my=my, half=half, extrapolate=False,
                                    effects=("longitudinal", "saturation"))
            solver.step(*args)
            out.append(_best(lambda: solver.step(*args), repeat))
        (mf, rf), (mh, rh) = out
        print(f"{mx}x{my:<4d} {mf:10.2f} {mh:10.2f} {mf / mh:9.2f} {abs(rh.Fx / rf.Fx - 1):9.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
