"""The documentation's gallery: the example plots ``make run`` writes into ``out/``, copied into
``docs/gallery/`` small enough to keep in the repository.

    python -m contact_tools.gallery [--src out] [--dest docs/gallery] [--width 900]

(``make gallery`` runs ``make run`` first.) Each image of :data:`GALLERY` is read from ``--src``,
scaled down to at most ``--width`` pixels wide and stored as a palette PNG (256 colours, which
the plots' flat colours and antialiased lines survive); an image missing from ``--src`` is an
error that names the example writing it. The page ``docs/gallery/index.md`` shows them with the
command of each.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

#: (file in out/, the example that writes it)
GALLERY = (
    ("creep_curves.png", "python examples/creep_curves.py"),
    ("fastsim_traction_map.png", "python examples/fastsim_traction_map.py"),
    ("exact_traction_map.png", "python examples/exact_traction_map.py"),
    ("fmu_demo.png", "python examples/fmu_demo.py"),
    ("hunting_limit_cycle.png", "python examples/run_hunting.py"),
    ("adhesion_curve.png", "python examples/adhesion.py"),
    ("adhesion_runs.png", "python examples/adhesion.py"),
    ("contact_geometry.png", "python examples/contact_geometry.py"),
    ("real_profile_hunting.png", "python examples/run_real_profiles.py"),
    ("real_profile_bifurcation.png", "python examples/run_real_profiles.py"),
    ("real_profile_curving.png", "python examples/run_real_profiles.py"),
    ("implicit_coupling.png", "python examples/run_implicit_coupling.py"),
)


def shrink(src: Path, dest: Path, width: int) -> None:
    """``src`` at most ``width`` pixels wide, as a 256-colour PNG at ``dest``."""
    from PIL import Image

    with Image.open(src) as im:
        im = im.convert("RGB")
        if im.width > width:
            im = im.resize((width, round(im.height * width / im.width)), Image.LANCZOS)
        im.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(dest, optimize=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--src", default="out", help="where the examples wrote their plots (out)")
    ap.add_argument("--dest", default="docs/gallery", help="the gallery's folder (docs/gallery)")
    ap.add_argument("--width", type=int, default=900, help="largest width in pixels (900)")
    a = ap.parse_args(argv)
    src, dest = Path(a.src), Path(a.dest)
    missing = [(name, cmd) for name, cmd in GALLERY if not (src / name).is_file()]
    if missing:
        ap.error("missing in " + str(src) + ": " + ", ".join(f"{n} (run `{c}`, or make run)"
                                                            for n, c in missing))
    dest.mkdir(parents=True, exist_ok=True)
    for name, _ in GALLERY:
        shrink(src / name, dest / name, a.width)
        print(f"{dest / name}: {(dest / name).stat().st_size / 1e3:.0f} kB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
