"""A realtime flood's frames (cangen's, not the simulator's) are counted from the bus log that
the evaluation has read once (hil.runs.evaluate.count_babbled), as read_log's frames count them."""
from __future__ import annotations

from collections import Counter
from types import SimpleNamespace

from hil.bus.candump import read_log
from hil.bus.logcolumns import read_blocks
from hil.runs.evaluate import count_babbled
from hil.scenario.faults import Flood


def _driver(*floods: Flood) -> SimpleNamespace:
    """What count_babbled reads of a driver: its injector's faults and counters."""
    return SimpleNamespace(injector=SimpleNamespace(faults=list(floods), counts=Counter()))


def test_flood_frames_are_counted_per_driver_as_read_log_counts_them(tmp_path):
    lines = ["(1.000000) vcan0 7FE#FFFFFFFFFFFFFFFF", "(1.000100) vcan0 123#0102",
             "(1.000200) vcan0 7FE#FFFFFFFFFFFFFFFF", "(1.000300) vcan0 000007FE#FF",
             "(1.000400) vcan0 000#FF", "", "(1.000500) vcan0 20000080#0000000000000000",
             "(1.000600) vcan0 7fe#ff"] + ["(1.001000) vcan0 000#FFFFFFFF"] * 5
    log = tmp_path / "bus.log"
    log.write_text("\n".join(lines) + "\n")
    a = _driver(Flood(start=0.0, duration=1.0, can_id=0x7FE))
    b = _driver(Flood(start=0.0, duration=1.0, can_id=0x000))
    quiet = _driver()
    count_babbled(list(read_blocks(log)), [a, b, quiet])
    by_id = Counter(f.frame_id for f in read_log(log))
    assert a.injector.counts == {"flood": by_id[0x7FE], "sent": by_id[0x7FE]} == {"flood": 4, "sent": 4}
    assert b.injector.counts == {"flood": by_id[0x000], "sent": by_id[0x000]} == {"flood": 6, "sent": 6}
    assert quiet.injector.counts == {"flood": 0, "sent": 0}
