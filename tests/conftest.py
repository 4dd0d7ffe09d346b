"""Shared test data: a default wheel/rail case and cheap options for the discretised methods."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

import contact_core as cc

#: Hypothesis profile, chosen with the environment variable HYPOTHESIS_PROFILE: "ci" (the
#: default: a fixed seed, sized so that the suite stays short) or "deep" (many more examples, no
#: deadline). Tests whose examples cost more than most scale their own counts with
#: :func:`examples`.
HYPOTHESIS_PROFILE = os.environ.get("HYPOTHESIS_PROFILE", "ci")
settings.register_profile("ci", max_examples=150, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("deep", max_examples=100_000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(HYPOTHESIS_PROFILE)


def examples(ci: int, deep: int) -> int:
    """A test's own number of examples (or steps) under the current profile."""
    return deep if HYPOTHESIS_PROFILE == "deep" else ci

#: Reference data: CONTACT's tractcurv example output (see README_reference.md there).
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


#: The shipped scenes, each built into an FMU once per session by the ``fmus`` fixture.
SCENES = ("traction", "tangent_track", "curving", "full")


@pytest.fixture(scope="session")
def fmus(tmp_path_factory) -> dict[str, Path]:
    """Each shipped scene's FMU with its default method (wheel_rail_fmu.build)."""
    from wheel_rail_fmu.build import build
    out = tmp_path_factory.mktemp("fmus")
    return {name: build(name, out=out) for name in SCENES}


@pytest.fixture(scope="session")
def other_version(tmp_path_factory) -> Path:
    """The traction FMU with linear theory, built from a copy of contact_core whose linear law
    doubles Fx: another version of the library."""
    from wheel_rail_fmu.build import build
    tmp = tmp_path_factory.mktemp("v2")
    core = tmp / "contact_core"
    shutil.copytree(Path(cc.__file__).parent, core,
                    ignore=shutil.ignore_patterns("__pycache__"))
    text = (core / "linear.py").read_text()
    assert "Fx = -G * c2 * c11 * xi" in text
    (core / "linear.py").write_text(text.replace("Fx = -G * c2 * c11 * xi",
                                                 "Fx = -2.0 * G * c2 * c11 * xi"))
    return build("traction", "linear", tmp, core=core, name="v2")
