/*
 * mps2_startup.c -- reset and the vector table of the Cortex-M4F image on
 * mps2-an386: initialised data copied from flash, .bss zeroed, the stack
 * painted (for mps2_stack_used), the FPU enabled, then main().
 */
#include <stdint.h>

extern uint32_t mps2_data_start, mps2_data_end, mps2_data_load;
extern uint32_t mps2_bss_start, mps2_bss_end;
extern uint32_t mps2_stack_bottom, mps2_stack_top;

int main(void);
void mps2_reset(void) __attribute__((noreturn));
void mps2_fault(void) __attribute__((noreturn));
void mps2_systick_isr(void);
void mps2_uart0_rx_isr(void);
void mps2_uart0_tx_isr(void);
void mps2_uart_overflow_isr(void);

#define MPS2_STACK_PAINT 0xA5A5A5A5u
#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)

/* Below the current stack pointer only: the reset handler's own frame is in use. */
static void paint_stack(void)
{
    uintptr_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    for (volatile uint32_t *p = &mps2_stack_bottom; (uintptr_t)p + 64u < sp; ++p) {
        *p = MPS2_STACK_PAINT;
    }
}

void mps2_reset(void)
{
    const uint32_t *src = &mps2_data_load;
    for (uint32_t *dst = &mps2_data_start; dst < &mps2_data_end; ++dst, ++src) {
        *dst = *src;
    }
    for (uint32_t *dst = &mps2_bss_start; dst < &mps2_bss_end; ++dst) {
        *dst = 0u;
    }
    paint_stack();
    SCB_CPACR |= 0xFu << 20; /* CP10, CP11: full access to the FPU */
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    (void)main();
    for (;;) {
        __asm__ volatile("wfi");
    }
}

/* Any fault or unexpected interrupt: stop here (a debugger sees where). */
void mps2_fault(void)
{
    for (;;) {
        __asm__ volatile("wfi");
    }
}

typedef void (*mps2_vector_t)(void);

/* 16 system exceptions, then the board's 32 interrupts: UART0 RX = 0,
 * UART0 TX = 1, the UARTs' combined overflow = 12. */
__attribute__((section(".isr_vector"), used)) const mps2_vector_t mps2_vectors[16 + 32] = {
    (mps2_vector_t)(uintptr_t)&mps2_stack_top,
    mps2_reset,
    mps2_fault, /* NMI */
    mps2_fault, /* HardFault */
    mps2_fault, /* MemManage */
    mps2_fault, /* BusFault */
    mps2_fault, /* UsageFault */
    0, 0, 0, 0,
    mps2_fault, /* SVCall */
    mps2_fault, /* DebugMonitor */
    0,
    mps2_fault, /* PendSV */
    mps2_systick_isr,
    mps2_uart0_rx_isr,
    mps2_uart0_tx_isr,
    mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault,
    mps2_fault, mps2_fault, mps2_fault,
    mps2_uart_overflow_isr,
    mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault,
    mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault,
    mps2_fault, mps2_fault, mps2_fault, mps2_fault, mps2_fault,
};
