/*
 * fcc_bus_msgs.h -- GENERATED from dbc/fcc_hil.dbc by `python -m hil.bus.cgen` (run dbc/generate).
 * Do not edit: change the DBC and regenerate.  tests/python/bus/test_bus_codegen.py
 * fails when this file and the DBC disagree.
 */

#ifndef FCC_BUS_MSGS_H
#define FCC_BUS_MSGS_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_bus_desc.h"
#include "fcc_hil.h"
#include "fcc_types.h"

/* Nodes: bit positions in fcc_bus_msg_desc_t.senders and .receivers. */
#define FCC_BUS_NODE_SIM 0u
#define FCC_BUS_NODE_CDRW_AOA_SENSOR 1u
#define FCC_BUS_NODE_CDRW_GYRO 2u
#define FCC_BUS_NODE_CDRW_ELEV_SENSOR 3u
#define FCC_BUS_NODE_MSL_GYRO 4u
#define FCC_BUS_NODE_MSL_ACCEL 5u
#define FCC_BUS_NODE_FCC 6u
#define FCC_BUS_N_NODES 7u

/* Messages: index in fcc_bus_msg_table[] (sorted by CAN identifier). */
typedef enum {
    FCC_MSG_TSYNC_SYNC = 0, /* 0x001 */
    FCC_MSG_TSYNC_FOLLOW_UP = 1, /* 0x002 */
    FCC_MSG_TSYNC_AUTH = 2, /* 0x003 */
    FCC_MSG_SIM_CONTROL = 3, /* 0x010 */
    FCC_MSG_SIM_CONTROL_AUTH = 4, /* 0x011 */
    FCC_MSG_SIM_TICK = 5, /* 0x020 */
    FCC_MSG_SIM_TICK_AUTH = 6, /* 0x021 */
    FCC_MSG_FCC_ACK = 7, /* 0x028 */
    FCC_MSG_MSL_ELEV_CMD = 8, /* 0x030 */
    FCC_MSG_MSL_RATE_GYRO = 9, /* 0x040 */
    FCC_MSG_MSL_ACCELEROMETER = 10, /* 0x041 */
    FCC_MSG_CDRW_AOA = 11, /* 0x050 */
    FCC_MSG_CDRW_PITCH_RATE = 12, /* 0x051 */
    FCC_MSG_CDRW_ELEVATOR = 13, /* 0x052 */
    FCC_MSG_MSL_STATE_EST = 14, /* 0x100 */
    FCC_MSG_MSL_ELEV_CMD_AUTH = 15, /* 0x101 */
    FCC_MSG_SID_AZKF_STATE = 16, /* 0x110 */
    FCC_MSG_SID_AZKF_BOUNDS = 17, /* 0x111 */
    FCC_MSG_SID_AZKF_MODEL_A = 18, /* 0x112 */
    FCC_MSG_SID_AZKF_MODEL_B = 19, /* 0x113 */
    FCC_MSG_SID_ZKF_STATE = 20, /* 0x120 */
    FCC_MSG_SID_ZKF_BOUNDS = 21, /* 0x121 */
    FCC_MSG_SID_ZKF_MODEL_A = 22, /* 0x122 */
    FCC_MSG_SID_ZKF_MODEL_B = 23, /* 0x123 */
    FCC_MSG_SID_KF_STATE = 24, /* 0x130 */
    FCC_MSG_SID_KF_BOUNDS = 25, /* 0x131 */
    FCC_MSG_SID_KF_MODEL_A = 26, /* 0x132 */
    FCC_MSG_SID_KF_MODEL_B = 27, /* 0x133 */
    FCC_MSG_SID_OUT_AUTH = 28, /* 0x134 */
    FCC_MSG_FCC_STATUS = 29, /* 0x700 */
    FCC_MSG_FCC_E2E_COUNTS = 30, /* 0x701 */
    FCC_MSG_FCC_E2E_FAULTS = 31, /* 0x702 */
    FCC_MSG_FCC_REJECT_COUNTS = 32, /* 0x703 */
    FCC_MSG_FCC_BUS_COUNTS = 33, /* 0x704 */
    FCC_MSG_FCC_SYNC_STATUS = 34, /* 0x705 */
    FCC_MSG_FCC_SEC_COUNTS = 35, /* 0x706 */
    FCC_MSG_FCC_SEC_SESSION = 36, /* 0x707 */
    FCC_MSG_FCC_SYNC_REFUSALS = 37, /* 0x708 */
    FCC_MSG_FCC_STATUS_AUTH = 38, /* 0x709 */
    FCC_MSG_SIM_EVENT = 39, /* 0x710 */
    FCC_MSG_RIG_PING = 40, /* 0x7F0 */
    FCC_MSG_RIG_PONG = 41, /* 0x7F1 */
    FCC_MSG_COUNT
} fcc_msg_t;

/* CAN identifiers. */
#define FCC_MSG_TSYNC_SYNC_ID 0x001u
#define FCC_MSG_TSYNC_FOLLOW_UP_ID 0x002u
#define FCC_MSG_TSYNC_AUTH_ID 0x003u
#define FCC_MSG_SIM_CONTROL_ID 0x010u
#define FCC_MSG_SIM_CONTROL_AUTH_ID 0x011u
#define FCC_MSG_SIM_TICK_ID 0x020u
#define FCC_MSG_SIM_TICK_AUTH_ID 0x021u
#define FCC_MSG_FCC_ACK_ID 0x028u
#define FCC_MSG_MSL_ELEV_CMD_ID 0x030u
#define FCC_MSG_MSL_RATE_GYRO_ID 0x040u
#define FCC_MSG_MSL_ACCELEROMETER_ID 0x041u
#define FCC_MSG_CDRW_AOA_ID 0x050u
#define FCC_MSG_CDRW_PITCH_RATE_ID 0x051u
#define FCC_MSG_CDRW_ELEVATOR_ID 0x052u
#define FCC_MSG_MSL_STATE_EST_ID 0x100u
#define FCC_MSG_MSL_ELEV_CMD_AUTH_ID 0x101u
#define FCC_MSG_SID_AZKF_STATE_ID 0x110u
#define FCC_MSG_SID_AZKF_BOUNDS_ID 0x111u
#define FCC_MSG_SID_AZKF_MODEL_A_ID 0x112u
#define FCC_MSG_SID_AZKF_MODEL_B_ID 0x113u
#define FCC_MSG_SID_ZKF_STATE_ID 0x120u
#define FCC_MSG_SID_ZKF_BOUNDS_ID 0x121u
#define FCC_MSG_SID_ZKF_MODEL_A_ID 0x122u
#define FCC_MSG_SID_ZKF_MODEL_B_ID 0x123u
#define FCC_MSG_SID_KF_STATE_ID 0x130u
#define FCC_MSG_SID_KF_BOUNDS_ID 0x131u
#define FCC_MSG_SID_KF_MODEL_A_ID 0x132u
#define FCC_MSG_SID_KF_MODEL_B_ID 0x133u
#define FCC_MSG_SID_OUT_AUTH_ID 0x134u
#define FCC_MSG_FCC_STATUS_ID 0x700u
#define FCC_MSG_FCC_E2E_COUNTS_ID 0x701u
#define FCC_MSG_FCC_E2E_FAULTS_ID 0x702u
#define FCC_MSG_FCC_REJECT_COUNTS_ID 0x703u
#define FCC_MSG_FCC_BUS_COUNTS_ID 0x704u
#define FCC_MSG_FCC_SYNC_STATUS_ID 0x705u
#define FCC_MSG_FCC_SEC_COUNTS_ID 0x706u
#define FCC_MSG_FCC_SEC_SESSION_ID 0x707u
#define FCC_MSG_FCC_SYNC_REFUSALS_ID 0x708u
#define FCC_MSG_FCC_STATUS_AUTH_ID 0x709u
#define FCC_MSG_SIM_EVENT_ID 0x710u
#define FCC_MSG_RIG_PING_ID 0x7F0u
#define FCC_MSG_RIG_PONG_ID 0x7F1u

