/*
 * m4f_image.c -- the smallest bare-metal program that pulls the firmware core
 * into a Cortex-M4F image.  It is never flashed; it exists so the cross build
 * can measure flash and static RAM, and so a link error proves that nothing in
 * the core reaches for an OS or the heap.
 */
#include "fcc_types.h"

int main(void);

int main(void)
{
    volatile fcc_status_t sink = FCC_OK;
    (void)fcc_status_str(sink);
    for (;;) {
    }
}
