"""Slave module of the DrivenWheelsetFMU FMU (pythonfmu); the class lives in the package
``wheelsets`` (``wheelsets.driven_wheel``), which the FMU bundles (``wheelsets.build``)."""
from wheelsets.driven_wheel import DrivenWheelsetFMU  # noqa: F401
__all__ = ["DrivenWheelsetFMU"]
