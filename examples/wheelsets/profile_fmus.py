"""Real-profile wheelset FMUs: the tangent-track and curving wheelsets on the contact-geometry table
of real wheel and rail profiles, with four contact patches (pythonfmu ``Fmi2Slave``).

Equations, frames and signs: ``profile_dynamics`` (module docstring). The FMU ships its
contact-geometry table (``contact_table.npz``, :meth:`contact_core.geometry.ContactTable.save`,
read with ``allow_pickle=False``) and the table's description (``contact_table.json``: the
nominal rolling radius), and runs on its own copy of ``contact_core`` (``profile_runtime``).

Variables, per patch ``P`` in Lt, Lf, Rt, Rf (left tread, left flange, right tread, right
flange):

* outputs to the patch's contact FMU (scene ``vehicle``): ``xi_P``, ``eta_P`` (1), ``phi_P``
  (1/m), ``N_P`` (N; 0 for an absent or unloaded patch), ``A_P``, ``B_P`` (1/m: its relative
  curvatures); and ``delta_P``, its contact angle (rad);
* inputs from it: ``Fx_P``, ``Fy_P`` (N), ``Mz_P`` (N.m): the rail on the wheel, in the patch's
  contact frame (the FMU turns them into the track frame);
* per wheel W in L, R: ``Q_W`` and ``Y_W``, the wheel's vertical and lateral force on the rail
  (N; Y positive to the right); ``F_flange`` the flange patches' lateral force on the wheelset;
  ``lifted`` (1 while a wheel would carry a negative load); the states ``y``, ``psi``, ``vy``,
  ``dpsi``; and for the curving wheelset ``kappa``.

Parameters: :class:`profile_dynamics.ProfileParams` (the curving wheelset with ``R`` and
``L_transition``) and the initial state ``y0``, ``psi0``, ``vy0``, ``dpsi0``. The contact FMUs
must use the table's elastic constants (E, ν; the defaults, 210 GPa and 0.28, for the shipped
table), with which it computed the patches' approach factors.
"""
from __future__ import annotations

import json

from pythonfmu import Fmi2Causality, Fmi2Slave

from .profile_dynamics import PATCH_INPUTS, PATCH_OUTPUTS, PATCHES, WHEELS, ProfileParams, \
    ProfileWheelset
from .profile_runtime import BUNDLE, TABLE_FILE, TABLE_INFO, geometry
from .wheelset_dynamics import LateralState, param_fields
from .wheelset_fmu_common import WheelsetSlaveBase

_CURVE_ONLY = ("R", "L_transition")
INITIAL_STATE = (("y0", 1e-3, "initial lateral displacement, m"),
                 ("psi0", 0.0, "initial yaw angle, rad"),
                 ("vy0", 0.0, "initial lateral velocity, m/s"),
                 ("dpsi0", 0.0, "initial yaw rate, rad/s"))
_UNITS = {"xi": "1", "eta": "1", "phi": "1/m", "N": "N", "A": "1/m", "B": "1/m", "Fx": "N",
          "Fy": "N", "Mz": "N.m", "delta": "rad"}
_PATCH_TEXT = {"Lt": "left tread", "Lf": "left flange", "Rt": "right tread",
               "Rf": "right flange"}
OTHER_OUTPUTS = tuple(
    [(f"delta_{p}", f"contact angle of the {_PATCH_TEXT[p]} patch, rad") for p in PATCHES]
    + [(f"{q}_{w}", f"{text} of the {side} wheel on the rail, N")
       for w, side in zip(WHEELS, ("left", "right"))
       for q, text in (("Q", "vertical force"), ("Y", "lateral force (+ right)"))]
    + [("F_flange", "lateral force of the flange patches on the wheelset, N"),
       ("lifted", "1 while a wheel would carry a negative load (the wheelset tips), else 0"),
       ("y", "lateral displacement of the wheelset, m (+ right)"),
       ("psi", "yaw angle of the wheelset, rad (+ nose to the right)"),
       ("vy", "lateral velocity, m/s"), ("dpsi", "yaw rate, rad/s")])


