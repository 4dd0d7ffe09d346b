"""Build the WheelRailContact FMU for a scene: ``python build_fmu.py --help``.

The same as the ``build-fmu`` command; the build itself is :mod:`wheel_rail_fmu.build`.
"""
import sys

from wheel_rail_fmu.build import main

if __name__ == "__main__":
    sys.exit(main())
