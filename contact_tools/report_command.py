"""The command line of the report generators that print a markdown report and may write it to a
file (``kalker_table``, ``bench_falling``)."""
from __future__ import annotations

import argparse
from typing import Callable


def report_command(doc: str, make: Callable[[], str], argv: list[str] | None = None) -> int:
    """``[--out FILE]`` of a generator whose docstring is ``doc``: prints the report ``make()``
    returns and, given FILE, writes it there too."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--out", help="also write the report (markdown) here")
    a = ap.parse_args(argv)
    text = make()
    print(text)
    if a.out:
        with open(a.out, "w", encoding="utf-8") as f:
            f.write(text)
    return 0
