"""contact_core: the wheel–rail rolling-contact law (Kalker's theories) behind one interface.

    >>> import contact_core as cc
    >>> p = cc.hertz(N=100e3, A=1.087, B=1.667, E=210e9, nu=0.28)
    >>> r = cc.solve("linear", xi=1e-3, eta=0.0, phi=0.0, N=100e3, mu=0.3, a=p.a, b=p.b,
    ...              G=cc.shear_modulus(210e9, 0.28), nu=0.28)

Units are SI throughout; forces are those of the rail on the wheel in Kalker's convention.
"""
from .api import METHODS, make_solver, methods, solve
from .base import ContactMethod
from .cache import clear_caches
from .coefficients import creep_coefficients
from .contacts import ContactFailure, ContactInputError, Contacts
from .effects import ALL_EFFECTS, EFFECT_NAMES, Effects
from .friction import FrictionLaw
from .jacobian import Jacobian
from .hertz import (HertzGeometry, HertzPatch, hertz, hertz_from_radii, hertz_geometry,
                    wheel_rail_curvatures)
from .material import contact_modulus, shear_modulus
from .result import ContactResult
from .scene import DEFAULT_SCENE, Scene, load_scene, scenes
from .variables import VARIABLES, Variable, scene_variables
from .wheel_rail import (VaryingGeometryConfig, VaryingGeometryEvaluator, WheelRailConfig,
                         WheelRailEvaluator)

__all__ = [
    "ALL_EFFECTS", "EFFECT_NAMES", "METHODS", "ContactMethod", "ContactResult", "Effects",
    "clear_caches",
    "HertzGeometry", "HertzPatch", "contact_modulus", "creep_coefficients", "hertz",
    "hertz_from_radii", "hertz_geometry", "make_solver", "methods", "shear_modulus", "solve",
    "wheel_rail_curvatures",
]
__all__ += ["FrictionLaw"]
__all__ += ["DEFAULT_SCENE", "Scene", "VARIABLES", "Variable", "WheelRailConfig",
            "WheelRailEvaluator", "load_scene", "scene_variables", "scenes"]
__all__ += ["VaryingGeometryConfig", "VaryingGeometryEvaluator"]
__all__ += ["ContactFailure", "ContactInputError", "Contacts", "Jacobian"]
