"""Write the reference systems as SSP 1.0 files, for ``fmpy.ssp.simulate_ssp``.

An SSP file is a zip with ``SystemStructure.ssd`` (components, their connectors, connections) and
the FMUs under ``resources/``. ``fmpy.ssp.simulate_ssp(ssp, stop_time=..., step_size=...,
parameter_set=...)`` runs it with a fixed-step *Jacobi* master (see ``master.py`` for why the
project's default is its own Gauss-Seidel master); :func:`parameter_set` builds the
``parameter_set`` argument (names ``"component.variable"``; simulate_ssp sets Real, Integer and
Boolean parameters, not String ones, so a contact FMU's ``method`` stays the one it was built
with).

    >>> write_ssp("hunting.ssp", {"contact_L": c, "contact_R": c, "wheelset": w}, CONNECTIONS,
    ...           extra_outputs={"wheelset": ["y", "psi"]})
    >>> res = fmpy.ssp.simulate_ssp("hunting.ssp", stop_time=1.0, step_size=1e-3,
    ...                             parameter_set=parameter_set({"wheelset": {"V": 40.0}}))
    >>> res["wheelset.y"]
"""
from __future__ import annotations

import zipfile
from pathlib import Path
from typing import Iterable, Mapping
from xml.etree.ElementTree import Element, SubElement, tostring

from fmpy import read_model_description

SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"


def _connector(parent: Element, name: str, kind: str) -> None:
    c = SubElement(parent, f"{{{SSD}}}Connector", name=name, kind=kind)
    SubElement(c, f"{{{SSC}}}Real")


def write_ssp(path: str | Path, components: Mapping[str, str | Path],
              connections: Iterable[tuple[str, str]],
              extra_outputs: Mapping[str, Iterable[str]] | None = None,
              name: str = "wheelset_system") -> Path:
    """Write an SSP with the given components (name -> FMU file) and connections
    ("src.var", "dst.var"). Connections whose end is not a variable of the FMU are left out
    (as ``master.CoSimulation`` does). ``extra_outputs``: further outputs to expose (recorded by
    simulate_ssp)."""
    path = Path(path)
    variables = {n: {v.name: v for v in read_model_description(str(f)).modelVariables}
                 for n, f in components.items()}
    conns = []
    for src, dst in connections:
        sc, sv = src.split(".", 1)
        dc, dv = dst.split(".", 1)
        if sv in variables[sc] and dv in variables[dc]:
            conns.append((sc, sv, dc, dv))
    ins = {n: [] for n in components}
    outs = {n: [] for n in components}
    for sc, sv, dc, dv in conns:
        if sv not in outs[sc]:
            outs[sc].append(sv)
        ins[dc].append(dv)
    for n, vs in (extra_outputs or {}).items():
        for v in vs:
            if v not in variables[n]:
                raise KeyError(f"{n} has no variable {v!r}")
            if v not in outs[n]:
                outs[n].append(v)

    root = Element(f"{{{SSD}}}SystemStructureDescription", version="1.0", name=name)
    system = SubElement(root, f"{{{SSD}}}System", name="root")
    elements = SubElement(system, f"{{{SSD}}}Elements")
    sources = {}
    for n, f in components.items():
        fname = Path(f).name
        sources[n] = f"resources/{fname}"
        comp = SubElement(elements, f"{{{SSD}}}Component", name=n, source=sources[n],
                          type="application/x-fmu-sharedlibrary")
        connectors = SubElement(comp, f"{{{SSD}}}Connectors")
        for v in ins[n]:
            _connector(connectors, v, "input")
        for v in outs[n]:
            _connector(connectors, v, "output")
    connections_el = SubElement(system, f"{{{SSD}}}Connections")
    for sc, sv, dc, dv in conns:
        SubElement(connections_el, f"{{{SSD}}}Connection", startElement=sc, startConnector=sv,
                   endElement=dc, endConnector=dv)
    xml = b'<?xml version="1.0" encoding="UTF-8"?>\n' + tostring(root)
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", xml)
        for f in sorted({Path(f) for f in components.values()}):
            z.write(f, f"resources/{f.name}")
    return path


def parameter_set(values: Mapping[str, Mapping[str, float]]):
    """An fmpy ``ParameterSet`` from {component: {variable: value}} (Real/Integer/Boolean)."""
    from fmpy.ssp.ssd import Parameter, ParameterSet
    ps = ParameterSet(name="parameters")
    for comp, vals in values.items():
        for k, v in vals.items():
            ps.parameters.append(Parameter(name=f"{comp}.{k}", type="Real", value=v))
    return ps
