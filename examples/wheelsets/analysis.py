"""Measurement helpers for the wheelset co-simulation results (shared by the demo and the tests)."""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import curve_fit


def fit_damped(t, y):
    """Least-squares fit y ≈ A e^{σt} cos(ωt + θ): returns (σ, ω)."""
    up = t[1:][(y[:-1] < 0) & (y[1:] >= 0)]
    w0 = 2 * math.pi / np.median(np.diff(up)) if len(up) > 1 else 10.0
    f = lambda t, A, s, w, th: A * np.exp(s * (t - t[0])) * np.cos(w * t + th)
    best = None
    for th in np.linspace(0, 2 * np.pi, 6, endpoint=False):
        try:
            p, _ = curve_fit(f, t, y, p0=[np.abs(y).max(), 0.0, w0, th], maxfev=4000)
        except RuntimeError:
            continue
        res = float(np.sum((f(t, *p) - y) ** 2))
        if best is None or res < best[0]:
            best = (res, p)
    return best[1][1], abs(best[1][2])
