/* A minimal FMI 2.0 co-simulation host for tests/test_fmu_hosts.py: a C process with no Python
 * of its own, no LD_PRELOAD and no PYTHONPATH.
 *
 *     host BINARY GUID RESOURCES_URI VR_XI VR_N VR_FX VR_E
 *
 * Instance "c": initialise, one step at xi = 1e-3, N = 1e5 (prints Fx), one step with xi = NaN.
 * Instance "d": E = -1 at initialisation. Every logged message is printed when it arrives, so the
 * output shows whether it came before the status. Then both are freed, the library is closed,
 * and main returns 0: a crash at exit shows in the exit status. */
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    (void)env;
    va_list ap;
    va_start(ap, message);
    printf("log %s %d ", instance, (int)status);
    vprintf(message, ap);
    printf("\n");
    va_end(ap);
}

#define LOAD(f)                                                                                 \
    f##TYPE *f = (f##TYPE *)dlsym(lib, #f);                                                     \
    if (!f) return 2;

int main(int argc, char **argv) {
    if (argc != 8) return 1;
    setvbuf(stdout, NULL, _IONBF, 0);
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        printf("dlopen: %s\n", dlerror());
        return 1;
    }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep)
    LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2ValueReference in[2] = {atoi(argv[4]), atoi(argv[5])}, out[1] = {atoi(argv[6])};
    fmi2ValueReference e[1] = {atoi(argv[7])};

    fmi2Component c = fmi2Instantiate("c", fmi2CoSimulation, argv[2], argv[3], &cb, 0, 0);
    if (!c) return 3;
    fmi2SetupExperiment(c, 0, 0, 0, 0, 0);
    fmi2EnterInitializationMode(c);
    printf("init %d\n", fmi2ExitInitializationMode(c));
    fmi2Real u[2] = {1e-3, 1e5}, y[1];
    fmi2SetReal(c, in, 2, u);
    printf("step %d\n", fmi2DoStep(c, 0, 1e-3, fmi2True));
    fmi2GetReal(c, out, 1, y);
    printf("Fx %.17g\n", y[0]);
    u[0] = NAN;
    fmi2SetReal(c, in, 2, u);
    printf("step %d\n", fmi2DoStep(c, 1e-3, 1e-3, fmi2True));

    fmi2Component d = fmi2Instantiate("d", fmi2CoSimulation, argv[2], argv[3], &cb, 0, 0);
    if (!d) return 4;
    fmi2Real bad[1] = {-1.0};
    fmi2SetupExperiment(d, 0, 0, 0, 0, 0);
    fmi2EnterInitializationMode(d);
    fmi2SetReal(d, e, 1, bad);
    printf("init %d\n", fmi2ExitInitializationMode(d));

    fmi2Terminate(c);
    fmi2FreeInstance(c);
    fmi2FreeInstance(d);
    dlclose(lib);
    printf("freed\n");
    return 0;
}
