"""``python -m contact_tools.table build ...`` (:mod:`.build`) and
``python -m contact_tools.table check ...`` (:mod:`.check`)."""
import sys

argv = sys.argv[1:]
if argv[:1] == ["check"]:
    from .check import main
    sys.exit(main(argv[1:]))
from .build import main

sys.exit(main(argv))
