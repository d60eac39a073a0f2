/*
 * fcc_event.c -- names of the event classes (see fcc_event.h).
 */
#include "fcc_event.h"

const char *fcc_event_class_str(fcc_event_class_t cls)
{
    static const char *const names[FCC_EV_COUNT] = {
        "unknown CAN id",      "wrong DLC",          "value out of range",
        "E2E ERROR",           "E2E WRONG_SEQUENCE", "E2E REPEATED",
        "sensor stale",        "sensor rejected",    "sensor misaligned",
        "sensor recovered",    "ticks lost",         "tick repeated",
        "tick behind",         "tick ignored",       "LQG design applied",
        "config rejected",     "reset",              "transmit failed",
        "transmit refused",    "step error",         "overrun",
        "interface down",      "interface up",       "bus errors",
        "authentication failed", "command refused in this mode", "mode",
        "time sync state",     "time sync input refused",
    };
    if ((unsigned int)cls >= (unsigned int)FCC_EV_COUNT) {
        return "unknown event";
    }
    return names[cls];
}
