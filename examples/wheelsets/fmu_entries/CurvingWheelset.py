"""Slave module of the CurvingWheelset FMU (pythonfmu); the class lives in the package
``wheelsets`` (``wheelsets.curving``), which the FMU bundles (``wheelsets.build``)."""
from wheelsets.curving import CurvingWheelset  # noqa: F401
__all__ = ["CurvingWheelset"]
