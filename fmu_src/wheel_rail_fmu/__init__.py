"""The WheelRailContact FMU (FMI 2.0 co-simulation) around ``contact_core``.

Runtime (bundled into every FMU, see :data:`wheel_rail_fmu.build.RUNTIME_MODULES`):
``slave`` (the Fmi2Slave: FMI variables onto :class:`contact_core.WheelRailEvaluator`),
``model_description`` (which variables a build exposes; the XML pythonfmu omits), ``state``
(serialized FMU states, data only), ``runtime`` (the bundled or installed packages to use).
``entry`` is copied in as the FMU's slave module and loads the rest.

Host side (never bundled): ``build`` (the build and the ``build-fmu`` command), ``native/`` (the
FMI wrapper's C source), ``validation`` (fmpy's validator and more), ``host`` (an FMU instance
through fmpy, for tests and benchmarks).
"""
