"""Shared test data: a default wheel/rail case and cheap options for the discretised methods."""
from __future__ import annotations

from pathlib import Path

import pytest

import contact_core as cc

#: Copies of shared/reference (CONTACT tractcurv output; see README_reference.md there).
REFERENCE_DIR = Path(__file__).parent / "data"

#: Options keeping the discretised methods cheap in generic (all-method) tests.
FAST_OPTIONS: dict[str, dict] = {"fastsim": {"nx": 20, "ny": 20}, "exact": {"mx": 16, "my": 16}}


def options_for(method: str) -> dict:
    return dict(FAST_OPTIONS.get(method, {}))


@pytest.fixture(scope="session")
def wheel_rail_case() -> dict:
    """r0 = 0.46 m wheel, conical tread, 0.3 m rail crown, 100 kN, steel, μ = 0.3 (SI)."""
    E, nu, N = 210e9, 0.28, 100e3
    p = cc.hertz_from_radii(N, 0.46, float("inf"), 0.3, E, nu)
    return dict(N=N, mu=0.3, a=p.a, b=p.b, G=cc.shear_modulus(E, nu), nu=nu)
