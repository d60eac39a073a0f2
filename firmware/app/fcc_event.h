/*
 * fcc_event.h -- things that happened and deserve one line in a log.
 *
 * The core only says WHAT happened (class, where, which step, a value); the
 * port decides how to report it.  On Linux that is one stderr line per class,
 * rate-limited, so a babbling node at full bus rate cannot flood the log and
 * every class still shows up at least once.
 */
#ifndef FCC_EVENT_H
#define FCC_EVENT_H

#include <stdint.h>

typedef enum {
    FCC_EV_UNKNOWN_ID = 0,   /* frame with an identifier this node does not consume */
    FCC_EV_WRONG_DLC,        /* frame with a length other than the DBC's */
    FCC_EV_OUT_OF_RANGE,     /* raw value outside the DBC range */
    FCC_EV_E2E_ERROR,        /* CRC mismatch */
    FCC_EV_E2E_WRONG_SEQ,    /* alive counter jumped or went back */
    FCC_EV_E2E_REPEATED,     /* alive counter repeated */
    FCC_EV_SENSOR_STALE,     /* no new frame beyond the stale limit */
    FCC_EV_SENSOR_REJECTED,  /* only rejected frames in a step */
    FCC_EV_SENSOR_MISALIGNED,/* lockstep: frames for another step */
    FCC_EV_SENSOR_RECOVERED, /* a sensor is good again */
    FCC_EV_TICK_LOST,        /* lockstep: ticks skipped (value = how many) */
    FCC_EV_TICK_REPEATED,    /* lockstep: same tick again, ACK resent */
    FCC_EV_TICK_BEHIND,      /* lockstep: tick older than the last one, ignored */
    FCC_EV_TICK_IGNORED,     /* tick in realtime mode or for a disabled app */
    FCC_EV_CONFIG_APPLIED,   /* new LQG design switched in (value = period in us) */
    FCC_EV_CONFIG_REJECTED,  /* SIM_CONTROL request refused (value = status) */
    FCC_EV_RESET,            /* both applications re-initialised */
    FCC_EV_TX_FAILED,        /* the port did not send a frame */
    FCC_EV_TX_REFUSED,       /* the frame layer refused to encode (NaN, range) */
    FCC_EV_STEP_ERROR,       /* an application step reported an error (value = status) */
    FCC_EV_OVERRUN,          /* realtime: a step started a whole period late */
    FCC_EV_IFACE_DOWN,       /* port: the interface stopped working */
    FCC_EV_IFACE_UP,         /* port: the interface works again */
    FCC_EV_BUS_ERROR,        /* port: CAN error frames / receive overflows */
    FCC_EV_AUTH_FAILED,      /* SecOC: authenticator refused (value = fcc_secoc_verdict_t) */
    FCC_EV_MODE_REFUSED,     /* authenticated command not allowed in this mode (value = command) */
    FCC_EV_MODE_CHANGED,     /* operating mode changed (value = new fcc_op_mode_t) */
    FCC_EV_SYNC_STATE,       /* time sync changed state (value = fcc_tsync_state_t) */
    FCC_EV_SYNC_REJECTED,    /* a time-sync input was refused (value = refusals so far) */
    FCC_EV_COUNT
} fcc_event_class_t;

#define FCC_EV_NO_APP 0xFFu
#define FCC_EV_NO_MSG 0xFFFFFFFFu

typedef struct {
    fcc_event_class_t cls;
    uint8_t app;      /* FCC_APP_* or FCC_EV_NO_APP */
    uint32_t can_id;  /* CAN identifier concerned, or FCC_EV_NO_MSG */
    uint32_t step;    /* step of app when it happened */
    int32_t value;    /* class-specific (see above) */
} fcc_event_t;

/* Short static name, e.g. "E2E ERROR" (never NULL). */
const char *fcc_event_class_str(fcc_event_class_t cls);

#endif /* FCC_EVENT_H */