/* Value tables (VAL_). */
#define FCC_MSG_SIM_CONTROL_COMMAND_NONE 0u
#define FCC_MSG_SIM_CONTROL_COMMAND_SHUTDOWN 1u
#define FCC_MSG_SIM_CONTROL_COMMAND_RESET 2u
#define FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT 3u
#define FCC_MSG_SIM_CONTROL_COMMAND_GROUND 4u
#define FCC_MSG_SIM_CONTROL_COMMAND_MAINTENANCE 5u
#define FCC_MSG_SIM_TICK_APP_CDRW_SID 0u
#define FCC_MSG_SIM_TICK_APP_MISSILE_LQG 1u
#define FCC_MSG_SIM_TICK_APP_PROBE 2u
#define FCC_MSG_FCC_ACK_APP_CDRW_SID 0u
#define FCC_MSG_FCC_ACK_APP_MISSILE_LQG 1u
#define FCC_MSG_FCC_ACK_APP_PROBE 2u
#define FCC_MSG_FCC_STATUS_MODE_LOCKSTEP 0u
#define FCC_MSG_FCC_STATUS_MODE_REALTIME 1u
#define FCC_MSG_FCC_STATUS_OP_MODE_GROUND 0u
#define FCC_MSG_FCC_STATUS_OP_MODE_FLIGHT 1u
#define FCC_MSG_FCC_STATUS_OP_MODE_MAINTENANCE 2u
#define FCC_MSG_FCC_SYNC_STATUS_STATE_FREE_RUN 0u
#define FCC_MSG_FCC_SYNC_STATUS_STATE_LOCKING 1u
#define FCC_MSG_FCC_SYNC_STATUS_STATE_LOCKED 2u
#define FCC_MSG_FCC_SYNC_STATUS_STATE_HOLDOVER 3u
#define FCC_MSG_FCC_SYNC_STATUS_STATE_LOST 4u
#define FCC_MSG_FCC_SYNC_STATUS_STATE_REFUSED 5u
#define FCC_MSG_SIM_EVENT_KIND_NONE 0u
#define FCC_MSG_SIM_EVENT_KIND_SPIKE 1u
#define FCC_MSG_SIM_EVENT_KIND_BIAS 2u
#define FCC_MSG_SIM_EVENT_KIND_STUCK 3u
#define FCC_MSG_SIM_EVENT_KIND_DROPOUT 4u
#define FCC_MSG_SIM_EVENT_KIND_NOISE_BURST 5u
#define FCC_MSG_SIM_EVENT_KIND_DRIFT 6u
#define FCC_MSG_SIM_EVENT_KIND_SCALE 7u
#define FCC_MSG_SIM_EVENT_KIND_LOSS 8u
#define FCC_MSG_SIM_EVENT_KIND_DELAY 9u
#define FCC_MSG_SIM_EVENT_KIND_DUPLICATE 10u
#define FCC_MSG_SIM_EVENT_KIND_REPLAY 11u
#define FCC_MSG_SIM_EVENT_KIND_BAD_CRC 12u
#define FCC_MSG_SIM_EVENT_KIND_COUNTER_FREEZE 13u
#define FCC_MSG_SIM_EVENT_KIND_COUNTER_JUMP 14u
#define FCC_MSG_SIM_EVENT_KIND_WRONG_DLC 15u
#define FCC_MSG_SIM_EVENT_KIND_OUT_OF_RANGE 16u
#define FCC_MSG_SIM_EVENT_KIND_FLOOD 17u
#define FCC_MSG_SIM_EVENT_KIND_SILENCE 18u
#define FCC_MSG_SIM_EVENT_KIND_BUS_ERROR 19u
#define FCC_MSG_SIM_EVENT_KIND_BABBLING_NODE 20u
#define FCC_MSG_SIM_EVENT_KIND_BUS_OFF 21u
#define FCC_MSG_SIM_EVENT_KIND_BUS_LOAD 22u

/* Physical values of each message (crc and counter are the frame layer's). */
/* TSYNC_SYNC (0x001, 100 ms, SIM -> FCC, E2E data ID 0x1001): Time synchronisation, first half (CANopen SYNC / AUTOSAR CAN time sync style): the time master (the simulator) sends it every interval_ms; its precise transmit time follows in TSYNC_FOLLOW_UP with the same seq. See firmware/app/README.md, Time synchronisation. */
typedef struct {
    uint8_t master; /* [0, 15]. Identifier of the time master (0 to 15); a slave follows one master and counts the others. */
    uint8_t seq; /* [0, 255]. Sync sequence number, +1 modulo 256 per SYNC; the FOLLOW_UP repeats it. */
    uint8_t interval_ms; /* [1, 255] ms. The master's sync period in ms (the slave's loss-of-sync timeout is 3 intervals). */
    uint32_t sec; /* [0, 4294967295] s. Whole seconds of the master time when the SYNC was queued (coarse part). */
} fcc_msg_tsync_sync_t;

/* TSYNC_FOLLOW_UP (0x002, 100 ms, SIM -> FCC, E2E data ID 0x1002): Time synchronisation, second half: the master time at which the SYNC of the same seq actually left (its transmit time stamp, taken after the frame was on the bus). */
typedef struct {
    uint8_t master; /* [0, 15]. Identifier of the time master (as in its SYNC). */
    uint8_t seq; /* [0, 255]. Sequence number of the SYNC this follows up. */
    bool sec_carry; /* [0, 1]. 1 when the transmit time is in the second after SYNC.sec. */
    uint32_t ns; /* [0, 999999999] ns. Nanoseconds within that second of the SYNC's transmit time. */
} fcc_msg_tsync_follow_up_t;

