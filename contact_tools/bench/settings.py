"""The method/setting matrix: one :class:`Setting` per label (method + options).

Every setting of a registered method runs through :func:`contact_core.solve` in-process and, if
``fmu`` is true, through the FMU (its ``method`` parameter and option parameters set to the same
values). A setting may instead carry ``call``: any callable with the keyword arguments of
:func:`contact_core.solve` (minus ``method``) returning an object with ``Fx, Fy, Mz`` — for
experiments and tests (e.g. a deliberately perturbed copy of a method); such settings are timed
in-process only.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable


@dataclass(frozen=True)
class Setting:
    """One method with fixed options. ``family`` groups settings in the plot (colour/marker)."""

    label: str
    method: str
    options: tuple[tuple[str, Any], ...] = ()
    family: str = ""
    call: Callable[..., Any] | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "options", tuple(sorted(dict(self.options).items())))
        if not self.family:
            object.__setattr__(self, "family", self.method)

    @property
    def fmu(self) -> bool:
        """Whether the FMU can run this setting (a registered method, no custom callable)."""
        return self.call is None

    @property
    def kwargs(self) -> dict[str, Any]:
        return dict(self.options)


def _fastsim(n: int, bound: str, flexibility: str | None = None) -> Setting:
    """FASTSIM n×n; ``flexibility`` None: the method's default (not in the label)."""
    extra = f" {flexibility}" if flexibility else ""
    opts: tuple[tuple[str, Any], ...] = (("nx", n), ("ny", n), ("bound", bound))
    if flexibility:
        opts += (("flexibility", flexibility),)
    return Setting(f"FASTSIM {n}×{n} {bound}{extra}", "fastsim", opts,
                   family=f"fastsim {bound}{extra}")


def _exact(m: int) -> Setting:
    return Setting(f"exact {m}×{m}", "exact", (("mx", m), ("my", m), ("extrapolate", False)))


def _exact_extrapolated(m: int) -> Setting:
    return Setting(f"exact {m}×{m} extrapolated", "exact", (("mx", m), ("my", m)),
                   family="exact extrapolated")


#: FASTSIM and exact grids per form of the benchmark; "fastsim other flexibilities": grids at
#: which FASTSIM also runs with its other blends of the flexibilities (module ``fastsim``).
GRIDS: dict[str, dict[str, tuple[int, ...]]] = {
    "short": {"fastsim": (5, 10, 20, 40), "fastsim other flexibilities": (),
              "exact": (12, 16, 24, 32), "exact extrapolated": (24, 52)},
    "full": {"fastsim": (5, 10, 20, 40, 80), "fastsim other flexibilities": (20,),
             "exact": (12, 16, 24, 32, 48), "exact extrapolated": (24, 48, 52)},
    "smoke": {"fastsim": (5, 10), "fastsim other flexibilities": (),
              "exact": (8, 12), "exact extrapolated": (16,)},
}


def default_settings(form: str = "short") -> list[Setting]:
    """linear; Johnson–Vermeulen (both normalisations, Shen–Hedrick–Elkins spin); Polach; FASTSIM at
    several grids with both traction bounds (in the full form also with its other blends of the
    flexibilities at 20×20); the table; exact at several grids, on one grid and
    extrapolated. Cheapest family first."""
    if form not in GRIDS:
        raise ValueError(f"form={form!r} is unknown: allowed {sorted(GRIDS)}")
    g = GRIDS[form]
    out = [Setting("linear", "linear"),
           Setting("JV kalker", "johnson_vermeulen", (("variant", "kalker"),),
                   family="johnson_vermeulen kalker"),
           Setting("JV original", "johnson_vermeulen", (("variant", "original"),),
                   family="johnson_vermeulen original"),
           Setting("Polach", "polach")]
    for bound in ("parabolic", "elliptic"):
        out += [_fastsim(n, bound) for n in g["fastsim"]]
        out += [_fastsim(n, bound, f) for n in g["fastsim other flexibilities"]
                for f in ("blended-contact", "separate")]
    out.append(Setting("table", "table"))
    out += [_exact(m) for m in g["exact"]]
    out += [_exact_extrapolated(m) for m in g["exact extrapolated"]]
    return out


def check_unique(settings: list[Setting]) -> None:
    labels = [s.label for s in settings]
    dup = sorted({x for x in labels if labels.count(x) > 1})
    if dup:
        raise ValueError(f"settings: duplicate label(s) {dup}")
