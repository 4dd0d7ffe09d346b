"""The FMI 2.0 co-simulation slave: a thin adapter from FMI variables onto ``contact_core``.

No physics here: every step is :meth:`contact_core.Contacts.evaluate` of the FMU's contacts
(one, or N with ``build-fmu --contacts N``), each a :class:`contact_core.WheelRailEvaluator`
(with the effect ``varying_geometry``: a :class:`contact_core.VaryingGeometryEvaluator` of the
curvature inputs A, B, or of the semi-axis inputs a, b). What this class does: declare the
variables the build chose (:mod:`.model_description`), follow the FMI 2.0 co-simulation state
machine (sec. 4.2.4) and the variables' variability, build the contacts from the parameters at
``fmi2ExitInitializationMode``, keep the values, give the directional derivatives of the
outputs (``fmi2GetDirectionalDerivative``, from :meth:`contact_core.Contacts.jacobian`), and
save and restore FMU states (:mod:`.state`).

Values: every Real variable (and the Integer output ``method_used``) lives in one array of
floats indexed by value reference, :attr:`_fmi_reals`, which the contacts read their inputs from
and write their outputs to (with a few slots of their own after the variables: a zero for the
inputs of effects the scene leaves out, the friction coefficient where it is not a variable, a
scratch slot for outputs the scene does not have). This project's FMI wrapper
(``native/fmi2_python.c``) reads and writes that array directly for ``fmi2SetReal`` of inputs in
Step Mode and ``fmi2GetReal`` of values that are up to date, without calling Python: the bytes
of :attr:`_fmi_flags` say per value reference what it may do (:data:`FAST_REAL`,
:data:`FAST_OUTPUT`, :data:`FAST_SETTABLE`), and the last byte whether the outputs are those of
the inputs (a set clears it). Everything else goes through the methods below, which the wrapper
calls otherwise and which pythonfmu's generic binary always calls.

Statuses (FMI 2.0 sec. 2.1.3), with this project's FMI wrapper, which tells the slave so with
``fmi_error_status=True`` and logs an exception's text before returning its status:

* NaN or infinite input: ``fmi2DoStep`` refuses the step with ``fmi2Discard`` (the parameter
  ``invalid_input="error"`` makes it ``fmi2Error``), the message names the variable (and, with
  several contacts, the contact: ``c[3]: xi=nan is out of range ...``), the outputs of every
  contact keep their last values, so do the warm starts, and the instance stays usable;
* invalid parameter: ``fmi2ExitInitializationMode`` returns ``fmi2Error`` with the parameter and
  its allowed range; the parameters may be corrected and the call repeated;
* a fixed parameter or an output set when it may not be, an unknown value reference, a call in
  the wrong mode (FMI 2.0 sec. 4.2.4), a step size that is not > 0, a start time that is not
  finite, a foreign, corrupted or crafted FMU state (outputs that are not the law's:
  :meth:`contact_core.WheelRailEvaluator.check_outputs`), a directional derivative of something
  that is not a Real output by a Real input: ``fmi2Error``, nothing changed;
* a call that logged a warning (a step that did not converge, the table's handover, the core's
  Python warnings, which go to the logger and never to the host's warning filters):
  ``fmi2Warning`` (the wrapper returns it for any call that logged one);
* ``fmi2Fatal`` never (it means the state of all instances is corrupted).

Under pythonfmu's generic binary (the fallback where no C compiler was available), a Python
exception is ``fmi2Fatal`` and makes the binary release references twice, which crashes the
host; so there the slave raises nothing: it logs the error, leaves its state unchanged and
returns normally (``fmi2OK``), and ``fmi2DoStep`` of an instance that could not be initialised
returns ``fmi2Discard``. That binary has no directional derivatives.
"""
from __future__ import annotations

import math
from array import array
from typing import Any, Mapping

from . import state as fmu_state
from .model_description import (INVALID_INPUT_CHOICES, PYTHON_TYPES, BuildConfig, VarSpec,
                                contact_variable, finalize_model_description, variables_for)
