"""Falling friction against CONTACT's published ``tractcurv`` example (Eurosprinter, Polach 2005).

    python examples/tractcurv_friction.py --out FILE            # series 2 and 4 of the example
    python examples/tractcurv_friction.py --cases CASES --out FILE

CONTACT's example ``tractcurv`` (E. A. H. Vollebregt, CONTACT user guide, example "tractcurv";
Vollebregt, *Numerical modeling of measured railway creep versus creep-force curves with
CONTACT*, Wear 314 (2014) 87-95; tests/data/contact_tractcurv_example.csv, its
README_reference.md) computes the creep-force curve of the Eurosprinter locomotive wheel of
Polach 2005 four ways; the two with falling friction are

* series 2: the exact theory (M=4, B=0) with CONTACT's exponential falling friction (L=4) and
  friction memory, and an elastic interfacial layer (GG3, LAYTHK; no plasticity, TAU_C0 = 0),
* series 4: the modified FASTSIM (M=3, parabolic bound B=3) with Spiryagin's slope reduction
  (K0_MF, ALFAMF, BETAMF) and the same kind of law.

Each case is solved here with the matching method, law and options, every input taken from the
CSV's own columns (units mm, N, N/mm², 1/mm, mm/s; CONTACT's sign convention, forces on the
upper body (the wheel), positive creepage giving a negative force, which is this package's):

* ``solver`` ``exact_steadyGS`` (B_digit 0): ``exact`` on CONTACT's grid (MX × MY over SCALE
  times the ellipse, ``extrapolate=False``, the numerical normal problem), M_digit 4 with
  ``layer`` = LAYTHK/GG3 (a layer with TAU_C0 > 0, plastic, is refused: not modelled);
  falling friction ``falling="local"`` (each element at its own slip velocity, as CONTACT);
* ``solver`` ``fastsim``/``fastsim_modified`` (M_digit 3): ``fastsim`` with the bound of B_digit
  (3 parabolic, 2 elliptic), CONTACT's discretisation (``scheme="kalker"``) on the comparable
  strip grid nx = MX/SCALE, ny = MY/SCALE (CONTACT's rectangle covers SCALE times the ellipse),
  CONTACT's flexibilities (``flexibility="blended-contact"``), ``k0``, ``alpha_inf``, ``beta``
  from K0_MF, ALFAMF, BETAMF, and with falling friction one coefficient at the creep velocity
  (``falling="creep"``: CONTACT's FASTSIM takes μ at V |(ξ, η)|, this package V s_C, the same
  without spin);
* L_digit 0: Coulomb friction with μ = FSTAT; 2, 3, 4: the linear, rational, exponential law
  (:meth:`contact_core.FrictionLaw.from_contact` of FSTAT, FKIN, FEXP1, SABSH1, FEXP2, SABSH2,
  MEMDST, MEM_S0) at the rolling speed VELOC;
* the contact: FN, CKSI, CETA, CPHI, POISS, G, and the Hertz patch of IPOTCN -1 (curvatures A1,
  B1) or -2 (A1 and the ratio AOB, B1 solved for it).

The output (``--out``, CSV) has one row per case: its ``case``, ``series``, ``solver``, the
method and options used, the creepages, CONTACT's Fx/(FSTAT·FN) (the column FX_over_FSTAT_FN;
empty for cases that have none), this package's, and their difference. The summary printed
gives the largest difference per series and, for the exact cases with a layer, the same without
the layer and without the friction memory: how much of the difference each accounts for.
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

from scipy.optimize import brentq

import contact_core as cc

ROOT = Path(__file__).resolve().parents[1]
#: CONTACT's tractcurv example (see tests/data/README_reference.md).
REFERENCE = ROOT / "tests" / "data" / "contact_tractcurv_example.csv"
#: The falling-friction series of the example.
SERIES = ("2", "4")
#: CONTACT's friction law digit L -> FrictionLaw.kind.
LAWS = {2: "linear", 3: "rational", 4: "exponential"}
COLUMNS = ("case", "series", "solver", "method", "CKSI", "CETA", "CPHI_per_mm",
           "FX_over_FSTAT_FN_contact", "FX_over_FSTAT_FN_ours", "difference")


def read_rows(path: Path) -> list[dict[str, str]]:
    """The CSV's rows (lines starting with '#' are comments)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def number(row: dict[str, str], column: str, default: float | None = None) -> float:
    """The column's value as a number: its leading token (CONTACT's notes such as
    "0 (input; printed as 1e-4)" follow it); an empty cell is ``default`` or an error."""
    text = (row.get(column) or "").strip()
    if not text:
        if default is None:
            raise ValueError(f"case {row.get('case')}: column {column} is empty")
        return default
    return float(text.split()[0])


