"""Kalker's exact steady-rolling theory as a boundary-element solver (method ``"exact"``).

Modules: :mod:`.influence` (rectangle-integrated Boussinesq–Cerruti coefficients),
:mod:`.normal` (normal problem, Polonsky–Keer CG), :mod:`.kernels` (the tangential kernel
tables and the slip sums over them), :mod:`.sweeps` (steady-rolling tangential problem,
SteadyGS-type Gauss–Seidel sweeps), :mod:`.anderson` (their acceleration), :mod:`.solver` (the
``ContactMethod``, its warm state and the discretised contact).
"""
from .kernels import kernel_tables, traction_differences
from .solver import (ContactGrid, Exact, ExactFields, ExactSolverWarning, ExactWarmState,
                     contact_grid)
from .sweeps import EXTERIOR, SLIP, STICK, slip_field

__all__ = ["EXTERIOR", "ContactGrid", "Exact", "ExactFields", "ExactSolverWarning",
           "ExactWarmState", "SLIP", "STICK", "contact_grid", "kernel_tables", "slip_field",
           "traction_differences"]
