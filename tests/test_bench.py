"""The accuracy-vs-time benchmark (contact_tools.bench): case set, smoke run, error metric."""
from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pytest

import contact_core as cc
from contact_tools.bench import Setting, make_cases, run
from contact_tools.bench.cases import REGIMES, load_spec
from contact_tools.bench.reference import REFERENCE_GRIDS
from contact_tools.bench.report import errors
from contact_tools.bench.settings import default_settings


# ---------------------------------------------------------------------------------------------
# Case set
# ---------------------------------------------------------------------------------------------

@pytest.mark.unit
def test_case_set_reproducible_and_spanning():
    spec = load_spec()
    a, b = make_cases("short"), make_cases("short")
    assert a == b                                   # seeded: identical on every call
    assert len(a) == 120
    assert {c.a_over_b for c in a} == {0.2, 0.5, 1.0, 2.0, 5.0}
    assert {c.mu for c in a} == set(spec["friction"]["mu"])
    assert {c.regime for c in a} == set(REGIMES)
    assert {c.kind for c in a} >= {"longitudinal", "lateral", "spin", "combined"}
    taus = [c.tau for c in a]
    assert min(taus) < 0.05 and max(taus) > 3.0     # linear range to full sliding
    full = make_cases("full")
    assert len(full) == 400 and make_cases("short") == a   # forms are independent streams


@pytest.mark.unit
def test_case_geometry_is_hertz_for_the_fmu_radii():
    for c in make_cases("short")[::7]:
        p = cc.hertz_from_radii(c.N, c.R_wheel, c.R_wheel_profile, c.R_rail_profile, c.E, c.nu)
        assert p.a == pytest.approx(c.a, rel=1e-12) and p.b == pytest.approx(c.b, rel=1e-12)
        assert c.a / c.b == pytest.approx(c.a_over_b, rel=1e-9)


@pytest.mark.unit
def test_tau_is_the_linear_force_over_mu_n_for_pure_cases():
    # Independent of the case generator: Kalker's linear theory through contact_core.solve.
    for c in make_cases("short"):
        if c.kind in ("longitudinal", "lateral", "spin"):
            r = cc.solve("linear", **c.solve_kwargs())
            assert math.hypot(r.Fx, r.Fy) / (c.mu * c.N) == pytest.approx(c.tau, rel=1e-9)


# ---------------------------------------------------------------------------------------------
# Smoke run (tiny case set, small reference grids, FMU timing with few repeats)
# ---------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def smoke(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    res = run("smoke", jobs=1, fmu=True, repeats=2, out=out / "out", docs=out / "docs",
              build_dir=out / "build", progress=False, log=lambda *_: None)
    return res, out


@pytest.mark.host
@pytest.mark.slow
def test_smoke_writes_table_and_plot(smoke):
    res, out = smoke
    md = (out / "out" / "accuracy_vs_time.md").read_text(encoding="utf-8")
    assert (out / "out" / "accuracy_vs_time.png").stat().st_size > 10_000
    assert (out / "docs" / "accuracy_vs_time.md").read_text(encoding="utf-8") == md
    assert (out / "docs" / "accuracy_vs_time.png").is_file()
    assert "nan" not in md.lower()
    summary = md.split("## Summary (all regimes)")[1].split("##")[0]
    for s in default_settings("smoke"):
        row = next(line for line in summary.splitlines() if line.startswith(f"| {s.label} |"))
        cells = [x.strip() for x in row.strip("|").split("|")]
        assert int(cells[1]) > 0                   # cases with a converged reference
        assert re.match(r"^[\d.,]+ \([\d.,]+–[\d.,]+\)$", cells[-2])   # in-process time
        assert re.match(r"^[\d.,]+ \([\d.,]+–[\d.,]+\)$", cells[-1])   # FMU time


