"""Elastic constants of wheel and rail (both bodies of the same material)."""
from __future__ import annotations


def shear_modulus(E: float, nu: float) -> float:
    """G = E / (2(1+ν)), Pa (Kalker 1979, eq 8)."""
    return E / (2.0 * (1.0 + nu))


def contact_modulus(E: float, nu: float) -> float:
    """Hertz contact modulus E* of two bodies of the same material, Pa.

    1/E* = (1-ν1²)/E1 + (1-ν2²)/E2 (Johnson, *Contact Mechanics*, 1985, eq. 4.22) = 2(1-ν²)/E.
    """
    return E / (2.0 * (1.0 - nu * nu))
