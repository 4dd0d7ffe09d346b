"""The FMI 2.0 co-simulation slave: a thin adapter from FMI variables onto ``contact_core``.

No physics here: every step is :meth:`contact_core.WheelRailEvaluator.evaluate` (with the
effect ``varying_geometry``: :meth:`contact_core.VaryingGeometryEvaluator.evaluate` of the
curvature inputs A, B, or of the semi-axis inputs a, b). What this class
does: declare the variables the build chose (:mod:`.model_description`), follow the FMI 2.0
co-simulation state machine (sec. 4.2.4) and the variables' variability, build the evaluator from
the parameters at ``fmi2ExitInitializationMode``, map inputs and outputs per step, and save and
restore FMU states (:mod:`.state`).

Statuses (FMI 2.0 sec. 2.1.3), with this project's FMI wrapper (``native/fmi2_python.c``), which
tells the slave so with ``fmi_error_status=True`` and logs an exception's text before returning
its status:

* NaN or infinite input: ``fmi2DoStep`` refuses the step with ``fmi2Discard`` (the parameter
  ``invalid_input="error"`` makes it ``fmi2Error``), the message names the variable, outputs keep
  their last finite values and the instance stays usable;
* invalid parameter: ``fmi2ExitInitializationMode`` returns ``fmi2Error`` with the parameter and
  its allowed range; the parameters may be corrected and the call repeated;
* a fixed parameter or an output set when it may not be, an unknown value reference, a call in
  the wrong mode, a step size that is not > 0, a foreign, corrupted or crafted FMU state
  (outputs that are not the law's: :meth:`contact_core.WheelRailEvaluator.check_outputs`):
  ``fmi2Error``, nothing changed;
* a call that logged a warning (a step that did not converge, the table's handover, the core's
  Python warnings, which go to the logger and never to the host's warning filters):
  ``fmi2Warning`` (the wrapper returns it for any call that logged one);
* ``fmi2Fatal`` never (it means the state of all instances is corrupted).

Under pythonfmu's generic binary (the fallback where no C compiler was available), a Python
exception is ``fmi2Fatal`` and makes the binary release references twice, which crashes the
host; so there the slave raises nothing: it logs the error, leaves its state unchanged and
returns normally (``fmi2OK``), and ``fmi2DoStep`` of an instance that could not be initialised
returns ``fmi2Discard``.
"""
from __future__ import annotations

import math
from typing import Any, Mapping

from . import state as fmu_state
from .model_description import (INVALID_INPUT_CHOICES, PYTHON_TYPES, BuildConfig, VarSpec,
                                finalize_model_description, variables_for)
from .runtime import contact_core, load_notices, pythonfmu

Fmi2Status = pythonfmu.enums.Fmi2Status
_VAR_TYPES = {"Real": pythonfmu.Real, "Integer": pythonfmu.Integer,
              "Boolean": pythonfmu.Boolean, "String": pythonfmu.String}
_ZERO = {t: py() for t, py in PYTHON_TYPES.items()}  # 0.0, 0, False, ""
#: FMI options of the model description (pythonfmu's names).
MODEL_OPTIONS = {"canGetAndSetFMUstate": True, "canSerializeFMUstate": True,
                 "needsExecutionTool": False}


class FmiStatusError(Exception):
    """Raised to the FMI wrapper: it logs the text and the call returns ``fmi_status``."""

    def __init__(self, message: str, status: int = Fmi2Status.error) -> None:
        super().__init__(message)
        self.fmi_status = int(status)


def _evaluator(config):
    """The evaluator of ``config``: a fixed geometry, or one given at every step."""
    if isinstance(config, contact_core.VaryingGeometryConfig):
        return contact_core.VaryingGeometryEvaluator(config)
    return contact_core.WheelRailEvaluator(config)


def _initial(spec: VarSpec) -> Any:
    """A variable's value at instantiation: its start value, or zero (outputs)."""
    return spec.start if spec.start is not None else _ZERO[spec.type]


