/*
 * fcc_bus_msgs.c -- GENERATED from dbc/fcc_hil.dbc by `python -m hil.bus.cgen` (run dbc/generate).
 * Do not edit: change the DBC and regenerate.  tests/python/bus/test_bus_codegen.py
 * fails when this file and the DBC disagree.
 */

#include <stddef.h>

#include "fcc_bus_msgs.h"

static const fcc_bus_signal_desc_t sig_tsync_sync[] = {
    {"master", (uint16_t)offsetof(fcc_msg_tsync_sync_t, master), (uint16_t)offsetof(struct fcc_hil_tsync_sync_t, master), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(15)},
    {"seq", (uint16_t)offsetof(fcc_msg_tsync_sync_t, seq), (uint16_t)offsetof(struct fcc_hil_tsync_sync_t, seq), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
    {"interval_ms", (uint16_t)offsetof(fcc_msg_tsync_sync_t, interval_ms), (uint16_t)offsetof(struct fcc_hil_tsync_sync_t, interval_ms), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(1), INT64_C(255)},
    {"sec", (uint16_t)offsetof(fcc_msg_tsync_sync_t, sec), (uint16_t)offsetof(struct fcc_hil_tsync_sync_t, sec), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
};

static int unpack_tsync_sync(void *raw, const uint8_t data[8])
{
    return fcc_hil_tsync_sync_unpack(raw, data, 8u);
}

static int pack_tsync_sync(uint8_t data[8], const void *raw)
{
    return fcc_hil_tsync_sync_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_tsync_follow_up[] = {
    {"master", (uint16_t)offsetof(fcc_msg_tsync_follow_up_t, master), (uint16_t)offsetof(struct fcc_hil_tsync_follow_up_t, master), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(15)},
    {"seq", (uint16_t)offsetof(fcc_msg_tsync_follow_up_t, seq), (uint16_t)offsetof(struct fcc_hil_tsync_follow_up_t, seq), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
    {"sec_carry", (uint16_t)offsetof(fcc_msg_tsync_follow_up_t, sec_carry), (uint16_t)offsetof(struct fcc_hil_tsync_follow_up_t, sec_carry), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"ns", (uint16_t)offsetof(fcc_msg_tsync_follow_up_t, ns), (uint16_t)offsetof(struct fcc_hil_tsync_follow_up_t, ns), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(999999999)},
};

static int unpack_tsync_follow_up(void *raw, const uint8_t data[8])
{
    return fcc_hil_tsync_follow_up_unpack(raw, data, 8u);
}

static int pack_tsync_follow_up(uint8_t data[8], const void *raw)
{
    return fcc_hil_tsync_follow_up_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_tsync_auth[] = {
    {"fv", (uint16_t)offsetof(fcc_msg_tsync_auth_t, fv), (uint16_t)offsetof(struct fcc_hil_tsync_auth_t, fv), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mac", (uint16_t)offsetof(fcc_msg_tsync_auth_t, mac), (uint16_t)offsetof(struct fcc_hil_tsync_auth_t, mac), FCC_FIELD_U64, FCC_FIELD_U64, FCC_R(1.0), INT64_C(0), INT64_C(281474976710655)},
};

static int unpack_tsync_auth(void *raw, const uint8_t data[8])
{
    return fcc_hil_tsync_auth_unpack(raw, data, 8u);
}

static int pack_tsync_auth(uint8_t data[8], const void *raw)
{
    return fcc_hil_tsync_auth_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sim_control[] = {
    {"command", (uint16_t)offsetof(fcc_msg_sim_control_t, command), (uint16_t)offsetof(struct fcc_hil_sim_control_t, command), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(5)},
    {"lqg_period", (uint16_t)offsetof(fcc_msg_sim_control_t, lqg_period), (uint16_t)offsetof(struct fcc_hil_sim_control_t, lqg_period), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(3000)},
    {"da_bits", (uint16_t)offsetof(fcc_msg_sim_control_t, da_bits), (uint16_t)offsetof(struct fcc_hil_sim_control_t, da_bits), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(16)},
};

static int unpack_sim_control(void *raw, const uint8_t data[8])
{
    return fcc_hil_sim_control_unpack(raw, data, 8u);
}

static int pack_sim_control(uint8_t data[8], const void *raw)
{
    return fcc_hil_sim_control_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sim_control_auth[] = {
    {"fv", (uint16_t)offsetof(fcc_msg_sim_control_auth_t, fv), (uint16_t)offsetof(struct fcc_hil_sim_control_auth_t, fv), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mac", (uint16_t)offsetof(fcc_msg_sim_control_auth_t, mac), (uint16_t)offsetof(struct fcc_hil_sim_control_auth_t, mac), FCC_FIELD_U64, FCC_FIELD_U64, FCC_R(1.0), INT64_C(0), INT64_C(281474976710655)},
};

static int unpack_sim_control_auth(void *raw, const uint8_t data[8])
{
    return fcc_hil_sim_control_auth_unpack(raw, data, 8u);
}

static int pack_sim_control_auth(uint8_t data[8], const void *raw)
{
    return fcc_hil_sim_control_auth_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sim_tick[] = {
    {"app", (uint16_t)offsetof(fcc_msg_sim_tick_t, app), (uint16_t)offsetof(struct fcc_hil_sim_tick_t, app), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(2)},
    {"step", (uint16_t)offsetof(fcc_msg_sim_tick_t, step), (uint16_t)offsetof(struct fcc_hil_sim_tick_t, step), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
};

static int unpack_sim_tick(void *raw, const uint8_t data[8])
{
    return fcc_hil_sim_tick_unpack(raw, data, 8u);
}

static int pack_sim_tick(uint8_t data[8], const void *raw)
{
    return fcc_hil_sim_tick_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sim_tick_auth[] = {
    {"fv", (uint16_t)offsetof(fcc_msg_sim_tick_auth_t, fv), (uint16_t)offsetof(struct fcc_hil_sim_tick_auth_t, fv), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mac", (uint16_t)offsetof(fcc_msg_sim_tick_auth_t, mac), (uint16_t)offsetof(struct fcc_hil_sim_tick_auth_t, mac), FCC_FIELD_U64, FCC_FIELD_U64, FCC_R(1.0), INT64_C(0), INT64_C(281474976710655)},
};

static int unpack_sim_tick_auth(void *raw, const uint8_t data[8])
{
    return fcc_hil_sim_tick_auth_unpack(raw, data, 8u);
}

static int pack_sim_tick_auth(uint8_t data[8], const void *raw)
{
    return fcc_hil_sim_tick_auth_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_ack[] = {
    {"app", (uint16_t)offsetof(fcc_msg_fcc_ack_t, app), (uint16_t)offsetof(struct fcc_hil_fcc_ack_t, app), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(2)},
    {"degraded", (uint16_t)offsetof(fcc_msg_fcc_ack_t, degraded), (uint16_t)offsetof(struct fcc_hil_fcc_ack_t, degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"step", (uint16_t)offsetof(fcc_msg_fcc_ack_t, step), (uint16_t)offsetof(struct fcc_hil_fcc_ack_t, step), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
    {"exec_us", (uint16_t)offsetof(fcc_msg_fcc_ack_t, exec_us), (uint16_t)offsetof(struct fcc_hil_fcc_ack_t, exec_us), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_ack(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_ack_unpack(raw, data, 8u);
}

static int pack_fcc_ack(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_ack_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_msl_elev_cmd[] = {
    {"degraded", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_t, degraded), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_t, degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"saturated", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_t, saturated), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_t, saturated), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"step", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_t, step), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"da_code", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_t, da_code), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_t, da_code), FCC_FIELD_I16, FCC_FIELD_I16, FCC_R(1.0), INT64_C(-32768), INT64_C(32767)},
    {"da_bits", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_t, da_bits), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_t, da_bits), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(1), INT64_C(16)},
};

static int unpack_msl_elev_cmd(void *raw, const uint8_t data[8])
{
    return fcc_hil_msl_elev_cmd_unpack(raw, data, 8u);
}

static int pack_msl_elev_cmd(uint8_t data[8], const void *raw)
{
    return fcc_hil_msl_elev_cmd_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_msl_rate_gyro[] = {
    {"step", (uint16_t)offsetof(fcc_msg_msl_rate_gyro_t, step), (uint16_t)offsetof(struct fcc_hil_msl_rate_gyro_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"q_g", (uint16_t)offsetof(fcc_msg_msl_rate_gyro_t, q_g), (uint16_t)offsetof(struct fcc_hil_msl_rate_gyro_t, q_g), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-2000000), INT64_C(2000000)},
};

static int unpack_msl_rate_gyro(void *raw, const uint8_t data[8])
{
    return fcc_hil_msl_rate_gyro_unpack(raw, data, 8u);
}

static int pack_msl_rate_gyro(uint8_t data[8], const void *raw)
{
    return fcc_hil_msl_rate_gyro_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_msl_accelerometer[] = {
    {"step", (uint16_t)offsetof(fcc_msg_msl_accelerometer_t, step), (uint16_t)offsetof(struct fcc_hil_msl_accelerometer_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"n_a", (uint16_t)offsetof(fcc_msg_msl_accelerometer_t, n_a), (uint16_t)offsetof(struct fcc_hil_msl_accelerometer_t, n_a), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(500.0), INT64_C(-2000000), INT64_C(2000000)},
};

static int unpack_msl_accelerometer(void *raw, const uint8_t data[8])
{
    return fcc_hil_msl_accelerometer_unpack(raw, data, 8u);
}

static int pack_msl_accelerometer(uint8_t data[8], const void *raw)
{
    return fcc_hil_msl_accelerometer_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_cdrw_aoa[] = {
    {"step", (uint16_t)offsetof(fcc_msg_cdrw_aoa_t, step), (uint16_t)offsetof(struct fcc_hil_cdrw_aoa_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"alpha", (uint16_t)offsetof(fcc_msg_cdrw_aoa_t, alpha), (uint16_t)offsetof(struct fcc_hil_cdrw_aoa_t, alpha), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(1000000.0), INT64_C(-1570800), INT64_C(1570800)},
};

static int unpack_cdrw_aoa(void *raw, const uint8_t data[8])
{
    return fcc_hil_cdrw_aoa_unpack(raw, data, 8u);
}

static int pack_cdrw_aoa(uint8_t data[8], const void *raw)
{
    return fcc_hil_cdrw_aoa_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_cdrw_pitch_rate[] = {
    {"step", (uint16_t)offsetof(fcc_msg_cdrw_pitch_rate_t, step), (uint16_t)offsetof(struct fcc_hil_cdrw_pitch_rate_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"q", (uint16_t)offsetof(fcc_msg_cdrw_pitch_rate_t, q), (uint16_t)offsetof(struct fcc_hil_cdrw_pitch_rate_t, q), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(1000000.0), INT64_C(-2000000), INT64_C(2000000)},
};

static int unpack_cdrw_pitch_rate(void *raw, const uint8_t data[8])
{
    return fcc_hil_cdrw_pitch_rate_unpack(raw, data, 8u);
}

static int pack_cdrw_pitch_rate(uint8_t data[8], const void *raw)
{
    return fcc_hil_cdrw_pitch_rate_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_cdrw_elevator[] = {
    {"step", (uint16_t)offsetof(fcc_msg_cdrw_elevator_t, step), (uint16_t)offsetof(struct fcc_hil_cdrw_elevator_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"delta_e", (uint16_t)offsetof(fcc_msg_cdrw_elevator_t, delta_e), (uint16_t)offsetof(struct fcc_hil_cdrw_elevator_t, delta_e), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(1000000.0), INT64_C(-523600), INT64_C(523600)},
};

static int unpack_cdrw_elevator(void *raw, const uint8_t data[8])
{
    return fcc_hil_cdrw_elevator_unpack(raw, data, 8u);
}

static int pack_cdrw_elevator(uint8_t data[8], const void *raw)
{
    return fcc_hil_cdrw_elevator_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_msl_state_est[] = {
    {"q_hat", (uint16_t)offsetof(fcc_msg_msl_state_est_t, q_hat), (uint16_t)offsetof(struct fcc_hil_msl_state_est_t, q_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"alpha_t_hat", (uint16_t)offsetof(fcc_msg_msl_state_est_t, alpha_t_hat), (uint16_t)offsetof(struct fcc_hil_msl_state_est_t, alpha_t_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"w_g_hat", (uint16_t)offsetof(fcc_msg_msl_state_est_t, w_g_hat), (uint16_t)offsetof(struct fcc_hil_msl_state_est_t, w_g_hat), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(100.0), INT64_C(-32768), INT64_C(32767)},
    {"step", (uint16_t)offsetof(fcc_msg_msl_state_est_t, step), (uint16_t)offsetof(struct fcc_hil_msl_state_est_t, step), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
};

static int unpack_msl_state_est(void *raw, const uint8_t data[8])
{
    return fcc_hil_msl_state_est_unpack(raw, data, 8u);
}

static int pack_msl_state_est(uint8_t data[8], const void *raw)
{
    return fcc_hil_msl_state_est_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_msl_elev_cmd_auth[] = {
    {"fv", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_auth_t, fv), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_auth_t, fv), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mac", (uint16_t)offsetof(fcc_msg_msl_elev_cmd_auth_t, mac), (uint16_t)offsetof(struct fcc_hil_msl_elev_cmd_auth_t, mac), FCC_FIELD_U64, FCC_FIELD_U64, FCC_R(1.0), INT64_C(0), INT64_C(281474976710655)},
};

static int unpack_msl_elev_cmd_auth(void *raw, const uint8_t data[8])
{
    return fcc_hil_msl_elev_cmd_auth_unpack(raw, data, 8u);
}

static int pack_msl_elev_cmd_auth(uint8_t data[8], const void *raw)
{
    return fcc_hil_msl_elev_cmd_auth_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_azkf_state[] = {
    {"alpha_hat", (uint16_t)offsetof(fcc_msg_sid_azkf_state_t, alpha_hat), (uint16_t)offsetof(struct fcc_hil_sid_azkf_state_t, alpha_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"q_hat", (uint16_t)offsetof(fcc_msg_sid_azkf_state_t, q_hat), (uint16_t)offsetof(struct fcc_hil_sid_azkf_state_t, q_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"order", (uint16_t)offsetof(fcc_msg_sid_azkf_state_t, order), (uint16_t)offsetof(struct fcc_hil_sid_azkf_state_t, order), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(1023)},
    {"fault", (uint16_t)offsetof(fcc_msg_sid_azkf_state_t, fault), (uint16_t)offsetof(struct fcc_hil_sid_azkf_state_t, fault), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"degraded", (uint16_t)offsetof(fcc_msg_sid_azkf_state_t, degraded), (uint16_t)offsetof(struct fcc_hil_sid_azkf_state_t, degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"step", (uint16_t)offsetof(fcc_msg_sid_azkf_state_t, step), (uint16_t)offsetof(struct fcc_hil_sid_azkf_state_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(4095)},
};

static int unpack_sid_azkf_state(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_azkf_state_unpack(raw, data, 8u);
}

static int pack_sid_azkf_state(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_azkf_state_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_azkf_bounds[] = {
    {"alpha_lo", (uint16_t)offsetof(fcc_msg_sid_azkf_bounds_t, alpha_lo), (uint16_t)offsetof(struct fcc_hil_sid_azkf_bounds_t, alpha_lo), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"alpha_hi", (uint16_t)offsetof(fcc_msg_sid_azkf_bounds_t, alpha_hi), (uint16_t)offsetof(struct fcc_hil_sid_azkf_bounds_t, alpha_hi), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"q_lo", (uint16_t)offsetof(fcc_msg_sid_azkf_bounds_t, q_lo), (uint16_t)offsetof(struct fcc_hil_sid_azkf_bounds_t, q_lo), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"q_hi", (uint16_t)offsetof(fcc_msg_sid_azkf_bounds_t, q_hi), (uint16_t)offsetof(struct fcc_hil_sid_azkf_bounds_t, q_hi), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
};

static int unpack_sid_azkf_bounds(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_azkf_bounds_unpack(raw, data, 8u);
}

static int pack_sid_azkf_bounds(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_azkf_bounds_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_azkf_model_a[] = {
    {"a11", (uint16_t)offsetof(fcc_msg_sid_azkf_model_a_t, a11), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_a_t, a11), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a12", (uint16_t)offsetof(fcc_msg_sid_azkf_model_a_t, a12), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_a_t, a12), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a21", (uint16_t)offsetof(fcc_msg_sid_azkf_model_a_t, a21), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_a_t, a21), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a22", (uint16_t)offsetof(fcc_msg_sid_azkf_model_a_t, a22), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_a_t, a22), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
};

static int unpack_sid_azkf_model_a(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_azkf_model_a_unpack(raw, data, 8u);
}

static int pack_sid_azkf_model_a(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_azkf_model_a_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_azkf_model_b[] = {
    {"b1", (uint16_t)offsetof(fcc_msg_sid_azkf_model_b_t, b1), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_b_t, b1), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"b2", (uint16_t)offsetof(fcc_msg_sid_azkf_model_b_t, b2), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_b_t, b2), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"rho", (uint16_t)offsetof(fcc_msg_sid_azkf_model_b_t, rho), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_b_t, rho), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(65535)},
    {"gain_norm", (uint16_t)offsetof(fcc_msg_sid_azkf_model_b_t, gain_norm), (uint16_t)offsetof(struct fcc_hil_sid_azkf_model_b_t, gain_norm), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_sid_azkf_model_b(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_azkf_model_b_unpack(raw, data, 8u);
}

static int pack_sid_azkf_model_b(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_azkf_model_b_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_zkf_state[] = {
    {"alpha_hat", (uint16_t)offsetof(fcc_msg_sid_zkf_state_t, alpha_hat), (uint16_t)offsetof(struct fcc_hil_sid_zkf_state_t, alpha_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"q_hat", (uint16_t)offsetof(fcc_msg_sid_zkf_state_t, q_hat), (uint16_t)offsetof(struct fcc_hil_sid_zkf_state_t, q_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"order", (uint16_t)offsetof(fcc_msg_sid_zkf_state_t, order), (uint16_t)offsetof(struct fcc_hil_sid_zkf_state_t, order), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(1023)},
    {"fault", (uint16_t)offsetof(fcc_msg_sid_zkf_state_t, fault), (uint16_t)offsetof(struct fcc_hil_sid_zkf_state_t, fault), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"degraded", (uint16_t)offsetof(fcc_msg_sid_zkf_state_t, degraded), (uint16_t)offsetof(struct fcc_hil_sid_zkf_state_t, degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"step", (uint16_t)offsetof(fcc_msg_sid_zkf_state_t, step), (uint16_t)offsetof(struct fcc_hil_sid_zkf_state_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(4095)},
};

static int unpack_sid_zkf_state(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_zkf_state_unpack(raw, data, 8u);
}

static int pack_sid_zkf_state(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_zkf_state_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_zkf_bounds[] = {
    {"alpha_lo", (uint16_t)offsetof(fcc_msg_sid_zkf_bounds_t, alpha_lo), (uint16_t)offsetof(struct fcc_hil_sid_zkf_bounds_t, alpha_lo), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"alpha_hi", (uint16_t)offsetof(fcc_msg_sid_zkf_bounds_t, alpha_hi), (uint16_t)offsetof(struct fcc_hil_sid_zkf_bounds_t, alpha_hi), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"q_lo", (uint16_t)offsetof(fcc_msg_sid_zkf_bounds_t, q_lo), (uint16_t)offsetof(struct fcc_hil_sid_zkf_bounds_t, q_lo), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"q_hi", (uint16_t)offsetof(fcc_msg_sid_zkf_bounds_t, q_hi), (uint16_t)offsetof(struct fcc_hil_sid_zkf_bounds_t, q_hi), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
};

static int unpack_sid_zkf_bounds(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_zkf_bounds_unpack(raw, data, 8u);
}

static int pack_sid_zkf_bounds(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_zkf_bounds_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_zkf_model_a[] = {
    {"a11", (uint16_t)offsetof(fcc_msg_sid_zkf_model_a_t, a11), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_a_t, a11), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a12", (uint16_t)offsetof(fcc_msg_sid_zkf_model_a_t, a12), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_a_t, a12), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a21", (uint16_t)offsetof(fcc_msg_sid_zkf_model_a_t, a21), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_a_t, a21), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a22", (uint16_t)offsetof(fcc_msg_sid_zkf_model_a_t, a22), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_a_t, a22), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
};

static int unpack_sid_zkf_model_a(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_zkf_model_a_unpack(raw, data, 8u);
}

static int pack_sid_zkf_model_a(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_zkf_model_a_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_zkf_model_b[] = {
    {"b1", (uint16_t)offsetof(fcc_msg_sid_zkf_model_b_t, b1), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_b_t, b1), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"b2", (uint16_t)offsetof(fcc_msg_sid_zkf_model_b_t, b2), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_b_t, b2), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"rho", (uint16_t)offsetof(fcc_msg_sid_zkf_model_b_t, rho), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_b_t, rho), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(65535)},
    {"gain_norm", (uint16_t)offsetof(fcc_msg_sid_zkf_model_b_t, gain_norm), (uint16_t)offsetof(struct fcc_hil_sid_zkf_model_b_t, gain_norm), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_sid_zkf_model_b(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_zkf_model_b_unpack(raw, data, 8u);
}

static int pack_sid_zkf_model_b(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_zkf_model_b_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_kf_state[] = {
    {"alpha_hat", (uint16_t)offsetof(fcc_msg_sid_kf_state_t, alpha_hat), (uint16_t)offsetof(struct fcc_hil_sid_kf_state_t, alpha_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"q_hat", (uint16_t)offsetof(fcc_msg_sid_kf_state_t, q_hat), (uint16_t)offsetof(struct fcc_hil_sid_kf_state_t, q_hat), FCC_FIELD_REAL, FCC_FIELD_I32, FCC_R(100000.0), INT64_C(-524288), INT64_C(524287)},
    {"order", (uint16_t)offsetof(fcc_msg_sid_kf_state_t, order), (uint16_t)offsetof(struct fcc_hil_sid_kf_state_t, order), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(1023)},
    {"fault", (uint16_t)offsetof(fcc_msg_sid_kf_state_t, fault), (uint16_t)offsetof(struct fcc_hil_sid_kf_state_t, fault), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"degraded", (uint16_t)offsetof(fcc_msg_sid_kf_state_t, degraded), (uint16_t)offsetof(struct fcc_hil_sid_kf_state_t, degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"step", (uint16_t)offsetof(fcc_msg_sid_kf_state_t, step), (uint16_t)offsetof(struct fcc_hil_sid_kf_state_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(4095)},
};

static int unpack_sid_kf_state(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_kf_state_unpack(raw, data, 8u);
}

static int pack_sid_kf_state(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_kf_state_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_kf_bounds[] = {
    {"alpha_lo", (uint16_t)offsetof(fcc_msg_sid_kf_bounds_t, alpha_lo), (uint16_t)offsetof(struct fcc_hil_sid_kf_bounds_t, alpha_lo), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"alpha_hi", (uint16_t)offsetof(fcc_msg_sid_kf_bounds_t, alpha_hi), (uint16_t)offsetof(struct fcc_hil_sid_kf_bounds_t, alpha_hi), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"q_lo", (uint16_t)offsetof(fcc_msg_sid_kf_bounds_t, q_lo), (uint16_t)offsetof(struct fcc_hil_sid_kf_bounds_t, q_lo), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"q_hi", (uint16_t)offsetof(fcc_msg_sid_kf_bounds_t, q_hi), (uint16_t)offsetof(struct fcc_hil_sid_kf_bounds_t, q_hi), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
};

static int unpack_sid_kf_bounds(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_kf_bounds_unpack(raw, data, 8u);
}

static int pack_sid_kf_bounds(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_kf_bounds_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_kf_model_a[] = {
    {"a11", (uint16_t)offsetof(fcc_msg_sid_kf_model_a_t, a11), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_a_t, a11), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a12", (uint16_t)offsetof(fcc_msg_sid_kf_model_a_t, a12), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_a_t, a12), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a21", (uint16_t)offsetof(fcc_msg_sid_kf_model_a_t, a21), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_a_t, a21), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"a22", (uint16_t)offsetof(fcc_msg_sid_kf_model_a_t, a22), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_a_t, a22), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
};

static int unpack_sid_kf_model_a(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_kf_model_a_unpack(raw, data, 8u);
}

static int pack_sid_kf_model_a(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_kf_model_a_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_kf_model_b[] = {
    {"b1", (uint16_t)offsetof(fcc_msg_sid_kf_model_b_t, b1), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_b_t, b1), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"b2", (uint16_t)offsetof(fcc_msg_sid_kf_model_b_t, b2), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_b_t, b2), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(10000.0), INT64_C(-32768), INT64_C(32767)},
    {"rho", (uint16_t)offsetof(fcc_msg_sid_kf_model_b_t, rho), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_b_t, rho), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(65535)},
    {"gain_norm", (uint16_t)offsetof(fcc_msg_sid_kf_model_b_t, gain_norm), (uint16_t)offsetof(struct fcc_hil_sid_kf_model_b_t, gain_norm), FCC_FIELD_REAL, FCC_FIELD_U16, FCC_R(10000.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_sid_kf_model_b(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_kf_model_b_unpack(raw, data, 8u);
}

static int pack_sid_kf_model_b(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_kf_model_b_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sid_out_auth[] = {
    {"fv", (uint16_t)offsetof(fcc_msg_sid_out_auth_t, fv), (uint16_t)offsetof(struct fcc_hil_sid_out_auth_t, fv), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mac", (uint16_t)offsetof(fcc_msg_sid_out_auth_t, mac), (uint16_t)offsetof(struct fcc_hil_sid_out_auth_t, mac), FCC_FIELD_U64, FCC_FIELD_U64, FCC_R(1.0), INT64_C(0), INT64_C(281474976710655)},
};

static int unpack_sid_out_auth(void *raw, const uint8_t data[8])
{
    return fcc_hil_sid_out_auth_unpack(raw, data, 8u);
}

static int pack_sid_out_auth(uint8_t data[8], const void *raw)
{
    return fcc_hil_sid_out_auth_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_status[] = {
    {"mode", (uint16_t)offsetof(fcc_msg_fcc_status_t, mode), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, mode), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"cdrw_degraded", (uint16_t)offsetof(fcc_msg_fcc_status_t, cdrw_degraded), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, cdrw_degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"msl_degraded", (uint16_t)offsetof(fcc_msg_fcc_status_t, msl_degraded), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, msl_degraded), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"sensor_stale", (uint16_t)offsetof(fcc_msg_fcc_status_t, sensor_stale), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, sensor_stale), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"e2e_fault", (uint16_t)offsetof(fcc_msg_fcc_status_t, e2e_fault), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, e2e_fault), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"overrun", (uint16_t)offsetof(fcc_msg_fcc_status_t, overrun), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, overrun), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"config_rejected", (uint16_t)offsetof(fcc_msg_fcc_status_t, config_rejected), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, config_rejected), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"overruns", (uint16_t)offsetof(fcc_msg_fcc_status_t, overruns), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, overruns), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(63)},
    {"op_mode", (uint16_t)offsetof(fcc_msg_fcc_status_t, op_mode), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, op_mode), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(2)},
    {"cdrw_steps", (uint16_t)offsetof(fcc_msg_fcc_status_t, cdrw_steps), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, cdrw_steps), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"msl_steps", (uint16_t)offsetof(fcc_msg_fcc_status_t, msl_steps), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, msl_steps), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"worst_step_us", (uint16_t)offsetof(fcc_msg_fcc_status_t, worst_step_us), (uint16_t)offsetof(struct fcc_hil_fcc_status_t, worst_step_us), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_status(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_status_unpack(raw, data, 8u);
}

static int pack_fcc_status(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_status_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_e2_e_counts[] = {
    {"ok", (uint16_t)offsetof(fcc_msg_fcc_e2_e_counts_t, ok), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_counts_t, ok), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"repeated", (uint16_t)offsetof(fcc_msg_fcc_e2_e_counts_t, repeated), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_counts_t, repeated), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"ok_some_lost", (uint16_t)offsetof(fcc_msg_fcc_e2_e_counts_t, ok_some_lost), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_counts_t, ok_some_lost), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"wrong_sequence", (uint16_t)offsetof(fcc_msg_fcc_e2_e_counts_t, wrong_sequence), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_counts_t, wrong_sequence), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_e2_e_counts(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_e2_e_counts_unpack(raw, data, 8u);
}

static int pack_fcc_e2_e_counts(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_e2_e_counts_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_e2_e_faults[] = {
    {"error", (uint16_t)offsetof(fcc_msg_fcc_e2_e_faults_t, error), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_faults_t, error), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"no_new_data", (uint16_t)offsetof(fcc_msg_fcc_e2_e_faults_t, no_new_data), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_faults_t, no_new_data), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"stale_now", (uint16_t)offsetof(fcc_msg_fcc_e2_e_faults_t, stale_now), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_faults_t, stale_now), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"own_id", (uint16_t)offsetof(fcc_msg_fcc_e2_e_faults_t, own_id), (uint16_t)offsetof(struct fcc_hil_fcc_e2_e_faults_t, own_id), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_e2_e_faults(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_e2_e_faults_unpack(raw, data, 8u);
}

static int pack_fcc_e2_e_faults(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_e2_e_faults_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_reject_counts[] = {
    {"unknown_id", (uint16_t)offsetof(fcc_msg_fcc_reject_counts_t, unknown_id), (uint16_t)offsetof(struct fcc_hil_fcc_reject_counts_t, unknown_id), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"wrong_dlc", (uint16_t)offsetof(fcc_msg_fcc_reject_counts_t, wrong_dlc), (uint16_t)offsetof(struct fcc_hil_fcc_reject_counts_t, wrong_dlc), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"out_of_range", (uint16_t)offsetof(fcc_msg_fcc_reject_counts_t, out_of_range), (uint16_t)offsetof(struct fcc_hil_fcc_reject_counts_t, out_of_range), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"tx_refused", (uint16_t)offsetof(fcc_msg_fcc_reject_counts_t, tx_refused), (uint16_t)offsetof(struct fcc_hil_fcc_reject_counts_t, tx_refused), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_reject_counts(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_reject_counts_unpack(raw, data, 8u);
}

static int pack_fcc_reject_counts(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_reject_counts_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_bus_counts[] = {
    {"bus_errors", (uint16_t)offsetof(fcc_msg_fcc_bus_counts_t, bus_errors), (uint16_t)offsetof(struct fcc_hil_fcc_bus_counts_t, bus_errors), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"rx_overflows", (uint16_t)offsetof(fcc_msg_fcc_bus_counts_t, rx_overflows), (uint16_t)offsetof(struct fcc_hil_fcc_bus_counts_t, rx_overflows), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"tx_dropped", (uint16_t)offsetof(fcc_msg_fcc_bus_counts_t, tx_dropped), (uint16_t)offsetof(struct fcc_hil_fcc_bus_counts_t, tx_dropped), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"tx_retries", (uint16_t)offsetof(fcc_msg_fcc_bus_counts_t, tx_retries), (uint16_t)offsetof(struct fcc_hil_fcc_bus_counts_t, tx_retries), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_bus_counts(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_bus_counts_unpack(raw, data, 8u);
}

static int pack_fcc_bus_counts(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_bus_counts_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_sync_status[] = {
    {"state", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, state), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, state), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(5)},
    {"master", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, master), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, master), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(15)},
    {"offset_us", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, offset_us), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, offset_us), FCC_FIELD_I16, FCC_FIELD_I16, FCC_R(1.0), INT64_C(-32768), INT64_C(32767)},
    {"rate_ppm", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, rate_ppm), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, rate_ppm), FCC_FIELD_REAL, FCC_FIELD_I16, FCC_R(100.0), INT64_C(-32768), INT64_C(32767)},
    {"syncs", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, syncs), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, syncs), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
    {"rejected", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, rejected), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, rejected), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
    {"losses", (uint16_t)offsetof(fcc_msg_fcc_sync_status_t, losses), (uint16_t)offsetof(struct fcc_hil_fcc_sync_status_t, losses), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
};

static int unpack_fcc_sync_status(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_sync_status_unpack(raw, data, 8u);
}

static int pack_fcc_sync_status(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_sync_status_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_sec_counts[] = {
    {"mac_failed", (uint16_t)offsetof(fcc_msg_fcc_sec_counts_t, mac_failed), (uint16_t)offsetof(struct fcc_hil_fcc_sec_counts_t, mac_failed), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"freshness_failed", (uint16_t)offsetof(fcc_msg_fcc_sec_counts_t, freshness_failed), (uint16_t)offsetof(struct fcc_hil_fcc_sec_counts_t, freshness_failed), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"unpaired", (uint16_t)offsetof(fcc_msg_fcc_sec_counts_t, unpaired), (uint16_t)offsetof(struct fcc_hil_fcc_sec_counts_t, unpaired), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mode_refused", (uint16_t)offsetof(fcc_msg_fcc_sec_counts_t, mode_refused), (uint16_t)offsetof(struct fcc_hil_fcc_sec_counts_t, mode_refused), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_fcc_sec_counts(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_sec_counts_unpack(raw, data, 8u);
}

static int pack_fcc_sec_counts(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_sec_counts_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_sec_session[] = {
    {"trip", (uint16_t)offsetof(fcc_msg_fcc_sec_session_t, trip), (uint16_t)offsetof(struct fcc_hil_fcc_sec_session_t, trip), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
    {"verified", (uint16_t)offsetof(fcc_msg_fcc_sec_session_t, verified), (uint16_t)offsetof(struct fcc_hil_fcc_sec_session_t, verified), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
};

static int unpack_fcc_sec_session(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_sec_session_unpack(raw, data, 8u);
}

static int pack_fcc_sec_session(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_sec_session_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_sync_refusals[] = {
    {"mac_failed", (uint16_t)offsetof(fcc_msg_fcc_sync_refusals_t, mac_failed), (uint16_t)offsetof(struct fcc_hil_fcc_sync_refusals_t, mac_failed), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"freshness_failed", (uint16_t)offsetof(fcc_msg_fcc_sync_refusals_t, freshness_failed), (uint16_t)offsetof(struct fcc_hil_fcc_sync_refusals_t, freshness_failed), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"unauthenticated", (uint16_t)offsetof(fcc_msg_fcc_sync_refusals_t, unauthenticated), (uint16_t)offsetof(struct fcc_hil_fcc_sync_refusals_t, unauthenticated), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"step_refused", (uint16_t)offsetof(fcc_msg_fcc_sync_refusals_t, step_refused), (uint16_t)offsetof(struct fcc_hil_fcc_sync_refusals_t, step_refused), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
    {"rate_refused", (uint16_t)offsetof(fcc_msg_fcc_sync_refusals_t, rate_refused), (uint16_t)offsetof(struct fcc_hil_fcc_sync_refusals_t, rate_refused), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
};

static int unpack_fcc_sync_refusals(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_sync_refusals_unpack(raw, data, 8u);
}

static int pack_fcc_sync_refusals(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_sync_refusals_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_fcc_status_auth[] = {
    {"fv", (uint16_t)offsetof(fcc_msg_fcc_status_auth_t, fv), (uint16_t)offsetof(struct fcc_hil_fcc_status_auth_t, fv), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
    {"mac", (uint16_t)offsetof(fcc_msg_fcc_status_auth_t, mac), (uint16_t)offsetof(struct fcc_hil_fcc_status_auth_t, mac), FCC_FIELD_U64, FCC_FIELD_U64, FCC_R(1.0), INT64_C(0), INT64_C(281474976710655)},
};

static int unpack_fcc_status_auth(void *raw, const uint8_t data[8])
{
    return fcc_hil_fcc_status_auth_unpack(raw, data, 8u);
}

static int pack_fcc_status_auth(uint8_t data[8], const void *raw)
{
    return fcc_hil_fcc_status_auth_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_sim_event[] = {
    {"active", (uint16_t)offsetof(fcc_msg_sim_event_t, active), (uint16_t)offsetof(struct fcc_hil_sim_event_t, active), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"oracle_fault", (uint16_t)offsetof(fcc_msg_sim_event_t, oracle_fault), (uint16_t)offsetof(struct fcc_hil_sim_event_t, oracle_fault), FCC_FIELD_BOOL, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(1)},
    {"fault_id", (uint16_t)offsetof(fcc_msg_sim_event_t, fault_id), (uint16_t)offsetof(struct fcc_hil_sim_event_t, fault_id), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(255)},
    {"kind", (uint16_t)offsetof(fcc_msg_sim_event_t, kind), (uint16_t)offsetof(struct fcc_hil_sim_event_t, kind), FCC_FIELD_U8, FCC_FIELD_U8, FCC_R(1.0), INT64_C(0), INT64_C(63)},
    {"target_id", (uint16_t)offsetof(fcc_msg_sim_event_t, target_id), (uint16_t)offsetof(struct fcc_hil_sim_event_t, target_id), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(2047)},
    {"step", (uint16_t)offsetof(fcc_msg_sim_event_t, step), (uint16_t)offsetof(struct fcc_hil_sim_event_t, step), FCC_FIELD_U16, FCC_FIELD_U16, FCC_R(1.0), INT64_C(0), INT64_C(65535)},
};

static int unpack_sim_event(void *raw, const uint8_t data[8])
{
    return fcc_hil_sim_event_unpack(raw, data, 8u);
}

static int pack_sim_event(uint8_t data[8], const void *raw)
{
    return fcc_hil_sim_event_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_rig_ping[] = {
    {"seq", (uint16_t)offsetof(fcc_msg_rig_ping_t, seq), (uint16_t)offsetof(struct fcc_hil_rig_ping_t, seq), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
    {"t_send_us", (uint16_t)offsetof(fcc_msg_rig_ping_t, t_send_us), (uint16_t)offsetof(struct fcc_hil_rig_ping_t, t_send_us), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
};

static int unpack_rig_ping(void *raw, const uint8_t data[8])
{
    return fcc_hil_rig_ping_unpack(raw, data, 8u);
}

static int pack_rig_ping(uint8_t data[8], const void *raw)
{
    return fcc_hil_rig_ping_pack(data, raw, 8u);
}

static const fcc_bus_signal_desc_t sig_rig_pong[] = {
    {"seq", (uint16_t)offsetof(fcc_msg_rig_pong_t, seq), (uint16_t)offsetof(struct fcc_hil_rig_pong_t, seq), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
    {"t_send_us", (uint16_t)offsetof(fcc_msg_rig_pong_t, t_send_us), (uint16_t)offsetof(struct fcc_hil_rig_pong_t, t_send_us), FCC_FIELD_U32, FCC_FIELD_U32, FCC_R(1.0), INT64_C(0), INT64_C(4294967295)},
};

static int unpack_rig_pong(void *raw, const uint8_t data[8])
{
    return fcc_hil_rig_pong_unpack(raw, data, 8u);
}

static int pack_rig_pong(uint8_t data[8], const void *raw)
{
    return fcc_hil_rig_pong_pack(data, raw, 8u);
}

const fcc_bus_msg_desc_t fcc_bus_msg_table[FCC_MSG_COUNT] = {
    {"TSYNC_SYNC", 0x001u, 0x1001u, 3u, 100u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_tsync_sync / sizeof sig_tsync_sync[0]), sig_tsync_sync, unpack_tsync_sync, pack_tsync_sync},
    {"TSYNC_FOLLOW_UP", 0x002u, 0x1002u, 3u, 100u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_tsync_follow_up / sizeof sig_tsync_follow_up[0]), sig_tsync_follow_up, unpack_tsync_follow_up, pack_tsync_follow_up},
    {"TSYNC_AUTH", 0x003u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_tsync_auth / sizeof sig_tsync_auth[0]), sig_tsync_auth, unpack_tsync_auth, pack_tsync_auth},
    {"SIM_CONTROL", 0x010u, 0x1010u, 3u, 0u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_sim_control / sizeof sig_sim_control[0]), sig_sim_control, unpack_sim_control, pack_sim_control},
    {"SIM_CONTROL_AUTH", 0x011u, 0x0000u, 3u, 0u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_sim_control_auth / sizeof sig_sim_control_auth[0]), sig_sim_control_auth, unpack_sim_control_auth, pack_sim_control_auth},
    {"SIM_TICK", 0x020u, 0x1020u, 3u, 20u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_sim_tick / sizeof sig_sim_tick[0]), sig_sim_tick, unpack_sim_tick, pack_sim_tick},
    {"SIM_TICK_AUTH", 0x021u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_sim_tick_auth / sizeof sig_sim_tick_auth[0]), sig_sim_tick_auth, unpack_sim_tick_auth, pack_sim_tick_auth},
    {"FCC_ACK", 0x028u, 0x1028u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_ack / sizeof sig_fcc_ack[0]), sig_fcc_ack, unpack_fcc_ack, pack_fcc_ack},
    {"MSL_ELEV_CMD", 0x030u, 0x1030u, 3u, 50u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_msl_elev_cmd / sizeof sig_msl_elev_cmd[0]), sig_msl_elev_cmd, unpack_msl_elev_cmd, pack_msl_elev_cmd},
    {"MSL_RATE_GYRO", 0x040u, 0x1040u, 3u, 50u, (1u << FCC_BUS_NODE_MSL_GYRO), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_msl_rate_gyro / sizeof sig_msl_rate_gyro[0]), sig_msl_rate_gyro, unpack_msl_rate_gyro, pack_msl_rate_gyro},
    {"MSL_ACCELEROMETER", 0x041u, 0x1041u, 3u, 50u, (1u << FCC_BUS_NODE_MSL_ACCEL), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_msl_accelerometer / sizeof sig_msl_accelerometer[0]), sig_msl_accelerometer, unpack_msl_accelerometer, pack_msl_accelerometer},
    {"CDRW_AOA", 0x050u, 0x1050u, 3u, 20u, (1u << FCC_BUS_NODE_CDRW_AOA_SENSOR), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_cdrw_aoa / sizeof sig_cdrw_aoa[0]), sig_cdrw_aoa, unpack_cdrw_aoa, pack_cdrw_aoa},
    {"CDRW_PITCH_RATE", 0x051u, 0x1051u, 3u, 20u, (1u << FCC_BUS_NODE_CDRW_GYRO), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_cdrw_pitch_rate / sizeof sig_cdrw_pitch_rate[0]), sig_cdrw_pitch_rate, unpack_cdrw_pitch_rate, pack_cdrw_pitch_rate},
    {"CDRW_ELEVATOR", 0x052u, 0x1052u, 3u, 20u, (1u << FCC_BUS_NODE_CDRW_ELEV_SENSOR), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_cdrw_elevator / sizeof sig_cdrw_elevator[0]), sig_cdrw_elevator, unpack_cdrw_elevator, pack_cdrw_elevator},
    {"MSL_STATE_EST", 0x100u, 0x0000u, 3u, 50u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_msl_state_est / sizeof sig_msl_state_est[0]), sig_msl_state_est, unpack_msl_state_est, pack_msl_state_est},
    {"MSL_ELEV_CMD_AUTH", 0x101u, 0x0000u, 3u, 50u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_msl_elev_cmd_auth / sizeof sig_msl_elev_cmd_auth[0]), sig_msl_elev_cmd_auth, unpack_msl_elev_cmd_auth, pack_msl_elev_cmd_auth},
    {"SID_AZKF_STATE", 0x110u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_azkf_state / sizeof sig_sid_azkf_state[0]), sig_sid_azkf_state, unpack_sid_azkf_state, pack_sid_azkf_state},
    {"SID_AZKF_BOUNDS", 0x111u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_azkf_bounds / sizeof sig_sid_azkf_bounds[0]), sig_sid_azkf_bounds, unpack_sid_azkf_bounds, pack_sid_azkf_bounds},
    {"SID_AZKF_MODEL_A", 0x112u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_azkf_model_a / sizeof sig_sid_azkf_model_a[0]), sig_sid_azkf_model_a, unpack_sid_azkf_model_a, pack_sid_azkf_model_a},
    {"SID_AZKF_MODEL_B", 0x113u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_azkf_model_b / sizeof sig_sid_azkf_model_b[0]), sig_sid_azkf_model_b, unpack_sid_azkf_model_b, pack_sid_azkf_model_b},
    {"SID_ZKF_STATE", 0x120u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_zkf_state / sizeof sig_sid_zkf_state[0]), sig_sid_zkf_state, unpack_sid_zkf_state, pack_sid_zkf_state},
    {"SID_ZKF_BOUNDS", 0x121u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_zkf_bounds / sizeof sig_sid_zkf_bounds[0]), sig_sid_zkf_bounds, unpack_sid_zkf_bounds, pack_sid_zkf_bounds},
    {"SID_ZKF_MODEL_A", 0x122u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_zkf_model_a / sizeof sig_sid_zkf_model_a[0]), sig_sid_zkf_model_a, unpack_sid_zkf_model_a, pack_sid_zkf_model_a},
    {"SID_ZKF_MODEL_B", 0x123u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_zkf_model_b / sizeof sig_sid_zkf_model_b[0]), sig_sid_zkf_model_b, unpack_sid_zkf_model_b, pack_sid_zkf_model_b},
    {"SID_KF_STATE", 0x130u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_kf_state / sizeof sig_sid_kf_state[0]), sig_sid_kf_state, unpack_sid_kf_state, pack_sid_kf_state},
    {"SID_KF_BOUNDS", 0x131u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_kf_bounds / sizeof sig_sid_kf_bounds[0]), sig_sid_kf_bounds, unpack_sid_kf_bounds, pack_sid_kf_bounds},
    {"SID_KF_MODEL_A", 0x132u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_kf_model_a / sizeof sig_sid_kf_model_a[0]), sig_sid_kf_model_a, unpack_sid_kf_model_a, pack_sid_kf_model_a},
    {"SID_KF_MODEL_B", 0x133u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_kf_model_b / sizeof sig_sid_kf_model_b[0]), sig_sid_kf_model_b, unpack_sid_kf_model_b, pack_sid_kf_model_b},
    {"SID_OUT_AUTH", 0x134u, 0x0000u, 3u, 20u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_sid_out_auth / sizeof sig_sid_out_auth[0]), sig_sid_out_auth, unpack_sid_out_auth, pack_sid_out_auth},
    {"FCC_STATUS", 0x700u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_status / sizeof sig_fcc_status[0]), sig_fcc_status, unpack_fcc_status, pack_fcc_status},
    {"FCC_E2E_COUNTS", 0x701u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_e2_e_counts / sizeof sig_fcc_e2_e_counts[0]), sig_fcc_e2_e_counts, unpack_fcc_e2_e_counts, pack_fcc_e2_e_counts},
    {"FCC_E2E_FAULTS", 0x702u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_e2_e_faults / sizeof sig_fcc_e2_e_faults[0]), sig_fcc_e2_e_faults, unpack_fcc_e2_e_faults, pack_fcc_e2_e_faults},
    {"FCC_REJECT_COUNTS", 0x703u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_reject_counts / sizeof sig_fcc_reject_counts[0]), sig_fcc_reject_counts, unpack_fcc_reject_counts, pack_fcc_reject_counts},
    {"FCC_BUS_COUNTS", 0x704u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_bus_counts / sizeof sig_fcc_bus_counts[0]), sig_fcc_bus_counts, unpack_fcc_bus_counts, pack_fcc_bus_counts},
    {"FCC_SYNC_STATUS", 0x705u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_sync_status / sizeof sig_fcc_sync_status[0]), sig_fcc_sync_status, unpack_fcc_sync_status, pack_fcc_sync_status},
    {"FCC_SEC_COUNTS", 0x706u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_sec_counts / sizeof sig_fcc_sec_counts[0]), sig_fcc_sec_counts, unpack_fcc_sec_counts, pack_fcc_sec_counts},
    {"FCC_SEC_SESSION", 0x707u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_sec_session / sizeof sig_fcc_sec_session[0]), sig_fcc_sec_session, unpack_fcc_sec_session, pack_fcc_sec_session},
    {"FCC_SYNC_REFUSALS", 0x708u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_sync_refusals / sizeof sig_fcc_sync_refusals[0]), sig_fcc_sync_refusals, unpack_fcc_sync_refusals, pack_fcc_sync_refusals},
    {"FCC_STATUS_AUTH", 0x709u, 0x0000u, 3u, 100u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_fcc_status_auth / sizeof sig_fcc_status_auth[0]), sig_fcc_status_auth, unpack_fcc_status_auth, pack_fcc_status_auth},
    {"SIM_EVENT", 0x710u, 0x1710u, 3u, 0u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_sim_event / sizeof sig_sim_event[0]), sig_sim_event, unpack_sim_event, pack_sim_event},
    {"RIG_PING", 0x7F0u, 0x0000u, 3u, 0u, (1u << FCC_BUS_NODE_SIM), (1u << FCC_BUS_NODE_FCC), (uint8_t)(sizeof sig_rig_ping / sizeof sig_rig_ping[0]), sig_rig_ping, unpack_rig_ping, pack_rig_ping},
    {"RIG_PONG", 0x7F1u, 0x0000u, 3u, 0u, (1u << FCC_BUS_NODE_FCC), (1u << FCC_BUS_NODE_SIM), (uint8_t)(sizeof sig_rig_pong / sizeof sig_rig_pong[0]), sig_rig_pong, unpack_rig_pong, pack_rig_pong},
};

const fcc_msg_t fcc_bus_app_cdrw_inputs[FCC_BUS_APP_CDRW_N_INPUTS] = {FCC_MSG_CDRW_AOA, FCC_MSG_CDRW_PITCH_RATE, FCC_MSG_CDRW_ELEVATOR};

const fcc_msg_t fcc_bus_app_missile_inputs[FCC_BUS_APP_MISSILE_N_INPUTS] = {FCC_MSG_MSL_RATE_GYRO, FCC_MSG_MSL_ACCELEROMETER};

const uint8_t fcc_bus_input_app[FCC_MSG_COUNT] = {
    (uint8_t)FCC_BUS_NO_APP, /* TSYNC_SYNC */
    (uint8_t)FCC_BUS_NO_APP, /* TSYNC_FOLLOW_UP */
    (uint8_t)FCC_BUS_NO_APP, /* TSYNC_AUTH */
    (uint8_t)FCC_BUS_NO_APP, /* SIM_CONTROL */
    (uint8_t)FCC_BUS_NO_APP, /* SIM_CONTROL_AUTH */
    (uint8_t)FCC_BUS_NO_APP, /* SIM_TICK */
    (uint8_t)FCC_BUS_NO_APP, /* SIM_TICK_AUTH */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_ACK */
    (uint8_t)FCC_BUS_NO_APP, /* MSL_ELEV_CMD */
    (uint8_t)FCC_BUS_APP_MISSILE, /* MSL_RATE_GYRO */
    (uint8_t)FCC_BUS_APP_MISSILE, /* MSL_ACCELEROMETER */
    (uint8_t)FCC_BUS_APP_CDRW, /* CDRW_AOA */
    (uint8_t)FCC_BUS_APP_CDRW, /* CDRW_PITCH_RATE */
    (uint8_t)FCC_BUS_APP_CDRW, /* CDRW_ELEVATOR */
    (uint8_t)FCC_BUS_NO_APP, /* MSL_STATE_EST */
    (uint8_t)FCC_BUS_NO_APP, /* MSL_ELEV_CMD_AUTH */
    (uint8_t)FCC_BUS_NO_APP, /* SID_AZKF_STATE */
    (uint8_t)FCC_BUS_NO_APP, /* SID_AZKF_BOUNDS */
    (uint8_t)FCC_BUS_NO_APP, /* SID_AZKF_MODEL_A */
    (uint8_t)FCC_BUS_NO_APP, /* SID_AZKF_MODEL_B */
    (uint8_t)FCC_BUS_NO_APP, /* SID_ZKF_STATE */
    (uint8_t)FCC_BUS_NO_APP, /* SID_ZKF_BOUNDS */
    (uint8_t)FCC_BUS_NO_APP, /* SID_ZKF_MODEL_A */
    (uint8_t)FCC_BUS_NO_APP, /* SID_ZKF_MODEL_B */
    (uint8_t)FCC_BUS_NO_APP, /* SID_KF_STATE */
    (uint8_t)FCC_BUS_NO_APP, /* SID_KF_BOUNDS */
    (uint8_t)FCC_BUS_NO_APP, /* SID_KF_MODEL_A */
    (uint8_t)FCC_BUS_NO_APP, /* SID_KF_MODEL_B */
    (uint8_t)FCC_BUS_NO_APP, /* SID_OUT_AUTH */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_STATUS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_E2E_COUNTS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_E2E_FAULTS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_REJECT_COUNTS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_BUS_COUNTS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_SYNC_STATUS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_SEC_COUNTS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_SEC_SESSION */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_SYNC_REFUSALS */
    (uint8_t)FCC_BUS_NO_APP, /* FCC_STATUS_AUTH */
    (uint8_t)FCC_BUS_NO_APP, /* SIM_EVENT */
    (uint8_t)FCC_BUS_NO_APP, /* RIG_PING */
    (uint8_t)FCC_BUS_NO_APP, /* RIG_PONG */
};

const fcc_secoc_desc_t fcc_secoc_table[FCC_SECOC_N_AUTH] = {
    {FCC_MSG_TSYNC_AUTH, 0x2001u, 2u, {FCC_MSG_TSYNC_SYNC, FCC_MSG_TSYNC_FOLLOW_UP}},
    {FCC_MSG_SIM_CONTROL_AUTH, 0x2010u, 1u, {FCC_MSG_SIM_CONTROL}},
    {FCC_MSG_SIM_TICK_AUTH, 0x2020u, 1u, {FCC_MSG_SIM_TICK}},
    {FCC_MSG_MSL_ELEV_CMD_AUTH, 0x2101u, 2u, {FCC_MSG_MSL_ELEV_CMD, FCC_MSG_MSL_STATE_EST}},
    {FCC_MSG_SID_OUT_AUTH, 0x2134u, 12u, {FCC_MSG_SID_AZKF_STATE, FCC_MSG_SID_AZKF_BOUNDS, FCC_MSG_SID_AZKF_MODEL_A, FCC_MSG_SID_AZKF_MODEL_B, FCC_MSG_SID_ZKF_STATE, FCC_MSG_SID_ZKF_BOUNDS, FCC_MSG_SID_ZKF_MODEL_A, FCC_MSG_SID_ZKF_MODEL_B, FCC_MSG_SID_KF_STATE, FCC_MSG_SID_KF_BOUNDS, FCC_MSG_SID_KF_MODEL_A, FCC_MSG_SID_KF_MODEL_B}},
    {FCC_MSG_FCC_STATUS_AUTH, 0x2700u, 9u, {FCC_MSG_FCC_STATUS, FCC_MSG_FCC_E2E_COUNTS, FCC_MSG_FCC_E2E_FAULTS, FCC_MSG_FCC_REJECT_COUNTS, FCC_MSG_FCC_BUS_COUNTS, FCC_MSG_FCC_SYNC_STATUS, FCC_MSG_FCC_SEC_COUNTS, FCC_MSG_FCC_SEC_SESSION, FCC_MSG_FCC_SYNC_REFUSALS}},
};
