/*
 * mps2_board.c -- mps2-an386: CMSDK APB UART driver, SysTick clock,
 * semihosting exit; see mps2_board.h.
 */
#include "mps2_board.h"

#include <stdbool.h>

/* ---- registers ---------------------------------------------------------------- */

typedef struct {
    volatile uint32_t data;      /* 0x00 */
    volatile uint32_t state;     /* 0x04: bit 0 TX full, 1 RX full, 2 TX overrun, 3 RX overrun */
    volatile uint32_t ctrl;      /* 0x08: bit 0 TX en, 1 RX en, 2 TX int, 3 RX int, 4/5 overrun int */
    volatile uint32_t intstatus; /* 0x0C: read status, write 1 to clear (TX 0, RX 1, TXO 2, RXO 3) */
    volatile uint32_t bauddiv;   /* 0x10 */
} cmsdk_uart_t;

#define UART0 ((cmsdk_uart_t *)0x40004000u)
#define UART1 ((cmsdk_uart_t *)0x40005000u)
#define UART_STATE_TXFULL 0x1u
#define UART_STATE_RXFULL 0x2u
#define UART_STATE_OVERRUN 0xCu
#define UART_CTRL_TX_EN 0x1u
#define UART_CTRL_RX_EN 0x2u
#define UART_CTRL_TX_INT 0x4u
#define UART_CTRL_RX_INT 0x8u
#define UART_CTRL_RXO_INT 0x20u
#define UART_INT_TX 0x1u
#define UART_INT_RX 0x2u
#define UART_INT_OVERRUN 0xCu
/* 25 MHz / 115200 baud: QEMU ignores the rate but wants a valid divider. */
#define UART_BAUDDIV 217u

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define NVIC_ISER0 (*(volatile uint32_t *)0xE000E100u)
#define DUALTIMER1_LOAD (*(volatile uint32_t *)0x40002000u)
#define DUALTIMER1_VALUE (*(volatile uint32_t *)0x40002004u)
#define DUALTIMER1_CTRL (*(volatile uint32_t *)0x40002008u)
#define DUALTIMER_CTRL_EN_32BIT_FREE 0x82u /* enable, 32-bit, free-running, no prescale */
#define SYST_CSR_ONE_SHOT 0x7u     /* CPU clock, interrupt, enable */
#define SYST_RELOAD_MAX 0xFFFFFFu  /* 24 bits: 0.67 s at 25 MHz */
#define TICKS_PER_US (MPS2_CPU_HZ / 1000000u)
/* How long the image lingers between its last byte and QEMU's exit. */
#define EXIT_LINGER_US 50000u
#define IRQ_UART0_RX 0u
#define IRQ_UART0_TX 1u
#define IRQ_UART_OVERFLOW 12u
/* Log UART: give up on a byte after this many polls (QEMU never blocks a
 * file or null backend; a stuck pty must not stop the flight computer). */
#define LOG_POLL_LIMIT 100000u

/* SLCAN line terminators: the byte after one begins a line. */
#define LINK_CR 0x0Du
#define LINK_LF 0x0Au

#define MPS2_STACK_PAINT 0xA5A5A5A5u
extern uint32_t mps2_stack_bottom, mps2_stack_top, mps2_bootcfg_start;

/* ---- state (one board) ----------------------------------------------------------- */

/* When a line's first byte came: its index in the receive ring's free-running
 * count, and the clock's low 32 bits (ticks) when the interrupt took it; and
 * when its terminator came (written before the terminator is in the ring).
 * Volatile: written by the interrupt before it moves stamp_head (rx_head for
 * `ended`), and neither side may reorder its accesses across that index. */
typedef struct {
    volatile uint32_t index;
    volatile uint32_t elapsed;
    volatile uint32_t ended;
} line_stamp_t;

