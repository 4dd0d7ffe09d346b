/*
 * FMI 2.0 co-simulation functions that run a pythonfmu-style Python slave in embedded CPython.
 *
 * Built by wheel_rail_fmu.build with the system C compiler against the building Python's
 * libpython (linked, with its directory as run path), it replaces pythonfmu's generic binary and
 * keeps pythonfmu's Python interface and packaging: resources/slavemodule.txt names the slave
 * module resources/<name>.py; its Fmi2Slave subclass (the one with the longest MRO) is
 * instantiated with the keyword arguments pythonfmu passes, and the FMI calls map onto the same
 * methods (setup_experiment, enter/exit_initialization_mode, do_step, terminate, get_/set_<type>,
 * _get_fmu_state, _set_fmu_state, _fmu_state_to_bytes, _fmu_state_from_bytes; log_queue).
 *
 * What differs from pythonfmu 0.7 (FMI 2.0 sec. 2.1.3 on statuses):
 *  - a call during which the slave logged a warning returns fmi2Warning (FMI 2.0 sec. 2.1.3);
 *  - a host's mistake (a String value that is NULL or not UTF-8, a buffer for the serialized
 *    state of another size, the GUID or resource folder of another FMU) is fmi2Error with a
 *    message saying so;
 *  - a Python exception is fmi2Error (the instance failed), never fmi2Fatal (which the standard
 *    keeps for corrupted state of all instances); an exception may carry an int attribute
 *    ``fmi_status`` (1 warning, 2 discard, 3 error) to choose the status, and its text is logged
 *    before the function returns. Slaves learn this from the keyword argument
 *    ``fmi_error_status=True``;
 *  - the slave module is imported by file under its own name (FMUs share modules only when
 *    their names are equal; this project's FMUs name theirs after a digest of their code), and
 *    resources/ is appended to sys.path, not put first, so project files stay importable as
 *    with pythonfmu without shadowing the host's modules (and removed from it by a later load
 *    once the host has deleted the folder, so that sys.path does not grow with every run);
 *  - fmuGUID is checked against the model description next to resources/ (FMI 2.0 sec. 2.1.5);
 *  - every reference is released exactly once; logged messages are released after delivery;
 *    messages are passed as "%s" arguments, never as format strings;
 *  - a C host needs no LD_PRELOAD: libpython is linked, and before initialising Python its
 *    symbols are made global (extension modules such as numpy resolve against them) and the
 *    library is pinned; the interpreter is never finalised (finalising with numpy/numba loaded
 *    can abort the host at exit);
 *  - without PYTHONHOME in the environment, an interpreter started here takes the Python the FMU
 *    was built with (WRC_PYTHON_EXECUTABLE, e.g. a virtual environment) as its executable, so it
 *    finds that environment's packages;
 *  - the optional slave method _check_fmu_state(state) validates a deserialized state;
 *  - the instance owns the FMU states it gives out (fmi2GetFMUstate, fmi2DeSerializeFMUstate),
 *    by address, until fmi2FreeFMUstate or fmi2FreeInstance (FMI 2.0 sec. 2.1.6: freeing an
 *    instance frees all it allocated). A state pointer it does not own (another instance's, one
 *    already freed, garbage) is refused with fmi2Error and never dereferenced;
 *  - fmi2GetRealStatus(fmi2LastSuccessfulTime) returns the slave's last_successful_time(), so
 *    that the time is part of the slave's FMU state and fmi2SetFMUstate restores it;
 *  - fmi2GetDirectionalDerivative calls the slave's optional method
 *    get_directional_derivative(unknowns, knowns, seed) (value references, value references,
 *    floats; it returns one float per unknown), and is unsupported (fmi2Error) without it;
 *  - a slave may keep its Real values in a buffer of doubles indexed by value reference,
 *    _fmi_reals, with a byte of flags per value reference in _fmi_flags (1: a Real variable,
 *    2: an output, 4: settable now) and one more byte, non-zero while the outputs are those of
 *    the inputs. fmi2SetReal of values that are all settable then writes the buffer and clears
 *    that byte, and fmi2GetReal of Real values none of which is an output out of date reads it,
 *    without calling Python (nor taking the interpreter's lock: the memory is the instance's,
 *    held by the buffer views for its lifetime, and FMI 2.0 forbids concurrent calls on one
 *    instance); any other call goes to the slave's methods as usual.
 *
 * The global interpreter lock is taken around every call (PyGILState_Ensure), so hosts may call
 * from any thread. Thread safety across instances follows from the lock.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <ctype.h>
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#ifndef WRC_PYTHON_EXECUTABLE
#define WRC_PYTHON_EXECUTABLE ""
#endif

/* Key in sys.modules of the helper module below (versioned: another build may define its own). */
#define LOADER_MODULE "_fmi2_python_loader_5"

