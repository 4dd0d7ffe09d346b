"""Slave module of the TangentTrackWheelset FMU (pythonfmu); the class lives in the package
``wheelsets`` (``wheelsets.tangent_track``), which the FMU bundles (``wheelsets.build``)."""
from wheelsets.tangent_track import TangentTrackWheelset  # noqa: F401
__all__ = ["TangentTrackWheelset"]