typedef struct {
    uint32_t last_elapsed;                      /* clock extension (main loop only) */
    uint32_t wraps;
    uint8_t rx[MPS2_LINK_RX_RING];
    volatile uint32_t rx_head;                  /* written by the RX interrupt */
    volatile uint32_t rx_tail;                  /* written by the main loop */
    /* line receive stamps: written by the RX interrupt, read by the main loop */
    line_stamp_t stamps[MPS2_LINK_LINE_STAMPS];
    volatile uint32_t stamp_head;               /* written by the RX interrupt */
    volatile uint32_t stamp_tail;               /* written by the main loop */
    bool isr_mid_line;                          /* RX interrupt: next byte continues a line */
    uint32_t isr_line_elapsed;                  /* RX interrupt: when this line began */
    bool isr_line_stamped;                      /* RX interrupt: this line has a stamp ... */
    uint32_t isr_line_stamp;                    /* ... at this stamp index */
    bool rd_mid_line;                           /* main loop: next byte continues a line */
    uint64_t rd_line_ticks;                     /* main loop: when the line being read began */
    uint32_t rd_line_index;                     /* main loop: its first byte's ring index */
    uint32_t rd_line_stamp;                     /* main loop: its stamp index (if stamped) */
    bool rd_line_stamped;
    uint64_t rd_end_ticks;                      /* main loop: when the line last read ended (0: unknown) */
    uint8_t tx[MPS2_LINK_TX_RING];
    volatile uint32_t tx_head;                  /* written by the main loop */
    volatile uint32_t tx_tail;                  /* written by the pump (interrupts masked) */
    volatile mps2_counters_t cnt;
} mps2_t;

static mps2_t g_board;

void mps2_systick_isr(void);
void mps2_uart0_rx_isr(void);
void mps2_uart0_tx_isr(void);
void mps2_uart_overflow_isr(void);

static uint32_t irq_save(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
    return primask;
}

static void irq_restore(uint32_t primask)
{
    __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
}

/* ---- clock ------------------------------------------------------------------------ */

/* The SysTick is the alarm: it fires once, at the deadline arm_alarm()
 * set (for the idle loop, or the wait before exit), and stops. */
void mps2_systick_isr(void)
{
    SYST_CSR = 0u;
}

/* The dual timer's first counter, free-running over 32 bits, is the clock:
 * QEMU derives its value from virtual time directly, whereas a periodic
 * SysTick drifts when the host serves its interrupts late.  Extended to 64
 * bits here (it wraps every 171 s; only the main loop reads it). */
uint64_t mps2_ticks(void)
{
    const uint32_t elapsed = 0xFFFFFFFFu - DUALTIMER1_VALUE;
    if (elapsed < g_board.last_elapsed) {
        ++g_board.wraps;
    }
    g_board.last_elapsed = elapsed;
    return ((uint64_t)g_board.wraps << 32) | elapsed;
}

uint64_t mps2_now_us(void)
{
    return mps2_ticks() / (MPS2_CPU_HZ / 1000000u);
}

static uint32_t elapsed_now(void)
{
    return 0xFFFFFFFFu - DUALTIMER1_VALUE;
}

/* A stamp taken within the last 171 s (the counter's wrap), on the 64-bit clock. */
static uint64_t ticks_of(uint32_t elapsed)
{
    const uint64_t now = mps2_ticks();
    return now - (uint32_t)((uint32_t)now - elapsed);
}

/* ---- link UART (UART0) -------------------------------------------------------------- */

static uint32_t ring_used(uint32_t head, uint32_t tail)
{
    return head - tail; /* free-running indices, power-of-two rings */
}

static bool is_terminator(uint8_t b)
{
    return b == LINK_CR || b == LINK_LF;
}

/* The stored byte at ring index `index`: a line's first byte leaves its
 * receive stamp, its terminator the line's time on the wire (counters). */
