"""Shared pythonfmu plumbing of the wheelset FMUs: declare parameters, inputs and outputs; the
FMU state.

Bundled into each wheelset FMU's ``resources/`` next to ``wheelset_dynamics.py``. No physics.
Outputs of a wheelset FMU depend on its states only (no direct feedthrough from the force inputs):
the model description says so (``dependencies=""``), which is what makes the Gauss-Seidel ordering
"contacts first, wheelset last" of ``master.py`` free of algebraic loops.

Each force input ``F`` (``Fx_L``, ...) has a companion input ``F_rate`` (N/s or N.m/s, default
0): over a step from t_k the model applies F + F_rate (t - t_k), a first-order hold of the
force. It stands in for FMI 2.0's ``fmi2SetRealInputDerivatives`` (sec. 4.2.1,
``canInterpolateInputs``), which the FMI wrapper does not route to the slave; the linearly
implicit master (``master.py``) sets it.

FMU state (``canGetAndSetFMUstate``, ``canSerializeFMUstate``): a plain mapping of floats and
strings, serialised as JSON (never pickled): :data:`STATE_FORMAT`, :data:`STATE_VERSION`, the
values of every Real variable, and the model's state (``state_values`` of the model class; None
before initialisation). A deserialised state is checked (format, version, names, types) before
it is used; restoring one with other parameter values rebuilds the model from them.
"""
from __future__ import annotations

import json
import math
from xml.etree.ElementTree import SubElement

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Initial

#: Contact-side outputs and inputs of a wheelset, with their units.
CONTACT_OUTPUTS = (("xi", "1", "longitudinal creepage"), ("eta", "1", "lateral creepage"),
                   ("phi", "1/m", "spin creepage"), ("N", "N", "normal load"))
CONTACT_INPUTS = (("Fx", "N", "longitudinal creep force, rail on wheel"),
                  ("Fy", "N", "lateral creep force, rail on wheel"),
                  ("Mz", "N.m", "spin moment about the contact normal, rail on wheel"))
#: Name and version of the FMU state's format (module docstring).
STATE_FORMAT, STATE_VERSION = "wheelsets.fmu_state", 1


class StateError(ValueError):
    """A state this FMU refuses: ``fmi2Error`` with this message alone (``fmi_status``, read by
    the FMI wrapper)."""

    fmi_status = 3


