"""FMU-side helpers of the WheelRailContact FMU (bundled into the FMU's resources).

``model_description``: which variables a build exposes and the modelDescription.xml post-processing;
``validation``: checks used by the tests and the build (fmpy's validator, units, archive files).
The slave class itself is ``fmu_src/wheel_rail_contact.py``; the build is ``build_fmu.py``.
"""
