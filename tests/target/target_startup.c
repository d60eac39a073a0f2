/*
 * target_startup.c -- reset, vector table and the C library's heap for the unit-test images
 * on QEMU's mps2-an386 (tests/target/README.md). newlib's librdimon does the rest over
 * semihosting: stdout/stderr, the test vectors' files on the host, and exit(), whose status
 * reaches QEMU's exit status (SYS_EXIT_EXTENDED).
 */
#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

extern uint32_t target_data_start, target_data_end, target_data_load;
extern uint32_t target_bss_start, target_bss_end;
extern uint32_t target_stack_top;
extern char end, target_heap_limit;

int main(void);
void initialise_monitor_handles(void);
void target_reset(void) __attribute__((noreturn));
void target_fault(void) __attribute__((noreturn));
void *_sbrk(ptrdiff_t increment);
void _fini(void);
int __real_vsnprintf(char *buf, size_t size, const char *format, va_list args);
int __wrap_vsnprintf(char *buf, size_t size, const char *format, va_list args);

/* The status of a test program that faulted (a stack overflow, a bad access). */
#define TARGET_FAULT_STATUS 70
#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)

/* The board's dual timer 1, free-running at the 25 MHz CPU clock: under QEMU's -icount shift=0
 * (1 instruction = 1 ns) one tick is 40 instructions; it wraps after 171 s of virtual time. */
#define DUALTIMER1_LOAD (*(volatile uint32_t *)0x40002000u)
#define DUALTIMER1_VALUE (*(volatile uint32_t *)0x40002004u)
#define DUALTIMER1_CTRL (*(volatile uint32_t *)0x40002008u)
#define DUALTIMER_CTRL_EN_32BIT_FREE 0x82u
#define INSTRUCTIONS_PER_TICK 40u

static unsigned long long instructions_since_reset(void)
{
    return (unsigned long long)(0xFFFFFFFFu - DUALTIMER1_VALUE) * INSTRUCTIONS_PER_TICK;
}

#ifdef FCC_TARGET_COVERAGE
#include <gcov.h>

extern const struct gcov_info *const __gcov_info_start[], *const __gcov_info_end[];

static void gcda_open(const char *name, void *arg)
{
    *(FILE **)arg = fopen(name, "wb");
}

static void gcda_write(const void *data, unsigned int n, void *arg)
{
    FILE *const f = *(FILE **)arg;
    if (f != NULL) {
        (void)fwrite(data, 1u, n, f);
    }
}

static void *gcda_allocate(unsigned int n, void *arg)
{
    (void)arg;
    return malloc(n);
}

/* gcov's counters as .gcda files next to the objects, on the host: librdimon's fopen and fwrite
 * are semihosting's SYS_OPEN and SYS_WRITE. */
static void write_coverage(void)
{
    for (const struct gcov_info *const *info = __gcov_info_start; info < __gcov_info_end; ++info) {
        FILE *f = NULL;
        __gcov_info_to_gcda(*info, gcda_open, gcda_write, gcda_allocate, &f);
        if (f == NULL || fclose(f) != 0) {
            printf("target: coverage not written\n");
        }
    }
}
#endif

/* The program's instruction count, the last line before its exit (scripts/test target-unit). */
static void report_instructions(void)
{
    printf("target: %llu instructions\n", instructions_since_reset());
}

/* Each test case's count: cmocka formats a case's start and end lines with vsnprintf (its
 * vprint_message), which the images link wrapped (-Wl,--wrap=vsnprintf); the end line gets a
 * second line with the instructions since the start, cmocka's own bookkeeping included. */
int __wrap_vsnprintf(char *buf, size_t size, const char *format, va_list args)
{
    static unsigned long long case_start;
    const int n = __real_vsnprintf(buf, size, format, args);
    if (strcmp(format, "[ RUN      ] %s\n") == 0) {
        case_start = instructions_since_reset();
    } else if ((strcmp(format, "[       OK ] %s\n") == 0 || strcmp(format, "[  FAILED  ] %s\n") == 0) &&
               n >= 0 && (size_t)n < size) {
        const int more = snprintf(buf + n, size - (size_t)n, "target: case %llu instructions\n",
                                  instructions_since_reset() - case_start);
        return more < 0 ? n : n + more;
    }
    return n;
}

void target_reset(void)
{
    const uint32_t *src = &target_data_load;
    for (uint32_t *dst = &target_data_start; dst < &target_data_end; ++dst, ++src) {
        *dst = *src;
    }
    for (uint32_t *dst = &target_bss_start; dst < &target_bss_end; ++dst) {
        *dst = 0u;
    }
    SCB_CPACR |= 0xFu << 20; /* CP10, CP11: full access to the FPU */
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    initialise_monitor_handles();
    DUALTIMER1_CTRL = 0u;
    DUALTIMER1_LOAD = 0xFFFFFFFFu;
    DUALTIMER1_CTRL = DUALTIMER_CTRL_EN_32BIT_FREE;
    (void)atexit(report_instructions);
#ifdef FCC_TARGET_COVERAGE
    (void)atexit(write_coverage);
#endif
    exit(main());
}

/* Any fault: say so on the host's stderr (SYS_WRITE0) and end QEMU with TARGET_FAULT_STATUS. */
void target_fault(void)
{
    static const char message[] = "target: fault (stack overflow or bad access)\n";
    /* static: the stack may be what faulted */
    static const uint32_t block[2] = {0x20026u /* ADP_Stopped_ApplicationExit */, TARGET_FAULT_STATUS};
    __asm__ volatile("mov r0, #0x04\n\tmov r1, %0\n\tbkpt #0xab" ::"r"(message) : "r0", "r1", "memory");
    __asm__ volatile("mov r0, #0x20\n\tmov r1, %0\n\tbkpt #0xab" ::"r"(block) : "r0", "r1", "memory");
    for (;;) {
    }
}

/* The heap: from the end of .bss to the end of RAM (the stack is below .data, target.ld). */
void *_sbrk(ptrdiff_t increment)
{
    static char *brk = &end;
    if (increment > &target_heap_limit - brk) {
        errno = ENOMEM;
        return (void *)-1;
    }
    char *const previous = brk;
    brk += increment;
    return previous;
}

/* exit()'s call of the destructors' section (crti.o's, which -nostartfiles leaves out): none. */
void _fini(void)
{
}

typedef void (*target_vector_t)(void);

__attribute__((section(".isr_vector"), used)) const target_vector_t target_vectors[16] = {
    (target_vector_t)(uintptr_t)&target_stack_top,
    target_reset,
    target_fault, /* NMI */
    target_fault, /* HardFault */
    target_fault, /* MemManage */
    target_fault, /* BusFault */
    target_fault, /* UsageFault */
    0, 0, 0, 0,
    target_fault, /* SVCall */
    target_fault, /* DebugMonitor */
    0,
    target_fault, /* PendSV */
    target_fault, /* SysTick */
};
