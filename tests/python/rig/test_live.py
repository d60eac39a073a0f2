"""`hil live`'s view of the bus (hil.rig.live.BusView) on frames encoded here: the measured
values, each filter's estimate and fault flag, fcc's health flags and E2E counters, active
simulator faults, rates."""
from __future__ import annotations

from hil.bus import SIM_NODES, FrameCodec, load
from hil.rig.live import BusView
from hil.sim.frame_faults import KIND_CODES

SPEC = load()


def test_view_shows_values_flags_and_counters():
    sim = FrameCodec(SPEC, SIM_NODES)
    fcc = FrameCodec(SPEC, "FCC")
    view = BusView(SPEC)
    t = 100.0
    for k in range(50):
        view.add(*sim.encode("CDRW_AOA", {"alpha": 0.1234, "step": k}), t + 0.02 * k)
    view.add(*sim.encode("CDRW_ELEVATOR", {"delta_e": -0.05, "step": 49}), t + 0.98)
    view.add(*fcc.encode("SID_AZKF_STATE", {"alpha_hat": 0.1201, "q_hat": -0.05, "order": 1000,
                                            "fault": 1, "degraded": 0, "step": 49}), t + 1.0)
    view.add(*fcc.encode("FCC_STATUS", {"mode": 1, "op_mode": 1, "cdrw_degraded": 0, "msl_degraded": 0,
                                        "sensor_stale": 1, "e2e_fault": 1, "overrun": 0,
                                        "config_rejected": 0, "overruns": 2, "cdrw_steps": 50,
                                        "msl_steps": 0, "worst_step_us": 40}), t + 1.0)
    view.add(*fcc.encode("FCC_E2E_COUNTS", {"ok": 147, "repeated": 1, "ok_some_lost": 2,
                                            "wrong_sequence": 3}), t + 1.0)
    view.add(*sim.encode("SIM_EVENT", {"active": 1, "oracle_fault": 1, "fault_id": 0, "kind": KIND_CODES["spike"],
                                       "target_id": 0x050, "step": 50}), t + 1.0)
    text = "\n".join(view.lines(t + 1.0))
    assert "alpha +0.1234 rad" in text and "elevator -0.0500 rad" in text and "(50 Hz)" in text
    assert "AZKF  alpha_hat +0.1201" in text and "order 1000  fault 1" in text
    assert "flags: sensor_stale e2e_fault" in text and "overruns 2" in text
    assert "ok 147  repeated 1  ok_some_lost 2  wrong_sequence 3" in text
    assert "active faults: #0 spike on 0x050" in text
    view.add(*sim.encode("SIM_EVENT", {"active": 0, "oracle_fault": 0, "fault_id": 0, "kind": KIND_CODES["spike"],
                                       "target_id": 0x050, "step": 55}), t + 1.1)
    assert "active faults: none" in "\n".join(view.lines(t + 1.1))
