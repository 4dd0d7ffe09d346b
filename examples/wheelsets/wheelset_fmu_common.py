"""Shared pythonfmu plumbing of the wheelset FMUs: declare parameters, inputs and outputs.

Bundled into each wheelset FMU's ``resources/`` next to ``wheelset_dynamics.py``. No physics.
Outputs of a wheelset FMU depend on its states only (no direct feedthrough from the force inputs):
the model description says so (``dependencies=""``), which is what makes the Gauss-Seidel ordering
"contacts first, wheelset last" of ``master.py`` free of algebraic loops.
"""
from __future__ import annotations

from xml.etree.ElementTree import SubElement

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Initial

#: Contact-side outputs and inputs of a wheelset, with their units.
CONTACT_OUTPUTS = (("xi", "1", "longitudinal creepage"), ("eta", "1", "lateral creepage"),
                   ("phi", "1/m", "spin creepage"), ("N", "N", "normal load"))
CONTACT_INPUTS = (("Fx", "N", "longitudinal creep force, rail on wheel"),
                  ("Fy", "N", "lateral creep force, rail on wheel"),
                  ("Mz", "N.m", "spin moment about the contact normal, rail on wheel"))


class WheelsetSlaveBase(Fmi2Slave):
    """Registers parameters (from a list of (name, default, description)), the per-contact
    inputs/outputs and model-specific outputs; subclasses implement ``_make_model``,
    ``_update_outputs`` and ``do_step``."""

    author = "contact_core contributors"
    license = "Apache-2.0"
    version = "0.1.0"

    def _declare(self, parameters, extra_inputs=(), extra_outputs=()):
        self._param_names = []
        for name, default, desc in parameters:
            setattr(self, name, float(default))
            self._param_names.append(name)
            self.register_variable(Real(name, causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.fixed,
                                        initial=Fmi2Initial.exact, description=desc))

        def signal(name, causality, desc):
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=causality,
                                        variability=Fmi2Variability.continuous, description=desc))

        for causality, per_contact, extra in ((Fmi2Causality.input, CONTACT_INPUTS, extra_inputs),
                                              (Fmi2Causality.output, CONTACT_OUTPUTS, extra_outputs)):
            for side in ("L", "R"):
                for base, _unit, desc in per_contact:
                    signal(f"{base}_{side}", causality, f"{desc}, {side} contact")
            for name, desc in extra:
                signal(name, causality, desc)
        self._model = None

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
        return root

    def params(self) -> dict:
        return {n: float(getattr(self, n)) for n in self._param_names}

    def _set_contact_outputs(self, values: dict) -> None:
        for k, v in values.items():
            setattr(self, k, v)

    def exit_initialization_mode(self):
        self._model = self._make_model()
        self._update_outputs()
