"""The hard inputs reported in issue 18, each now with the physical answer. Every method on every
finite input (property-based: bounded, against the slip, symmetric, the linear limit, monotonic
in ξ, μN at full sliding, any scale) is the shared contract, ``tests/test_method_contract.py``.

References: Coulomb's bound (Kalker 1979 sec. 2); at vanishing creepage no element slips and the
forces are linear in the creepages (Kalker 1979 eq 18); at full sliding |F| = μN against the slip.
"""
from __future__ import annotations

import math

import pytest

from test_method_contract import forces_ok, solve

pytestmark = pytest.mark.unit

#: The failures reported in issue 18 (method, inputs over the default contact, expectation).
CONTACT = dict(xi=0.0, eta=0.0, phi=0.0, N=1e5, mu=0.3, a=6e-3, b=4e-3, G=8e10, nu=0.28)
REPORTED = [
    ("fastsim", dict(xi=1e-162, eta=1e-162), "linear"),
    ("fastsim", dict(xi=1e145), "sliding"), ("fastsim", dict(eta=-1e150), "sliding"),
    ("fastsim", dict(xi=1e144), "sliding"), ("fastsim", dict(xi=1e300), "sliding"),
    ("fastsim", dict(phi=1e300), "bounded"),
    ("exact", dict(xi=1e155), "sliding"),
    ("exact", dict(xi=1e-3, a=1e150, b=1e150), "sliding"),
    ("johnson_vermeulen", dict(xi=1e-3, N=5e-324), "bounded"),
    ("johnson_vermeulen", dict(xi=1e-3, N=1e-200, mu=1e-200), "bounded"),
    ("johnson_vermeulen", dict(xi=1e-3, a=1e150, b=1e150), "sliding"),
]


@pytest.mark.parametrize("method, inputs, expect", REPORTED)
def test_reported_failures(method, inputs, expect):
    """Each reported input now gives the physical answer: forces linear in vanishing creepages,
    μN against the slip at full sliding, a finite bounded force otherwise."""
    kw = CONTACT | inputs
    r = solve(method, **kw)
    forces_ok(method, r, kw)
    if expect == "linear":  # no slip: the forces are linear in the creepages
        f = 1e153
        ref = solve(method, **(kw | {k: v * f for k, v in inputs.items()}))
        assert ref.slip_fraction == 0.0
        assert (r.Fx, r.Fy, r.Mz) == pytest.approx((ref.Fx / f, ref.Fy / f, ref.Mz / f),
                                                   rel=1e-9)
    elif expect == "sliding":
        s = math.hypot(kw["xi"], kw["eta"])
        assert math.hypot(r.Fx, r.Fy) == pytest.approx(kw["mu"] * kw["N"], rel=1e-9)
        assert (r.Fx * kw["xi"] + r.Fy * kw["eta"]) / s < 0