@pytest.mark.host
@pytest.mark.slow
def test_smoke_reports_reference_convergence(smoke):
    res, out = smoke
    md = res.markdown
    assert "## Reference convergence per a/b" in md
    conv = md.split("## Reference convergence per a/b")[1]
    for ab in (0.5, 2.0):
        assert re.search(rf"^\| {ab:g} \| 6 \| \d+ \|", conv, re.M)
    assert "### Cases whose reference is not converged (excluded)" in md
    assert len(res.refs) == len(res.cases) == 12
    assert res.refs[0].grids == REFERENCE_GRIDS["smoke"]
    # excluded cases are listed by id, converged ones are not
    listed = conv.split("### Cases whose reference is not converged (excluded)")[1]
    for c, r in zip(res.cases, res.refs):
        assert (f"| {c.id} | {c.a_over_b:g} | {c.kind} |" in listed) == (not r.converged)


@pytest.mark.host
@pytest.mark.slow
def test_smoke_fmu_computes_what_solve_computes(smoke):
    res, _ = smoke
    assert res.t_fmu is not None
    # closed-form methods: the FMU's outputs are the in-process results (same Hertz arithmetic)
    assert "FMU vs in-process" in res.markdown
    for s in res.settings:
        assert res.t_fmu[s.label].shape[0] == len(res.cases)
        assert np.all(res.t_fmu[s.label] > 0) and np.all(res.t_in[s.label] > 0)


# ---------------------------------------------------------------------------------------------
# The error metric is against the reference, not against the method itself
# ---------------------------------------------------------------------------------------------

def _scaled(method: str, factor: float, **options):
    def call(**kw):
        r = cc.solve(method, **kw, **options)
        return replace(r, Fx=factor * r.Fx, Fy=factor * r.Fy, Mz=factor * r.Mz)
    return call


def _rotated(method: str, angle: float, **options):
    def call(**kw):
        r = cc.solve(method, **kw, **options)
        cs, sn = math.cos(angle), math.sin(angle)
        return replace(r, Fx=cs * r.Fx - sn * r.Fy, Fy=sn * r.Fx + cs * r.Fy)
    return call


@pytest.fixture(scope="module")
def perturbed():
    cases = [c for c in make_cases("short") if c.a_over_b == 1.0 and c.mu == 0.2]
    cases = [replace(c, id=i) for i, c in enumerate(cases)]
    settings = [Setting("linear", "linear"),
                Setting("exact 16×16", "exact", (("mx", 16), ("my", 16), ("extrapolate", False))),
                Setting("exact 16×16 ×1.1", "exact", family="test",
                        call=_scaled("exact", 1.1, mx=16, my=16, extrapolate=False)),
                Setting("exact 16×16 turned 10°", "exact", family="test",
                        call=_rotated("exact", math.radians(10), mx=16, my=16,
                                      extrapolate=False))]
    # the short form's reference grids: most of these cases converge to <= 0.5 % of μN
    return run("smoke", cases=cases, settings=settings, ref_grids=REFERENCE_GRIDS["short"],
               fmu=False, repeats=1, out=None, progress=False, log=lambda *_: None)


def _independent_reference(c, grids):
    """Fx, Fy and Mz extrapolated to zero element size (first order in 1/m), computed here (not
    by the benchmark)."""
    q = [[r.Fx, r.Fy, r.Mz] for r in (cc.solve("exact", **c.solve_kwargs(), mx=m, my=m,
                                                extrapolate=False) for m in grids)]
    x = 1.0 / np.asarray(grids, dtype=float)
    return np.polyfit(x, np.array(q), 1)[1]