static void stamp_byte(uint8_t b, uint32_t index)
{
    if (!g_board.isr_mid_line) {
        const uint32_t elapsed = elapsed_now();
        const uint32_t head = g_board.stamp_head;
        g_board.isr_line_stamped = ring_used(head, g_board.stamp_tail) < MPS2_LINK_LINE_STAMPS;
        if (g_board.isr_line_stamped) {
            g_board.stamps[head % MPS2_LINK_LINE_STAMPS].index = index;
            g_board.stamps[head % MPS2_LINK_LINE_STAMPS].elapsed = elapsed;
            g_board.stamps[head % MPS2_LINK_LINE_STAMPS].ended = elapsed;
            g_board.isr_line_stamp = head;
            g_board.stamp_head = head + 1u;
        } else {
            g_board.cnt.stamps_lost = g_board.cnt.stamps_lost + 1u;
        }
        g_board.isr_line_elapsed = elapsed;
    }
    if (is_terminator(b)) {
        const uint32_t ended = elapsed_now();
        if (g_board.isr_line_stamped) {
            g_board.stamps[g_board.isr_line_stamp % MPS2_LINK_LINE_STAMPS].ended = ended;
        }
        const uint32_t on_line_us = (ended - g_board.isr_line_elapsed) / TICKS_PER_US;
        g_board.cnt.line_us_sum = g_board.cnt.line_us_sum + on_line_us;
        g_board.cnt.line_us_worst =
            (on_line_us > g_board.cnt.line_us_worst) ? on_line_us : g_board.cnt.line_us_worst;
        g_board.cnt.lines = g_board.cnt.lines + 1u;
    }
    g_board.isr_mid_line = !is_terminator(b);
}

void mps2_uart0_rx_isr(void)
{
    /* Clear first, then drain: a byte that lands after the last read raises
     * the interrupt again instead of waiting unseen in the UART. */
    UART0->intstatus = UART_INT_RX;
    while ((UART0->state & UART_STATE_RXFULL) != 0u) {
        const uint8_t b = (uint8_t)UART0->data;
        const uint32_t head = g_board.rx_head;
        if (ring_used(head, g_board.rx_tail) < MPS2_LINK_RX_RING) {
            g_board.rx[head % MPS2_LINK_RX_RING] = b;
            stamp_byte(b, head);
            g_board.rx_head = head + 1u;
            g_board.cnt.rx_bytes = g_board.cnt.rx_bytes + 1u;
        } else {
            g_board.cnt.rx_overflows = g_board.cnt.rx_overflows + 1u;
        }
    }
}

void mps2_uart_overflow_isr(void)
{
    if ((UART0->state & UART_STATE_OVERRUN) != 0u) {
        g_board.cnt.rx_overflows = g_board.cnt.rx_overflows + 1u;
    }
    UART0->state = UART_STATE_OVERRUN;   /* write 1 to clear */
    UART0->intstatus = UART_INT_OVERRUN;
    UART1->state = UART_STATE_OVERRUN;
    UART1->intstatus = UART_INT_OVERRUN;
}

/* Moves queued bytes into the UART while it takes them; asks for the TX
 * interrupt only while bytes remain.  Called with interrupts masked. */
static void tx_pump(void)
{
    uint32_t tail = g_board.tx_tail;
    while (tail != g_board.tx_head && (UART0->state & UART_STATE_TXFULL) == 0u) {
        UART0->data = g_board.tx[tail % MPS2_LINK_TX_RING];
        ++tail;
    }
    g_board.tx_tail = tail;
    if (tail != g_board.tx_head) {
        UART0->ctrl |= UART_CTRL_TX_INT;
    } else {
        UART0->ctrl &= ~UART_CTRL_TX_INT;
    }
}

void mps2_uart0_tx_isr(void)
{
    UART0->intstatus = UART_INT_TX;
    tx_pump();
}

/* The receive stamp of the line that begins at ring index `index` (stamps of
 * lines before it are dropped); the current time if it has none (its stamp
 * was lost: the stamp ring was full).  Its stamp's index is kept for the
 * line's end (line_end_ticks). */
static uint64_t line_ticks(uint32_t index)
{
    uint32_t st = g_board.stamp_tail;
    uint64_t ticks = mps2_ticks();
    g_board.rd_line_index = index;
    g_board.rd_line_stamped = false;
    while (st != g_board.stamp_head) {
        const line_stamp_t *s = &g_board.stamps[st % MPS2_LINK_LINE_STAMPS];
        const int32_t ahead = (int32_t)(s->index - index);
        if (ahead > 0) {
            break; /* a later line's: this one's was lost */
        }
        ++st;
        if (ahead == 0) {
            ticks = ticks_of(s->elapsed);
            g_board.rd_line_stamp = st - 1u;
            g_board.rd_line_stamped = true;
            break;
        }
    }
    g_board.stamp_tail = st;
    return ticks;
}