class WheelsetSlaveBase(Fmi2Slave):
    """Registers parameters (from a list of (name, default, description)), the per-contact
    inputs/outputs and model-specific outputs; subclasses implement ``_make_model``,
    ``_update_outputs`` and ``do_step``."""

    author = "contact_core contributors"
    license = "Apache-2.0"
    version = "0.1.0"

    def _declare(self, parameters, extra_inputs=(), extra_outputs=()):
        """Register the parameters, the two contacts' inputs (with their rates) and outputs,
        and ``extra_inputs``, ``extra_outputs`` ((name, description) pairs)."""
        self._declare_parameters(parameters)
        for causality, per_contact, extra in ((Fmi2Causality.input, CONTACT_INPUTS, extra_inputs),
                                              (Fmi2Causality.output, CONTACT_OUTPUTS, extra_outputs)):
            for side in ("L", "R"):
                for base, _unit, desc in per_contact:
                    self._signal(f"{base}_{side}", causality, f"{desc}, {side} contact")
            if causality == Fmi2Causality.input:
                for side in ("L", "R"):
                    for base, unit, _desc in per_contact:
                        self._signal(f"{base}_{side}_rate", causality,
                                     f"rate of {base}_{side} over the step, {unit}/s: the model "
                                     f"applies {base}_{side} + {base}_{side}_rate (t - t_k) "
                                     "(0: held)")
            for name, desc in extra:
                self._signal(name, causality, desc)

    def _declare_parameters(self, parameters):
        """Register the parameters, from (name, default, description); the model is made when
        initialisation ends."""
        self._param_names = []
        for name, default, desc in parameters:
            setattr(self, name, float(default))
            self._param_names.append(name)
            self.register_variable(Real(name, causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.fixed,
                                        initial=Fmi2Initial.exact, description=desc))
        self._model = None

    def _signal(self, name, causality, desc):
        """Register a continuous Real input or output (0 until set)."""
        setattr(self, name, 0.0)
        self.register_variable(Real(name, causality=causality,
                                    variability=Fmi2Variability.continuous, description=desc))

    def to_xml(self, model_options=dict()):
        root = super().to_xml(model_options)
        structure = root.find("ModelStructure")
        outputs = structure.find("Outputs")
        if outputs is not None:
            initial = SubElement(structure, "InitialUnknowns")
            for unknown in outputs.iter("Unknown"):
                # Outputs are functions of the states only: no direct feedthrough from inputs.
                unknown.set("dependencies", "")
                # initial="calculated" (FMI 2.0 default for outputs): listed here, computed from
                # the parameters at exitInitializationMode (no dependencies attribute: all knowns).
                SubElement(initial, "Unknown", attrib={"index": unknown.get("index")})
        cosim = root.find("CoSimulation")
        cosim.set("canGetAndSetFMUstate", "true")
        cosim.set("canSerializeFMUstate", "true")
        return root

    def rates(self) -> tuple[float, ...]:
        """The force inputs' rates, in the order Fx_L, Fy_L, Mz_L, Fx_R, Fy_R, Mz_R."""
        return tuple(getattr(self, f"{base}_{side}_rate")
                     for side in ("L", "R") for base, _, _ in CONTACT_INPUTS)

    def params(self) -> dict:
        return {n: float(getattr(self, n)) for n in self._param_names}

    def _set_contact_outputs(self, values: dict) -> None:
        for k, v in values.items():
            setattr(self, k, v)

    def exit_initialization_mode(self):
        self._model = self._make_model()
        self._update_outputs()

    # -- FMU state (module docstring) ------------------------------------------------------------
    def _model_state(self) -> dict[str, float]:
        return self._model.state_values()

    def _set_model_state(self, values: dict[str, float]) -> None:
        self._model.set_state_values(values)

    def _real_names(self) -> list[str]:
        names = self.__dict__.get("_state_names")
        if names is None:   # the variables are all registered by now
            names = self._state_names = [v.name for v in self.vars.values()
                                         if isinstance(v, Real)]
        return names

    def _get_fmu_state(self) -> dict:
        return {"format": STATE_FORMAT, "version": STATE_VERSION,
                "values": {n: float(getattr(self, n)) for n in self._real_names()},
                "model": None if self._model is None else self._model_state()}

    def _check_fmu_state(self, state) -> None:
        """ValueError unless ``state`` is a state of this FMU (module docstring)."""
        if not isinstance(state, dict) or set(state) != {"format", "version", "values",
                                                         "model"}:
            raise StateError("FMU state: expected a mapping with the keys format, version, "
                             "values, model")
        if state["format"] != STATE_FORMAT or state["version"] != STATE_VERSION:
            raise StateError(f"FMU state: format {state['format']!r} version "
                             f"{state['version']!r}; allowed {STATE_FORMAT!r} version "
                             f"{STATE_VERSION}")
        values, model = state["values"], state["model"]
        if not isinstance(values, dict) or set(values) != set(self._real_names()):
            raise StateError("FMU state: values must name exactly this FMU's Real variables")
        if model is not None and not isinstance(model, dict):
            raise StateError("FMU state: model must be a mapping or null")
        for name, v in list(values.items()) + list((model or {}).items()):
            if type(v) is not float:
                raise StateError(f"FMU state: {name}={v!r} is not a float")
        for name in self._param_names:
            if not math.isfinite(values[name]):
                raise StateError(f"FMU state: parameter {name}={values[name]!r} is not finite")

    def _set_fmu_state(self, state: dict) -> None:
        # a state is this instance's own (_get_fmu_state) or was checked when deserialised
        values, model = state["values"], state["model"]
        # a refused state leaves the instance as it was: its attributes (variables, model and
        # what _make_model sets) and the model's state
        saved = dict(self.__dict__)
        saved_model_state = None if self._model is None else self._model_state()
        try:
            new_params = any(values[n] != getattr(self, n) for n in self._param_names)
            for name, value in values.items():
                setattr(self, name, value)
            if model is None:
                self._model = None
                return
            if self._model is None or new_params:
                self._model = self._make_model()
            if set(model) != set(self._model_state()):
                raise StateError("FMU state: the model's state must name "
                                 f"{sorted(self._model_state())}")
            self._set_model_state(model)
        except Exception:
            self.__dict__.clear()
            self.__dict__.update(saved)
            if saved_model_state is not None:
                self._set_model_state(saved_model_state)
            raise

    @staticmethod
    def _fmu_state_to_bytes(state: dict) -> bytes:
        return json.dumps(state).encode("utf-8")

    def _fmu_state_from_bytes(self, data: bytes) -> dict:
        try:
            state = json.loads(data.decode("utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as e:
            raise StateError(f"FMU state: not this FMU's serialised state ({e})") from None
        self._check_fmu_state(state)
        return state
