"""The linear estimate of the real-profile wheelset's critical speed: the linear wheelset of
``linear_model`` with the quasi-linear parameters of the contact-geometry table at an amplitude of
the motion.

Real profiles make the wheelset's geometry nonlinear in y; for a hunting motion y = A sin τ each
nonlinear function of y is replaced by the gain of its first harmonic (harmonic linearisation, the
describing function; Polach 2010, Vehicle System Dynamics 48 S1, for the contact geometry; EN
15302 for the equivalent conicity),

    g(A) = 1/(πA) ∫_0^{2π} f(A sin τ) sin τ dτ,

and the 4-state linear wheelset of ``linear_model`` (Wickens 2003, single wheelset with Kalker's
linear creep coefficients) takes

* λ = the equivalent conicity γ_e(A) (``ContactTable.equivalent_conicity``: g of Δr, halved);
* r0, b0: the centred wheelset's rolling radius and half distance between its contact points;
* Kalker's f11, f22, f23, f33 of the centred tread contact (its A, B from the table, half the
  axle load; ``profile_systems.centred_contact``);
* the lateral force of the normal loads, F_N(y) = Σ N_i sin δ_i of the nonlinear model at rest
  (``ProfileWheelset``'s load sharing without creep forces): F_N ≈ −K_g y with the
  gravitational stiffness K_g = −g_{F_N}(A) (Wickens 2003: the lateral components of the normal
  loads, from the contact-angle difference of the two wheels; zero for cones);
* the spin of the contact angle: each patch spins at sin δ_i / r0 + ψ̇/V (``profile_dynamics``:
  pitch rate −V/r0 about the axle; the spin creepage of a wheel on a contact plane inclined by
  δ, Kalker 1979 sec. 2 and fig. 2c), so the wheels' spin sum, weighted by their loads, is
  F_N(y)/(W/2 r0) + 2ψ̇/V; in Kalker's linear theory (Kalker 1979: Fy = −f23 φ, Mz = −f33 φ)
  its lateral force and yaw moment are −f23 and −f33 times that: lateral stiffness
  K_φy = f23 g_{F_N}/(W/2 r0), yaw coupling K_φψ = f33 g_{F_N}/(W/2 r0) (derived here from
  these two, with f23 and f33 of the centred contact).

The critical speed of that model at amplitude A is the speed at which a hunting motion of that
amplitude neither grows nor decays, to the accuracy of harmonic linearisation: the co-simulation's
limit cycle at speed V has the amplitude A at which the estimate is V (the describing-function
prediction of a limit cycle by harmonic balance, A. Gelb & W. E. Vander Velde, *Multiple-Input
Describing Functions and Nonlinear System Design*, McGraw-Hill 1968; for the wheelset's
contact geometry through γ_e(A), Polach 2010).
"""
from __future__ import annotations

import numpy as np

from contact_core.geometry.table import harmonic_gain as table_harmonic_gain

from .linear_model import LinearWheelset
from .profile_dynamics import ProfileParams, ProfileWheelset
from .profile_systems import centred_contact
from .wheelset_dynamics import LateralState


def harmonic_gain(f, amplitude: float, n: int = 512) -> float:
    """g(A) of the module docstring for a scalar function ``f`` of y
    (:func:`contact_core.geometry.table.harmonic_gain`, ``n`` points over a period)."""
    return float(table_harmonic_gain(np.vectorize(f, otypes=[float]), amplitude, n)[0])


def normal_load_force(table, nominal_radius: float, axle_load: float = 100e3):
    """F_N(y): the lateral force of the normal loads on the wheelset at rest (N, track frame),
    from :class:`profile_dynamics.ProfileWheelset`'s load sharing."""
    w = ProfileWheelset(ProfileParams(axle_load=axle_load), table, nominal_radius,
                        LateralState())

    def force(y: float) -> float:
        w.s.y = float(y)
        return -sum(w.loads().Y.values())
    return force


class ProfileLinearWheelset(LinearWheelset):
    """:class:`linear_model.LinearWheelset` with the real profiles' quasi-linear parameters at
    ``amplitude`` (m; module docstring). Attributes: ``lam`` (γ_e), ``K_g`` (N/m), ``K_phi_y``
    (N/m), ``K_phi_psi`` (N), and the inherited ``f`` (Kalker's coefficients)."""

    def __init__(self, table, amplitude: float, nominal_radius: float = 0.46, m: float = 1500.0,
                 I_z: float = 800.0, k_y: float = 1e6, k_psi: float = 2e6,
                 axle_load: float = 100e3) -> None:
        c = centred_contact(table, axle_load)
        lam = float(table.equivalent_conicity(amplitude)[0])
        super().__init__(m=m, I_z=I_z, r0=c["r"], b0=c["b0"], conicity=lam, k_y=k_y,
                         k_psi=k_psi, axle_load=axle_load, E=table.E, nu=table.nu)
        self.f = {k: c[k] for k in ("f11", "f22", "f23", "f33", "a", "b")}
        self.amplitude = amplitude
        gain = harmonic_gain(normal_load_force(table, nominal_radius, axle_load), amplitude)
        self.K_g = -gain
        per_spin = gain / (0.5 * axle_load * c["r"])
        self.K_phi_y = self.f["f23"] * per_spin
        self.K_phi_psi = self.f["f33"] * per_spin

    def split(self, V):
        """As ``LinearWheelset.split``, with the normal loads' lateral force (gravitational
        stiffness, Wickens 2003) and the contact angle's spin (Kalker's f23, f33) in the creep
        forces (module docstring: derived there)."""
        As, Bs, Kc = super().split(V)
        Kc = Kc.copy()
        Kc[0, 0] -= self.K_g + self.K_phi_y
        Kc[1, 0] -= self.K_phi_psi
        return As, Bs, Kc
