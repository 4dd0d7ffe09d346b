"""The Manchester Contact Benchmark, case A-2.2 (Shackleton & Iwnicki 2008): both wheels through
contact_core.geometry and the table method (examples/manchester_benchmark.py), the left wheel
against CONTACT's published results (tests/data/mbench_a22_left_contact.csv)."""
from __future__ import annotations

import csv

import pytest

import manchester_benchmark as mb

pytestmark = pytest.mark.unit


@pytest.fixture(scope="module")
def rows() -> list[dict]:
    return mb.run(mb.benchmark_cases())


@pytest.fixture(scope="module")
def left(rows) -> dict[int, dict]:
    return {r["case"]: r for r in rows if r["wheel"] == "left"}


@pytest.fixture(scope="module")
def right(rows) -> dict[int, dict]:
    return {r["case"]: r for r in rows if r["wheel"] == "right"}


REFS = mb.reference_rows()


def test_sign_mapping_at_half_a_millimetre(left):
    # CONTACT's signs (README of the benchmark data): at y = 0.5 mm the left patch has
    # ξ = −3.7e-4, η = 1.2e-3 and the rail feels FX = +887 N, FS = −2370 N
    r = left[2]
    assert r["y_ws_mm"] == 0.5
    assert r["cksi"] == pytest.approx(-3.708e-4, rel=0.05)
    assert r["ceta"] == pytest.approx(1.2e-3, rel=0.05)
    assert r["FX_N"] == pytest.approx(887.1, abs=0.05 * mb.MU * 10050)
    assert r["FS_N"] == pytest.approx(-2370.0, abs=0.05 * mb.MU * 10050)


def test_each_wheel_carries_its_vertical_force(rows):
    for r in rows:
        assert r["FZ_tr_N"] == pytest.approx(10e3, rel=1e-6)


def test_left_wheel_meets_the_targets_on_elliptic_tread_patches(left):
    # every left patch of is a single tread patch clear of the flange root in CONTACT
    # (one patch, |δ| < 0.03 rad); the targets hold where the patch is close to Hertz's ellipse
    # (examples/manchester_benchmark.py, ELLIPTIC_WIDTH_RATIO)
    assert all(REFS[n]["deltcp_rad"] < 0.03 for n in left)
    elliptic = [n for n, r in left.items() if mb.is_elliptic(r)]
    assert len(elliptic) >= 20
    for n in elliptic:
        for col, kind, bound in mb.TARGETS:
            dev = mb.deviation(col, kind, left[n][col], REFS[n])
            assert dev <= bound, f"case {n}: {col} deviates by {dev:.3g} ({kind}), target {bound}"


def test_patch_far_from_an_ellipse_differs_in_the_normal_problem_only(left):
    # where the overlap is far from a parabola's (near-conformal tread at y = 0), the contact point,
    # contact angle, normal and lateral forces still meet their targets, and at CONTACT's own
    # height our geometry and kinematics give CONTACT's ξ: the difference in ξ (and so in FX) comes
    # from Hertz's normal problem against CONTACT's non-Hertzian one (docs/reports/
    # manchester_benchmark.md)
    at_ref = mb.geometry_at_reference_heights()
    others = [n for n, r in left.items() if not mb.is_elliptic(r)]
    for n in others:
        for col, kind, bound in mb.TARGETS:
            if col in ("ycp_rail_mm", "deltcp_rad", "ceta", "cphi_per_mm", "FN_N", "FS_N"):
                assert mb.deviation(col, kind, left[n][col], REFS[n]) <= bound, (n, col)
        assert mb.deviation("cksi", "rel", at_ref[n]["cksi"], REFS[n]) <= 0.05


def test_geometry_and_kinematics_at_contacts_heights():
    # the left wheel at CONTACT's solved heights (no normal problem of ours): contact reference
    # point, contact angle and creepages on all 21 cases within the targets
    at_ref = mb.geometry_at_reference_heights()
    for n, g in at_ref.items():
        assert g["n_patches"] == 1
        for col, kind, bound in mb.TARGETS[:5]:
            assert mb.deviation(col, kind, g[col], REFS[n]) <= bound, (n, col)


def test_right_wheel(left, right):
    # symmetry at y = 0: the right wheel is the left one mirrored
    l1, r1 = left[1], right[1]
    for col in ("FN_N", "FX_N", "cksi", "rolling_radius_mm", "z_ws_mm"):
        assert r1[col] == pytest.approx(l1[col], rel=1e-9, abs=1e-12)
    for col in ("ycp_rail_mm", "deltcp_rad", "FS_N", "MN_Nmm", "cphi_per_mm"):
        assert r1[col] == pytest.approx(-l1[col], rel=1e-9, abs=1e-12)
    # the right wheel meets its flange root at y = 5 mm (two patches sharing the load) and runs on
    # its flange from y = 6.5 mm, where CONTACT's solved heights jump (z_ws < −3 mm)
    two = right[11]
    assert two["n_patches"] == 2 and {two["slot"], two["slot_2"]} == {0, 1}
    assert two["FN_N"] > two["FN_N_2"] > 0.0
    for n in range(14, 22):
        r = right[n]
        assert r["slot"] == 1 and abs(r["deltcp_rad"]) > 0.7 and r["deltcp_rad"] < 0.0
        assert REFS[n]["z_ws_mm"] < -3.0 and r["z_ws_mm"] < -3.0
        assert r["FN_N"] > 10e3                  # the steep flange carries more than the load


def test_cases_file(tmp_path):
    cases = tmp_path / "cases.csv"
    cases.write_text("case,y_ws_mm,yaw_ws,roll_ws,fz_N,vx_ws_mm_s,vpitch_ws\n"
                     "1,3.0,0.0,0.0,20000,10000,-21.739\n"
                     "2,-2.0,0.004,0.0,5000,2000,-4.3478\n")
    out = tmp_path / "out.csv"
    assert mb.main(["--out", str(out), "--cases", str(cases)]) == 0
    with open(out, newline="") as f:
        got = list(csv.DictReader(f))
    assert [(r["case"], r["wheel"]) for r in got] == [("1", "left"), ("1", "right"),
                                                      ("2", "left"), ("2", "right")]
    assert set(mb.COLUMNS) <= set(got[0])
    for r, fz in zip(got, (20e3, 20e3, 5e3, 5e3)):
        assert float(r["FZ_tr_N"]) == pytest.approx(fz, rel=1e-6)
    bad = tmp_path / "bad.csv"
    bad.write_text("case,y_ws_mm,yaw_ws,roll_ws,vx_ws_mm_s,vpitch_ws\n1,0,0,0,2000,-4.3\n")
    with pytest.raises(ValueError, match="fz_N"):
        mb.read_cases(bad)