/* TSYNC_AUTH (0x003, 100 ms, SIM -> FCC): SecOC authenticator of the time synchronisation (TSYNC_SYNC, TSYNC_FOLLOW_UP, concatenated in this order): sent by the time master right after the FOLLOW_UP. fcc uses a SYNC/FOLLOW_UP pair (with the SYNC's receive stamp) only once this authenticator verified it; frames without a valid one are refused and counted in FCC_SYNC_REFUSALS. fv = low 16 bits of the 64-bit freshness value (trip << 32 | message counter), mac = the first 48 bits of AES-128-CMAC(key, SecOC_DataID (2 bytes, big-endian) | the SYNC's 8 bytes | the FOLLOW_UP's 8 bytes | the full freshness value (8 bytes, big-endian)). See dbc/README.md, Authentication. Time synchronisation: firmware/app/README.md. */
typedef struct {
    uint16_t fv; /* [0, 65535]. Low 16 bits of the freshness value (its message counter, +1 per authenticator sent, from 1). */
    uint64_t mac; /* [0, 281474976710655]. First 48 bits of the AES-128-CMAC, the 6 bytes in frame order. */
} fcc_msg_tsync_auth_t;

/* SIM_CONTROL (0x010, event, SIM -> FCC, E2E data ID 0x1010): Run-time configuration and commands from the simulator to the FCC. Sent on demand. A field at 0 keeps the current setting. */
typedef struct {
    uint8_t command; /* [0, 5]. 0 none, 1 shut the FCC down cleanly, 2 reset both applications to their initial state, 3 enter FLIGHT, 4 enter GROUND (end of flight), 5 enter MAINTENANCE. Accepted only when authenticated and allowed in the current mode (firmware/app/README.md, Modes). */
    fcc_real_t lqg_period; /* [0, 0.3] s, LSB 0.0001. New LQG sampling period T in seconds (valid 0.02 to 0.3); 0 keeps the current period. The FCC redesigns the LQG for the new T. */
    uint8_t da_bits; /* [0, 16] bit. New D/A word length N in bits (valid 1 to 16); 0 keeps the current word length. */
} fcc_msg_sim_control_t;

/* SIM_CONTROL_AUTH (0x011, event, SIM -> FCC): SecOC authenticator of SIM_CONTROL: sent right after it by the same sender. fv = low 16 bits of the 64-bit freshness value (trip << 32 | message counter), mac = the first 48 bits of AES-128-CMAC(key, SecOC_DataID (2 bytes, big-endian) | the authentic frame bytes | the full freshness value (8 bytes, big-endian)). See dbc/README.md, Authentication. */
typedef struct {
    uint16_t fv; /* [0, 65535]. Truncated freshness value: the low 16 bits of the message counter. */
    uint64_t mac; /* [0, 281474976710655]. Truncated MAC: the first 6 bytes of the AES-128-CMAC, in bytes 2 to 7 in order. */
} fcc_msg_sim_control_auth_t;

/* SIM_TICK (0x020, 20 ms, SIM -> FCC, E2E data ID 0x1020): Lockstep tick: every sensor frame of this step has been sent; the FCC runs one step of the application and answers with FCC_ACK. 50 Hz for the CDRW, 1/T for the missile (default T = 0.05 s). */
typedef struct {
    uint8_t app; /* [0, 2]. Application to step: 0 CDRW system identification, 1 missile LQG autopilot, 2 the probe (the test build's third application, cmake -DFCC_APP_PROBE=ON; a shipped fcc ignores its ticks). */
    uint32_t step; /* [0, 4294967295]. Step index k of that application, from 0; the low 16 bits match the step field of the sensor frames. */
} fcc_msg_sim_tick_t;

/* SIM_TICK_AUTH (0x021, 20 ms, SIM -> FCC): SecOC authenticator of SIM_TICK: sent right after it by the same sender. fv = low 16 bits of the 64-bit freshness value (trip << 32 | message counter), mac = the first 48 bits of AES-128-CMAC(key, SecOC_DataID (2 bytes, big-endian) | the authentic frame bytes | the full freshness value (8 bytes, big-endian)). See dbc/README.md, Authentication. */
typedef struct {
    uint16_t fv; /* [0, 65535]. Truncated freshness value: the low 16 bits of the message counter. */
    uint64_t mac; /* [0, 281474976710655]. Truncated MAC: the first 6 bytes of the AES-128-CMAC, in bytes 2 to 7 in order. */
} fcc_msg_sim_tick_auth_t;

/* FCC_ACK (0x028, 20 ms, FCC -> SIM, E2E data ID 0x1028): Lockstep acknowledge: the FCC has finished step k of an application and has sent every output frame of that step before this one (send through one ordered transmit queue). */
typedef struct {
    uint8_t app; /* [0, 2]. Application whose step is complete: 0 CDRW system identification, 1 missile LQG autopilot, 2 the probe (test build). */
    bool degraded; /* [0, 1]. 1 when the step ran on degraded inputs (stale, rejected or E2E-failed sensor data). */
    uint32_t step; /* [0, 4294967295]. Step index k just completed (copy of SIM_TICK.step). */
    uint16_t exec_us; /* [0, 65535] us. Execution time of this step in microseconds, saturated at 65535. */
} fcc_msg_fcc_ack_t;

/* MSL_ELEV_CMD (0x030, 50 ms, FCC -> SIM, E2E data ID 0x1030): Missile elevator command: the code written to the N-bit D/A converter, held for one period (zero-order hold). delta_e = da_code * 0.8 / 2^da_bits rad. */
typedef struct {
    bool degraded; /* [0, 1]. 1 when the command was computed from degraded inputs. */
    bool saturated; /* [0, 1]. 1 when the LQG command was clamped to the D/A range (|u| > 0.4 rad). */
    uint16_t step; /* [0, 65535]. Step index k (low 16 bits) this command belongs to. */
    int16_t da_code; /* [-32768, 32767]. Signed D/A code, clamp(round(u / LSB), -2^(N-1), 2^(N-1)-1), LSB = 0.8 / 2^N rad. */
    uint8_t da_bits; /* [1, 16] bit. D/A word length N in bits used to compute da_code. */
} fcc_msg_msl_elev_cmd_t;

/* MSL_RATE_GYRO (0x040, 50 ms, MSL_GYRO -> FCC, E2E data ID 0x1040): Missile rate gyro sample q_g = q + v_g, taken at the sampling instant of step k. */
typedef struct {
    uint16_t step; /* [0, 65535]. Step index k (low 16 bits) of the sample, for lockstep alignment. */
    fcc_real_t q_g; /* [-20, 20] rad/s, LSB 1e-05. Measured pitch rate. Range +-20 rad/s because the noise standard deviation is about 0.9 rad/s. */
} fcc_msg_msl_rate_gyro_t;

