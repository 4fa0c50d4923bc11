/* A minimal FMI 2.0 Co-Simulation importer in plain C, built from the same source for Linux (gcc)
 * and for Windows (x86_64-w64-mingw32-gcc, run under Wine), so that one session can be run on
 * both binaries of a packaged FMU and the transcripts compared. tests/python/test_win64.py drives it.
 *
 *   fmu_session BINARY MODEL_IDENTIFIER GUID RESOURCE_URI < script > transcript
 *
 * The script has one call per line; each call prints one transcript line:
 *   instantiate NAME                 instantiate NAME ok | null
 *   setup TOLERANCE START            setup STATUS         (TOLERANCE <= 0: none defined)
 *   init                             init STATUS          (enter, then exit initialization mode)
 *   set VR VALUE [VR VALUE ...]      set STATUS           (fmi2SetReal; "nan" and "inf" are read)
 *   step T H                         step STATUS
 *   get VR [VR ...]                  get STATUS VALUE ... (fmi2GetReal, %.17g)
 *   terminate                        terminate STATUS
 *   free                             free
 * and every message the FMU logs is a line "log STATUS CATEGORY MESSAGE".
 * Its own types stand in for fmi2Functions.h (the FMI 2.0 headers are not vendored here); they
 * follow the standard's fmi2TypesPlatform.h and fmi2FunctionTypes.h. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _WIN32
#include <windows.h>
#define LOAD(path) ((void *)LoadLibraryA(path))
#define SYMBOL(lib, name) ((void *)GetProcAddress((HMODULE)(lib), name))
#else
#include <dlfcn.h>
#define LOAD(path) dlopen(path, RTLD_NOW | RTLD_LOCAL)
#define SYMBOL(lib, name) dlsym(lib, name)
#endif

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef int fmi2Boolean;
typedef int fmi2Status;
typedef void (*fmi2CallbackLogger)(void *, const char *, fmi2Status, const char *, const char *, ...);
typedef struct {
    fmi2CallbackLogger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;

typedef fmi2Component (*Instantiate)(const char *, int, const char *, const char *, const fmi2CallbackFunctions *,
                                     fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*SetupExperiment)(fmi2Component, fmi2Boolean, double, double, fmi2Boolean, double);
typedef fmi2Status (*OneArgument)(fmi2Component);
typedef fmi2Status (*RealAccess)(fmi2Component, const fmi2ValueReference *, size_t, double *);
typedef fmi2Status (*DoStep)(fmi2Component, double, double, fmi2Boolean);
typedef void (*FreeInstance)(fmi2Component);

static const char *STATUS[] = {"OK", "Warning", "Discard", "Error", "Fatal", "Pending"};

static const char *status_name(fmi2Status s) { return s >= 0 && s <= 5 ? STATUS[s] : "?"; }

static void logger(void *env, const char *instance, fmi2Status status, const char *category, const char *format,
                   ...) {
    char message[2048];
    va_list args;
    (void)env;
    (void)instance;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    printf("log %s %s %s\n", status_name(status), category, message);
}

static void *function(void *library, const char *name) {
    void *f = SYMBOL(library, name);
    if (!f) {
        fprintf(stderr, "fmu_session: the binary does not export %s\n", name);
        exit(3);
    }
    return f;
}

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: fmu_session BINARY MODEL_IDENTIFIER GUID RESOURCE_URI < script\n");
        return 2;
    }
    void *library = LOAD(argv[1]);
    if (!library) {
        fprintf(stderr, "fmu_session: cannot load %s\n", argv[1]);
        return 3;
    }
    Instantiate instantiate = (Instantiate)function(library, "fmi2Instantiate");
    SetupExperiment setup = (SetupExperiment)function(library, "fmi2SetupExperiment");
    OneArgument enter = (OneArgument)function(library, "fmi2EnterInitializationMode");
    OneArgument leave = (OneArgument)function(library, "fmi2ExitInitializationMode");
    OneArgument terminate = (OneArgument)function(library, "fmi2Terminate");
    RealAccess set_real = (RealAccess)function(library, "fmi2SetReal");
    RealAccess get_real = (RealAccess)function(library, "fmi2GetReal");
    DoStep do_step = (DoStep)function(library, "fmi2DoStep");
    FreeInstance free_instance = (FreeInstance)function(library, "fmi2FreeInstance");
    const char *(*version)(void) = (const char *(*)(void))function(library, "fmi2GetVersion");
    printf("version %s\n", version());

    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = NULL;
    char line[65536];
    while (fgets(line, sizeof line, stdin)) {
        char *word = strtok(line, " \t\r\n");
        if (!word) continue;
        if (!strcmp(word, "instantiate")) {
            const char *name = strtok(NULL, " \t\r\n");
            c = instantiate(name, 1 /* fmi2CoSimulation */, argv[3], argv[4], &callbacks, 0, 0);
            printf("instantiate %s %s\n", name, c ? "ok" : "null");
        } else if (!strcmp(word, "setup")) {
            double tolerance = strtod(strtok(NULL, " \t\r\n"), NULL);
            double start = strtod(strtok(NULL, " \t\r\n"), NULL);
            printf("setup %s\n", status_name(setup(c, tolerance > 0, tolerance, start, 0, 0.0)));
        } else if (!strcmp(word, "init")) {
            fmi2Status s = enter(c);
            printf("init %s\n", status_name(s <= 1 ? leave(c) : s));
        } else if (!strcmp(word, "set")) {
            fmi2ValueReference vr[64];
            double value[64];
            size_t n = 0;
            char *token;
            while (n < 64 && (token = strtok(NULL, " \t\r\n"))) {
                vr[n] = (fmi2ValueReference)strtoul(token, NULL, 10);
                value[n++] = strtod(strtok(NULL, " \t\r\n"), NULL);
            }
            printf("set %s\n", status_name(set_real(c, vr, n, value)));
        } else if (!strcmp(word, "step")) {
            double t = strtod(strtok(NULL, " \t\r\n"), NULL);
            double h = strtod(strtok(NULL, " \t\r\n"), NULL);
            printf("step %s\n", status_name(do_step(c, t, h, 1)));
        } else if (!strcmp(word, "get")) {
            fmi2ValueReference vr[64];
            double value[64];
            size_t n = 0;
            char *token;
            while (n < 64 && (token = strtok(NULL, " \t\r\n"))) vr[n++] = (fmi2ValueReference)strtoul(token, NULL, 10);
            printf("get %s", status_name(get_real(c, vr, n, value)));
            for (size_t k = 0; k < n; k++) printf(" %.17g", value[k]);
            printf("\n");
        } else if (!strcmp(word, "terminate")) {
            printf("terminate %s\n", status_name(terminate(c)));
        } else if (!strcmp(word, "free")) {
            free_instance(c);
            c = NULL;
            printf("free\n");
        } else {
            fprintf(stderr, "fmu_session: unknown call %s\n", word);
            return 2;
        }
    }
    return 0;
}