static const char LOADER_SOURCE[] =
    "import importlib.util, sys, threading, traceback\n"
    "from pathlib import Path\n"
    "\n"
    "ADDED = []\n"
    "\n"
    "class LoadError(Exception):\n"
    "    fmi_status = 3  # the host's arguments: said as they are, no traceback\n"
    "\n"
    "# one load at a time: a module executing in one thread (the GIL is released while it\n"
    "# imports) is in sys.modules half made, and another thread must not take it\n"
    "LOCK = threading.Lock()\n"
    "\n"
    "def load(resources, guid):\n"
    "    with LOCK:\n"
    "        return _load(resources, guid)\n"
    "\n"
    "def _load(resources, guid):\n"
    "    folder = Path(resources)\n"
    "    md = folder.parent / 'modelDescription.xml'\n"
    "    if md.is_file():\n"
    "        import xml.etree.ElementTree as ET\n"
    "        own = ET.parse(md).getroot().get('guid')\n"
    "        if own != guid:\n"
    "            raise LoadError(f'fmuGUID {guid} is not the GUID of this FMU, {own}')\n"
    "    if not (folder / 'slavemodule.txt').is_file():\n"
    "        raise LoadError(f'fmuResourceLocation {resources!r} is not the resources '\n"
    "                        'folder of this FMU (it has no slavemodule.txt)')\n"
    "    # resources/ folders this loader added that hosts have since deleted leave sys.path\n"
    "    for p in [p for p in ADDED if not Path(p).is_dir()]:\n"
    "        ADDED.remove(p)\n"
    "        while p in sys.path:\n"
    "            sys.path.remove(p)\n"
    "    if str(folder) not in sys.path:\n"
    "        sys.path.append(str(folder))\n"
    "        ADDED.append(str(folder))\n"
    "    name = (folder / 'slavemodule.txt').read_text(encoding='utf-8').strip()\n"
    "    module = sys.modules.get(name)\n"
    "    if module is None:\n"
    "        spec = importlib.util.spec_from_file_location(name, folder / (name + '.py'))\n"
    "        module = importlib.util.module_from_spec(spec)\n"
    "        sys.modules[name] = module\n"
    "        try:\n"
    "            spec.loader.exec_module(module)\n"
    "        except BaseException:\n"
    "            del sys.modules[name]\n"
    "            raise\n"
    "    best = None\n"
    "    for value in list(vars(module).values()):\n"
    "        if (isinstance(value, type) and not getattr(value, '__abstractmethods__', None)\n"
    "                and any(c.__name__ == 'Fmi2Slave' for c in value.__mro__[1:])\n"
    "                and (best is None or len(value.__mro__) > len(best.__mro__))):\n"
    "            best = value\n"
    "    if best is None:\n"
    "        raise ImportError(f'{name}.py defines no subclass of Fmi2Slave')\n"
    "    return best\n"
    "\n"
    "def describe(exc, where):\n"
    "    status = getattr(exc, 'fmi_status', None)\n"
    "    if type(status) is int and 1 <= status <= 3:\n"
    "        return status, str(exc)\n"
    "    text = ''.join(traceback.format_exception(type(exc), exc, exc.__traceback__))\n"
    "    return 3, f'{where}: unexpected Python exception\\n{text.rstrip()}'\n";

typedef struct {
    char *name;
    fmi2CallbackFunctions cb;
    int logging_on;
    PyObject *cls;     /* the slave class */
    PyObject *kwargs;  /* its constructor arguments (again at fmi2Reset) */
    PyObject *slave;   /* the instance */
    PyObject *strings; /* list of bytes: what the last fmi2GetString returned points into */
    PyObject *states;  /* dict: the address (int) of each FMU state given out -> the state */
    int fast;          /* the slave's buffers below are held (values set and read directly) */
    Py_buffer reals;   /* _fmi_reals: doubles by value reference */
    Py_buffer flags;   /* _fmi_flags: FAST_* per value reference, then the outputs' freshness */
} Instance;

enum { FAST_REAL = 1, FAST_OUTPUT = 2, FAST_SETTABLE = 4 };

/* ------------------------------------------------------------------------------------------ */
/* Logging                                                                                     */
/* ------------------------------------------------------------------------------------------ */

static const char *category_of(fmi2Status s) {
    switch (s) {
    case fmi2OK: return "logAll";
    case fmi2Warning: return "logStatusWarning";
    case fmi2Discard: return "logStatusDiscard";
    case fmi2Error: return "logStatusError";
    default: return "logStatusFatal";
    }
}

/* Warnings and worse are always delivered; OK-level messages only with logging on. */
static void log_text(const Instance *in, fmi2Status s, const char *category, const char *text) {
    if (in == NULL || in->cb.logger == NULL) return;
    if (s == fmi2OK && !in->logging_on) return;
    in->cb.logger(in->cb.componentEnvironment, in->name, s,
                  category ? category : category_of(s), "%s", text ? text : "");
}

/* Deliver and release the slave's queued messages (pythonfmu's LogMsg: status, category, msg).
   Returns fmi2Warning if one of them was a warning or worse (FMI 2.0 sec. 2.1.3: fmi2Warning
   means the logger was called with "not quite right"), else fmi2OK. */
static fmi2Status drain_log(Instance *in) {
    fmi2Status worst = fmi2OK;
    if (in->slave == NULL) return worst;
    PyObject *queue = PyObject_GetAttrString(in->slave, "log_queue");
    if (queue == NULL || !PyList_Check(queue)) {
        PyErr_Clear();
        Py_XDECREF(queue);
        return worst;
    }
    Py_ssize_t n = PyList_GET_SIZE(queue);
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *item = PyList_GET_ITEM(queue, i);
        PyObject *status = PyObject_GetAttrString(item, "status");
        PyObject *category = PyObject_GetAttrString(item, "category");
        PyObject *msg = PyObject_GetAttrString(item, "msg");
        PyObject *text = msg ? PyObject_Str(msg) : NULL;
        long s = status ? PyLong_AsLong(status) : fmi2Error;
        const char *cat = (category && PyUnicode_Check(category)) ? PyUnicode_AsUTF8(category)
                                                                    : NULL;
        const char *t = text ? PyUnicode_AsUTF8(text) : NULL;
        PyErr_Clear();
        if (s < fmi2OK || s > fmi2Fatal) s = fmi2Error;
        if (s != fmi2OK) worst = fmi2Warning;
        log_text(in, (fmi2Status)s, cat, t ? t : "(message could not be converted)");
        Py_XDECREF(status);
        Py_XDECREF(category);
        Py_XDECREF(msg);
        Py_XDECREF(text);
    }
    if (PyList_SetSlice(queue, 0, n, NULL) < 0) PyErr_Clear();
    Py_DECREF(queue);
    return worst;
}

