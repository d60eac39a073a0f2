/*
 * fcc_e2e.c -- CRC-8 SAE J1850, alive counter, receiver classification.
 * See fcc_e2e.h and dbc/README.md ("E2E").
 */
#include "fcc_e2e.h"

#define CRC8_POLY 0x1Du
#define CRC8_INIT 0xFFu
#define CRC8_XOROUT 0xFFu

/* Bitwise, MSB first: 9 bytes per frame do not justify a 256-byte table in flash. */
static uint8_t crc8_update(uint8_t crc, uint8_t byte)
{
    unsigned int c = (unsigned int)crc ^ byte;
    for (unsigned int bit = 0u; bit < 8u; ++bit) {
        c = (c & 0x80u) ? ((c << 1) ^ CRC8_POLY) : (c << 1);
    }
    return (uint8_t)(c & 0xFFu);
}

uint8_t fcc_e2e_crc8(const uint8_t *data, size_t len)
{
    uint8_t crc = CRC8_INIT;
    if (data != NULL) {
        for (size_t i = 0u; i < len; ++i) {
            crc = crc8_update(crc, data[i]);
        }
    }
    return (uint8_t)(crc ^ CRC8_XOROUT);
}

uint8_t fcc_e2e_frame_crc(uint16_t data_id, const uint8_t frame[FCC_E2E_FRAME_LEN])
{
    uint8_t crc = CRC8_INIT;
    crc = crc8_update(crc, (uint8_t)(data_id & 0xFFu));
    crc = crc8_update(crc, (uint8_t)(data_id >> 8));
    for (size_t i = 1u; i < FCC_E2E_FRAME_LEN; ++i) {
        crc = crc8_update(crc, frame[i]);
    }
    return (uint8_t)(crc ^ CRC8_XOROUT);
}

fcc_status_t fcc_e2e_protect(uint16_t data_id, uint8_t counter, uint8_t frame[FCC_E2E_FRAME_LEN])
{
    if (frame == NULL || counter >= FCC_E2E_COUNTER_MOD) {
        return FCC_ERR_ARG;
    }
    frame[1] = (uint8_t)((frame[1] & 0xF0u) | counter);
    frame[0] = fcc_e2e_frame_crc(data_id, frame);
    return FCC_OK;
}

fcc_status_t fcc_e2e_tx_init(fcc_e2e_tx_t *tx, uint16_t data_id)
{
    if (tx == NULL) {
        return FCC_ERR_ARG;
    }
    tx->data_id = data_id;
    tx->counter = 0u;
    return FCC_OK;
}

fcc_status_t fcc_e2e_tx_protect(fcc_e2e_tx_t *tx, uint8_t frame[FCC_E2E_FRAME_LEN])
{
    if (tx == NULL) {
        return FCC_ERR_ARG;
    }
    const fcc_status_t st = fcc_e2e_protect(tx->data_id, tx->counter, frame);
    if (st == FCC_OK) {
        tx->counter = (uint8_t)((tx->counter + 1u) % FCC_E2E_COUNTER_MOD);
    }
    return st;
}

fcc_status_t fcc_e2e_rx_init(fcc_e2e_rx_t *rx, uint16_t data_id, uint8_t max_delta)
{
    if (rx == NULL || max_delta > FCC_E2E_COUNTER_MOD - 2u) {
        return FCC_ERR_ARG;
    }
    *rx = (fcc_e2e_rx_t){0};
    rx->data_id = data_id;
    rx->max_delta = (max_delta == 0u) ? (uint8_t)FCC_E2E_DEFAULT_MAX_DELTA : max_delta;
    rx->last_status = (uint8_t)FCC_E2E_NO_NEW_DATA;
    return FCC_OK;
}

static fcc_e2e_status_t classify(fcc_e2e_rx_t *rx, const uint8_t *frame, size_t len)
{
    if (len != FCC_E2E_FRAME_LEN || frame[0] != fcc_e2e_frame_crc(rx->data_id, frame)) {
        return FCC_E2E_ERROR;
    }
    const uint8_t counter = (uint8_t)(frame[1] & 0x0Fu);
    if (!rx->synced) {
        rx->synced = true;
        rx->last_counter = counter;
        return FCC_E2E_OK;
    }
    const uint8_t delta = (uint8_t)((counter - rx->last_counter) & 0x0Fu);
    if (delta == 0u) {
        return FCC_E2E_REPEATED;
    }
    rx->last_counter = counter;
    if (delta == 1u) {
        return FCC_E2E_OK;
    }
    if (delta <= rx->max_delta) {
        rx->lost_frames += (uint32_t)delta - 1u;
        return FCC_E2E_OK_SOME_LOST;
    }
    return FCC_E2E_WRONG_SEQUENCE;
}

fcc_e2e_status_t fcc_e2e_rx_check(fcc_e2e_rx_t *rx, const uint8_t *frame, size_t len)
{
    if (rx == NULL) {
        return FCC_E2E_ERROR;
    }
    const fcc_e2e_status_t status = (frame == NULL) ? FCC_E2E_ERROR : classify(rx, frame, len);
    if (rx->frames_this_period < UINT8_MAX) {
        ++rx->frames_this_period;
    }
    ++rx->count[status];
    rx->last_status = (uint8_t)status;
    return status;
}

bool fcc_e2e_rx_end_period(fcc_e2e_rx_t *rx)
{
    if (rx == NULL) {
        return false;
    }
    rx->stale = (rx->frames_this_period == 0u);
    if (rx->stale) {
        ++rx->count[FCC_E2E_NO_NEW_DATA];
        rx->last_status = (uint8_t)FCC_E2E_NO_NEW_DATA;
    }
    rx->frames_this_period = 0u;
    return rx->stale;
}

void fcc_e2e_rx_resync(fcc_e2e_rx_t *rx)
{
    if (rx != NULL) {
        rx->synced = false;
        rx->frames_this_period = 0u;
    }
}

bool fcc_e2e_usable(fcc_e2e_status_t status)
{
    return status == FCC_E2E_OK || status == FCC_E2E_OK_SOME_LOST;
}

const char *fcc_e2e_status_str(fcc_e2e_status_t status)
{
    switch (status) {
    case FCC_E2E_OK: return "OK";
    case FCC_E2E_REPEATED: return "REPEATED";
    case FCC_E2E_OK_SOME_LOST: return "OK_SOME_LOST";
    case FCC_E2E_WRONG_SEQUENCE: return "WRONG_SEQUENCE";
    case FCC_E2E_ERROR: return "ERROR";
    case FCC_E2E_NO_NEW_DATA: return "NO_NEW_DATA";
    case FCC_E2E_N_STATUS:
    default: return "UNKNOWN";
    }
}