/* MSL_ACCELEROMETER (0x041, 50 ms, MSL_ACCEL -> FCC, E2E data ID 0x1041): Missile normal accelerometer sample n_a = -26.74 q - 568.4 alpha_T + v_a, taken at the sampling instant of step k. */
typedef struct {
    uint16_t step; /* [0, 65535]. Step index k (low 16 bits) of the sample, for lockstep alignment. */
    fcc_real_t n_a; /* [-4000, 4000] ft/s^2, LSB 0.002. Measured normal acceleration. */
} fcc_msg_msl_accelerometer_t;

/* CDRW_AOA (0x050, 20 ms, CDRW_AOA_SENSOR -> FCC, E2E data ID 0x1050): CDRW angle-of-attack sample at step k (50 Hz). */
typedef struct {
    uint16_t step; /* [0, 65535]. Step index k (low 16 bits) of the sample, for lockstep alignment. */
    fcc_real_t alpha; /* [-1.5708, 1.5708] rad, LSB 1e-06. Measured angle of attack, 1e-6 rad resolution because the identification differentiates the data. */
} fcc_msg_cdrw_aoa_t;

/* CDRW_PITCH_RATE (0x051, 20 ms, CDRW_GYRO -> FCC, E2E data ID 0x1051): CDRW pitch-rate sample at step k (50 Hz). */
typedef struct {
    uint16_t step; /* [0, 65535]. Step index k (low 16 bits) of the sample, for lockstep alignment. */
    fcc_real_t q; /* [-2, 2] rad/s, LSB 1e-06. Measured pitch rate, 1e-6 rad/s resolution; range +-2 rad/s (a +-125 deg/s MEMS gyro setting). */
} fcc_msg_cdrw_pitch_rate_t;

/* CDRW_ELEVATOR (0x052, 20 ms, CDRW_ELEV_SENSOR -> FCC, E2E data ID 0x1052): CDRW elevator deflection sample at step k (50 Hz). */
typedef struct {
    uint16_t step; /* [0, 65535]. Step index k (low 16 bits) of the sample, for lockstep alignment. */
    fcc_real_t delta_e; /* [-0.5236, 0.5236] rad, LSB 1e-06. Measured elevator deflection, 1e-6 rad resolution. */
} fcc_msg_cdrw_elevator_t;

/* MSL_STATE_EST (0x100, 50 ms, FCC -> SIM): Missile LQG state estimate after the measurement update of step k. */
typedef struct {
    fcc_real_t q_hat; /* [-5.24288, 5.24287] rad/s, LSB 1e-05. Estimated pitch rate q. */
    fcc_real_t alpha_t_hat; /* [-5.24288, 5.24287] rad, LSB 1e-05. Estimated angle of attack alpha_T. */
    fcc_real_t w_g_hat; /* [-327.68, 327.67] ft/s, LSB 0.01. Estimated vertical gust velocity w_g. */
    uint8_t step; /* [0, 255]. Step index k (low 8 bits). */
} fcc_msg_msl_state_est_t;

/* MSL_ELEV_CMD_AUTH (0x101, 50 ms, FCC -> SIM): SecOC authenticator of the missile outputs of one step (MSL_ELEV_CMD, MSL_STATE_EST, concatenated in this order): sent by the FCC right after MSL_STATE_EST, before FCC_ACK. The simulator acts on the command, and the rig reports the estimate, only once this authenticator verified both. fv = low 16 bits of the 64-bit freshness value (trip << 32 | message counter), mac = the first 48 bits of AES-128-CMAC(key, SecOC_DataID (2 bytes, big-endian) | MSL_ELEV_CMD's 8 bytes | MSL_STATE_EST's 8 bytes | the full freshness value (8 bytes, big-endian)). See dbc/README.md, Authentication. */
typedef struct {
    uint16_t fv; /* [0, 65535]. Truncated freshness value: the low 16 bits of the message counter. */
    uint64_t mac; /* [0, 281474976710655]. Truncated MAC: the first 6 bytes of the AES-128-CMAC, in bytes 2 to 7 in order. */
} fcc_msg_msl_elev_cmd_auth_t;

/* SID_AZKF_STATE (0x110, 20 ms, FCC -> SIM): MLS-AZKF (adaptive-order zonotopic Kalman filter) state estimate, order in use and flags at step k. */
typedef struct {
    fcc_real_t alpha_hat; /* [-5.24288, 5.24287] rad, LSB 1e-05. Estimated angle of attack (centre of the state zonotope). */
    fcc_real_t q_hat; /* [-5.24288, 5.24287] rad/s, LSB 1e-05. Estimated pitch rate (centre of the state zonotope). */
    uint16_t order; /* [0, 1023]. Zonotope reduction order q in use at this step. */
    bool fault; /* [0, 1]. 1 when the sensor-fault detector flags a fault at this step. */
    bool degraded; /* [0, 1]. 1 when the step ran on degraded inputs or the estimator kept its last good model. */
    uint16_t step; /* [0, 4095]. Step index k (low 12 bits). */
} fcc_msg_sid_azkf_state_t;

/* SID_AZKF_BOUNDS (0x111, 20 ms, FCC -> SIM): MLS-AZKF interval hull of the state zonotope at step k. */
typedef struct {
    fcc_real_t alpha_lo; /* [-3.2768, 3.2767] rad, LSB 0.0001. Lower bound of alpha. */
    fcc_real_t alpha_hi; /* [-3.2768, 3.2767] rad, LSB 0.0001. Upper bound of alpha. */
    fcc_real_t q_lo; /* [-3.2768, 3.2767] rad/s, LSB 0.0001. Lower bound of q. */
    fcc_real_t q_hi; /* [-3.2768, 3.2767] rad/s, LSB 0.0001. Upper bound of q. */
} fcc_msg_sid_azkf_bounds_t;

/* SID_AZKF_MODEL_A (0x112, 20 ms, FCC -> SIM): MLS-AZKF identified discrete state matrix A_k (dt = 0.02 s). */
typedef struct {
    fcc_real_t a11; /* [-3.2768, 3.2767], LSB 0.0001. A_k(1,1). */
    fcc_real_t a12; /* [-3.2768, 3.2767] s, LSB 0.0001. A_k(1,2). */
    fcc_real_t a21; /* [-3.2768, 3.2767] 1/s, LSB 0.0001. A_k(2,1). */
    fcc_real_t a22; /* [-3.2768, 3.2767], LSB 0.0001. A_k(2,2). */
} fcc_msg_sid_azkf_model_a_t;

/* SID_AZKF_MODEL_B (0x113, 20 ms, FCC -> SIM): MLS-AZKF identified input matrix B_k, spectral radius of A_k and gain norm at step k. */
typedef struct {
    fcc_real_t b1; /* [-3.2768, 3.2767], LSB 0.0001. B_k(1). */
    fcc_real_t b2; /* [-3.2768, 3.2767] 1/s, LSB 0.0001. B_k(2). */
    fcc_real_t rho; /* [0, 6.5535], LSB 0.0001. Spectral radius max |lambda_i(A_k)|; above 1 the identified model is unstable. */
    fcc_real_t gain_norm; /* [0, 6.5535], LSB 0.0001. Spectral norm of the filter gain G_k. */
} fcc_msg_sid_azkf_model_b_t;