from .runtime import contact_core, load_notices, pythonfmu

Fmi2Status = pythonfmu.enums.Fmi2Status
_VAR_TYPES = {"Real": pythonfmu.Real, "Integer": pythonfmu.Integer,
              "Boolean": pythonfmu.Boolean, "String": pythonfmu.String}
_ZERO = {t: py() for t, py in PYTHON_TYPES.items()}  # 0.0, 0, False, ""
#: FMI options of the model description (pythonfmu's names).
MODEL_OPTIONS = {"canGetAndSetFMUstate": True, "canSerializeFMUstate": True,
                 "needsExecutionTool": False}
#: Bits of :attr:`WheelRailContact._fmi_flags` per value reference (module docstring): a Real
#: variable, an output (read directly only while the outputs are up to date), a Real the
#: wrapper may set directly now (the inputs, in Step Mode).
FAST_REAL, FAST_OUTPUT, FAST_SETTABLE = 1, 2, 4
#: Where a variable's value is kept: a float slot, an Integer in a float slot (method_used),
#: a Python object.
_FLOAT, _INT, _OBJECT = 0, 1, 2
#: The contacts' slots after the variables: a zero, the friction coefficient where it is not a
#: variable, a scratch slot.
_ZERO_SLOT, _MU_SLOT, _SCRATCH_SLOT, _EXTRA_SLOTS = 0, 1, 2, 3