/* When the line being read ended (its terminator is read now): its stamp's
 * `ended`, unless the line had no stamp or the interrupt has since reused the
 * slot for a later line (128 lines behind): then the current time. */
static uint64_t line_end_ticks(void)
{
    const line_stamp_t *s = &g_board.stamps[g_board.rd_line_stamp % MPS2_LINK_LINE_STAMPS];
    const bool kept = g_board.rd_line_stamped && (s->index == g_board.rd_line_index);
    return kept ? ticks_of(s->ended) : mps2_ticks();
}

int mps2_link_getc(uint8_t *byte, uint64_t *line_rx_us)
{
    const uint32_t tail = g_board.rx_tail;
    if (tail == g_board.rx_head) {
        return 0;
    }
    *byte = g_board.rx[tail % MPS2_LINK_RX_RING];
    if (!g_board.rd_mid_line) {
        g_board.rd_line_ticks = line_ticks(tail);
    }
    g_board.rd_mid_line = !is_terminator(*byte);
    if (!g_board.rd_mid_line) {
        g_board.rd_end_ticks = line_end_ticks();
    }
    g_board.rx_tail = tail + 1u;
    *line_rx_us = g_board.rd_line_ticks / TICKS_PER_US;
    return 1;
}

uint64_t mps2_link_line_end_us(void)
{
    return g_board.rd_end_ticks / TICKS_PER_US;
}

fcc_status_t mps2_link_write(void *ctx, const uint8_t *bytes, size_t n)
{
    (void)ctx;
    if (bytes == NULL || n > MPS2_LINK_TX_RING) {
        return FCC_ERR_ARG;
    }
    const uint32_t primask = irq_save();
    uint32_t head = g_board.tx_head;
    if ((size_t)(MPS2_LINK_TX_RING - ring_used(head, g_board.tx_tail)) < n) {
        g_board.cnt.tx_refused = g_board.cnt.tx_refused + 1u;
        irq_restore(primask);
        return FCC_ERR_AGAIN;
    }
    for (size_t i = 0u; i < n; ++i) {
        g_board.tx[head % MPS2_LINK_TX_RING] = bytes[i];
        ++head;
    }
    g_board.tx_head = head;
    g_board.cnt.tx_bytes = g_board.cnt.tx_bytes + (uint32_t)n;
    tx_pump();
    irq_restore(primask);
    return FCC_OK;
}

/* ---- log UART (UART1) --------------------------------------------------------------- */

void mps2_log(const char *text)
{
    for (const char *p = text; p != NULL && *p != '\0'; ++p) {
        uint32_t polls = 0u;
        while ((UART1->state & UART_STATE_TXFULL) != 0u && polls < LOG_POLL_LIMIT) {
            ++polls;
        }
        if (polls == LOG_POLL_LIMIT) {
            g_board.cnt.log_dropped = g_board.cnt.log_dropped + 1u;
            continue;
        }
        UART1->data = (uint8_t)*p;
    }
}

void mps2_log_u64(uint64_t v)
{
    char buf[21];
    size_t i = sizeof buf - 1u;
    buf[i] = '\0';
    do {
        buf[--i] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u && i > 0u);
    mps2_log(&buf[i]);
}

/* ---- board ------------------------------------------------------------------------- */

void mps2_board_init(void)
{
    SYST_CSR = 0u; /* armed by arm_alarm() only */
    DUALTIMER1_CTRL = 0u;
    DUALTIMER1_LOAD = 0xFFFFFFFFu;
    DUALTIMER1_CTRL = DUALTIMER_CTRL_EN_32BIT_FREE;
    UART0->bauddiv = UART_BAUDDIV;
    UART0->ctrl = UART_CTRL_TX_EN | UART_CTRL_RX_EN | UART_CTRL_RX_INT | UART_CTRL_RXO_INT;
    /* An empty read (nothing received yet: RX was off since reset) tells
     * the emulator the receiver is ready: QEMU's UART model announces
     * "ready" only on a data read, and bytes its line buffer took before
     * RX was enabled would otherwise wait there for the next byte. */
    (void)UART0->data;
    UART1->bauddiv = UART_BAUDDIV;
    UART1->ctrl = UART_CTRL_TX_EN;
    NVIC_ISER0 = (1u << IRQ_UART0_RX) | (1u << IRQ_UART0_TX) | (1u << IRQ_UART_OVERFLOW);
}