/* SID_ZKF_STATE (0x120, 20 ms, FCC -> SIM): MLS-ZKF (fixed-order zonotopic Kalman filter) state estimate, order and flags at step k. */
typedef struct {
    fcc_real_t alpha_hat; /* [-5.24288, 5.24287] rad, LSB 1e-05. Estimated angle of attack (centre of the state zonotope). */
    fcc_real_t q_hat; /* [-5.24288, 5.24287] rad/s, LSB 1e-05. Estimated pitch rate (centre of the state zonotope). */
    uint16_t order; /* [0, 1023]. Zonotope reduction order q (fixed). */
    bool fault; /* [0, 1]. 1 when the sensor-fault detector flags a fault at this step (information only). */
    bool degraded; /* [0, 1]. 1 when the step ran on degraded inputs or the estimator kept its last good model. */
    uint16_t step; /* [0, 4095]. Step index k (low 12 bits). */
} fcc_msg_sid_zkf_state_t;

/* SID_ZKF_BOUNDS (0x121, 20 ms, FCC -> SIM): MLS-ZKF interval hull of the state zonotope at step k. */
typedef struct {
    fcc_real_t alpha_lo; /* [-3.2768, 3.2767] rad, LSB 0.0001. Lower bound of alpha. */
    fcc_real_t alpha_hi; /* [-3.2768, 3.2767] rad, LSB 0.0001. Upper bound of alpha. */
    fcc_real_t q_lo; /* [-3.2768, 3.2767] rad/s, LSB 0.0001. Lower bound of q. */
    fcc_real_t q_hi; /* [-3.2768, 3.2767] rad/s, LSB 0.0001. Upper bound of q. */
} fcc_msg_sid_zkf_bounds_t;

/* SID_ZKF_MODEL_A (0x122, 20 ms, FCC -> SIM): MLS-ZKF identified discrete state matrix A_k (dt = 0.02 s). */
typedef struct {
    fcc_real_t a11; /* [-3.2768, 3.2767], LSB 0.0001. A_k(1,1). */
    fcc_real_t a12; /* [-3.2768, 3.2767] s, LSB 0.0001. A_k(1,2). */
    fcc_real_t a21; /* [-3.2768, 3.2767] 1/s, LSB 0.0001. A_k(2,1). */
    fcc_real_t a22; /* [-3.2768, 3.2767], LSB 0.0001. A_k(2,2). */
} fcc_msg_sid_zkf_model_a_t;

/* SID_ZKF_MODEL_B (0x123, 20 ms, FCC -> SIM): MLS-ZKF identified input matrix B_k, spectral radius of A_k and gain norm at step k. */
typedef struct {
    fcc_real_t b1; /* [-3.2768, 3.2767], LSB 0.0001. B_k(1). */
    fcc_real_t b2; /* [-3.2768, 3.2767] 1/s, LSB 0.0001. B_k(2). */
    fcc_real_t rho; /* [0, 6.5535], LSB 0.0001. Spectral radius max |lambda_i(A_k)|; above 1 the identified model is unstable. */
    fcc_real_t gain_norm; /* [0, 6.5535], LSB 0.0001. Spectral norm of the filter gain G_k. */
} fcc_msg_sid_zkf_model_b_t;

/* SID_KF_STATE (0x130, 20 ms, FCC -> SIM): MLS-KF (Kalman filter) state estimate and flags at step k. */
typedef struct {
    fcc_real_t alpha_hat; /* [-5.24288, 5.24287] rad, LSB 1e-05. Estimated angle of attack. */
    fcc_real_t q_hat; /* [-5.24288, 5.24287] rad/s, LSB 1e-05. Estimated pitch rate. */
    uint16_t order; /* [0, 1023]. Always 0: a Kalman filter has no zonotope order. */
    bool fault; /* [0, 1]. 1 when the sensor-fault detector flags a fault at this step (information only). */
    bool degraded; /* [0, 1]. 1 when the step ran on degraded inputs or the estimator kept its last good model. */
    uint16_t step; /* [0, 4095]. Step index k (low 12 bits). */
} fcc_msg_sid_kf_state_t;

/* SID_KF_BOUNDS (0x131, 20 ms, FCC -> SIM): MLS-KF state bounds at step k: estimate +- 3 standard deviations. */
typedef struct {
    fcc_real_t alpha_lo; /* [-3.2768, 3.2767] rad, LSB 0.0001. Lower bound of alpha. */
    fcc_real_t alpha_hi; /* [-3.2768, 3.2767] rad, LSB 0.0001. Upper bound of alpha. */
    fcc_real_t q_lo; /* [-3.2768, 3.2767] rad/s, LSB 0.0001. Lower bound of q. */
    fcc_real_t q_hi; /* [-3.2768, 3.2767] rad/s, LSB 0.0001. Upper bound of q. */
} fcc_msg_sid_kf_bounds_t;

/* SID_KF_MODEL_A (0x132, 20 ms, FCC -> SIM): MLS-KF identified discrete state matrix A_k (dt = 0.02 s). */
typedef struct {
    fcc_real_t a11; /* [-3.2768, 3.2767], LSB 0.0001. A_k(1,1). */
    fcc_real_t a12; /* [-3.2768, 3.2767] s, LSB 0.0001. A_k(1,2). */
    fcc_real_t a21; /* [-3.2768, 3.2767] 1/s, LSB 0.0001. A_k(2,1). */
    fcc_real_t a22; /* [-3.2768, 3.2767], LSB 0.0001. A_k(2,2). */
} fcc_msg_sid_kf_model_a_t;

/* SID_KF_MODEL_B (0x133, 20 ms, FCC -> SIM): MLS-KF identified input matrix B_k, spectral radius of A_k and gain norm at step k. */
typedef struct {
    fcc_real_t b1; /* [-3.2768, 3.2767], LSB 0.0001. B_k(1). */
    fcc_real_t b2; /* [-3.2768, 3.2767] 1/s, LSB 0.0001. B_k(2). */
    fcc_real_t rho; /* [0, 6.5535], LSB 0.0001. Spectral radius max |lambda_i(A_k)|; above 1 the identified model is unstable. */
    fcc_real_t gain_norm; /* [0, 6.5535], LSB 0.0001. Spectral norm of the Kalman gain K_k. */
} fcc_msg_sid_kf_model_b_t;

