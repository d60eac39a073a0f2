"""The rig's bus layer on python-can + cantools, one specification with firmware/bus.

* hil.bus.dbc    -- the DBC as both codecs see it (raw limits, E2E data IDs)
* hil.bus.e2e    -- CRC-8 SAE J1850, alive counter, receiver classification
* hil.bus.codec  -- FrameCodec: encode/decode with E2E and range checks, counters
* hil.bus.node   -- BusNode: a FrameCodec on a python-can bus with one Notifier
* hil.bus.busload -- frame lengths (exact bit stuffing) and bus load
* hil.bus.wcrt   -- worst-case response times of the cyclic frames (Davis et al. 2007)
* hil.bus.candump -- candump -L log reading/writing
* hil.bus.diag   -- scripts/diag: per-message rate, jitter, E2E classes, bus load
* hil.bus.secoc  -- SecOC: AES-128-CMAC authenticators, freshness, the bus key
* hil.bus.protocol -- the rig protocol's numbers from the DBC's value tables (SIM_CONTROL
                    commands, applications, modes)
* hil.bus.logio, rawcan, cgen, digest -- ASC/BLF logs, raw sockets, the firmware's C and the
                    spec digest generated from the DBC (dbc/generate)

Room 3: may import hil.util (rounding as the firmware rounds); python-can, cantools and
cryptography are imported where they are used, not at start-up.
"""
from __future__ import annotations

from hil.bus.codec import Counters, Decoded, EncodeError, FrameCodec, Verdict
from hil.bus.dbc import FCC_NODE, PACKAGED_DBC, BusSpec, MessageSpec, SignalSpec, load
from hil.bus.e2e import E2EReceiver, E2ESender, E2EStatus, crc8_j1850, protect

#: The simulator process speaks for the simulator core and every sensor node: every node of the
#: packaged DBC's but fcc (BU_, in its order; the packaged one: a DBC named by $FCC_HIL_DBC is
#: checked when a command loads it, one line if broken, not when hil is imported)
SIM_NODES = tuple(n for n in load(PACKAGED_DBC).nodes if n != FCC_NODE)

__all__ = [
    "BusSpec", "Counters", "Decoded", "E2EReceiver", "E2ESender", "E2EStatus", "EncodeError",
    "FCC_NODE", "FrameCodec", "MessageSpec", "SIM_NODES", "SignalSpec", "Verdict",
    "crc8_j1850", "load", "protect",
]