@pytest.mark.unit
@pytest.mark.slow
def test_errors_are_against_the_reference(perturbed):
    res = perturbed
    grids = REFERENCE_GRIDS["short"]
    ok = [j for j, r in enumerate(res.refs) if r.converged]
    assert len(ok) >= 6
    eF_pert, _ = errors(res.cases, res.refs, res.results["exact 16×16 ×1.1"])
    eF_base, _ = errors(res.cases, res.refs, res.results["exact 16×16"])
    for j in ok[::2]:
        c = res.cases[j]
        fx, fy, mz = _independent_reference(c, grids)
        ref = res.refs[j]
        fs = c.mu * c.N
        assert (ref.Fx, ref.Fy) == pytest.approx((fx, fy), rel=1e-9, abs=1e-9 * fs)
        assert ref.Mz == pytest.approx(mz, rel=1e-9, abs=1e-9 * fs * c.c)
        r16 = cc.solve("exact", **c.solve_kwargs(), mx=16, my=16, extrapolate=False)
        # the force error is the vector's: its direction counts, not its magnitude alone
        assert eF_pert[j] == pytest.approx(math.hypot(1.1 * r16.Fx - fx, 1.1 * r16.Fy - fy) / fs,
                                           rel=1e-9)
        assert eF_base[j] == pytest.approx(math.hypot(r16.Fx - fx, r16.Fy - fy) / fs, rel=1e-9)
        # 1.1 F16 - F_ref = 0.1 F_ref + 1.1 (F16 - F_ref): the perturbation shows in full
        assert abs(eF_pert[j] - 0.1 * math.hypot(fx, fy) / fs) <= 1.1 * eF_base[j] + 1e-12


@pytest.mark.unit
@pytest.mark.slow
def test_a_wrong_direction_shows_at_the_right_magnitude(perturbed):
    # the force turned by 10° keeps its magnitude: only the vector error sees it, as
    # |F_ref| · 2 sin(5°) = 0.174 |F_ref| (up to the 16×16 grid's own error)
    res = perturbed
    turned = res.results["exact 16×16 turned 10°"]
    eF, _ = errors(res.cases, res.refs, turned)
    eF_base, _ = errors(res.cases, res.refs, res.results["exact 16×16"])
    chord = 2 * math.sin(math.radians(5))
    assert sum(r.converged for r in res.refs) >= 6
    for j, (c, r) in enumerate(zip(res.cases, res.refs)):
        if not r.converged:
            continue
        expected = chord * r.F / (c.mu * c.N)
        assert abs(eF[j] - expected) <= eF_base[j] + 1e-12
        magnitude_error = abs(math.hypot(*turned[j, :2]) - r.F) / (c.mu * c.N)
        assert magnitude_error <= eF_base[j] + 1e-12


@pytest.mark.unit
@pytest.mark.slow
def test_perturbation_shows_in_the_table(perturbed):
    res = perturbed
    st = {(s.label, s.regime): s for s in res.stats}
    sat_p = st[("exact 16×16 ×1.1", "near saturation")]
    sat_b = st[("exact 16×16", "near saturation")]
    assert sat_p.n > 0
    # near saturation |F_ref| ~ μN: the 10 % perturbation is ~10 % of μN in the table
    assert 0.07 < sat_p.eF[0] < 0.13
    assert sat_b.eF[1] < 0.03
    # linear theory is right only in the linear range (no self-reference anywhere)
    lin = st[("linear", "linear")]
    assert lin.n > 0 and lin.eF[2] < 0.02
    assert st[("linear", "near saturation")].eF[0] > 0.5
    assert "exact 16×16 ×1.1" in res.markdown


@pytest.mark.unit
def test_reference_takes_any_executor():
    # the sweep only needs submit() + futures: a thread pool (or Dask's client.get_executor())
    from concurrent.futures import ThreadPoolExecutor

    from contact_tools.bench.reference import compute_references
    cases = make_cases("smoke")[:3]
    inline = compute_references(cases, (12, 16, 20), progress=False)
    with ThreadPoolExecutor(2) as ex:
        pooled = compute_references(cases, (12, 16, 20), executor=ex, progress=False)
    assert [(r.Fx, r.Fy, r.Mz, r.u_F) for r in inline] == \
        [(r.Fx, r.Fy, r.Mz, r.u_F) for r in pooled]