/* The SysTick fires once at until_us (at most 0.67 s ahead: the caller
 * looks again then).  A one-shot alarm, not a periodic tick: under QEMU every
 * timer interrupt is a round of its main loop and vCPU thread, and a 1 ms
 * tick cost ~16 system calls each while the image waited for the rig. */
static void arm_alarm(uint64_t until_us)
{
    const uint64_t now = mps2_now_us();
    const uint64_t wait_us = (until_us > now) ? until_us - now : 1u;
    const uint32_t reload = (wait_us > SYST_RELOAD_MAX / TICKS_PER_US)
                                ? SYST_RELOAD_MAX
                                : (uint32_t)(wait_us * TICKS_PER_US);
    SYST_CSR = 0u;
    SYST_RVR = reload;
    SYST_CVR = 0u;
    SYST_CSR = SYST_CSR_ONE_SHOT;
}

void mps2_idle(uint64_t until_us)
{
    if (mps2_now_us() >= until_us) {
        return;
    }
    /* Masked check-then-sleep: an interrupt that arrives in between still
     * ends the WFI (it is pending), so no byte waits for the alarm. */
    const uint32_t primask = irq_save();
    if (g_board.rx_tail == g_board.rx_head) {
        arm_alarm(until_us);
        g_board.cnt.sleeps = g_board.cnt.sleeps + 1u;
        __asm__ volatile("dsb\n\twfi" ::: "memory");
    }
    irq_restore(primask);
}

uint32_t mps2_stack_used(void)
{
    const uint32_t *p = &mps2_stack_bottom;
    while (p < &mps2_stack_top && *p == MPS2_STACK_PAINT) {
        ++p;
    }
    return (uint32_t)((uintptr_t)&mps2_stack_top - (uintptr_t)p);
}

void mps2_counters(mps2_counters_t *out)
{
    const uint32_t primask = irq_save();
    out->rx_bytes = g_board.cnt.rx_bytes;
    out->rx_overflows = g_board.cnt.rx_overflows;
    out->tx_bytes = g_board.cnt.tx_bytes;
    out->tx_refused = g_board.cnt.tx_refused;
    out->log_dropped = g_board.cnt.log_dropped;
    out->sleeps = g_board.cnt.sleeps;
    out->lines = g_board.cnt.lines;
    out->line_us_sum = g_board.cnt.line_us_sum;
    out->line_us_worst = g_board.cnt.line_us_worst;
    out->stamps_lost = g_board.cnt.stamps_lost;
    irq_restore(primask);
}

void mps2_exit(int status)
{
    /* SYS_EXIT_EXTENDED (0x20): r1 -> {ADP_Stopped_ApplicationExit, status}. */
    static volatile uint32_t block[2];
    block[0] = 0x20026u;
    block[1] = (uint32_t)status;
    /* Let the link drain first: the last heartbeat must leave the board. */
    for (uint32_t i = 0u; i < 1000000u && g_board.tx_tail != g_board.tx_head; ++i) {
        const uint32_t primask = irq_save();
        tx_pump();
        irq_restore(primask);
    }
    /* Then give the far end of the line time to take it: QEMU's exit closes
     * its pty, and the kernel drops what the pty's reader (slcand's line
     * discipline) had not yet processed -- the last heartbeat, the counters
     * the rig reports.  Received bytes no longer matter: sleep through them. */
    const uint64_t until = mps2_now_us() + EXIT_LINGER_US;
    while (mps2_now_us() < until) {
        arm_alarm(until);
        __asm__ volatile("dsb\n\twfi" ::: "memory");
    }
    __asm__ volatile("mov r0, #0x20\n\tmov r1, %0\n\tbkpt #0xab" ::"r"(block) : "r0", "r1", "memory");
    for (;;) {
        __asm__ volatile("wfi");
    }
}

const volatile uint8_t *mps2_bootcfg(void)
{
    return (const volatile uint8_t *)&mps2_bootcfg_start;
}