class WheelRailContact(pythonfmu.Fmi2Slave):

    author = "contact_core contributors"
    license = "Apache-2.0"
    version = "0.1.0"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._raises = kwargs.get("fmi_error_status") is True
        build = BuildConfig.load(self.resources)
        self._build = build
        self.guid = build.guid
        self.description = (f"Wheel-rail rolling contact (Kalker's theories, contact_core), scene "
                            f"'{build.scene}': {build.scene_description}")
        self._specs = variables_for(build.effects, build.method, contact_core.METHODS,
                                    build.parameters, build.geometry_input)
        self._names = {s.name for s in self._specs}
        # varying_geometry: the geometry inputs (curvatures A, B, or semi-axes a, b: then a and
        # b are not outputs), else None
        self._geometry = (build.geometry_input if "varying_geometry" in build.effects
                          else None)
        self._patch_outputs = self._geometry != "semi_axes"
        # Inputs of effects the scene leaves out are 0 (the core requires that); mu is a parameter
        # or an input, or unused (no saturation: the core's mu -> inf limit).
        self.xi = self.eta = self.phi = 0.0
        self.mu = contact_core.variables.DEFAULTS["mu"]
        self.V = None  # the rolling speed: an input with falling_friction only
        self._by_vr: dict[int, VarSpec] = {}
        self._refusal = Fmi2Status.discard
        self._mode = "instantiated"
        self._time = 0.0  # fmi2LastSuccessfulTime: the start time, then each step's end
        self._evaluator: contact_core.WheelRailEvaluator | None = None
        # The outputs are the law at the current inputs (the ModelStructure declares them
        # directly dependent): a set clears _fresh, an evaluation sets it, an output read
        # without it evaluates first; a step with it has nothing to compute unless the last
        # evaluation stopped before converging (_converged), which the next step goes on with.
        self._fresh = False
        self._converged = True
        self._handover_logged = False
        # The core's warnings (C33 held beyond a/b = 10, the table's fallback, an exact solve
        # that stopped early) go to the FMI logger once per kind, never to the host's warning
        # filters or stderr: contact_core.notices' sink of this thread, set around each
        # evaluation.
        self._notices = contact_core.notices.local
        self._sink = self._core_warning
        self._context: tuple[str, float] = ("", 0.0)
        self._forwarded: set[type] = set()
        for spec in self._specs:
            if hasattr(type(self), spec.name) or spec.name.startswith("_"):
                raise RuntimeError(f"variable name {spec.name!r} clashes with the slave class")
            setattr(self, spec.name, _initial(spec))
            var = _VAR_TYPES[spec.type](
                spec.name, causality=pythonfmu.Fmi2Causality[spec.causality],
                variability=pythonfmu.Fmi2Variability[spec.variability],
                initial=pythonfmu.Fmi2Initial[spec.initial] if spec.initial else None,
                description=spec.description)
            self.register_variable(var)
            self._by_vr[var.value_reference] = spec
        # Per type, value reference -> name: what may be read, and what may be set per mode
        # (FMI 2.0 sec. 4.2.4: fixed parameters only before fmi2ExitInitializationMode).
        self._readable = {t: {vr: s.name for vr, s in self._by_vr.items() if s.type == t}
                          for t in PYTHON_TYPES}
        self._outputs = {vr for vr, s in self._by_vr.items() if s.causality == "output"}
        self._settable_by_mode = {
            mode: {t: {vr: s.name for vr, s in self._by_vr.items() if s.type == t
                       and (s.causality == "input" or (s.causality == "parameter"
                                                       and mode != "step"))}
                   for t in PYTHON_TYPES}
            for mode in ("instantiated", "initialization", "step")}
        self._settable = self._settable_by_mode["instantiated"]
        for notice in load_notices():
            self.log(notice, Fmi2Status.warning)

    # -- model description ---------------------------------------------------------------------
    def to_xml(self, model_options=MODEL_OPTIONS):
        root = super().to_xml(model_options)
        return finalize_model_description(root, self._specs, self.guid, self.description)

    # -- statuses ------------------------------------------------------------------------------
    def _reject(self, message: str, status: int = Fmi2Status.error) -> None:
        """Refuse the current call with ``status`` (see the module docstring); a warning is
        logged and the call goes on."""
        if self._raises and status != Fmi2Status.warning:
            raise FmiStatusError(message, status)
        self.log(message, Fmi2Status(status))

    def _enter(self, mode: str) -> None:
        self._mode = mode
        self._settable = self._settable_by_mode.get(mode, {t: {} for t in PYTHON_TYPES})
        if mode == "step":
            self._refusal = (Fmi2Status.discard if self.invalid_input == "discard"
                             else Fmi2Status.error)

    def _expect_mode(self, where: str, *modes: str) -> bool:
        if self._mode in modes:
            return True
        self._reject(f"{where} is not allowed in {self._mode} mode (allowed in: "
                     f"{', '.join(modes)})")
        return False

    # -- state machine -------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if self._expect_mode("fmi2SetupExperiment", "instantiated"):
            self._time = float(start_time)

    def enter_initialization_mode(self):
        if self._expect_mode("fmi2EnterInitializationMode", "instantiated"):
            self._enter("initialization")
            self._evaluator = None

    def exit_initialization_mode(self):
        if not self._expect_mode("fmi2ExitInitializationMode", "initialization"):
            return
        if self._evaluator is not None or self._initial_outputs("fmi2ExitInitializationMode"):
            self._enter("step")

    def _initial_outputs(self, where: str) -> bool:
        """Outputs have initial="calculated" (FMI 2.0 sec. 2.2.7): in Initialization Mode they
        are computed from the parameters and inputs set so far, by a new evaluator (as for the
        first step), when first read or at ``fmi2ExitInitializationMode``; a value set since
        then drops them (``self._evaluator`` is None until they are computed)."""
        try:
            evaluator = _evaluator(self._config())
        except ValueError as e:  # names the parameter and its allowed range
            self._reject(f"{where}: invalid parameter: {e}")
            return False
        self._evaluator = evaluator
        if self._step(self._time, where, Fmi2Status.error):
            return True
        self._evaluator = None
        return False

    def terminate(self):
        if self._expect_mode("fmi2Terminate", "step", "initialization"):
            self._enter("terminated")

    def do_step(self, current_time, step_size):
        if self._mode != "step":
            self._expect_mode(f"fmi2DoStep at t={current_time!r}", "step")
            return False
        end = current_time + step_size
        if not (step_size > 0.0 and math.isfinite(end)):  # FMI 2.0 sec. 4.2.2: h > 0
            self._reject(f"fmi2DoStep at t={current_time!r} with communicationStepSize="
                         f"{step_size!r}: allowed a step size > 0 and a finite time")
            return False
        if not ((self._fresh and self._converged)
                or self._step(current_time, "fmi2DoStep", self._refusal)):
            return False
        self._time = end
        return True

    def last_successful_time(self) -> float:
        """fmi2GetRealStatus(fmi2LastSuccessfulTime) (FMI 2.0 sec. 4.2.3): the end of the last
        step done, or the start time before the first; an FMU state holds it."""
        return self._time

    def _core_warning(self, category: type[Warning], message: str) -> None:
        if category not in self._forwarded:
            self._forwarded.add(category)
            where, t = self._context
            self.log(f"{where} at t={t!r}: {category.__name__}: {message} (logged once per "
                     "kind)", Fmi2Status.warning)

    def _step(self, t: float, where: str, refusal: int) -> bool:
        ev = self._evaluator
        self._context = (where, t)
        self._notices.sink = self._sink
        try:
            geometry = self._geometry
            if geometry is None:
                r = ev.evaluate(self.xi, self.eta, self.phi, self.N, self.mu, self.V)
            elif geometry == "curvatures":
                r = ev.evaluate(self.xi, self.eta, self.phi, self.N, self.mu, self.A, self.B)
            else:
                r = ev.evaluate(self.xi, self.eta, self.phi, self.N, self.mu, self.a, self.b)
        except ValueError as e:  # names the input and its allowed range
            self._reject(f"{where} at t={t!r} refused: {e}; outputs keep their last values",
                         refusal)
            return False
        except Exception as e:  # a method's failure: the step cannot be done
            self._reject(f"{where} at t={t!r} failed: {type(e).__name__}: {e}")
            return False
        finally:
            self._notices.sink = None
        self.Fx = r.Fx
        self.Fy = r.Fy
        self.Mz = r.Mz
        if self._patch_outputs:
            self.a = ev.a
            self.b = ev.b
        self.p0 = ev.p0
        self.slip_fraction = r.slip_fraction
        self.method_used = ev.method_code
        self._fresh = True
        self._converged = r.converged
        if r.method != ev.config.method and not self._handover_logged:
            self._handover_logged = True
            self.log(f"{where} at t={t!r}: a/b = {ev.a / ev.b:.6g}, nu = {ev.nu:g} are outside "
                     f"the domain of method {ev.config.method!r}; its steps are solved by method "
                     f"{r.method!r} (method_used = {ev.method_code}); logged once",
                     Fmi2Status.warning)
        if not r.converged:
            self.log(f"{where} at t={t!r}: method {r.method!r} stopped after {r.iterations} "
                     f"iterations at residual {r.residual!r}", Fmi2Status.warning)
        return True

    def _config(self, values: Mapping[str, Any] | None = None) -> Any:
        """The evaluator's configuration from the parameters (this instance's, or ``values``):
        a ``WheelRailConfig``, or with ``varying_geometry`` a ``VaryingGeometryConfig``."""
        def get(name: str) -> Any:
            return values[name] if values is not None else getattr(self, name)
        choice = get("invalid_input")
        if choice not in INVALID_INPUT_CHOICES:
            raise ValueError(f"invalid_input={choice!r} is invalid: allowed "
                             f"{' or '.join(map(repr, INVALID_INPUT_CHOICES))}")
        method = get("method")
        by_method: dict[str, dict[str, Any]] = {}
        for spec in self._specs:
            if spec.option is not None:
                owner, opt = spec.option  # owner "*": shared by every method with this option
                for name, cls in contact_core.METHODS.items():
                    if owner in (name, "*") and opt in cls.default_options:
                        by_method.setdefault(name, {})[opt] = get(spec.name)
        options = by_method.pop(method, {})
        # a parameter of another method is checked too: a wrong value is an error, not ignored
        for name, others in by_method.items():
            try:
                contact_core.make_solver(name, self._build.effects, **others)
            except ValueError as e:
                raise ValueError(f"{e} (a parameter of method {name!r}, checked although "
                                 f"method={method!r} is selected)") from None
        mu = float(get("mu")) if "mu" in self._names else self.mu
        if self._geometry is not None:
            return contact_core.VaryingGeometryConfig(method=method, effects=self._build.effects,
                                                      mu=mu, E=float(get("E")),
                                                      nu=float(get("nu")), options=options,
                                                      geometry_input=self._geometry)
        friction = None
        if "friction_law" in self._names:
            friction = contact_core.variables.friction_law(
                get("friction_law"), float(get("friction_kinetic_ratio")),
                float(get("friction_slip_half")))
        return contact_core.WheelRailConfig(
            method=method, effects=self._build.effects,
            mu=mu, E=float(get("E")),
            nu=float(get("nu")), R_wheel=float(get("R_wheel")),
            R_wheel_profile=float(get("R_wheel_profile")),
            R_rail_profile=float(get("R_rail_profile")), options=options, friction=friction)

    # -- values --------------------------------------------------------------------------------
    def _lookup(self, vr: int, kind: str) -> VarSpec | None:
        spec = self._by_vr.get(vr)
        if spec is None or spec.type != kind:
            self._reject(f"valueReference {vr} is not a {kind} variable of this FMU")
            return None
        return spec

    def _get(self, vrs, kind: str) -> list:
        names = self._readable[kind]
        if not self._fresh and any(vr in self._outputs for vr in vrs):
            self._update_outputs(f"fmi2Get{kind}")
        try:
            return [getattr(self, names[vr]) for vr in vrs]
        except KeyError:
            for vr in vrs:
                self._lookup(vr, kind)
            return [_ZERO[kind]] * len(vrs)

    def _update_outputs(self, where: str) -> None:
        """The outputs for the values set since the last evaluation (FMI 2.0 sec. 2.2.8: they
        depend directly on the inputs), read in Initialization Mode (:meth:`_initial_outputs`)
        or at a communication point, where inputs a step would refuse give a warning and
        leave the last outputs."""
        if self._mode == "initialization":
            if self._evaluator is None:
                self._initial_outputs(f"{where} in initialization mode")
        elif self._evaluator is not None:  # step or terminated mode
            self._step(self._time, where, Fmi2Status.warning)

    def _set(self, vrs, values, kind: str) -> None:
        settable = self._settable[kind]
        try:
            names = [settable[vr] for vr in vrs]
        except KeyError:  # say why, change nothing
            self._refuse_set(vrs, kind)
            return
        for name, value in zip(names, values):
            setattr(self, name, value)
        self._fresh = False
        if self._mode == "initialization":
            self._evaluator = None  # the initial outputs are computed again when read

    def _refuse_set(self, vrs, kind: str) -> None:
        if self._mode == "terminated":
            self._reject(f"fmi2Set{kind} is not allowed after fmi2Terminate")
            return
        for vr in vrs:
            spec = self._lookup(vr, kind)
            if spec is None:
                return
            if spec.causality == "output":
                self._reject(f"{spec.name} is an output: it cannot be set")
                return
            if spec.variability == "fixed" and vr not in self._settable[kind]:
                self._reject(f"{spec.name} is a fixed parameter: it can be set only before "
                             f"fmi2ExitInitializationMode (it keeps its value "
                             f"{getattr(self, spec.name)!r})")
                return

    def get_real(self, vrs):
        return self._get(vrs, "Real")

    def get_integer(self, vrs):
        return self._get(vrs, "Integer")

    def get_boolean(self, vrs):
        return self._get(vrs, "Boolean")

    def get_string(self, vrs):
        return self._get(vrs, "String")

    def set_real(self, vrs, values):
        self._set(vrs, values, "Real")

    def set_integer(self, vrs, values):
        self._set(vrs, values, "Integer")

    def set_boolean(self, vrs, values):
        self._set(vrs, values, "Boolean")

    def set_string(self, vrs, values):
        self._set(vrs, values, "String")

    # -- FMU state (the state object is its serialized form: an immutable snapshot) -------------
    def _get_fmu_state(self) -> bytes:
        values = {s.name: PYTHON_TYPES[s.type](getattr(self, s.name)) for s in self._specs}
        ev = self._evaluator
        return fmu_state.write(fmu_state.FmuState(self.guid, self._mode, self._time,
                                                  self._fresh, values,
                                                  ev.last if ev is not None else None))

    def _restore(self, blob: bytes, where: str):
        """Read and check a state; returns (state, evaluator) or None after rejecting it."""
        try:
            st = fmu_state.read(blob, self.guid,
                                [(s.name, s.type, s.causality) for s in self._specs])
            evaluator = None
            if st.mode == "instantiated":  # no output computed yet
                for spec in self._specs:
                    value = st.values[spec.name]
                    if spec.causality == "output" and value != _initial(spec):
                        raise ValueError(f"{spec.name}={value!r} in a state before "
                                         f"initialization: allowed {_initial(spec)!r}")
            if st.mode in ("step", "terminated"):
                config = self._config(st.values)
                ev = self._evaluator
                evaluator = (ev if ev is not None and ev.config == config
                             else _evaluator(config))
                used = (config.method, contact_core.METHODS[config.method].fallback)
                if st.result is not None and st.result.method not in used:
                    raise ValueError(f"the state's result is of method {st.result.method!r}, "
                                     f"its parameters select {config.method!r}")
                if st.fresh:  # outputs the next read returns as they are: they must be the law's
                    v = st.values
                    geometry = ([v[n] for n in evaluator.geometry]
                                if self._geometry is not None else ())
                    evaluator.check_outputs(v["N"], v.get("mu", config.mu), v.get("Fx", 0.0),
                                            v.get("Fy", 0.0), v["a"], v["b"], v["p0"],
                                            v["slip_fraction"], *geometry)
        except ValueError as e:
            self._reject(f"{where}: {e}; the instance keeps its state")
            return None
        return st, evaluator

    def _check_fmu_state(self, state) -> None:
        self._restore(state, "fmi2DeSerializeFMUstate")

    def _set_fmu_state(self, state) -> None:
        restored = self._restore(state, "fmi2SetFMUstate")
        if restored is None:
            return
        st, evaluator = restored
        for name, value in st.values.items():
            setattr(self, name, value)
        self._enter(st.mode)
        self._time = st.time
        # in Initialization Mode the outputs are computed again when read (_initial_outputs)
        self._fresh = st.fresh and st.mode != "initialization"
        self._converged = st.result is None or st.result.converged
        if evaluator is not None:
            evaluator.last = st.result
        self._evaluator = evaluator

    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        return bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes) -> bytes:
        return bytes(state)  # checked by _check_fmu_state and again by _set_fmu_state