/* SID_OUT_AUTH (0x134, 20 ms, FCC -> SIM): SecOC authenticator of the identification outputs of one CDRW step (the 12 frames SID_AZKF_STATE to SID_KF_MODEL_B, concatenated in identifier order): sent by the FCC right after SID_KF_MODEL_B, before FCC_ACK. The rig reports an estimate, bound, model or flag only once this authenticator verified the whole step; a step sent incompletely (a value that cannot be encoded) is not sent at all. fv = low 16 bits of the 64-bit freshness value (trip << 32 | message counter), mac = the first 48 bits of AES-128-CMAC(key, SecOC_DataID (2 bytes, big-endian) | the 12 frames' 96 bytes | the full freshness value (8 bytes, big-endian)). See dbc/README.md, Authentication. */
typedef struct {
    uint16_t fv; /* [0, 65535]. Truncated freshness value: the low 16 bits of the message counter. */
    uint64_t mac; /* [0, 281474976710655]. Truncated MAC: the first 6 bytes of the AES-128-CMAC, in bytes 2 to 7 in order. */
} fcc_msg_sid_out_auth_t;

/* FCC_STATUS (0x700, 100 ms, FCC -> SIM): FCC heartbeat at 10 Hz: mode, step counters, overruns, worst step time and health flags. Counters wrap. */
typedef struct {
    uint8_t mode; /* [0, 1]. 0 lockstep (steps on SIM_TICK), 1 real time (steps on its own clock). */
    bool cdrw_degraded; /* [0, 1]. 1 when the last CDRW step was degraded. */
    bool msl_degraded; /* [0, 1]. 1 when the last missile step was degraded. */
    bool sensor_stale; /* [0, 1]. 1 when at least one sensor frame had no new data in the last period. */
    bool e2e_fault; /* [0, 1]. 1 when an E2E ERROR or WRONG_SEQUENCE was seen since the last heartbeat. */
    bool overrun; /* [0, 1]. 1 when a step overran its period since the last heartbeat. */
    bool config_rejected; /* [0, 1]. 1 when the last SIM_CONTROL request was refused (value out of range or redesign failed). */
    uint8_t overruns; /* [0, 63]. Number of step overruns since start (wraps). */
    uint8_t op_mode; /* [0, 2]. Operating mode: 0 GROUND (standby), 1 FLIGHT, 2 MAINTENANCE. */
    uint16_t cdrw_steps; /* [0, 65535]. CDRW steps run since start (wraps). */
    uint16_t msl_steps; /* [0, 65535]. Missile steps run since start (wraps). */
    uint16_t worst_step_us; /* [0, 65535] us. Worst step execution time since start, microseconds, saturated at 65535. */
} fcc_msg_fcc_status_t;

/* FCC_E2E_COUNTS (0x701, 100 ms, FCC -> SIM): FCC receiver E2E classification counters, summed over every E2E-protected frame it receives (wrap). */
typedef struct {
    uint16_t ok; /* [0, 65535]. Frames classified OK (counter +1). */
    uint16_t repeated; /* [0, 65535]. Frames classified REPEATED (same counter again); their data are not used. */
    uint16_t ok_some_lost; /* [0, 65535]. Frames classified OK_SOME_LOST (counter jumped by 2 up to the maximum delta); data used. */
    uint16_t wrong_sequence; /* [0, 65535]. Frames classified WRONG_SEQUENCE (counter jumped beyond the maximum delta or went back); data not used, receiver resynchronises. */
} fcc_msg_fcc_e2_e_counts_t;

/* FCC_E2E_FAULTS (0x702, 100 ms, FCC -> SIM): FCC receiver E2E error and staleness counters, and frames impersonating the FCC (wrap). */
typedef struct {
    uint16_t error; /* [0, 65535]. Frames classified ERROR (CRC mismatch); data not used. */
    uint16_t no_new_data; /* [0, 65535]. Receive periods that ended without any frame of a monitored message (NO_NEW_DATA). */
    uint16_t stale_now; /* [0, 65535]. Number of monitored messages whose last period ended without a frame. */
    uint16_t own_id; /* [0, 65535]. Frames received on an identifier the FCC itself sends (its outputs, authenticators, heartbeat): the FCC never receives its own frames, so each was sent by another node impersonating it. Counted in unknown_id as well. A run in which it is not 0 fails (hil: exit 1). */
} fcc_msg_fcc_e2_e_faults_t;

/* FCC_REJECT_COUNTS (0x703, 100 ms, FCC -> SIM): FCC frame rejection counters, one per class (wrap). */
typedef struct {
    uint16_t unknown_id; /* [0, 65535]. Frames with an identifier the FCC does not consume. */
    uint16_t wrong_dlc; /* [0, 65535]. Frames with a data length other than the DBC length. */
    uint16_t out_of_range; /* [0, 65535]. Frames with a raw value outside the DBC minimum and maximum. */
    uint16_t tx_refused; /* [0, 65535]. Frames the FCC refused to encode (NaN, infinite or out-of-range value). */
} fcc_msg_fcc_reject_counts_t;

/* FCC_BUS_COUNTS (0x704, 100 ms, FCC -> SIM): FCC SocketCAN port counters (wrap). */
typedef struct {
    uint16_t bus_errors; /* [0, 65535]. CAN error frames received. */
    uint16_t rx_overflows; /* [0, 65535]. Frames dropped by the kernel receive queue (SO_RXQ_OVFL). */
    uint16_t tx_dropped; /* [0, 65535]. Frames dropped after the bounded transmit retry (ENOBUFS or EAGAIN). */
    uint16_t tx_retries; /* [0, 65535]. Transmit retries after ENOBUFS or EAGAIN. */
} fcc_msg_fcc_bus_counts_t;

/* FCC_SYNC_STATUS (0x705, 100 ms, FCC -> SIM): Time synchronisation status of the FCC (the slave): part of the heartbeat, authenticated with it by FCC_STATUS_AUTH. */
typedef struct {
    uint8_t state; /* [0, 5]. 0 free-run (never synchronised: own clock), 1 locking, 2 locked, 3 holdover (no authentic sync for 3 intervals: the last estimate goes on, degraded), 4 lost (no accepted sync for 50 intervals: the estimate is dropped, own clock), 5 refused (the last authenticated master time failed the plausibility check against fcc's own clock: not followed, the last estimate goes on). */
    uint8_t master; /* [0, 15]. Time master followed. */
    int16_t offset_us; /* [-32768, 32767] us. Last sync residual: master time of the SYNC minus the slave's estimate of it, saturated. */
    fcc_real_t rate_ppm; /* [-327.68, 327.67] ppm, LSB 0.01. Estimated rate of the master clock relative to the slave's, ppm. */
    uint8_t syncs; /* [0, 255]. SYNC/FOLLOW_UP pairs used, modulo 256. */
    uint8_t rejected; /* [0, 255]. Sync inputs refused, every class together (the servo's: past/future outlier, backwards, missing or orphan follow-up, foreign master, repeated sequence; and those of FCC_SYNC_REFUSALS: not authenticated, implausible), modulo 256. */
    uint8_t losses; /* [0, 255]. Losses of sync (no usable sync for 3 intervals), modulo 256. */
} fcc_msg_fcc_sync_status_t;