/* ------------------------------------------------------------------------------------------ */
/* Python                                                                                      */
/* ------------------------------------------------------------------------------------------ */

static pthread_mutex_t start_lock = PTHREAD_MUTEX_INITIALIZER;

/* Start the interpreter if the host has none. Returns NULL or a static error message. */
static const char *start_python(void) {
    const char *error = NULL;
    int major = 0, minor = 0;
    if (sscanf(Py_GetVersion(), "%d.%d", &major, &minor) != 2 || major != PY_MAJOR_VERSION ||
        minor != PY_MINOR_VERSION)
        return "this FMU was built for Python " PY_VERSION " and the process runs another "
               "Python version: build the FMU with the Python of this host";
    pthread_mutex_lock(&start_lock);
    if (!Py_IsInitialized()) {
        /* Extension modules are not linked to libpython: its symbols must be global. Pinned,
           because the interpreter outlives this library if the host unloads it. */
        Dl_info info;
        if (dladdr((void *)&Py_IsInitialized, &info) && info.dli_fname)
            dlopen(info.dli_fname, RTLD_NOW | RTLD_GLOBAL | RTLD_NOLOAD | RTLD_NODELETE);
        PyConfig config;
        PyConfig_InitPythonConfig(&config);
        config.install_signal_handlers = 0;
        config.parse_argv = 0;
        PyStatus st = PyStatus_Ok();
        const char *home = getenv("PYTHONHOME");
        if ((home == NULL || *home == '\0') && WRC_PYTHON_EXECUTABLE[0] != '\0')
            st = PyConfig_SetBytesString(&config, &config.executable, WRC_PYTHON_EXECUTABLE);
        if (!PyStatus_Exception(st)) st = Py_InitializeFromConfig(&config);
        PyConfig_Clear(&config);
        if (PyStatus_Exception(st))
            error = "the embedded Python interpreter could not be started";
        else
            PyEval_SaveThread(); /* release the lock: every call takes it with PyGILState */
    }
    pthread_mutex_unlock(&start_lock);
    return error;
}

/* The helper module (LOADER_SOURCE), created once per process. New reference or NULL. */
static PyObject *loader(void) {
    PyObject *modules = PyImport_GetModuleDict();
    PyObject *mod = PyDict_GetItemString(modules, LOADER_MODULE);
    if (mod != NULL) {
        Py_INCREF(mod);
        return mod;
    }
    mod = PyModule_New(LOADER_MODULE);
    if (mod == NULL) return NULL;
    PyObject *dict = PyModule_GetDict(mod);
    if (PyDict_SetItemString(dict, "__builtins__", PyEval_GetBuiltins()) < 0) goto fail;
    PyObject *r = PyRun_String(LOADER_SOURCE, Py_file_input, dict, dict);
    if (r == NULL) goto fail;
    Py_DECREF(r);
    /* Running the source may release the GIL (imports): another thread may have registered its
       loader meanwhile, and its lock must be the only one. The first registered is kept. */
    PyObject *key = PyUnicode_FromString(LOADER_MODULE);
    PyObject *kept = key ? PyDict_SetDefault(modules, key, mod) : NULL;
    Py_XDECREF(key);
    if (kept == NULL) goto fail;
    Py_INCREF(kept);
    Py_DECREF(mod);
    return kept;
fail:
    Py_DECREF(mod);
    return NULL;
}

/* Report the pending Python exception of `where` (after the slave's queued messages). */
static fmi2Status report_exception(Instance *in, const char *where) {
    PyObject *type, *value, *tb;
    PyErr_Fetch(&type, &value, &tb);
    PyErr_NormalizeException(&type, &value, &tb);
    if (value != NULL && tb != NULL) PyException_SetTraceback(value, tb);
    drain_log(in);
    fmi2Status status = fmi2Error;
    PyObject *mod = loader();
    PyObject *d = (mod && value) ? PyObject_CallMethod(mod, "describe", "(Os)", value, where)
                                 : NULL;
    long s = 0;
    const char *text = NULL;
    if (d && PyArg_ParseTuple(d, "ls", &s, &text)) {
        status = (fmi2Status)s;
        log_text(in, status, NULL, text);
    } else {
        PyErr_Clear();
        char buf[256];
        snprintf(buf, sizeof buf, "%s: Python exception (its description failed)", where);
        log_text(in, fmi2Error, NULL, buf);
    }
    Py_XDECREF(d);
    Py_XDECREF(mod);
    Py_XDECREF(type);
    Py_XDECREF(value);
    Py_XDECREF(tb);
    return status;
}

/* Status of a call into the slave: its result (NULL: an exception) and the messages it queued. */
static fmi2Status finish(Instance *in, PyObject *result, const char *where) {
    if (result == NULL) return report_exception(in, where);
    Py_DECREF(result);
    return drain_log(in);
}

