"""The plain result object every method returns."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class ContactResult:
    """Creep forces and spin moment of one contact, with diagnostics.

    Sign convention (Kalker 1979 sec. 2 and eq 17): forces and moment are those exerted by the
    rail on the wheel, in the contact frame (x rolling direction, y lateral, z into the rail). For
    small creepage ``Fx = -G c² C11 ξ``: the force opposes the creepage.

    Attributes
    ----------
    Fx, Fy : float
        Tangential creep forces, N.
    Mz : float
        Spin moment about the contact normal, N·m.
    method : str
        Registered name of the method that produced the result.
    slip_fraction : float
        Fraction of the contact area in (micro-)slip, 0..1 (0 for linear theory by definition).
    converged : bool
        False only for iterative methods that stopped before their tolerance (they also warn).
    iterations : int
        Iterations used by iterative methods (0 for closed-form methods).
    residual : float
        Final relative residual of iterative methods (0.0 for closed-form methods).
    fields : Any
        Method-specific traction fields when requested with ``fields=True``, else None.
    warm_state : Any
        Opaque state a method can start from at the next nearby call (``warm_start=result``).
    jacobian : Jacobian or None
        With ``solve(..., jacobian=True)``: the derivatives of the outputs with respect to the
        inputs (:class:`contact_core.jacobian.Jacobian`), else None.
    """

    Fx: float
    Fy: float
    Mz: float
    method: str
    slip_fraction: float = 0.0
    converged: bool = True
    iterations: int = 0
    residual: float = 0.0
    fields: Any = None
    warm_state: Any = None
    jacobian: Any = None


_DEFAULTS = {"slip_fraction": 0.0, "converged": True, "iterations": 0, "residual": 0.0,
             "fields": None, "warm_state": None, "jacobian": None}
_new = object.__new__


def make_result(Fx: float, Fy: float, Mz: float, method: str, slip_fraction: float = 0.0,
                fields: Any = None) -> ContactResult:
    """``ContactResult(Fx, Fy, Mz, method, slip_fraction=..., fields=...)`` for hot paths.

    Same object, built by filling its ``__dict__`` instead of calling the frozen-dataclass
    ``__init__`` (one ``object.__setattr__`` per field), which would cost a large part of the
    per-call budget of the linear and Johnson–Vermeulen laws (docs/notes/performance.md).
    """
    r = _new(ContactResult)
    d = r.__dict__
    d.update(_DEFAULTS)
    d["Fx"] = Fx
    d["Fy"] = Fy
    d["Mz"] = Mz
    d["method"] = method
    d["slip_fraction"] = slip_fraction
    if fields is not None:
        d["fields"] = fields
    return r
