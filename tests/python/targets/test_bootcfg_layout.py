"""The Python writer of the boot configuration record (hil.targets.bootcfg) puts every field where
the firmware reads it: the offsets and sizes of firmware/app/fcc_bootcfg.h (FCC_BOOTCFG_*_OFF,
*_LEN), the one definition of the layout, parsed from the header here."""
from __future__ import annotations

import re
import struct
import zlib
from pathlib import Path

from hil.targets.bootcfg import SIZE, VERSION, BootConfig

HEADER = Path("firmware/app/fcc_bootcfg.h")
#: each field the writer fills: its struct code (little-endian) and BootConfig's value
FIELD_CODES = {"MAGIC": "4s", "VERSION": "H", "LENGTH": "H", "MODE": "B", "APPS": "B",
               "STALE_LIMIT": "H", "STATUS_RATE": "f", "LQG_PERIOD": "d", "LQG_BITS": "B",
               "DETECTOR": "B", "FAULT_POLICY": "B", "PAD": "B", "GYRO_VAR": "d",
               "ACCEL_VAR": "d", "LQG_DELAY": "d", "RESERVED": "8s", "CRC": "I"}


def layout(repo: Path) -> dict[str, tuple[int, int]]:
    text = (repo / HEADER).read_text()
    num = {m[1]: int(m[2]) for m in re.finditer(r"#define FCC_BOOTCFG_(\w+) (\d+)u\b", text)}
    return {name[:-4]: (num[name], num[name[:-4] + "_LEN"])
            for name in num if name.endswith("_OFF")}


def test_layout_of_the_header_covers_the_record(repo: Path) -> None:
    fields = sorted(layout(repo).items(), key=lambda kv: kv[1][0])
    assert [name for name, _ in fields] == list(FIELD_CODES)
    end = 0
    for name, (off, size) in fields:
        assert off == end, name
        assert struct.calcsize("<" + FIELD_CODES[name]) == size, name
        end = off + size
    assert end == SIZE


def test_writer_puts_each_field_at_the_header_offset(repo: Path) -> None:
    cfg = BootConfig(mode="realtime", apps=("missile",), stale_limit=517, status_rate=12.5,
                     lqg_period=0.125, lqg_bits=13, detector="off", fault_policy="skip",
                     gyro_var=0.375, accel_var=3.25, lqg_delay=0.0078125)
    rec = cfg.encode()
    assert len(rec) == SIZE
    expected = {"MAGIC": b"FCCB", "VERSION": VERSION, "LENGTH": SIZE, "MODE": 1, "APPS": 2,
                "STALE_LIMIT": 517, "STATUS_RATE": 12.5, "LQG_PERIOD": 0.125, "LQG_BITS": 13,
                "DETECTOR": 2, "FAULT_POLICY": 1, "PAD": 0, "GYRO_VAR": 0.375,
                "ACCEL_VAR": 3.25, "LQG_DELAY": 0.0078125, "RESERVED": bytes(8)}
    fields = layout(repo)
    for name, value in expected.items():
        off, _ = fields[name]
        assert struct.unpack_from("<" + FIELD_CODES[name], rec, off)[0] == value, name
    crc_off, _ = fields["CRC"]
    assert struct.unpack_from("<I", rec, crc_off)[0] == zlib.crc32(rec[:crc_off])
