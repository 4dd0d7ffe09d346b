"""A trivial pythonfmu FMU with the same interface as WheelRailContact (full scene): the baseline
of ``contact_tools/bench_fmu.py``. Its step copies inputs to outputs, so its time per
setReal + doStep + getReal is pythonfmu's and the host's own overhead."""
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


class TrivialContact(Fmi2Slave):

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.xi = self.eta = self.phi = self.N = 0.0
        self.mu = 0.3
        self.Fx = self.Fy = self.Mz = self.a = self.b = self.p0 = self.slip_fraction = 0.0
        self.method_used = 0
        for name in ("xi", "eta", "phi", "N", "mu"):
            self.register_variable(Real(name, causality=Fmi2Causality.input))
        for name in ("Fx", "Fy", "Mz", "a", "b", "p0", "slip_fraction"):
            self.register_variable(Real(name, causality=Fmi2Causality.output))
        self.register_variable(Integer("method_used", causality=Fmi2Causality.output,
                                       variability=Fmi2Variability.discrete))

    def do_step(self, current_time, step_size):
        self.Fx = self.xi
        self.Fy = self.eta
        self.Mz = self.phi
        self.a = self.b = self.p0 = self.N
        self.slip_fraction = self.mu
        return True
