"""Kalker's exact steady-rolling theory as a boundary-element solver (method ``"exact"``).

Modules: :mod:`.influence` (rectangle-integrated Boussinesq–Cerruti coefficients),
:mod:`.normal` (normal problem, Polonsky–Keer CG), :mod:`.tangential` (steady-rolling
tangential problem, SteadyGS-type solver), :mod:`.solver` (the ``ContactMethod``).
"""
from .solver import Exact, ExactFields, ExactSolverWarning
from .tangential import EXTERIOR, SLIP, STICK

__all__ = ["EXTERIOR", "Exact", "ExactFields", "ExactSolverWarning", "SLIP", "STICK"]