/* FCC_SEC_COUNTS (0x706, 100 ms, FCC -> SIM): FCC authentication and mode counters since start (wrap). */
typedef struct {
    uint16_t mac_failed; /* [0, 65535]. Authenticators received whose MAC matched no pending secured frame (forgeries, frames of another session or key). */
    uint16_t freshness_failed; /* [0, 65535]. Authenticators whose freshness value was not newer than the last accepted one or beyond the acceptance window (replays). */
    uint16_t unpaired; /* [0, 65535]. Secured frames dropped without a valid authenticator (evicted or superseded). */
    uint16_t mode_refused; /* [0, 65535]. Authenticated commands refused in the current mode (for example RESET, SHUTDOWN or a new LQG design in flight, a tick on the ground). */
} fcc_msg_fcc_sec_counts_t;

/* FCC_SEC_SESSION (0x707, 100 ms, FCC -> SIM): FCC authentication session. */
typedef struct {
    uint32_t trip; /* [0, 4294967295]. Trip counter: the high 32 bits of every freshness value of this fcc process, drawn at start (never 0). The simulator uses it for the frames it authenticates. */
    uint32_t verified; /* [0, 4294967295]. Secured frames received, authenticated and accepted since start. */
} fcc_msg_fcc_sec_session_t;

/* FCC_SYNC_REFUSALS (0x708, 100 ms, FCC -> SIM): Time synchronisation refusals of the FCC: what it did not take from the bus's time master (forged, replayed, implausible). Part of the heartbeat, authenticated with it by FCC_STATUS_AUTH. Counters since start, wrapping at their width. */
typedef struct {
    uint16_t mac_failed; /* [0, 65535]. TSYNC_AUTH authenticators whose MAC matched no held SYNC/FOLLOW_UP pair (forged). */
    uint16_t freshness_failed; /* [0, 65535]. TSYNC_AUTH authenticators not newer than the last accepted one, or beyond the acceptance window (replayed). */
    uint16_t unauthenticated; /* [0, 65535]. SYNC and FOLLOW_UP frames dropped without a valid authenticator (forged frames, or genuine ones whose authenticator never came). */
    uint8_t step_refused; /* [0, 255]. Authenticated pairs refused: the master time stepped by more than the step bound (1 ms) against fcc's own clock. */
    uint8_t rate_refused; /* [0, 255]. Authenticated pairs refused: the master time drifted from fcc's own clock faster than the rate bound (200 ppm). */
} fcc_msg_fcc_sync_refusals_t;

/* FCC_STATUS_AUTH (0x709, 100 ms, FCC -> SIM): SecOC authenticator of the heartbeat (FCC_STATUS, FCC_E2E_COUNTS, FCC_E2E_FAULTS, FCC_REJECT_COUNTS, FCC_BUS_COUNTS, FCC_SYNC_STATUS, FCC_SEC_COUNTS, FCC_SEC_SESSION, FCC_SYNC_REFUSALS, concatenated in this order): sent right after it by the same sender. fv = low 16 bits of the 64-bit freshness value (trip << 32 | message counter), mac = the first 48 bits of AES-128-CMAC(key, SecOC_DataID (2 bytes, big-endian) | the authentic frame bytes | the full freshness value (8 bytes, big-endian)). See dbc/README.md, Authentication. */
typedef struct {
    uint16_t fv; /* [0, 65535]. Truncated freshness value: the low 16 bits of the message counter. */
    uint64_t mac; /* [0, 281474976710655]. Truncated MAC: the first 6 bytes of the AES-128-CMAC, in bytes 2 to 7 in order. */
} fcc_msg_fcc_status_auth_t;

/* SIM_EVENT (0x710, event, SIM -> FCC, E2E data ID 0x1710): Fault-injection event from the simulator, sent when a fault starts or ends. Diagnostic only, except oracle_fault which the FCC oracle fault detector reads. */
typedef struct {
    bool active; /* [0, 1]. 1 when the fault starts, 0 when it ends. */
    bool oracle_fault; /* [0, 1]. 1 while at least one sensor-level fault on a CDRW sensor is active (ground truth for the oracle detector). */
    uint8_t fault_id; /* [0, 255]. Index of the fault in the scenario. */
    uint8_t kind; /* [0, 63]. Kind of fault (see value table). */
    uint16_t target_id; /* [0, 2047]. CAN identifier of the affected frame or sensor, 0 for the whole bus. */
    uint16_t step; /* [0, 65535]. Step index (low 16 bits) at which the event happens. */
} fcc_msg_sim_event_t;

/* RIG_PING (0x7F0, event, SIM -> FCC): Rig round-trip probe: the echo tool (can_echo) answers with RIG_PONG carrying the same payload. Used by the tests and the latency benchmark. */
typedef struct {
    uint32_t seq; /* [0, 4294967295]. Sequence number of the probe. */
    uint32_t t_send_us; /* [0, 4294967295] us. Sender clock at transmission (microseconds, wraps). */
} fcc_msg_rig_ping_t;

/* RIG_PONG (0x7F1, event, FCC -> SIM): Rig round-trip answer: copy of the RIG_PING payload, sent on identifier RIG_PING + 1. */
typedef struct {
    uint32_t seq; /* [0, 4294967295]. Sequence number copied from RIG_PING. */
    uint32_t t_send_us; /* [0, 4294967295] us. Sender clock copied from RIG_PING. */
} fcc_msg_rig_pong_t;

