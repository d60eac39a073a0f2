/*
 * canbus_faults.c -- fault confinement counters and fault checks (see canbus_faults.h).
 */
#include "canbus_faults.h"

#include <stddef.h>

/* The counters' largest value: an error-passive receiver's REC stops here. */
#define REC_CEILING 255u
/* A successful reception brings a REC above 127 back to a value in 119..127; this model: 127. */
#define REC_AFTER_PASSIVE 127u

bool canbus_fault_valid(const canbus_fault_t *f)
{
    return f != NULL && f->id_min <= f->id_max && f->id_max <= CANBUS_EXT_ID_MAX &&
           f->t_from <= f->t_to && f->every >= 1u &&
           (f->bit <= CANBUS_BIT_MAX || f->bit == CANBUS_BIT_CRC_DELIM) &&
           f->superposed <= CANBUS_SUPERPOSED_MAX && (!f->until_bus_off || f->node != CANBUS_ANY_NODE);
}

canbus_state_t canbus_confine_state(uint32_t tec, uint32_t rec)
{
    if (tec >= CANBUS_PASSIVE_LIMIT || rec >= CANBUS_PASSIVE_LIMIT) {
        return CANBUS_ERROR_PASSIVE;
    }
    if (tec >= CANBUS_WARNING_LIMIT || rec >= CANBUS_WARNING_LIMIT) {
        return CANBUS_ERROR_WARNING;
    }
    return CANBUS_ERROR_ACTIVE;
}

static void note_max(canbus_confine_t *n)
{
    n->tec_max = n->tec > n->tec_max ? n->tec : n->tec_max;
    n->rec_max = n->rec > n->rec_max ? n->rec : n->rec_max;
}

void canbus_confine_tx_error(canbus_confine_t *n)
{
    n->tec += 8u;
    ++n->tx_errors;
    note_max(n);
}

void canbus_confine_rx_error(canbus_confine_t *n)
{
    n->rec = n->rec < REC_CEILING ? n->rec + 1u : REC_CEILING;
    ++n->rx_errors;
    note_max(n);
}

void canbus_confine_tx_ok(canbus_confine_t *n)
{
    n->tec = n->tec > 0u ? n->tec - 1u : 0u;
}

void canbus_confine_rx_ok(canbus_confine_t *n)
{
    if (n->rec > REC_AFTER_PASSIVE) {
        n->rec = REC_AFTER_PASSIVE;
    } else if (n->rec > 0u) {
        --n->rec;
    }
}

uint32_t canbus_fault_bit(const canbus_fault_t *f, uint32_t bits)
{
    /* the CRC delimiter follows the stuffed region: the frame's bits less the 13 after it */
    return f->bit == CANBUS_BIT_CRC_DELIM ? bits - CANBUS_TAIL_BITS : f->bit;
}
