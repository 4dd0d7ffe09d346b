"""An FMU instance driven through fmpy's ``FMU2Slave``, with its log messages kept (host side).

The one FMU host class of the project (tests, benchmarks, the wheelset co-simulation master):
values by name, typed setters/getters, statuses as fmpy's ``FMICallException`` (``.status``),
and every message the FMU logs, counted per status (the last :data:`KEEP` kept as text, so a
long run does not grow).

Instances may be created from several threads (hosts with thread pools): extracting and loading
are serialised by one lock. fmpy's FMU constructor (``_FMU.__init__`` in fmpy/fmi1.py) changes the
process's working directory to the binaries folder around ``dlopen`` and back, so two threads
loading at once could leave the whole process in the binaries folder.

Log messages: FMI loggers are variadic, so fmpy passes them through its native proxy
(``addLoggerProxy``), which keeps one Python callback per process, the last one registered (a
static in fmpy's native/src/logging/logging.c, FMPy 0.3.x). A callback per instance would
therefore receive every instance's messages, and once collected crash the host at the next
message. So there is one callback, :data:`_LOGGER`, alive as long as the process and registered
again by every new instance, and it hands each message to the instance whose number the FMU
passes back as ``componentEnvironment`` (FMI 2.0 sec. 2.1.5). A later ``fmpy.simulate_fmu(...,
logger=...)`` in the same process registers its own callback for every FMU, and frees it when it
returns: create instances after such calls, not before.
"""
from __future__ import annotations

import atexit
import itertools
import shutil
import threading
import weakref
from collections import Counter, deque
from ctypes import byref
from pathlib import Path
from typing import Any, Mapping, Sequence

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy

#: How many log messages an instance keeps as text.
KEEP = 1000
STATUS_NAMES = ("ok", "warning", "discard", "error", "fatal", "pending")
_unzipped: dict[tuple, str] = {}
#: Held while an FMU is extracted or its library loaded (module docstring).
_LOADING = threading.RLock()
#: FMU2Slave's setter and getter per variable type.
_SETTERS = {"Real": "setReal", "Integer": "setInteger", "Enumeration": "setInteger",
            "Boolean": "setBoolean", "String": "setString"}
_GETTERS = {"Real": "getReal", "Integer": "getInteger", "Enumeration": "getInteger",
            "Boolean": "getBoolean", "String": "getString"}
#: Live instances by the number their FMU passes to the logger (module docstring).
_BY_NUMBER: "weakref.WeakValueDictionary[int, FmuInstance]" = weakref.WeakValueDictionary()
_numbers = itertools.count(1)


def _log(environment, instance_name, status, category, message) -> None:
    instance = _BY_NUMBER.get(environment or 0)
    if instance is not None:
        instance.counts[status] += 1
        instance.messages.append((status, message.decode("utf-8", "replace")))


#: The process's one logger callback (module docstring), and memory callbacks.
_LOGGER = fmi2CallbackLoggerTYPE(_log)
_ALLOCATE = fmi2CallbackAllocateMemoryTYPE(calloc)
_FREE = fmi2CallbackFreeMemoryTYPE(free)


def unzipped(path: str | Path) -> str:
    """The folder an FMU is extracted to (once per process and version of the file; removed at
    exit)."""
    path = Path(path).resolve()
    st = path.stat()
    key = (path, st.st_mtime_ns, st.st_size)
    with _LOADING:
        if key not in _unzipped:
            _unzipped[key] = extract(str(path))
            atexit.register(shutil.rmtree, _unzipped[key], True)
        return _unzipped[key]


