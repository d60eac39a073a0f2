"""hil.bus.wcrt's FIFO bound against what fcc's FIFO did: the default flights in lockstep over
the wire-time bus (hil.rig.lockstep_wire, deterministic), at 250k, 500k and 1M.  Every frame
of fcc's the model carried is judged against its FIFO bound and stays within it; fcc's
heartbeat (0x700-0x70F, wall-paced) is not on the model (docs/bus-timing.md), so it is not
measured here."""
from __future__ import annotations

from pathlib import Path

import pytest
from hil.results.busstats import WITHIN
from hil.scenario.file import load_default_scenario
from rig_helpers import fly

pytestmark = pytest.mark.vcan

#: fcc's frames each default flight sends a step (its answer and the lockstep ACK)
FCC_FRAMES = {"missile": ("FCC_ACK", "MSL_ELEV_CMD", "MSL_STATE_EST", "MSL_ELEV_CMD_AUTH"),
              "cdrw": ("FCC_ACK", "SID_KF_STATE", "SID_OUT_AUTH")}


@pytest.mark.parametrize("bitrate", [250_000, 500_000, 1_000_000])
@pytest.mark.parametrize("aircraft", ["missile", "cdrw"])
def test_fccs_fifo_frames_stay_within_their_fifo_bound(aircraft: str, bitrate: int, tmp_path: Path) -> None:
    o = fly(tmp_path, load_default_scenario(aircraft), bus="wire", bitrate=bitrate)
    frames = o.summary["bus"]["frames"]
    fifo = {n: f for n, f in frames.items() if f["queue"] == "fifo"}
    assert set(FCC_FRAMES[aircraft]) <= set(fifo)
    for name, f in fifo.items():
        assert f["wcrt_s"] is not None and f["verdict"] == WITHIN, (name, f)
        assert 0 < f["max_s"] <= f["wcrt_s"], (name, f)
    if aircraft == "cdrw":   # the FIFO shows: the ACK waits behind the step's 13 outputs
        assert fifo["FCC_ACK"]["p50_s"] > 10 * (44 + 64) / bitrate