def load_bundled_table():
    """The contact-geometry table the FMU ships and the wheels' nominal rolling radius (m)."""
    if BUNDLE is None:
        raise RuntimeError("no bundled contact-geometry table: this is not an FMU's copy of "
                           "the package (build one with wheelsets.build)")
    info = json.loads((BUNDLE / TABLE_INFO).read_text(encoding="utf-8"))
    return geometry.load_table(BUNDLE / TABLE_FILE), float(info["nominal_radius"])


class TangentTrackProfileWheelset(WheelsetSlaveBase):
    """The real-profile wheelset on tangent track (module docstring)."""

    description = ("Wheelset on real profiles (contact-geometry table, four contact patches: "
                   "tread and flange of each wheel), lateral + yaw, primary stiffness to a "
                   "frame at constant speed")

    def __init__(self, **kwargs):
        Fmi2Slave.__init__(self, **kwargs)
        params = [f for f in param_fields(ProfileParams) if f[0] not in _CURVE_ONLY]
        self._declare_patches(params + list(INITIAL_STATE), OTHER_OUTPUTS)

    def _declare_patches(self, parameters, extra_outputs):
        """Register the parameters, the patches' inputs and outputs and ``extra_outputs``."""
        self._declare_parameters(parameters)
        for patch in PATCHES:
            for base in PATCH_INPUTS:
                self._signal(f"{base}_{patch}", Fmi2Causality.input,
                             f"{base} of the {_PATCH_TEXT[patch]} patch, rail on wheel, contact "
                             f"frame, {_UNITS[base]}")
        for patch in PATCHES:
            for base in PATCH_OUTPUTS:
                self._signal(f"{base}_{patch}", Fmi2Causality.output,
                             f"{base} of the {_PATCH_TEXT[patch]} patch, {_UNITS[base]}")
        for name, desc in extra_outputs:
            self._signal(name, Fmi2Causality.output, desc)

    def _model_params(self) -> ProfileParams:
        p = self.params()
        return ProfileParams(**{k: v for k, v in p.items()
                                if k in ProfileParams.__dataclass_fields__})

    def _make_model(self):
        table, r0 = load_bundled_table()
        return ProfileWheelset(self._model_params(), table, r0,
                               LateralState(self.y0, self.psi0, self.vy0, self.dpsi0))

    def _update_outputs(self):
        m = self._model
        self._set_contact_outputs(m.contact_outputs())
        s = m.s
        self.y, self.psi, self.vy, self.dpsi = s.y, s.psi, s.vy, s.dpsi

    def do_step(self, current_time, step_size):
        self._model.step(step_size, [tuple(getattr(self, f"{q}_{p}") for q in PATCH_INPUTS)
                                     for p in PATCHES])
        self._update_outputs()
        return True


class CurvingProfileWheelset(TangentTrackProfileWheelset):
    """The real-profile wheelset in a constant-radius curve at balance speed (module docstring;
    the curvature ramps over ``L_transition`` from t = 0): parameters ``R`` (default 300 m) and
    ``L_transition`` (default 0), initial state centred (y0 = 0), output ``kappa``."""

    description = ("Wheelset on real profiles in a constant-radius curve at balance speed "
                   "(contact-geometry table, four contact patches), lateral + yaw, primary "
                   "stiffness to a frame following the track")
    _DEFAULTS = {"R": 300.0, "L_transition": 0.0, "y0": 0.0}

    def __init__(self, **kwargs):
        Fmi2Slave.__init__(self, **kwargs)
        params = [(n, self._DEFAULTS.get(n, d), doc) for n, d, doc in param_fields(ProfileParams)]
        init = [(n, self._DEFAULTS.get(n, d), doc) for n, d, doc in INITIAL_STATE]
        self._declare_patches(params + init,
                              OTHER_OUTPUTS + (("kappa", "track curvature, 1/m"),))

    def _update_outputs(self):
        super()._update_outputs()
        self.kappa = self._model.curvature(self._model.t)[0]
