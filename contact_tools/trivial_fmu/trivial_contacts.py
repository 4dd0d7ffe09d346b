"""A trivial pythonfmu FMU with the interface of a WheelRailContact of the ``vehicle`` scene with
several contacts (``build-fmu --scene vehicle --contacts N``: inputs and outputs ``c[k].<name>``,
k = 1 .. N, N read from the resource file ``contacts.txt``): the baseline of
``contact_tools/bench_multi.py``. Its step copies inputs to outputs, so its time per
setReal + doStep + getReal is pythonfmu's and the host's own overhead for that interface."""
from pathlib import Path

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real

INPUTS = ("xi", "eta", "phi", "N", "mu", "A", "B")
OUTPUTS = ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction")


class TrivialContacts(Fmi2Slave):

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.n = int((Path(self.resources) / "contacts.txt").read_text())
        self.values = {}
        for k in range(1, self.n + 1):
            for name in INPUTS:
                self._add(Real, f"c[{k}].{name}", Fmi2Causality.input, 0.3 if name == "mu"
                          else 1.0 if name in ("A", "B") else 0.0)
            for name in OUTPUTS:
                self._add(Real, f"c[{k}].{name}", Fmi2Causality.output, 0.0)
            self._add(Integer, f"c[{k}].method_used", Fmi2Causality.output, 0,
                      Fmi2Variability.discrete)
        self.pairs = [(f"c[{k}].{i}", f"c[{k}].{o}") for k in range(1, self.n + 1)
                      for i, o in zip(INPUTS, OUTPUTS)]

    def _add(self, kind, name, causality, start, variability=None):
        self.values[name] = start
        self.register_variable(kind(name, causality=causality, variability=variability,
                                    getter=lambda: self.values[name],
                                    setter=lambda v: self.values.__setitem__(name, v)),
                               nested=False)

    def do_step(self, current_time, step_size):
        values = self.values
        for i, o in self.pairs:
            values[o] = values[i]
        return True