/* Call a slave method with a Py_BuildValue argument tuple format. */
#define CALL(in, method, ...) PyObject_CallMethod((in)->slave, method, __VA_ARGS__)

static PyObject *index_list(const fmi2ValueReference vr[], size_t nvr) {
    PyObject *list = PyList_New((Py_ssize_t)nvr);
    for (size_t i = 0; list && i < nvr; i++) {
        PyObject *v = PyLong_FromUnsignedLong(vr[i]);
        if (v == NULL) {
            Py_CLEAR(list);
            break;
        }
        PyList_SET_ITEM(list, (Py_ssize_t)i, v);
    }
    return list;
}

/* Common entry checks: a non-NULL instance whose slave exists and arrays when nvr > 0. */
static int bad_call(Instance *in, const char *where, const void *a, const void *b, size_t n) {
    if (in == NULL) return 1;
    if (in->slave == NULL) {
        char buf[256];
        snprintf(buf, sizeof buf, "%s: the instance has no slave", where);
        log_text(in, fmi2Error, NULL, buf);
        return 1;
    }
    if (n > 0 && (a == NULL || b == NULL)) {
        char buf[256];
        snprintf(buf, sizeof buf, "%s: NULL array with %zu elements", where, n);
        log_text(in, fmi2Error, NULL, buf);
        return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* Instances                                                                                   */
/* ------------------------------------------------------------------------------------------ */

/* Local path of a file: URI (percent-decoded; "file:///p", "file:/p", "file://localhost/p") or
   of a plain path. malloc'ed; trailing slashes removed. */
static char *uri_to_path(const char *uri) {
    const char *p = uri;
    if (strncmp(p, "file://localhost/", 17) == 0)
        p += 16;
    else if (strncmp(p, "file:///", 8) == 0)
        p += 7;
    else if (strncmp(p, "file:/", 6) == 0)
        p += 5;
    size_t n = strlen(p);
    char *out = malloc(n + 1), *o = out;
    if (out == NULL) return NULL;
    for (size_t i = 0; i < n; i++) {
        unsigned int c;
        if (p[i] == '%' && i + 2 < n && isxdigit((unsigned char)p[i + 1]) &&
            isxdigit((unsigned char)p[i + 2]) && sscanf(p + i + 1, "%2x", &c) == 1) {
            *o++ = (char)c;
            i += 2;
        } else {
            *o++ = p[i];
        }
    }
    while (o > out + 1 && o[-1] == '/') o--;
    *o = '\0';
    return out;
}

/* Release the slave's buffers (GIL held). */
static void unbind_fast(Instance *in) {
    if (!in->fast) return;
    in->fast = 0;
    PyBuffer_Release(&in->flags);
    PyBuffer_Release(&in->reals);
}

/* Hold the slave's _fmi_reals and _fmi_flags buffers if it has them in the expected form (GIL
   held); otherwise values go through its methods. */
static void bind_fast(Instance *in) {
    unbind_fast(in);
    PyObject *reals = PyObject_GetAttrString(in->slave, "_fmi_reals");
    PyObject *flags = reals ? PyObject_GetAttrString(in->slave, "_fmi_flags") : NULL;
    if (flags != NULL &&
        PyObject_GetBuffer(reals, &in->reals, PyBUF_WRITABLE | PyBUF_FORMAT | PyBUF_ND) == 0) {
        if (PyObject_GetBuffer(flags, &in->flags, PyBUF_WRITABLE) == 0) {
            int ok = in->reals.ndim == 1 && in->reals.itemsize == (Py_ssize_t)sizeof(double) &&
                     in->reals.format != NULL && strcmp(in->reals.format, "d") == 0 &&
                     PyBuffer_IsContiguous(&in->reals, 'C') && in->flags.len >= 1 &&
                     in->reals.len / (Py_ssize_t)sizeof(double) >= in->flags.len - 1;
            if (ok) {
                in->fast = 1;
            } else {
                PyBuffer_Release(&in->flags);
                PyBuffer_Release(&in->reals);
            }
        } else {
            PyBuffer_Release(&in->reals);
        }
    }
    PyErr_Clear();
    Py_XDECREF(reals);
    Py_XDECREF(flags);
}

/* fmi2SetReal without Python: 1 if done (every value settable now, at least one: whether no
   value may be set, the state decides), else 0. */
static int fast_set(Instance *in, const fmi2ValueReference vr[], size_t nvr,
                    const fmi2Real value[]) {
    if (!in->fast || nvr == 0 || vr == NULL || value == NULL) return 0;
    unsigned char *flags = in->flags.buf;
    size_t n = (size_t)in->flags.len - 1;
    for (size_t i = 0; i < nvr; i++)
        if (vr[i] >= n || !(flags[vr[i]] & FAST_SETTABLE)) return 0;
    double *reals = in->reals.buf;
    for (size_t i = 0; i < nvr; i++) reals[vr[i]] = value[i];
    flags[n] = 0; /* the outputs are no longer those of the inputs */
    return 1;
}

/* fmi2GetReal without Python: 1 if done (Real values, no output out of date), else 0. */
static int fast_get(Instance *in, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    if (!in->fast || (nvr > 0 && (vr == NULL || value == NULL))) return 0;
    const unsigned char *flags = in->flags.buf;
    size_t n = (size_t)in->flags.len - 1;
    int fresh = flags[n] != 0;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= n) return 0;
        unsigned char f = flags[vr[i]];
        if (!(f & FAST_REAL) || ((f & FAST_OUTPUT) && !fresh)) return 0;
    }
    const double *reals = in->reals.buf;
    for (size_t i = 0; i < nvr; i++) value[i] = reals[vr[i]];
    return 1;
}

