"""Curving wheelset FMU: the tangent-track wheelset in a constant-radius curve (pythonfmu).

Equations and sign conventions: ``wheelset_dynamics`` (module docstring). Steady-state curving of
a single wheelset with primary yaw (and lateral) stiffness to a frame that follows the track:
Wickens, *Fundamentals of Rail Vehicle Dynamics* (2003), on steady-state curving of the single wheelset, and Iwnicki
(ed.), *Handbook of Railway Vehicle Dynamics* (2006), on curving. The curvature κ = 1/R enters the longitudinal
creepages (b0 κ: the outer wheel rolls further), the spin (κ: the wheelset yaws at V κ) and, in the
transition, the inertial yaw moment ``I_z V dκ/dt``. Cant balances the centripetal acceleration
(balance speed). The curvature ramps linearly over ``L_transition`` metres from t = 0.

Parameters: those of ``tangent_track.py`` plus R (m; + curve to the right; default 1000 m) and
L_transition (m; default 0: the curve starts at t = 0). Initial state default: centred (y0 = 0).
"""
from __future__ import annotations

from .tangent_track import INITIAL_STATE, STATE_OUTPUTS, TangentTrackWheelset
from .wheelset_dynamics import LateralParams, param_fields

from pythonfmu import Fmi2Slave

_DEFAULTS = {"R": 1000.0, "L_transition": 0.0, "y0": 0.0}


class CurvingWheelset(TangentTrackWheelset):
    """Wheelset with lateral and yaw freedom in a curve (see module docstring)."""

    description = ("Reference wheelset in a constant-radius curve (lateral + yaw, conical wheels, "
                   "primary yaw/lateral stiffness to a frame following the track); Wickens 2003 (curving)")

    def __init__(self, **kwargs):
        Fmi2Slave.__init__(self, **kwargs)
        params = [(n, _DEFAULTS.get(n, d), doc) for n, d, doc in param_fields(LateralParams)]
        init = [(n, _DEFAULTS.get(n, d), doc) for n, d, doc in INITIAL_STATE]
        self._declare(params + init, extra_outputs=STATE_OUTPUTS + (
            ("kappa", "track curvature at the wheelset, 1/m"),))

    def _update_outputs(self):
        super()._update_outputs()
        self.kappa = self._model.curvature(self._model.t)[0]
