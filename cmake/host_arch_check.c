/* Built into every host program of an FCC_HOST_ARCH build (cmake/host-arch.cmake), compiled
 * for the portable x86-64: before main, a CPU without the instructions the program was built
 * for gets one line and exit status 1 instead of an illegal instruction somewhere later. */
#include <stdio.h>
#include <stdlib.h>

#ifndef FCC_HOST_ARCH_NAME
#error "FCC_HOST_ARCH_NAME: the -march level the program was built for, e.g. \"x86-64-v3\""
#endif

static void fcc_host_arch_check(void) __attribute__((constructor(101)));

static void fcc_host_arch_check(void)
{
    __builtin_cpu_init();
    if (!__builtin_cpu_supports(FCC_HOST_ARCH_NAME)) {
        (void)fprintf(stderr, "this program was built for %s (-DFCC_HOST_ARCH) and this CPU lacks "
                      "its instructions; use the portable build (configure without FCC_HOST_ARCH)\n",
                      FCC_HOST_ARCH_NAME);
        exit(1);
    }
}