static void free_instance(Instance *in) {
    if (in == NULL) return;
    if (Py_IsInitialized() && (in->slave || in->cls || in->kwargs || in->strings || in->states)) {
        PyGILState_STATE g = PyGILState_Ensure();
        unbind_fast(in);
        Py_CLEAR(in->slave);
        Py_CLEAR(in->cls);
        Py_CLEAR(in->kwargs);
        Py_CLEAR(in->strings);
        Py_CLEAR(in->states); /* the states the host did not free */
        PyGILState_Release(g);
    }
    free(in->name);
    free(in);
}

/* Create in->slave from in->cls and in->kwargs (GIL held). */
static fmi2Status make_slave(Instance *in, const char *where) {
    PyObject *args = PyTuple_New(0);
    PyObject *slave = args ? PyObject_Call(in->cls, args, in->kwargs) : NULL;
    Py_XDECREF(args);
    if (slave == NULL) return report_exception(in, where);
    unbind_fast(in);
    Py_XSETREF(in->slave, slave);
    bind_fast(in);
    return drain_log(in);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    Instance *in = calloc(1, sizeof *in);
    if (in == NULL) return NULL;
    in->name = strdup(instanceName ? instanceName : "");
    if (functions) in->cb = *functions;
    in->logging_on = loggingOn == fmi2True;
    if (fmuType != fmi2CoSimulation) {
        log_text(in, fmi2Error, NULL, "fmi2Instantiate: this FMU supports co-simulation only");
        free_instance(in);
        return NULL;
    }
    if (fmuResourceLocation == NULL || fmuGUID == NULL) {
        log_text(in, fmi2Error, NULL, "fmi2Instantiate: fmuResourceLocation and fmuGUID are required");
        free_instance(in);
        return NULL;
    }
    const char *error = start_python();
    if (error != NULL) {
        log_text(in, fmi2Error, NULL, error);
        free_instance(in);
        return NULL;
    }
    char *resources = uri_to_path(fmuResourceLocation);
    PyGILState_STATE g = PyGILState_Ensure();
    fmi2Status status = fmi2Error;
    PyObject *mod = loader();
    in->cls = (mod && resources) ? PyObject_CallMethod(mod, "load", "(ss)", resources, fmuGUID)
                                 : NULL;
    Py_XDECREF(mod);
    if (in->cls == NULL) {
        report_exception(in, "fmi2Instantiate: loading the slave module");
    } else {
        in->kwargs = Py_BuildValue("{s:s,s:s,s:O,s:O,s:O}", "instance_name", in->name,
                                   "resources", resources, "visible",
                                   visible == fmi2True ? Py_True : Py_False, "logger", Py_None,
                                   "fmi_error_status", Py_True);
        status = in->kwargs ? make_slave(in, "fmi2Instantiate")
                            : report_exception(in, "fmi2Instantiate");
    }
    PyGILState_Release(g);
    free(resources);
    if (status > fmi2Warning) {
        free_instance(in);
        return NULL;
    }
    return in;
}

