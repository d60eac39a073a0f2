"""The boot configuration record of the Cortex-M4F image (firmware/app/fcc_bootcfg.h).

The host fcc takes its configuration on the command line; the image has none and
reads these 64 bytes from its configuration sector instead (QEMU's generic loader
puts them there: see firmware/port/mps2_an386/README.md).  encode() checks nothing that the
image does not check again: the image refuses a bad record with exit status 2.
"""
from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass
from pathlib import Path

ADDRESS = 0x000FFF00
SIZE = 64
VERSION = 1
MODES = {"lockstep": 0, "realtime": 1}
APPS = {"cdrw": 1, "missile": 2}
DETECTORS = {"zonotope": 0, "oracle": 1, "off": 2}
POLICIES = {"order": 0, "skip": 1}
_LAYOUT = struct.Struct("<4sHHBBHfdBBBBddd8s")


@dataclass(frozen=True)
class BootConfig:
    """The host fcc's options of the same names (firmware/port/linux/fcc_cli.c defaults)."""

    mode: str = "lockstep"
    apps: tuple[str, ...] = ("cdrw", "missile")
    stale_limit: int = 1
    status_rate: float = 10.0
    lqg_period: float = 0.05
    lqg_bits: int = 8
    detector: str = "zonotope"
    fault_policy: str = "order"
    gyro_var: float = 0.8
    accel_var: float = 0.8
    lqg_delay: float = 0.0      # s, 0 <= d < lqg_period (--lqg-delay D; bytes 44-51, zero before)

    def encode(self) -> bytes:
        """The 64-byte record, CRC-32 included."""
        mask = 0
        for a in self.apps:
            mask |= APPS[a]
        body = _LAYOUT.pack(b"FCCB", VERSION, SIZE, MODES[self.mode], mask, self.stale_limit,
                            self.status_rate, self.lqg_period, self.lqg_bits,
                            DETECTORS[self.detector], POLICIES[self.fault_policy], 0,
                            self.gyro_var, self.accel_var, self.lqg_delay, bytes(8))
        return body + struct.pack("<I", zlib.crc32(body))

    def write(self, path: Path) -> Path:
        path.write_bytes(self.encode())
        return path


assert _LAYOUT.size == SIZE - 4
