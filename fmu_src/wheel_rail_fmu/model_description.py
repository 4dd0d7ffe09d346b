"""The FMU's model description: which variables a build exposes, and the XML pythonfmu omits.

Separation of concerns (as in FMPy): this module decides *what* the FMU declares; the slave
(:mod:`.slave`) only maps values; :mod:`.build` packs the archive.

Which variables: the build bakes a small JSON file (:data:`BUILD_CONFIG`) into the FMU's resources;
the slave reads it when instantiated (the build instantiates it once to write
modelDescription.xml, and the host at run time: both see the same resources folder), and
:func:`variables_for` turns the scene's effects into the variable list:

* inputs ``xi`` (longitudinal), ``eta`` (lateral), ``phi`` (spin) of the selected effects, ``N``
  always, ``mu`` with ``variable_friction``, the rolling speed ``V`` with ``falling_friction``;
* with ``varying_geometry`` the inputs ``A``, ``B`` (the build's ``geometry_input``
  "curvatures", the default) or ``a``, ``b`` ("semi_axes": then not outputs), instead of the
  parameters ``R_wheel``, ``R_wheel_profile``, ``R_rail_profile``
  (:func:`contact_core.variables.scene_variables`);
* outputs ``Fx`` (longitudinal), ``Fy`` (lateral), ``Mz`` (spin), and always ``a``, ``b``, ``p0``,
  ``slip_fraction``, ``method_used``;
* with ``contacts`` N > 1 (``build-fmu --contacts N``) each of those inputs and outputs once per
  contact, named ``c[k].<name>`` for k = 1 .. N (:func:`contact_variable`; FMI 2.0's structured
  naming, sec. 2.2.9), each output depending on its own contact's inputs only; the parameters
  are shared;
* parameters ``method``, ``mu`` (with ``saturation`` and without ``variable_friction``), ``E``,
  ``nu``, ``R_wheel``, ``R_wheel_profile``, ``R_rail_profile``, the friction law's
  ``friction_*`` with ``falling_friction``, and the numeric/string options of
  every method registered in :data:`contact_core.METHODS` at build time (grid sizes, tolerances...;
  an option named by several methods with different defaults becomes ``<method>_<option>``).

XML post-processing (:func:`finalize_model_description`), because pythonfmu 0.7 writes neither units
nor ``ModelStructure/InitialUnknowns``: adds ``UnitDefinitions`` and each Real's ``unit``;
rebuilds ``ModelStructure`` with ``Outputs`` (each with its input
dependencies) and
``InitialUnknowns`` (every output has ``initial="calculated"``, FMI 2.0 sec. 2.2.8, so each must be listed; no dependencies
attribute there = depends on all knowns, i.e. inputs and parameters); writes Real start values
round-trip exactly (``repr``) and finite (hosts such as OMSimulator refuse infinite values: a
straight profile radius is 0); sets a deterministic GUID and
drops ``generationDateAndTime`` unless ``SOURCE_DATE_EPOCH`` is set (reproducible builds).
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Any
from xml.etree.ElementTree import Element, SubElement

from .runtime import contact_core

#: File name of the build configuration inside the FMU's ``resources/`` folder.
BUILD_CONFIG = "wheel_rail_contact.json"

#: Units used by the FMU: name -> SI base-unit exponents (FMI 2.0 ``BaseUnit``).
UNITS: dict[str, dict[str, int]] = {
    "1": {},
    "1/m": {"m": -1},
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "m/Pa": {"kg": -1, "m": 2, "s": 2},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N.m": {"kg": 1, "m": 2, "s": -2},
    "Pa": {"kg": 1, "m": -1, "s": -2},
}


#: The Python type of the values of each FMI 2.0 variable type.
PYTHON_TYPES: dict[str, type] = {"Real": float, "Integer": int, "Boolean": bool, "String": str}


@dataclass(frozen=True)
class VarSpec:
    """One FMU variable. ``type``: Real/Integer/Boolean/String; ``depends``: for outputs, the
    inputs it depends on; ``option``: (method, option name) for method-option parameters;
    ``contact``: the contact (1 .. N) of a contact's input or output in an FMU of N > 1
    contacts, else 0; ``local``: the contact's own name of the variable (``xi`` of
    ``c[2].xi``), else ``name``."""

    name: str
    type: str
    causality: str
    variability: str
    description: str
    unit: str | None = None
    start: Any = None
    initial: str | None = None
    depends: tuple[str, ...] = ()
    option: tuple[str, str] | None = None
    contact: int = 0
    local: str = ""

    def __post_init__(self) -> None:
        if not self.local:
            object.__setattr__(self, "local", self.name)


@dataclass(frozen=True)
class BuildConfig:
    """What the build baked into the FMU (read back from :data:`BUILD_CONFIG`)."""

    scene: str
    scene_description: str
    effects: tuple[str, ...]
    method: str
    guid: str
    parameters: dict[str, Any]
    #: with ``varying_geometry``: "curvatures" (inputs A, B) or "semi_axes" (inputs a, b)
    geometry_input: str = contact_core.variables.GEOMETRY_INPUTS[0]
    #: the number of contacts (``c[k].<name>`` variables when more than one)
    contacts: int = 1

    @classmethod
    def load(cls, resources: str | os.PathLike) -> "BuildConfig":
        with open(Path(resources) / BUILD_CONFIG, encoding="utf-8") as f:
            d = json.load(f)
        return cls(d["scene"], d.get("scene_description", ""), tuple(d["effects"]), d["method"],
                   d["guid"], dict(d.get("parameters", {})),
                   d.get("geometry_input", contact_core.variables.GEOMETRY_INPUTS[0]),
                   int(d.get("contacts", 1)))

    def to_json(self) -> str:
        d = {"scene": self.scene, "scene_description": self.scene_description,
             "effects": list(self.effects), "method": self.method, "guid": self.guid,
             "parameters": self.parameters}
        if "varying_geometry" in self.effects:
            d["geometry_input"] = self.geometry_input
        if self.contacts != 1:
            d["contacts"] = self.contacts
        return json.dumps(d, indent=2, sort_keys=True) + "\n"


# ----------------------------------------------------------------------------------------------
# Which variables
# ----------------------------------------------------------------------------------------------

#: Option names never exposed: the FMU returns no traction fields, and the exact solver's
#: half-grid and warm-start switches are for benchmarks (their defaults are the best).
HIDDEN_OPTIONS = frozenset({"fields", "half", "predictor"})

_TYPES = ((bool, "Boolean"), (int, "Integer"), (float, "Real"), (str, "String"))


def _fmi_type(value: Any) -> str | None:
    for py, fmi in _TYPES:  # bool before int: bool is an int subclass
        if type(value) is py:
            return fmi
    return None


def option_parameters(methods: dict[str, type]) -> list[VarSpec]:
    """Parameters for the options of the registered methods (``contact_core.METHODS``).

    Each option whose default is a bool, int, float or str becomes a parameter named like the
    option; an option name shared by methods with different types/defaults, or clashing with
    another variable, becomes ``<method>_<option>``.
    """
    by_name: dict[str, list[tuple[str, Any]]] = {}
    for mname, cls in methods.items():
        for opt, default in cls.default_options.items():
            if opt in HIDDEN_OPTIONS or _fmi_type(default) is None:
                continue
            by_name.setdefault(opt, []).append((mname, default))
    reserved = set(contact_core.variables.BY_NAME) | set(FMU_PARAMETERS)
    specs = []
    for opt, users in by_name.items():
        shared = len({(type(d), d) for _, d in users}) == 1 and opt not in reserved
        for mname, default in users:
            if shared and specs and specs[-1].name == opt:
                continue  # one parameter serves every method with this option
            name = opt if shared else f"{mname}_{opt}"
            owners = ", ".join(repr(m) for m, _ in users) if shared else repr(mname)
            specs.append(VarSpec(
                name, _fmi_type(default), "parameter", "fixed",
                f"Option {opt!r} of method {owners} (see its documentation); default {default!r}",
                unit=(getattr(methods[mname], "option_units", {}).get(opt, "1")
                      if type(default) is float else None), start=default, initial="exact",
                option=(mname if not shared else "*", opt)))
    return specs


#: Parameters of the FMU itself (not of the contact): the method and what a refused step returns.
FMU_PARAMETERS = ("method", "invalid_input")
#: What a step with a NaN or infinite input returns (parameter ``invalid_input``).
INVALID_INPUT_CHOICES = ("discard", "error")


def _description(v) -> str:
    r = v.range
    bounded = r is not None and (r.lo, r.hi) != (-math.inf, math.inf)
    return v.description + (f"; allowed {r.text(v.name)}" if bounded else "")


#: The largest number of contacts of one FMU.
MAX_CONTACTS = 1000


def contact_variable(k: int, name: str) -> str:
    """The FMU's name of contact ``k``'s (1-based) variable ``name`` in an FMU of several
    contacts: ``c[k].name`` (FMI 2.0 structured naming, sec. 2.2.9)."""
    return f"c[{k}].{name}"


def check_contacts(contacts: Any) -> int:
    """``contacts`` as an int 1 <= N <= :data:`MAX_CONTACTS`, else ``ValueError``."""
    if isinstance(contacts, bool) or not isinstance(contacts, int) \
            or not 1 <= contacts <= MAX_CONTACTS:
        raise ValueError(f"contacts={contacts!r} is invalid: allowed an integer 1 <= contacts "
                         f"<= {MAX_CONTACTS}")
    return contacts


def _per_contact(specs: list[VarSpec], contacts: int) -> list[VarSpec]:
    """Each of ``specs`` (a contact's inputs or outputs) once per contact (module docstring)."""
    if contacts == 1:
        return specs
    return [replace(v, name=contact_variable(k, v.name), contact=k, local=v.name,
                    depends=tuple(contact_variable(k, d) for d in v.depends))
            for k in range(1, contacts + 1) for v in specs]


def variables_for(effects: tuple[str, ...], method: str, methods: dict[str, type],
                  parameters: dict[str, Any] | None = None,
                  geometry_input: str = contact_core.variables.GEOMETRY_INPUTS[0],
                  contacts: int = 1) -> list[VarSpec]:
    """The variables of an FMU built for ``effects`` with default ``method``: the contact's
    (:func:`contact_core.variables.scene_variables`), once per contact, the FMU's own
    parameters and the options of the registered methods.

    ``methods`` is the registry (name -> class with ``code`` and ``default_options``);
    ``parameters`` overrides start values of parameters by name; ``geometry_input``: how the
    geometry comes in with ``varying_geometry``; ``contacts``: their number (module docstring).
    """
    table = contact_core.variables.scene_variables(contact_core.Effects.from_names(effects),
                                                   geometry_input)
    overrides = dict(parameters or {})
    inputs = [VarSpec(v.name, v.type, "input", "continuous", _description(v), v.unit, v.default)
              for v in table if v.causality == "input"]
    all_in = tuple(v.name for v in inputs)
    outputs = []
    for v in table:
        if v.causality != "output":
            continue
        desc = v.description
        if v.name == "method_used":
            desc += ": " + ", ".join(f"{c.code} = {n}" for n, c in methods.items())
        outputs.append(VarSpec(v.name, v.type, "output",
                               "continuous" if v.type == "Real" else "discrete", desc, v.unit,
                               initial="calculated",
                               depends=all_in if v.depends is None else v.depends))
    params = [VarSpec("method", "String", "parameter", "fixed", "Contact method, one of: "
                      + ", ".join(methods), start=method, initial="exact"),
              VarSpec("invalid_input", "String", "parameter", "fixed", "Status of a step with a "
                      "NaN or infinite input: 'discard' (fmi2Discard, the host may retry) or "
                      "'error' (fmi2Error, for hosts that go on after fmi2Discard)",
                      start=INVALID_INPUT_CHOICES[0], initial="exact")]
    params += [VarSpec(v.name, v.type, "parameter", "fixed", _description(v), v.unit, v.default,
                       "exact") for v in table if v.causality == "parameter"]
    params += option_parameters(methods)

    check_contacts(contacts)
    specs = _per_contact(inputs, contacts) + _per_contact(outputs, contacts) + params
    known = {v.name for v in params}
    unknown = sorted(set(overrides) - known)
    if unknown:
        raise ValueError(f"parameters: unknown parameter(s) {unknown}; allowed: {sorted(known)}")
    return [_override(v, overrides) for v in specs]


def _override(v: VarSpec, overrides: dict[str, Any]) -> VarSpec:
    if v.name not in overrides:
        return v
    return replace(v, start=PYTHON_TYPES[v.type](overrides[v.name]))


# ----------------------------------------------------------------------------------------------
# XML post-processing
# ----------------------------------------------------------------------------------------------

def _format_real(name: str, x: float) -> str:
    if not math.isfinite(x):
        raise ValueError(f"start value {name}={x!r} is not finite: allowed a finite number")
    return repr(float(x))


def finalize_model_description(root: Element, specs: list[VarSpec], guid: str,
                               description: str) -> Element:
    """Complete pythonfmu's modelDescription (in place): see the module docstring."""
    root.set("guid", guid)
    root.set("description", description)
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch:
        root.set("generationDateAndTime", datetime.fromtimestamp(int(epoch), timezone.utc)
                 .strftime("%Y-%m-%dT%H:%M:%SZ"))
    elif "generationDateAndTime" in root.attrib:
        del root.attrib["generationDateAndTime"]

    # UnitDefinitions right after CoSimulation (schema order: CoSimulation, UnitDefinitions, ...).
    used = {v.unit for v in specs if v.unit}
    units = Element("UnitDefinitions")
    for name, exps in UNITS.items():
        if name in used:
            SubElement(SubElement(units, "Unit", name=name), "BaseUnit",
                       {k: str(e) for k, e in exps.items()})
    cs = next(i for i, c in enumerate(root) if c.tag == "CoSimulation")
    root.insert(cs + 1, units)

    by_name = {v.name: v for v in specs}
    index: dict[str, int] = {}
    mv = root.find("ModelVariables")
    for i, sv in enumerate(mv.findall("ScalarVariable"), start=1):
        name = sv.get("name")
        index[name] = i
        spec = by_name[name]
        typed = sv.find(spec.type)
        if spec.unit and spec.type == "Real":
            typed.set("unit", spec.unit)
        if spec.type == "Real" and "start" in typed.attrib:  # the value itself, not its text
            start = spec.start if spec.start is not None else float(typed.get("start"))
            typed.set("start", _format_real(name, float(start)))
    if set(index) != set(by_name):
        raise RuntimeError(f"model variables {sorted(index)} differ from the specification "
                           f"{sorted(by_name)}")

    old = root.find("ModelStructure")
    if old is not None:
        root.remove(old)
    ms = SubElement(root, "ModelStructure")
    outputs = sorted((index[v.name], v) for v in specs if v.causality == "output")
    if outputs:
        out_el = SubElement(ms, "Outputs")
        for i, v in outputs:
            deps = sorted(index[d] for d in v.depends)
            SubElement(out_el, "Unknown", index=str(i),
                       dependencies=" ".join(map(str, deps)),
                       dependenciesKind=" ".join("dependent" for _ in deps))
    initial = sorted(i for i, v in outputs if v.initial in ("approx", "calculated"))
    initial += sorted(index[v.name] for v in specs if v.causality == "calculatedParameter")
    if initial:
        ini_el = SubElement(ms, "InitialUnknowns")
        for i in sorted(initial):
            SubElement(ini_el, "Unknown", index=str(i))
    return root