void fmi2FreeInstance(fmi2Component c) { free_instance((Instance *)c); }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    Instance *in = c;
    if (in == NULL) return fmi2Error;
    in->logging_on = loggingOn == fmi2True;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined,
                               fmi2Real stopTime) {
    Instance *in = c;
    if (bad_call(in, "fmi2SetupExperiment", in, in, 0)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *stop = stopTimeDefined ? PyFloat_FromDouble(stopTime) : Py_NewRef(Py_None);
    PyObject *tol = toleranceDefined ? PyFloat_FromDouble(tolerance) : Py_NewRef(Py_None);
    PyObject *r = (stop && tol) ? CALL(in, "setup_experiment", "(dOO)", startTime, stop, tol)
                                : NULL;
    Py_XDECREF(stop);
    Py_XDECREF(tol);
    fmi2Status s = finish(in, r, "fmi2SetupExperiment");
    PyGILState_Release(g);
    return s;
}

static fmi2Status simple_call(fmi2Component c, const char *method, const char *where) {
    Instance *in = c;
    if (bad_call(in, where, in, in, 0)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    fmi2Status s = finish(in, CALL(in, method, NULL), where);
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    return simple_call(c, "enter_initialization_mode", "fmi2EnterInitializationMode");
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    return simple_call(c, "exit_initialization_mode", "fmi2ExitInitializationMode");
}

fmi2Status fmi2Terminate(fmi2Component c) { return simple_call(c, "terminate", "fmi2Terminate"); }

fmi2Status fmi2Reset(fmi2Component c) {
    Instance *in = c;
    if (in == NULL || in->cls == NULL) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    fmi2Status s = make_slave(in, "fmi2Reset");
    PyGILState_Release(g);
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* Values                                                                                      */
/* ------------------------------------------------------------------------------------------ */

typedef enum { REAL, INTEGER, BOOLEAN, STRING } Kind;
static const char *const GETTERS[] = {"get_real", "get_integer", "get_boolean", "get_string"};
static const char *const SETTERS[] = {"set_real", "set_integer", "set_boolean", "set_string"};

static fmi2Status get_values(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                             void *out, Kind kind, const char *where) {
    Instance *in = c;
    if (bad_call(in, where, vr, out, nvr)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *vrs = index_list(vr, nvr);
    PyObject *r = vrs ? CALL(in, GETTERS[kind], "(O)", vrs) : NULL;
    Py_XDECREF(vrs);
    fmi2Status s = fmi2OK;
    if (r != NULL && (!PyList_Check(r) || PyList_GET_SIZE(r) != (Py_ssize_t)nvr)) {
        Py_DECREF(r);
        r = NULL;
        PyErr_Format(PyExc_TypeError, "%s returned no list of %zu values", GETTERS[kind], nvr);
    }
    PyObject *strings = NULL;
    if (r != NULL && kind == STRING) strings = PyList_New((Py_ssize_t)nvr);
    for (size_t i = 0; r != NULL && i < nvr; i++) {
        PyObject *v = PyList_GET_ITEM(r, (Py_ssize_t)i);
        int ok = 1;
        switch (kind) {
        case REAL:
            ((fmi2Real *)out)[i] = PyFloat_AsDouble(v);
            break;
        case INTEGER:
            ((fmi2Integer *)out)[i] = (fmi2Integer)PyLong_AsLong(v);
            break;
        case BOOLEAN: {
            int t = PyObject_IsTrue(v);
            ((fmi2Boolean *)out)[i] = t > 0 ? fmi2True : fmi2False;
            ok = t >= 0;
            break;
        }
        case STRING: {
            PyObject *b = strings ? PyUnicode_AsUTF8String(v) : NULL;
            ok = b != NULL;
            if (ok) {
                PyList_SET_ITEM(strings, (Py_ssize_t)i, b);
                ((fmi2String *)out)[i] = PyBytes_AS_STRING(b);
            }
            break;
        }
        }
        if (!ok || PyErr_Occurred()) Py_CLEAR(r);
    }
    if (r == NULL) {
        Py_XDECREF(strings);
        s = report_exception(in, where);
    } else {
        if (kind == STRING) Py_XSETREF(in->strings, strings); /* valid until the next call */
        s = finish(in, r, where);
    }
    PyGILState_Release(g);
    return s;
}

static fmi2Status set_values(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                             const void *values, Kind kind, const char *where) {
    Instance *in = c;
    if (bad_call(in, where, vr, values, nvr)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *vrs = index_list(vr, nvr);
    PyObject *list = PyList_New((Py_ssize_t)nvr);
    for (size_t i = 0; list && i < nvr; i++) {
        PyObject *v = NULL;
        switch (kind) {
        case REAL: v = PyFloat_FromDouble(((const fmi2Real *)values)[i]); break;
        case INTEGER: v = PyLong_FromLong(((const fmi2Integer *)values)[i]); break;
        case BOOLEAN: v = PyBool_FromLong(((const fmi2Boolean *)values)[i] != fmi2False); break;
        case STRING: {
            const char *t = ((const fmi2String *)values)[i];
            if (t != NULL) v = PyUnicode_DecodeUTF8(t, (Py_ssize_t)strlen(t), "strict");
            if (v == NULL) { /* the host's mistake: say which value, change nothing */
                char buf[256];
                PyErr_Clear();
                snprintf(buf, sizeof buf, "%s: the value of valueReference %u is %s: allowed "
                         "UTF-8 text; nothing was set", where, vr[i],
                         t == NULL ? "NULL" : "not UTF-8");
                Py_XDECREF(vrs);
                Py_XDECREF(list);
                log_text(in, fmi2Error, NULL, buf);
                PyGILState_Release(g);
                return fmi2Error;
            }
            break;
        }
        }
        if (v == NULL) {
            Py_CLEAR(list);
            break;
        }
        PyList_SET_ITEM(list, (Py_ssize_t)i, v);
    }
    PyObject *r = (vrs && list) ? CALL(in, SETTERS[kind], "(OO)", vrs, list) : NULL;
    Py_XDECREF(vrs);
    Py_XDECREF(list);
    fmi2Status s = finish(in, r, where);
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
    if (c != NULL && fast_get(c, vr, nvr, value)) return fmi2OK;
    return get_values(c, vr, nvr, value, REAL, "fmi2GetReal");
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    return get_values(c, vr, nvr, value, INTEGER, "fmi2GetInteger");
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    return get_values(c, vr, nvr, value, BOOLEAN, "fmi2GetBoolean");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    return get_values(c, vr, nvr, value, STRING, "fmi2GetString");
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    if (c != NULL && fast_set(c, vr, nvr, value)) return fmi2OK;
    return set_values(c, vr, nvr, value, REAL, "fmi2SetReal");
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    return set_values(c, vr, nvr, value, INTEGER, "fmi2SetInteger");
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
    return set_values(c, vr, nvr, value, BOOLEAN, "fmi2SetBoolean");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
    return set_values(c, vr, nvr, value, STRING, "fmi2SetString");
}

/* ------------------------------------------------------------------------------------------ */
/* FMU state: a Python object owned by the instance (in->states) until freed                   */
/* ------------------------------------------------------------------------------------------ */

/* Whether the instance gave out `state` and has not freed it (GIL held); if not, logs why. The
   pointer is only compared, never dereferenced. */
static int owns_state(Instance *in, fmi2FMUstate state, const char *where) {
    PyObject *key = PyLong_FromVoidPtr(state);
    int owned = key && in->states ? PyDict_Contains(in->states, key) : 0;
    Py_XDECREF(key);
    PyErr_Clear();
    if (owned == 1) return 1;
    char buf[256];
    snprintf(buf, sizeof buf, "%s: the FMU state %p is not one of this instance's: allowed a "
             "state of its fmi2GetFMUstate or fmi2DeSerializeFMUstate not yet freed", where, state);
    log_text(in, fmi2Error, NULL, buf);
    return 0;
}

/* The instance keeps the new state `st` (a new reference, taken over); 0, or -1 with a Python
   error (st released). */
static int keep_state(Instance *in, PyObject *st) {
    PyObject *key = PyLong_FromVoidPtr(st);
    if (in->states == NULL) in->states = PyDict_New();
    int r = key && in->states ? PyDict_SetItem(in->states, key, st) : -1;
    Py_XDECREF(key);
    Py_DECREF(st); /* the dict's reference is the only one */
    return r;
}

/* The instance frees the state it owns (GIL held). */
static void drop_state(Instance *in, fmi2FMUstate state) {
    PyObject *key = PyLong_FromVoidPtr(state);
    if (key && PyDict_DelItem(in->states, key) < 0) PyErr_Clear();
    Py_XDECREF(key);
}

/* Give out the new state `st` of `where` (a new reference, taken over; NULL: a Python error) in
   place of `*state`, which the caller checked is NULL or owned (GIL held). */
static fmi2Status give_state(Instance *in, PyObject *st, fmi2FMUstate *state, const char *where) {
    if (st == NULL || keep_state(in, st) < 0) return report_exception(in, where);
    if (*state != NULL) drop_state(in, *state);
    *state = st;
    return drain_log(in);
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Instance *in = c;
    if (bad_call(in, "fmi2GetFMUstate", state, state, 1)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    /* FMI 2.0 sec. 2.1.8: a given state (this instance's) is overwritten */
    fmi2Status s = *state != NULL && !owns_state(in, *state, "fmi2GetFMUstate")
        ? fmi2Error
        : give_state(in, CALL(in, "_get_fmu_state", NULL), state, "fmi2GetFMUstate");
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    Instance *in = c;
    if (bad_call(in, "fmi2SetFMUstate", state, state, 1)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    fmi2Status s = owns_state(in, state, "fmi2SetFMUstate")
        ? finish(in, CALL(in, "_set_fmu_state", "(O)", (PyObject *)state), "fmi2SetFMUstate")
        : fmi2Error;
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Instance *in = c;
    if (in == NULL || state == NULL) return fmi2Error;
    if (*state == NULL) return fmi2OK;
    if (!Py_IsInitialized()) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    fmi2Status s = fmi2Error;
    if (owns_state(in, *state, "fmi2FreeFMUstate")) {
        drop_state(in, *state);
        *state = NULL;
        s = fmi2OK;
    }
    PyGILState_Release(g);
    return s;
}

/* The serialized bytes of a state (new reference to a bytes object, or NULL with an error). */
static PyObject *state_bytes(Instance *in, fmi2FMUstate state) {
    PyObject *b = CALL(in, "_fmu_state_to_bytes", "(O)", (PyObject *)state);
    if (b != NULL && !PyBytes_Check(b)) {
        Py_DECREF(b);
        PyErr_SetString(PyExc_TypeError, "_fmu_state_to_bytes returned no bytes");
        return NULL;
    }
    return b;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    Instance *in = c;
    if (bad_call(in, "fmi2SerializedFMUstateSize", state, size, 1)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    if (!owns_state(in, state, "fmi2SerializedFMUstateSize")) {
        PyGILState_Release(g);
        return fmi2Error;
    }
    PyObject *b = state_bytes(in, state);
    if (b) *size = (size_t)PyBytes_GET_SIZE(b);
    fmi2Status s = finish(in, b, "fmi2SerializedFMUstateSize");
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte serializedState[],
                                 size_t size) {
    Instance *in = c;
    if (bad_call(in, "fmi2SerializeFMUstate", state, serializedState, 1)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    if (!owns_state(in, state, "fmi2SerializeFMUstate")) {
        PyGILState_Release(g);
        return fmi2Error;
    }
    PyObject *b = state_bytes(in, state);
    if (b && (size_t)PyBytes_GET_SIZE(b) != size) { /* the host's mistake: say so */
        char buf[256];
        snprintf(buf, sizeof buf, "fmi2SerializeFMUstate: the serialized state has %zd bytes, "
                 "the host gave %zu (fmi2SerializedFMUstateSize tells)", PyBytes_GET_SIZE(b),
                 size);
        Py_DECREF(b);
        drain_log(in);
        log_text(in, fmi2Error, NULL, buf);
        PyGILState_Release(g);
        return fmi2Error;
    }
    if (b) memcpy(serializedState, PyBytes_AS_STRING(b), size);
    fmi2Status s = finish(in, b, "fmi2SerializeFMUstate");
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *state) {
    Instance *in = c;
    if (bad_call(in, "fmi2DeSerializeFMUstate", serializedState, state, 1)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    /* as fmi2GetFMUstate, a given state (this instance's) is overwritten */
    if (*state != NULL && !owns_state(in, *state, "fmi2DeSerializeFMUstate")) {
        PyGILState_Release(g);
        return fmi2Error;
    }
    PyObject *b = PyBytes_FromStringAndSize(serializedState, (Py_ssize_t)size);
    PyObject *st = b ? CALL(in, "_fmu_state_from_bytes", "(O)", b) : NULL;
    Py_XDECREF(b);
    if (st != NULL && PyObject_HasAttrString(in->slave, "_check_fmu_state")) {
        PyObject *ok = CALL(in, "_check_fmu_state", "(O)", st);
        if (ok == NULL) Py_CLEAR(st);
        Py_XDECREF(ok);
    }
    fmi2Status s = give_state(in, st, state, "fmi2DeSerializeFMUstate");
    PyGILState_Release(g);
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* Co-simulation                                                                               */
/* ------------------------------------------------------------------------------------------ */

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Instance *in = c;
    if (bad_call(in, "fmi2DoStep", in, in, 0)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *r = CALL(in, "do_step", "(dd)", currentCommunicationPoint, communicationStepSize);
    fmi2Status s;
    if (r == NULL) {
        s = report_exception(in, "fmi2DoStep");
    } else {
        int done = PyObject_IsTrue(r);
        Py_DECREF(r);
        fmi2Status logged = drain_log(in);
        s = done > 0 ? logged : fmi2Discard; /* pythonfmu: do_step returns False to refuse */
        if (done < 0) s = report_exception(in, "fmi2DoStep");
    }
    PyGILState_Release(g);
    return s;
}

static fmi2Status unsupported(fmi2Component c, const char *what) {
    char buf[256];
    snprintf(buf, sizeof buf, "%s is not supported by this FMU (see its capability flags)", what);
    log_text((Instance *)c, fmi2Error, NULL, buf);
    return fmi2Error;
}

fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

/* The slave's get_directional_derivative(unknowns, knowns, seed) (FMI 2.0 sec. 2.1.9). */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[],
                                        size_t nUnknown, const fmi2ValueReference vKnown[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[]) {
    const char *where = "fmi2GetDirectionalDerivative";
    Instance *in = c;
    if (bad_call(in, where, vUnknown, dvUnknown, nUnknown) ||
        bad_call(in, where, vKnown, dvKnown, nKnown))
        return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    if (!PyObject_HasAttrString(in->slave, "get_directional_derivative")) {
        PyGILState_Release(g);
        return unsupported(c, where);
    }
    PyObject *unknowns = index_list(vUnknown, nUnknown);
    PyObject *knowns = unknowns ? index_list(vKnown, nKnown) : NULL;
    PyObject *seed = knowns ? PyList_New((Py_ssize_t)nKnown) : NULL;
    for (size_t i = 0; seed && i < nKnown; i++) {
        PyObject *v = PyFloat_FromDouble(dvKnown[i]);
        if (v == NULL) {
            Py_CLEAR(seed);
            break;
        }
        PyList_SET_ITEM(seed, (Py_ssize_t)i, v);
    }
    PyObject *r = seed ? CALL(in, "get_directional_derivative", "(OOO)", unknowns, knowns, seed)
                       : NULL;
    Py_XDECREF(unknowns);
    Py_XDECREF(knowns);
    Py_XDECREF(seed);
    if (r != NULL && (!PyList_Check(r) || PyList_GET_SIZE(r) != (Py_ssize_t)nUnknown)) {
        Py_CLEAR(r);
        PyErr_Format(PyExc_TypeError, "get_directional_derivative returned no list of %zu "
                     "values", nUnknown);
    }
    for (size_t i = 0; r != NULL && i < nUnknown; i++) {
        double d = PyFloat_AsDouble(PyList_GET_ITEM(r, (Py_ssize_t)i));
        if (d == -1.0 && PyErr_Occurred()) Py_CLEAR(r);
        else dvUnknown[i] = d;
    }
    fmi2Status s = finish(in, r, where);
    PyGILState_Release(g);
    return s;
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr, (void)nvr, (void)order, (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t nvr, const fmi2Integer order[], fmi2Real value[]) {
    (void)vr, (void)nvr, (void)order, (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

/* Steps are synchronous: only the last successful time and "terminated" are available. */
fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s, (void)value;
    return c ? fmi2Discard : fmi2Error;
}

/* fmi2LastSuccessfulTime is the slave's (method last_successful_time): an FMU state holds it.
   The slave refuses the call outside the states FMI 2.0 sec. 4.2.4 allows it in, whatever the
   kind; another kind is then fmi2Discard ("not able to return the status", sec. 2.1.3). */
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *in = c;
    if (bad_call(in, "fmi2GetRealStatus", value, value, 1)) return fmi2Error;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *r = CALL(in, "last_successful_time", NULL);
    double t = r ? PyFloat_AsDouble(r) : -1.0;
    if (r != NULL && t == -1.0 && PyErr_Occurred()) Py_CLEAR(r);
    fmi2Status status = finish(in, r, "fmi2GetRealStatus");
    if (status <= fmi2Warning && s != fmi2LastSuccessfulTime) {
        log_text(in, fmi2Discard, NULL, "fmi2GetRealStatus: only fmi2LastSuccessfulTime is "
                                        "available (steps are synchronous)");
        status = fmi2Discard;
    } else if (status <= fmi2Warning) {
        *value = t;
    }
    PyGILState_Release(g);
    return status;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s, (void)value;
    return c ? fmi2Discard : fmi2Error;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    if (c == NULL || value == NULL) return fmi2Error;
    if (s != fmi2Terminated) return fmi2Discard;
    *value = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s, (void)value;
    return c ? fmi2Discard : fmi2Error;
}