/* Any message, physical values. */
typedef union {
    fcc_msg_tsync_sync_t tsync_sync;
    fcc_msg_tsync_follow_up_t tsync_follow_up;
    fcc_msg_tsync_auth_t tsync_auth;
    fcc_msg_sim_control_t sim_control;
    fcc_msg_sim_control_auth_t sim_control_auth;
    fcc_msg_sim_tick_t sim_tick;
    fcc_msg_sim_tick_auth_t sim_tick_auth;
    fcc_msg_fcc_ack_t fcc_ack;
    fcc_msg_msl_elev_cmd_t msl_elev_cmd;
    fcc_msg_msl_rate_gyro_t msl_rate_gyro;
    fcc_msg_msl_accelerometer_t msl_accelerometer;
    fcc_msg_cdrw_aoa_t cdrw_aoa;
    fcc_msg_cdrw_pitch_rate_t cdrw_pitch_rate;
    fcc_msg_cdrw_elevator_t cdrw_elevator;
    fcc_msg_msl_state_est_t msl_state_est;
    fcc_msg_msl_elev_cmd_auth_t msl_elev_cmd_auth;
    fcc_msg_sid_azkf_state_t sid_azkf_state;
    fcc_msg_sid_azkf_bounds_t sid_azkf_bounds;
    fcc_msg_sid_azkf_model_a_t sid_azkf_model_a;
    fcc_msg_sid_azkf_model_b_t sid_azkf_model_b;
    fcc_msg_sid_zkf_state_t sid_zkf_state;
    fcc_msg_sid_zkf_bounds_t sid_zkf_bounds;
    fcc_msg_sid_zkf_model_a_t sid_zkf_model_a;
    fcc_msg_sid_zkf_model_b_t sid_zkf_model_b;
    fcc_msg_sid_kf_state_t sid_kf_state;
    fcc_msg_sid_kf_bounds_t sid_kf_bounds;
    fcc_msg_sid_kf_model_a_t sid_kf_model_a;
    fcc_msg_sid_kf_model_b_t sid_kf_model_b;
    fcc_msg_sid_out_auth_t sid_out_auth;
    fcc_msg_fcc_status_t fcc_status;
    fcc_msg_fcc_e2_e_counts_t fcc_e2_e_counts;
    fcc_msg_fcc_e2_e_faults_t fcc_e2_e_faults;
    fcc_msg_fcc_reject_counts_t fcc_reject_counts;
    fcc_msg_fcc_bus_counts_t fcc_bus_counts;
    fcc_msg_fcc_sync_status_t fcc_sync_status;
    fcc_msg_fcc_sec_counts_t fcc_sec_counts;
    fcc_msg_fcc_sec_session_t fcc_sec_session;
    fcc_msg_fcc_sync_refusals_t fcc_sync_refusals;
    fcc_msg_fcc_status_auth_t fcc_status_auth;
    fcc_msg_sim_event_t sim_event;
    fcc_msg_rig_ping_t rig_ping;
    fcc_msg_rig_pong_t rig_pong;
} fcc_msg_data_t;

/* Any message, cantools raw struct (frame-layer scratch). */
typedef union {
    struct fcc_hil_tsync_sync_t tsync_sync;
    struct fcc_hil_tsync_follow_up_t tsync_follow_up;
    struct fcc_hil_tsync_auth_t tsync_auth;
    struct fcc_hil_sim_control_t sim_control;
    struct fcc_hil_sim_control_auth_t sim_control_auth;
    struct fcc_hil_sim_tick_t sim_tick;
    struct fcc_hil_sim_tick_auth_t sim_tick_auth;
    struct fcc_hil_fcc_ack_t fcc_ack;
    struct fcc_hil_msl_elev_cmd_t msl_elev_cmd;
    struct fcc_hil_msl_rate_gyro_t msl_rate_gyro;
    struct fcc_hil_msl_accelerometer_t msl_accelerometer;
    struct fcc_hil_cdrw_aoa_t cdrw_aoa;
    struct fcc_hil_cdrw_pitch_rate_t cdrw_pitch_rate;
    struct fcc_hil_cdrw_elevator_t cdrw_elevator;
    struct fcc_hil_msl_state_est_t msl_state_est;
    struct fcc_hil_msl_elev_cmd_auth_t msl_elev_cmd_auth;
    struct fcc_hil_sid_azkf_state_t sid_azkf_state;
    struct fcc_hil_sid_azkf_bounds_t sid_azkf_bounds;
    struct fcc_hil_sid_azkf_model_a_t sid_azkf_model_a;
    struct fcc_hil_sid_azkf_model_b_t sid_azkf_model_b;
    struct fcc_hil_sid_zkf_state_t sid_zkf_state;
    struct fcc_hil_sid_zkf_bounds_t sid_zkf_bounds;
    struct fcc_hil_sid_zkf_model_a_t sid_zkf_model_a;
    struct fcc_hil_sid_zkf_model_b_t sid_zkf_model_b;
    struct fcc_hil_sid_kf_state_t sid_kf_state;
    struct fcc_hil_sid_kf_bounds_t sid_kf_bounds;
    struct fcc_hil_sid_kf_model_a_t sid_kf_model_a;
    struct fcc_hil_sid_kf_model_b_t sid_kf_model_b;
    struct fcc_hil_sid_out_auth_t sid_out_auth;
    struct fcc_hil_fcc_status_t fcc_status;
    struct fcc_hil_fcc_e2_e_counts_t fcc_e2_e_counts;
    struct fcc_hil_fcc_e2_e_faults_t fcc_e2_e_faults;
    struct fcc_hil_fcc_reject_counts_t fcc_reject_counts;
    struct fcc_hil_fcc_bus_counts_t fcc_bus_counts;
    struct fcc_hil_fcc_sync_status_t fcc_sync_status;
    struct fcc_hil_fcc_sec_counts_t fcc_sec_counts;
    struct fcc_hil_fcc_sec_session_t fcc_sec_session;
    struct fcc_hil_fcc_sync_refusals_t fcc_sync_refusals;
    struct fcc_hil_fcc_status_auth_t fcc_status_auth;
    struct fcc_hil_sim_event_t sim_event;
    struct fcc_hil_rig_ping_t rig_ping;
    struct fcc_hil_rig_pong_t rig_pong;
} fcc_bus_raw_t;

extern const fcc_bus_msg_desc_t fcc_bus_msg_table[FCC_MSG_COUNT];

/* fcc's applications (FccApp; the ids are SIM_TICK.app's values) and each
 * one's inputs: the frames sent to FCC with its FccApp, in identifier order (its input
 * slots).  fcc_bus_input_app[]: the application whose input a message is, else FCC_BUS_NO_APP. */
#define FCC_BUS_APP_CDRW 0u
#define FCC_BUS_APP_MISSILE 1u
#define FCC_BUS_APP_PROBE 2u
#define FCC_BUS_N_APPS 3u
#define FCC_BUS_NO_APP FCC_BUS_N_APPS
#define FCC_BUS_APP_CDRW_N_INPUTS 3u
#define FCC_BUS_APP_MISSILE_N_INPUTS 2u
#define FCC_BUS_APP_PROBE_N_INPUTS 0u
#define FCC_BUS_MAX_APP_INPUTS 3u /* at least 1: an array's size */
extern const fcc_msg_t fcc_bus_app_cdrw_inputs[FCC_BUS_APP_CDRW_N_INPUTS];
extern const fcc_msg_t fcc_bus_app_missile_inputs[FCC_BUS_APP_MISSILE_N_INPUTS];
extern const uint8_t fcc_bus_input_app[FCC_MSG_COUNT];

/* SecOC: authenticator frames and the frames each authenticates (SecOC_DataID,
 * SecOC_Pdus); firmware/bus/fcc_secoc.h. */
#define FCC_SECOC_N_AUTH 6u
#define FCC_SECOC_MAX_PDUS 12u
typedef struct {
    fcc_msg_t auth;       /* the authenticator frame */
    uint16_t data_id;     /* SecOC data ID in the MAC input */
    uint8_t n_pdus;       /* frames authenticated, concatenated in this order */
    fcc_msg_t pdus[FCC_SECOC_MAX_PDUS];
} fcc_secoc_desc_t;
extern const fcc_secoc_desc_t fcc_secoc_table[FCC_SECOC_N_AUTH];

#endif /* FCC_BUS_MSGS_H */
