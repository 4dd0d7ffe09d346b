"""The FMI 2.0 co-simulation slave: a thin adapter from FMI variables onto ``contact_core``.

No physics here: every step is :meth:`contact_core.wheel_rail.WheelRailEvaluator.evaluate`.
What this class does: declare the variables the build chose (``wheel_rail_fmu.model_description``),
build the evaluator from the parameters at ``exit_initialization_mode``, map inputs/outputs per
step, turn bad values into FMI error statuses with a log message, and save/restore FMU state.

Status mapping (pythonfmu 0.7): ``do_step`` returning False gives ``fmi2Discard``; an exception
gives ``fmi2Fatal`` with the exception text logged. Hence:

* NaN/inf input -> ``do_step`` logs an error naming the variable and returns False: the step is
  refused (``fmi2Discard``), outputs keep their last (finite) values, the instance stays usable;
* invalid parameter -> ``exit_initialization_mode`` logs the error (parameter and allowed range)
  and raises: ``fmi2ExitInitializationMode`` fails (``fmi2Fatal``: pythonfmu reports every Python
  exception as fatal), the host must free the instance.

pythonfmu 0.7 releases its references to the instance, its log queue and the slave class twice
after a Python exception (once when reporting it, once in ``fmi2FreeInstance``); the host then
segfaults after a few failed instances. :func:`_raise_to_host` adds the one reference each that
this takes, so a failed initialisation is a clean fatal status and freeing the instance is safe
(on a pythonfmu without that bug the cost is three small objects never freed per failed instance).
Exceptions are raised on that path only; ``do_step`` never raises.
"""
from __future__ import annotations

import ctypes
import pickle

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.enums import Fmi2Initial, Fmi2Status

import contact_core
from contact_core.wheel_rail import WheelRailConfig, WheelRailEvaluator
from wheel_rail_fmu.model_description import BuildConfig, finalize_model_description, variables_for

_VAR_TYPES = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}
_STATE_KEY = "__wheel_rail_contact__"


def _raise_to_host(slave: Fmi2Slave, message: str):
    """Log ``message`` as an error and raise it to pythonfmu (-> fmi2Fatal), pre-paying the extra
    reference releases of pythonfmu 0.7's exception path (see the module docstring)."""
    slave.log(message, Fmi2Status.error)
    for obj in (slave, type(slave), slave.log_queue):
        ctypes.pythonapi.Py_IncRef(ctypes.py_object(obj))
    raise ValueError(message)


class WheelRailContact(Fmi2Slave):

    author = "contact_core contributors"
    license = "Apache-2.0"
    version = "0.1.0"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        build = BuildConfig.load(self.resources)
        self._build = build
        self.guid = build.guid
        self.description = (f"Wheel-rail rolling contact (Kalker's theories, contact_core), scene "
                            f"'{build.scene}': {build.scene_description}")
        self._specs = variables_for(build.effects, build.method, contact_core.METHODS,
                                    build.parameters)
        # Inputs of effects the scene leaves out are 0 (the core requires that); mu is a parameter
        # or an input, or unused (no saturation: the core's mu -> inf limit).
        self.xi = self.eta = self.phi = 0.0
        self.mu = 0.3
        self.Fx = self.Fy = self.Mz = 0.0
        self._params = []   # parameter specs, in declaration order
        self._evaluator = None
        for spec in self._specs:
            if hasattr(type(self), spec.name) or spec.name.startswith("_"):
                raise RuntimeError(f"variable name {spec.name!r} clashes with the slave class")
            setattr(self, spec.name, spec.start if spec.start is not None else
                    (0 if spec.type == "Integer" else 0.0))
            if spec.causality == "parameter":
                self._params.append(spec)
            self.register_variable(_VAR_TYPES[spec.type](
                spec.name, causality=Fmi2Causality[spec.causality],
                variability=Fmi2Variability[spec.variability],
                initial=Fmi2Initial[spec.initial] if spec.initial else None,
                description=spec.description))

    # -- model description ---------------------------------------------------------------------
    def to_xml(self, model_options=dict()):
        root = super().to_xml(model_options)
        return finalize_model_description(root, self._specs, self.guid, self.description)

    # -- initialisation ------------------------------------------------------------------------
    def _config(self) -> WheelRailConfig:
        method = self.method
        accepted = getattr(contact_core.METHODS.get(method), "default_options", {})
        options = {}
        for spec in self._params:
            if spec.option is not None:
                owner, opt = spec.option  # owner "*": shared by every method with this option
                if owner in (method, "*") and opt in accepted:
                    options[opt] = getattr(self, spec.name)
        return WheelRailConfig(method=method, effects=self._build.effects, mu=float(self.mu),
                               E=float(self.E), nu=float(self.nu), R_wheel=float(self.R_wheel),
                               R_wheel_profile=float(self.R_wheel_profile),
                               R_rail_profile=float(self.R_rail_profile), options=options)

    def _make_evaluator(self) -> None:
        try:
            self._evaluator = WheelRailEvaluator(self._config())
        except Exception as e:  # ValueError names the parameter and its allowed range
            self._evaluator = None
            _raise_to_host(self, f"invalid parameter: {e}")

    def exit_initialization_mode(self):
        self._make_evaluator()
        # Outputs have initial="calculated": compute them from the inputs known now.
        if not self._step(0.0, "exitInitializationMode"):
            _raise_to_host(self, "invalid input at initialisation (see the previous message)")

    # -- stepping ------------------------------------------------------------------------------
    def _step(self, t: float, where: str) -> bool:
        ev = self._evaluator
        try:
            r = ev.evaluate(self.xi, self.eta, self.phi, self.N, self.mu)
        except Exception as e:  # ValueError names the input; anything else must not reach the host
            if ev is None:
                self.log(f"{where} at t={t!r}: the FMU is not initialised", Fmi2Status.error)
            else:
                self.log(f"{where} at t={t!r} refused: {type(e).__name__}: {e}; outputs keep "
                         "their last values", Fmi2Status.error)
            return False
        self.Fx = r.Fx
        self.Fy = r.Fy
        self.Mz = r.Mz
        self.a = ev.a
        self.b = ev.b
        self.p0 = ev.p0
        self.slip_fraction = r.slip_fraction
        self.method_used = ev.method_code
        if not r.converged:
            self.log(f"{where} at t={t!r}: method {r.method!r} stopped after {r.iterations} "
                     f"iterations at residual {r.residual!r}", Fmi2Status.warning)
        return True

    def do_step(self, current_time, step_size):
        return self._step(current_time, "doStep")

    # -- FMU state -----------------------------------------------------------------------------
    def _get_fmu_state(self):
        state = {v.name: v.getter() for v in self.vars.values()}
        ev = self._evaluator
        # The warm start (last loaded result, incl. an iterative method's warm_state arrays),
        # pickled now: a snapshot that later steps cannot mutate.
        state[_STATE_KEY] = (ev is not None, pickle.dumps(ev.last if ev else None, protocol=4))
        return state

    def _set_fmu_state(self, state):
        initialized, last = state[_STATE_KEY]
        for v in self.vars.values():
            setattr(self, v.name, state[v.name])
        if initialized:
            if self._evaluator is None or self._evaluator.config != self._config():
                self._make_evaluator()
            self._evaluator.last = pickle.loads(last)
        else:
            self._evaluator = None

    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        return pickle.dumps(state, protocol=4)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes):
        return pickle.loads(state)
