"""run_info.json's fcc_command names only files that outlive the run: the session's own key
(a temporary file) as the copy kept in the run directory, the staging directory's files
relative to the run directory (it is renamed when the run is done); a user's --key-file as given."""
from __future__ import annotations

from pathlib import Path

from hil.rig.config import RigConfig
from hil.rig.flight import lasting_command


def test_temporary_and_staged_paths_are_named_as_they_outlive_the_run(tmp_path: Path) -> None:
    stage = tmp_path / ".run.partial-host-1-0123456789abcdef"
    cfg = RigConfig(out_dir=stage)
    cmd = ["qemu-system-arm", "-device", f"loader,file={stage}/bootcfg.bin,addr=0x000fff00",
           "-D", f"{stage}/qemu.log", "--key-file", "/tmp/hil-key-x/session.key", "--trip", "7"]
    assert lasting_command(cmd, stage, cfg) == ("qemu-system-arm -device loader,file=bootcfg.bin,addr=0x000fff00 "
                                                "-D qemu.log --key-file session.key --trip 7")
    mine = RigConfig(out_dir=stage, key_file=Path("keys/bus.key"))
    assert lasting_command(["fcc", "--key-file", "keys/bus.key"], stage, mine) == "fcc --key-file keys/bus.key"