def patch(row: dict[str, str], E: float, nu: float) -> tuple[float, float]:
    """Semi-axes (a, b) in m of the Hertz patch of IPOTCN -1 (A1, B1) or -2 (A1, AOB)."""
    N = number(row, "FN_N")
    A = number(row, "A1_per_mm") * 1e3
    ipotcn = int(number(row, "IPOTCN"))
    if ipotcn == -1:
        p = cc.hertz(N, A, number(row, "B1_per_mm") * 1e3, E, nu)
        return p.a, p.b
    if ipotcn != -2:
        raise ValueError(f"case {row['case']}: IPOTCN={ipotcn}: allowed -1 (A1, B1) or -2 "
                         "(A1, AOB), a Hertzian contact")
    def log_ab(lg: float) -> float:           # a/b grows with B/A
        p = cc.hertz(N, A, A * math.exp(lg), E, nu)
        return math.log(p.a / p.b)
    target = math.log(number(row, "AOB"))
    t = brentq(lambda lg: log_ab(lg) - target, -6.9, 6.9, xtol=1e-14)   # A/B 1e-3..1e3
    p = cc.hertz(N, A, A * math.exp(t), E, nu)
    return p.a, p.b


def setting(row: dict[str, str], layer: bool = True, memory: bool = True) -> dict:
    """The solve of one case: keyword arguments of ``contact_core.solve`` (method, options,
    effects, friction, V and the contact) and FSTAT. ``layer``/``memory`` False leave out the
    interfacial layer / the friction memory (to measure their share)."""
    solver, m_digit = row["solver"], int(number(row, "M_digit"))
    b_digit, l_digit = int(number(row, "B_digit")), int(number(row, "L_digit"))
    G = number(row, "G_N_per_mm2") * 1e6
    nu = number(row, "POISS")
    a, b = patch(row, 2.0 * G * (1.0 + nu), nu)
    mx, my, scale = int(number(row, "MX")), int(number(row, "MY")), number(row, "SCALE")
    fstat = number(row, "FSTAT")
    kw = dict(xi=number(row, "CKSI"), eta=number(row, "CETA"),
              phi=number(row, "CPHI_per_mm") * 1e3, N=number(row, "FN_N"), mu=fstat, a=a, b=b,
              G=G, nu=nu)
    if solver.startswith("exact"):
        if b_digit != 0 or m_digit not in (0, 4):
            raise ValueError(f"case {row['case']}: exact with B_digit={b_digit}, "
                             f"M_digit={m_digit}: allowed B 0 and M 0 or 4")
        options = dict(mx=mx, my=my, scale=scale, extrapolate=False, falling="local")
        if m_digit == 4 and layer:
            if number(row, "TAU_C0_N_per_mm2", 0.0) > 0.0:
                raise ValueError(f"case {row['case']}: TAU_C0_N_per_mm2 > 0, a plastic "
                                 "interfacial layer, is not modelled: allowed TAU_C0 <= 0")
            options["layer"] = number(row, "LAYTHK_mm") * 1e-3 / (number(row, "GG3_N_per_mm2")
                                                                   * 1e6)
        method = "exact"
    elif solver.startswith("fastsim"):
        if m_digit != 3 or b_digit not in (2, 3):
            raise ValueError(f"case {row['case']}: FASTSIM with M_digit={m_digit}, "
                             f"B_digit={b_digit}: allowed M 3 and B 2 or 3")
        options = dict(nx=round(mx / scale), ny=round(my / scale), scheme="kalker",
                       bound="parabolic" if b_digit == 3 else "elliptic",
                       flexibility="blended-contact", falling="creep",
                       k0=number(row, "K0_MF", 1.0), alpha_inf=number(row, "ALFAMF", 1.0),
                       beta=number(row, "BETAMF", 0.0))
        method = "fastsim"
    else:
        raise ValueError(f"case {row['case']}: solver={solver!r}: allowed exact_steadyGS, "
                         "fastsim, fastsim_modified")
    if l_digit == 0:
        effects, extra = ("longitudinal", "lateral", "spin", "saturation"), {}
    elif l_digit in LAWS:
        law = cc.FrictionLaw.from_contact(
            LAWS[l_digit], fstat, number(row, "FKIN"), number(row, "FEXP1"),
            number(row, "SABSH1_mm_per_s") * 1e-3, number(row, "FEXP2", 0.0),
            number(row, "SABSH2_mm_per_s", 0.0) * 1e-3 or 1.0,
            number(row, "MEMDST_mm", 0.0) * 1e-3 if memory else 0.0,
            number(row, "MEM_S0_mm_per_s", 0.0) * 1e-3)
        effects = ("longitudinal", "lateral", "spin", "saturation", "falling_friction")
        extra = dict(friction=law, V=number(row, "VELOC_mm_per_s") * 1e-3)
    else:
        raise ValueError(f"case {row['case']}: L_digit={l_digit}: allowed 0, 2, 3, 4")
    return dict(method=method, options=options, effects=effects, extra=extra, kw=kw,
                fstat=fstat)