class FmuInstance:
    """One co-simulation instance of the FMU at ``path`` (see the module docstring).

    ``start``: start values set in initialisation mode; ``initialize=False`` stops after
    ``fmi2Instantiate`` (call :meth:`init`). ``step(h, **inputs)`` sets inputs and does one step.
    """

    def __init__(self, path: str | Path, name: str = "instance",
                 start: Mapping[str, Any] | None = None, initialize: bool = True,
                 logging_on: bool = True, start_time: float = 0.0,
                 stop_time: float | None = None) -> None:
        self.path = Path(path)
        self.name = name
        self.md = read_model_description(str(path))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.messages: deque[tuple[int, str]] = deque(maxlen=KEEP)
        self.counts: Counter[int] = Counter()
        number = next(_numbers)
        _BY_NUMBER[number] = self
        cb = fmi2CallbackFunctions()
        cb.logger = _LOGGER
        cb.allocateMemory = _ALLOCATE
        cb.freeMemory = _FREE
        cb.componentEnvironment = number
        addLoggerProxy(byref(cb))
        self._callbacks = cb  # the FMU may keep a pointer to it until fmi2FreeInstance
        with _LOADING:
            self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=unzipped(path),
                                 modelIdentifier=self.md.coSimulation.modelIdentifier,
                                 instanceName=name)
        self.fmu.instantiate(callbacks=cb, loggingOn=logging_on)
        self.t = start_time
        self.stop_time = stop_time
        self.initialized = False
        if initialize:
            self.init(start)

    def init(self, start: Mapping[str, Any] | None = None) -> None:
        """Set up, enter initialisation mode, set ``start`` values, exit initialisation mode."""
        self.fmu.setupExperiment(startTime=self.t, stopTime=self.stop_time)
        self.fmu.enterInitializationMode()
        self.set(**(start or {}))
        self.fmu.exitInitializationMode()
        self.initialized = True

    def variable(self, name: str):
        """The model description's variable ``name`` (KeyError listing the names otherwise)."""
        try:
            return self.vars[name]
        except KeyError:
            raise KeyError(f"{self.name}: no variable {name!r} (has {sorted(self.vars)})") \
                from None

    def vr(self, name: str) -> int:
        """The value reference of the variable ``name``."""
        return self.variable(name).valueReference

    def set(self, **values: Any) -> None:
        for name, value in values.items():
            v = self.variable(name)
            getattr(self.fmu, _SETTERS[v.type])([v.valueReference], [value])

    def get(self, *names: str) -> list:
        out = []
        for name in names:
            v = self.variable(name)
            value = getattr(self.fmu, _GETTERS[v.type])([v.valueReference])[0]
            out.append(value.decode() if isinstance(value, bytes) else value)
        return out

    def step(self, h: float = 1e-3, **inputs: float) -> None:
        """Set ``inputs`` and do one step of size ``h`` (fmpy raises on a status above warning)."""
        self.set(**inputs)
        self.fmu.doStep(self.t, h)
        self.t += h

    def errors(self, least: int = 3) -> list[str]:
        """The kept messages logged with a status >= ``least`` (3: error)."""
        return [m for s, m in self.messages if s >= least]

    def log_text(self) -> str:
        """The kept messages, one per line with their status."""
        return "\n".join(f"[{STATUS_NAMES[s] if 0 <= s < 6 else s}] {m}" for s, m in self.messages)

    def free(self) -> None:
        """Terminate (if initialised) and free the instance; the library is unloaded."""
        try:
            if self.initialized:
                self.fmu.terminate()
        except FMICallException:
            pass  # freeing must not fail: the instance goes anyway
        finally:
            self.fmu.freeInstance()

    def __enter__(self) -> "FmuInstance":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.free()


def run_in_libcosim(paths: list[str | Path], inputs: Mapping[str, float], steps: int = 5,
                    initial: bool = False,
                    outputs: Sequence[str] = ("Fx", "Fy", "Mz")) -> list[dict[str, float]]:
    """Run the contact FMUs ``paths`` in one libcosim execution (DNV's co-simulation engine,
    through libcosimpy; 1 ms steps) with constant ``inputs`` (set as initial values with
    ``initial``, else overridden at every step); their last ``outputs`` (those they have)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    execution = CosimExecution.from_step_size(step_size=int(1e6))  # 1 ms
    manipulator = CosimManipulator.create_override()
    observer = CosimObserver.create_last_value()
    execution.add_manipulator(manipulator=manipulator)
    execution.add_observer(observer=observer)
    slaves = []
    for k, path in enumerate(paths):
        index = execution.add_local_slave(CosimLocalSlave(fmu_path=str(path),
                                                          instance_name=f"contact{k}"))
        vr = {v.name: v.valueReference for v in read_model_description(str(path)).modelVariables}
        names = [n for n in inputs if n in vr]
        if initial:
            for n in names:
                execution.real_initial_value(index, vr[n], inputs[n])
        else:
            manipulator.slave_real_values(index, [vr[n] for n in names],
                                          [inputs[n] for n in names])
        slaves.append((index, vr))
    if not execution.simulate_until(target_time=int(steps * 1e6)):
        raise RuntimeError("libcosim stopped the run (an FMU returned a status other than OK)")
    out = []
    for i, vr in slaves:
        names = [n for n in outputs if n in vr]
        out.append(dict(zip(names, observer.last_real_values(i, [vr[n] for n in names]))))
    return out