class FmiStatusError(Exception):
    """Raised to the FMI wrapper: it logs the text and the call returns ``fmi_status``."""

    def __init__(self, message: str, status: int = Fmi2Status.error) -> None:
        super().__init__(message)
        self.fmi_status = int(status)


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
                                    build.parameters, build.geometry_input, build.contacts)
        self._n_contacts = build.contacts
        self._names = {s.local for s in self._specs}
        # varying_geometry: the geometry inputs (curvatures A, B, or semi-axes a, b: then a and
        # b are not outputs), else None
        self._geometry = (build.geometry_input if "varying_geometry" in build.effects
                          else None)
        self._by_vr: dict[int, VarSpec] = {}
        self._refusal = Fmi2Status.discard
        self._mode = "instantiated"
        self._time = 0.0  # fmi2LastSuccessfulTime: the start time, then each step's end
        self._contacts: contact_core.Contacts | None = None
        # The outputs are the law at the current inputs (the ModelStructure declares them
        # directly dependent): a set clears _fresh, an evaluation sets it, an output read
        # without it evaluates first; a step with it has nothing to compute unless the last
        # evaluation stopped before converging (_converged), which the next step goes on with.
        self._converged = True
        self._handover_logged = False
        self._jacobians: dict[int, Any] = {}
        # The core's warnings (C33 held beyond a/b = 10, the table's fallback, an exact solve
        # that stopped early) go to the FMI logger once per kind, never to the host's warning
        # filters or stderr: contact_core.notices' sink of this thread, set around each
        # evaluation.
        self._notices = contact_core.notices.local
        self._sink = self._core_warning
        self._context: tuple[str, float] = ("", 0.0)
        self._forwarded: set[type] = set()
        n = len(self._specs)
        #: Real values (and method_used) by value reference, then the contacts' own slots
        self._fmi_reals = array("d", bytes(8 * (n + _EXTRA_SLOTS)))
        #: per value reference the FAST_* bits; the last byte: the outputs are up to date
        self._fmi_flags = bytearray(n + 1)
        self._objects: dict[int, Any] = {}
        self._where: dict[int, int] = {}
        self._vr: dict[str, int] = {}
        for spec in self._specs:
            var = _VAR_TYPES[spec.type](
                spec.name, causality=pythonfmu.Fmi2Causality[spec.causality],
                variability=pythonfmu.Fmi2Variability[spec.variability],
                initial=pythonfmu.Fmi2Initial[spec.initial] if spec.initial else None,
                description=spec.description, getter=lambda: None)
            self.register_variable(var, nested=False)
            vr = var.value_reference
            self._by_vr[vr] = spec
            self._vr[spec.name] = vr
            if spec.type == "Real":
                self._where[vr] = _FLOAT
                self._fmi_flags[vr] = FAST_REAL | (FAST_OUTPUT if spec.causality == "output"
                                                   else 0)
            else:
                self._where[vr] = _INT if spec.causality == "output" else _OBJECT
            self._store(vr, _initial(spec))
        self._slot = {"zero": n + _ZERO_SLOT, "mu": n + _MU_SLOT, "scratch": n + _SCRATCH_SLOT}
        self._fmi_reals[self._slot["mu"]] = contact_core.variables.DEFAULTS["mu"]
        # Per type, value reference -> where its value is: what may be read, and what may be
        # set per mode (FMI 2.0 sec. 4.2.4: fixed parameters only before
        # fmi2ExitInitializationMode).
        self._readable = {t: {vr: self._where[vr] for vr, s in self._by_vr.items()
                              if s.type == t} for t in PYTHON_TYPES}
        self._outputs = {vr for vr, s in self._by_vr.items() if s.causality == "output"}
        self._settable_by_mode = {
            mode: {t: {vr: self._where[vr] for vr, s in self._by_vr.items() if s.type == t
                       and (s.causality == "input" or (s.causality == "parameter"
                                                       and mode != "step"))}
                   for t in PYTHON_TYPES}
            for mode in ("instantiated", "initialization", "step")}
        self._settable = self._settable_by_mode["instantiated"]
        # directional derivatives: Real outputs and Real inputs by value reference -> (contact
        # (0-based), the contact's own name)
        self._unknowns = {vr: (max(s.contact, 1) - 1, s.local) for vr, s in self._by_vr.items()
                          if s.causality == "output" and s.type == "Real"}
        self._knowns = {vr: (max(s.contact, 1) - 1, s.local) for vr, s in self._by_vr.items()
                        if s.causality == "input" and s.type == "Real"}
        for notice in load_notices():
            self.log(notice, Fmi2Status.warning)

    # -- values --------------------------------------------------------------------------------
    def _store(self, vr: int, value: Any) -> None:
        if self._where[vr] == _OBJECT:
            self._objects[vr] = value
        else:
            self._fmi_reals[vr] = value

    def _load(self, vr: int) -> Any:
        where = self._where[vr]
        if where == _FLOAT:
            return self._fmi_reals[vr]
        return int(self._fmi_reals[vr]) if where == _INT else self._objects[vr]

    def _named(self, name: str) -> Any:
        """The value of the variable ``name``."""
        return self._load(self._vr[name])

    def _contact_name(self, k: int, name: str) -> str:
        """The FMU's name of contact ``k``'s (1-based) variable ``name``."""
        return contact_variable(k, name) if self._n_contacts > 1 else name

    def _contact_index(self, inputs: tuple[str, ...], k: int) -> list[int]:
        """Where contact ``k``'s ``inputs`` (:func:`contact_core.contacts.contact_inputs`) and
        outputs are (:class:`contact_core.Contacts`): a variable, or the slots of those the
        scene does not have."""
        out = []
        for name in inputs:
            vr = self._vr.get(self._contact_name(k, name))
            if vr is None and name == "mu":
                vr = self._vr.get("mu", self._slot["mu"])    # a parameter, or not used
            out.append(self._slot["zero"] if vr is None else vr)
        for name in contact_core.contacts.OUTPUTS:
            name = "method_used" if name == "method_code" else name
            vr = self._vr.get(self._contact_name(k, name))
            # (a, b with geometry_input="semi_axes" are inputs)
            is_output = vr is not None and self._by_vr[vr].causality == "output"
            out.append(vr if is_output else self._slot["scratch"])
        return out

    @property
    def _fresh(self) -> bool:
        return self._fmi_flags[-1] != 0

    @_fresh.setter
    def _fresh(self, value: bool) -> None:
        self._fmi_flags[-1] = 1 if value else 0

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
        flags = self._fmi_flags
        fast = self._settable["Real"] if mode == "step" else {}
        for vr, spec in self._by_vr.items():
            if spec.type == "Real":
                flags[vr] = (flags[vr] & ~FAST_SETTABLE) | (FAST_SETTABLE if vr in fast else 0)
        if mode == "step":
            self._refusal = (Fmi2Status.discard if self._named("invalid_input") == "discard"
                             else Fmi2Status.error)

    def _expect_mode(self, where: str, *modes: str) -> bool:
        if self._mode in modes:
            return True
        self._reject(f"{where} is not allowed in {self._mode} mode (allowed in: "
                     f"{', '.join(modes)})")
        return False

    # -- state machine -------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if not self._expect_mode("fmi2SetupExperiment", "instantiated"):
            return
        if not math.isfinite(start_time):  # it is the last successful time an FMU state holds
            self._reject(f"fmi2SetupExperiment: startTime={start_time!r} is out of range: "
                         "allowed a finite number")
            return
        self._time = float(start_time)

    def enter_initialization_mode(self):
        if self._expect_mode("fmi2EnterInitializationMode", "instantiated"):
            self._enter("initialization")
            self._contacts = None

    def exit_initialization_mode(self):
        if not self._expect_mode("fmi2ExitInitializationMode", "initialization"):
            return
        if self._contacts is not None or self._initial_outputs("fmi2ExitInitializationMode"):
            self._enter("step")

    def _initial_outputs(self, where: str) -> bool:
        """Outputs have initial="calculated" (FMI 2.0 sec. 2.2.7): in Initialization Mode they
        are computed from the parameters and inputs set so far, by new contacts (as for the
        first step), when first read or at ``fmi2ExitInitializationMode``; a value set since
        then drops them (``self._contacts`` is None until they are computed)."""
        try:
            contacts = self._new_contacts(self._config())
        except ValueError as e:  # names the parameter and its allowed range
            self._reject(f"{where}: invalid parameter: {e}")
            return False
        self._contacts = contacts
        done = False
        try:  # (a refusal raises: the contacts go all the same)
            done = self._step(self._time, where, Fmi2Status.error)
        finally:
            if not done:
                self._contacts = None
        return done

    def _new_contacts(self, config) -> contact_core.Contacts:
        self._fmi_reals[self._slot["mu"]] = config.mu
        inputs = contact_core.contacts.contact_inputs(config)
        index = [self._contact_index(inputs, k) for k in range(1, self._n_contacts + 1)]
        return contact_core.Contacts(config, self._fmi_reals, index)

    def terminate(self):
        # FMI 2.0 sec. 4.2.4: from Step Mode only (not from Initialization Mode)
        if self._expect_mode("fmi2Terminate", "step"):
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
        if not ((self._fmi_flags[-1] and self._converged)
                or self._step(current_time, "fmi2DoStep", self._refusal)):
            return False
        self._time = end
        return True

    def last_successful_time(self) -> float:
        """fmi2GetRealStatus(fmi2LastSuccessfulTime) (FMI 2.0 sec. 4.2.3): the end of the last
        step done, or the start time before the first; an FMU state holds it. Allowed in Step
        Mode and after fmi2Terminate (sec. 4.2.4), an error before."""
        self._expect_mode("fmi2GetRealStatus", "step", "terminated")
        return self._time

    def _core_warning(self, category: type[Warning], message: str) -> None:
        if category not in self._forwarded:
            self._forwarded.add(category)
            where, t = self._context
            self.log(f"{where} at t={t!r}: {category.__name__}: {message} (logged once per "
                     "kind)", Fmi2Status.warning)

    def _which(self, index: int) -> str:
        """How messages name contact ``index`` (0-based): ``c[k]: ``, or nothing with one."""
        return f"c[{index + 1}]: " if self._n_contacts > 1 else ""

    def _step(self, t: float, where: str, refusal: int) -> bool:
        contacts = self._contacts
        self._context = (where, t)
        self._notices.sink = self._sink
        try:
            notes = contacts.evaluate()
        except contact_core.ContactInputError as e:  # names the input and its allowed range
            self._reject(f"{where} at t={t!r} refused: {self._which(e.index)}{e}; outputs "
                         "keep their last values", refusal)
            return False
        except contact_core.ContactFailure as e:     # a method's failure: no step
            self._reject(f"{where} at t={t!r} failed: {self._which(e.index)}{e}")
            return False
        finally:
            self._notices.sink = None
        self._fmi_flags[-1] = 1
        self._jacobians.clear()
        self._converged = True
        for i, r in notes:
            ev = contacts.evaluators[i]
            if r.method != ev.config.method and not self._handover_logged:
                self._handover_logged = True
                self.log(f"{where} at t={t!r}: {self._which(i)}a/b = {ev.a / ev.b:.6g}, nu = "
                         f"{ev.nu:g} are outside the domain of method {ev.config.method!r}; its "
                         f"steps are solved by method {r.method!r} (method_used = "
                         f"{ev.method_code}); logged once", Fmi2Status.warning)
            if not r.converged:
                self._converged = False
                self.log(f"{where} at t={t!r}: {self._which(i)}method {r.method!r} stopped "
                         f"after {r.iterations} iterations at residual {r.residual!r}",
                         Fmi2Status.warning)
        return True

    def _config(self, values: Mapping[str, Any] | None = None) -> Any:
        """The contacts' configuration from the parameters (this instance's, or ``values``):
        a ``WheelRailConfig``, or with ``varying_geometry`` a ``VaryingGeometryConfig``."""
        def get(name: str) -> Any:
            return values[name] if values is not None else self._named(name)
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
        # the parameter mu; an input mu (variable_friction) is each step's, not the build's
        mu = (float(get("mu")) if "mu" in self._vr
              and self._by_vr[self._vr["mu"]].causality == "parameter"
              else contact_core.variables.DEFAULTS["mu"])
        friction = None
        if "friction_law" in self._names:
            friction = contact_core.variables.friction_law(
                get("friction_law"), float(get("friction_kinetic_ratio")),
                float(get("friction_slip_half")))
        if self._geometry is not None:
            return contact_core.VaryingGeometryConfig(method=method, effects=self._build.effects,
                                                      mu=mu, E=float(get("E")),
                                                      nu=float(get("nu")), options=options,
                                                      geometry_input=self._geometry,
                                                      friction=friction)
        return contact_core.WheelRailConfig(
            method=method, effects=self._build.effects,
            mu=mu, E=float(get("E")),
            nu=float(get("nu")), R_wheel=float(get("R_wheel")),
            R_wheel_profile=float(get("R_wheel_profile")),
            R_rail_profile=float(get("R_rail_profile")), options=options, friction=friction)

    # -- get and set ---------------------------------------------------------------------------
    def _lookup(self, vr: int, kind: str) -> VarSpec | None:
        spec = self._by_vr.get(vr)
        if spec is None or spec.type != kind:
            self._reject(f"valueReference {vr} is not a {kind} variable of this FMU")
            return None
        return spec

    def _get(self, vrs, kind: str) -> list:
        readable = self._readable[kind]
        wheres = [readable.get(vr) for vr in vrs]
        if None in wheres:  # say why before computing anything: a refused call changes nothing
            self._lookup(vrs[wheres.index(None)], kind)
            return [_ZERO[kind]] * len(vrs)
        if not self._fmi_flags[-1] and not self._outputs.isdisjoint(vrs):
            self._update_outputs(f"fmi2Get{kind}")
        reals, objects = self._fmi_reals, self._objects
        return [reals[vr] if where == _FLOAT else int(reals[vr]) if where == _INT
                else objects[vr] for vr, where in zip(vrs, wheres)]

    def _update_outputs(self, where: str) -> None:
        """The outputs for the values set since the last evaluation (FMI 2.0 sec. 2.2.8: they
        depend directly on the inputs), read in Initialization Mode (:meth:`_initial_outputs`)
        or at a communication point, where inputs a step would refuse give a warning and
        leave the last outputs."""
        if self._mode == "initialization":
            if self._contacts is None:
                self._initial_outputs(f"{where} in initialization mode")
        elif self._contacts is not None:  # step or terminated mode
            self._step(self._time, where, Fmi2Status.warning)

    def _set(self, vrs, values, kind: str) -> None:
        if self._mode == "terminated":  # even no value (FMI 2.0 sec. 4.2.4)
            self._refuse_set(vrs, kind)
            return
        settable = self._settable[kind]
        try:
            wheres = [settable[vr] for vr in vrs]
        except KeyError:  # say why, change nothing
            self._refuse_set(vrs, kind)
            return
        reals, objects = self._fmi_reals, self._objects
        for vr, where, value in zip(vrs, wheres, values):
            if where == _FLOAT:
                reals[vr] = value
            else:
                objects[vr] = value
        self._fmi_flags[-1] = 0
        if self._mode == "initialization":
            self._contacts = None  # the initial outputs are computed again when read

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
                             f"{self._load(vr)!r})")
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

    # -- directional derivatives (FMI 2.0 sec. 2.1.9; called by this project's wrapper) ---------
    def get_directional_derivative(self, unknowns, knowns, seed) -> list[float]:
        """fmi2GetDirectionalDerivative: Σ_j ∂unknown_i/∂known_j seed_j for Real outputs
        ``unknowns`` and Real inputs ``knowns`` (value references) at the current inputs, from
        each contact's Jacobian (:meth:`contact_core.Contacts.jacobian`; zero between
        different contacts). Refused (``fmi2Error``, nothing changed) outside Initialization
        Mode, Step Mode and Terminated, for anything else than a Real output by a Real input,
        a seed that is not finite, or inputs the law refuses."""
        where = "fmi2GetDirectionalDerivative"
        zero = [0.0] * len(unknowns)
        if not self._expect_mode(where, "initialization", "step", "terminated"):
            return zero
        rows, cols = [], []
        for vr in unknowns:
            if vr not in self._unknowns:
                self._reject(f"{where}: valueReference {vr} is not a Real output of this FMU "
                             "(allowed: the outputs, by the inputs they depend on)")
                return zero
            rows.append(self._unknowns[vr])
        for vr, s in zip(knowns, seed):
            if vr not in self._knowns:
                self._reject(f"{where}: valueReference {vr} is not a Real input of this FMU "
                             "(allowed: the inputs)")
                return zero
            if not math.isfinite(s):
                self._reject(f"{where}: the seed of {self._by_vr[vr].name}, {s!r}, is not "
                             "finite: allowed a finite number")
                return zero
            cols.append(self._knowns[vr])
        if not self._fmi_flags[-1]:
            self._update_outputs(where)
            if not self._fmi_flags[-1]:
                self._reject(f"{where}: the outputs cannot be computed at the current inputs "
                             "(see the message before)")
                return zero
        out = []
        for i, name in rows:
            total = 0.0
            for (j, known), s in zip(cols, seed):
                if j == i and s:
                    jac = self._jacobian(i, where)
                    if jac is None:
                        return zero
                    total += jac[name, known] * s
            out.append(total)
        return out

    def _jacobian(self, i: int, where: str) -> Any:
        """Contact ``i``'s Jacobian at its current inputs (kept until they change), or None
        after rejecting the call."""
        jac = self._jacobians.get(i)
        if jac is None:
            self._notices.sink = self._sink
            self._context = (where, self._time)
            try:
                jac = self._contacts.jacobian(i)
            except ValueError as e:
                self._reject(f"{where}: {self._which(i)}{e}")
                return None
            finally:
                self._notices.sink = None
            self._jacobians[i] = jac
        return jac

    # -- FMU state (the state object is its serialized form: an immutable snapshot) -------------
    def _get_fmu_state(self) -> bytes:
        values = {s.name: PYTHON_TYPES[s.type](self._load(vr)) for vr, s in self._by_vr.items()}
        c = self._contacts
        results = ([ev.last for ev in c.evaluators] if c is not None
                   else [None] * self._n_contacts)
        return fmu_state.write(fmu_state.FmuState(
            self.guid, self._mode, self._time, self._fresh, values,
            results[0] if self._n_contacts == 1 else results))

    def _restore(self, blob: bytes, where: str):
        """Read and check a state; returns (state, contacts) or None after rejecting it."""
        try:
            st = fmu_state.read(blob, self.guid,
                                [(s.name, s.type, s.causality) for s in self._specs],
                                self._n_contacts)
            contacts = None
            if st.mode == "instantiated":  # no output computed yet
                for spec in self._specs:
                    value = st.values[spec.name]
                    if spec.causality == "output" and value != _initial(spec):
                        raise ValueError(f"{spec.name}={value!r} in a state before "
                                         f"initialization: allowed {_initial(spec)!r}")
            if st.mode in ("step", "terminated"):
                config = self._config(st.values)
                c = self._contacts
                contacts = c if c is not None and c.config == config else \
                    self._new_contacts(config)
                used = (config.method, contact_core.METHODS[config.method].fallback)
                results = st.result if self._n_contacts > 1 else [st.result]
                for k, r in enumerate(results, start=1):
                    if r is not None and r.method not in used:
                        raise ValueError(f"the state's result of {self._contact_name(k, 'Fx')}"
                                         f" is of method {r.method!r}, its parameters select "
                                         f"{config.method!r}")
                if st.fresh:  # outputs the next read returns as they are: they must be the law's
                    for k, ev in enumerate(contacts.evaluators, start=1):
                        self._check_outputs(ev, st.values, k, config)
        except ValueError as e:
            self._reject(f"{where}: {e}; the instance keeps its state")
            return None
        return st, contacts

    def _check_outputs(self, ev, values: Mapping[str, Any], k: int, config) -> None:
        """Contact ``k``'s outputs of a restored state, checked as the law's
        (``check_outputs``, whose message is prefixed with the contact's name)."""
        def v(name, default=None):
            full = self._contact_name(k, name)
            if full in values:
                return values[full]
            if default is None:
                return values[name]
            return values.get(name, default)
        geometry = ([v(n) for n in ev.geometry] if self._geometry is not None else ())
        try:
            ev.check_outputs(v("N"), v("mu", config.mu), v("Fx", 0.0), v("Fy", 0.0), v("a"),
                             v("b"), v("p0"), v("slip_fraction"), *geometry)
        except ValueError as e:
            raise ValueError(f"{self._which(k - 1)}{e}") from None

    def _check_fmu_state(self, state) -> None:
        self._restore(state, "fmi2DeSerializeFMUstate")

    def _set_fmu_state(self, state) -> None:
        restored = self._restore(state, "fmi2SetFMUstate")
        if restored is None:
            return
        st, contacts = restored
        for name, value in st.values.items():
            self._store(self._vr[name], value)
        self._enter(st.mode)
        self._time = st.time
        # in Initialization Mode the outputs are computed again when read (_initial_outputs)
        self._fresh = st.fresh and st.mode != "initialization"
        results = st.result if self._n_contacts > 1 else [st.result]
        self._converged = all(r is None or r.converged for r in results)
        if contacts is not None:
            for i, r in enumerate(results):
                contacts.set_last(i, r)
        self._contacts = contacts
        self._jacobians.clear()

    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        return bytes(state)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes) -> bytes:
        return bytes(state)  # checked by _check_fmu_state and again by _set_fmu_state