@pytest.mark.unit
def test_reference_solutions_are_kept_and_reused(tmp_path, monkeypatch):
    # a rerun with the same cases reuses the kept grid solutions (data only) and gives the same
    # references; other cases are solved anew
    from contact_tools.bench import reference
    cases = make_cases("smoke")[:3]
    first = reference.compute_references(cases, (12, 16, 20), progress=False, cache=tmp_path)
    assert len(list(tmp_path.glob("reference_*.npz"))) == 1

    def no_solving(*args, **kwargs):
        raise AssertionError("kept solutions were not reused")
    monkeypatch.setattr(reference, "grid_solutions", no_solving)
    again = reference.compute_references(cases, (12, 16, 20), progress=False, cache=tmp_path)
    assert [(r.Fx, r.Fy, r.Mz, r.u_F, r.solver_converged) for r in again] == \
        [(r.Fx, r.Fy, r.Mz, r.u_F, r.solver_converged) for r in first]
    with pytest.raises(AssertionError, match="not reused"):
        reference.compute_references(cases[:2], (12, 16, 20), progress=False, cache=tmp_path)


@pytest.mark.unit
def test_held_out_references_are_solved_again_when_the_exact_solver_changes(tmp_path,
                                                                             monkeypatch):
    # the table check's references (held-out sets) are kept like the benchmark's, named by the
    # exact solver's source: kept ones once outlived a change of its spin discretisation
    from contact_tools.bench import reference
    from contact_tools.table import check
    from contact_tools.table.build import AXES
    monkeypatch.setattr(check, "GRIDS", (12, 16, 20))
    cases = check.spin_cases(2, 1, AXES["full"])
    first, seconds = check.references(cases, workers=1, progress=False, folder=tmp_path)
    assert first.shape == (2, 3) and np.isfinite(first).all() and seconds > 0
    solved = reference.grid_solutions

    def no_solving(*args, **kwargs):
        raise AssertionError("kept solutions were not reused")
    monkeypatch.setattr(reference, "grid_solutions", no_solving)
    again, _ = check.references(cases, workers=1, progress=False, folder=tmp_path)
    assert (again == first).all()
    monkeypatch.setattr(reference, "_SOURCES", reference._SOURCES[:-1])   # "the solver changed"
    with pytest.raises(AssertionError, match="not reused"):
        check.references(cases, workers=1, progress=False, folder=tmp_path)
    monkeypatch.setattr(reference, "grid_solutions", solved)
    check.references(cases, workers=1, progress=False, folder=tmp_path)
    assert len(list(tmp_path.glob("reference_*.npz"))) == 2


@pytest.mark.unit
def test_kept_solutions_are_named_by_the_solve_task_and_the_file_layout(tmp_path, monkeypatch):
    # of contact_tools.bench.reference only the code that makes or reads a kept file names it:
    # a changed solve task (or reader, writer) computes the solutions anew
    from contact_tools.bench import reference
    kwargs, grids = [{"xi": 1e-3, "eta": 0.0}], (12, 16, 20)
    name = reference._cache_file(tmp_path, kwargs, grids)
    assert reference._cache_file(tmp_path, kwargs, grids) == name

    def _solve_exact(kw, m):  # another solve task
        return reference._solve_exact({**kw, "eta": 0.0}, m)
    monkeypatch.setattr(reference, "_KEPT_CODE", (_solve_exact, *reference._KEPT_CODE[1:]))
    assert reference._cache_file(tmp_path, kwargs, grids) != name


@pytest.mark.unit
def test_hard_sweep_leaves_the_dear_methods_out_with_zero_exact_cases(tmp_path, capsys):
    # ``--exact-cases 0`` runs the closed-form methods and FASTSIM only; counts below 0 (or no
    # cases) are refused by name instead of failing inside the sweep
    from contact_tools.bench import hard
    assert hard.main(["--cases", "60", "--exact-cases", "0", "--out", str(tmp_path),
                      "--no-progress"]) == 0
    text = (tmp_path / "hard_cases.md").read_text(encoding="utf-8")
    rows = [line.split("|")[1].strip() for line in text.splitlines()
            if line.startswith("| ") and line.split("|")[2].strip() == "60"]
    assert rows == ["linear", "johnson_vermeulen", "polach", "fastsim"]
    for argv, name in ((["--cases", "0"], "--cases"), (["--exact-cases", "-1"], "--exact-cases")):
        with pytest.raises(SystemExit):
            hard.main(argv)
        assert name in capsys.readouterr().err