def solve_case(row: dict[str, str], **kw) -> tuple[float, str]:
    """This package's Fx/(FSTAT·FN) of one case and a description of the method used."""
    s = setting(row, **kw)
    r = cc.solve(s["method"], effects=s["effects"], **s["kw"], **s["extra"], **s["options"])
    text = s["method"] + " " + " ".join(f"{k}={v}" for k, v in s["options"].items())
    return r.Fx / (s["fstat"] * s["kw"]["N"]), text


def run(rows: list[dict[str, str]]) -> list[dict[str, object]]:
    out = []
    for row in rows:
        ours, text = solve_case(row)
        contact = (row.get("FX_over_FSTAT_FN") or "").strip()
        ref = float(contact) if contact else None
        out.append({"case": row["case"], "series": row.get("series", ""),
                    "solver": row["solver"], "method": text, "CKSI": row["CKSI"],
                    "CETA": row["CETA"], "CPHI_per_mm": row["CPHI_per_mm"],
                    "FX_over_FSTAT_FN_contact": "" if ref is None else ref,
                    "FX_over_FSTAT_FN_ours": f"{ours:.6f}",
                    "difference": "" if ref is None else f"{ours - ref:.6f}"})
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output CSV")
    ap.add_argument("--cases", help="a CSV in the tractcurv file's columns (default: series "
                    "2 and 4 of the shipped example)")
    a = ap.parse_args(argv)
    if a.cases:
        rows = read_rows(Path(a.cases))
    else:
        rows = [r for r in read_rows(REFERENCE) if r["series"] in SERIES]
    t0 = time.perf_counter()
    out = run(rows)
    wall = time.perf_counter() - t0
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(out)
    print(f"{len(out)} cases in {wall:.1f} s -> {a.out}")
    for series in sorted({str(r["series"]) for r in out}):
        diffs = [abs(float(r["difference"])) for r in out
                 if r["series"] == series and r["difference"] != ""]
        if diffs:
            print(f"series {series}: largest |difference| {100 * max(diffs):.3f} % of "
                  f"FSTAT FN over {len(diffs)} cases")
    layered = [r for r in rows if r["solver"].startswith("exact") and r["M_digit"] == "4"
               and (r.get("FX_over_FSTAT_FN") or "").strip()]
    if layered:
        for label, kw in (("without the interfacial layer", dict(layer=False)),
                          ("without the friction memory", dict(memory=False))):
            worst = max(abs(solve_case(r, **kw)[0] - float(r["FX_over_FSTAT_FN"]))
                        for r in layered)
            print(f"exact cases with a layer, {label}: largest |difference| "
                  f"{100 * worst:.3f} % of FSTAT FN")
    return 0


if __name__ == "__main__":
    sys.exit(main())
