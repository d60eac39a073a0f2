"""A CAN interface that cannot be opened is one line saying why and what to do (hil.bus.canif),
from `hil run`, `hil live` and scripts/diag, exit status 1 (diag: 2): on the host, whose kernel
has no CAN, and in the guest with an interface that does not exist or is down."""
from __future__ import annotations

import errno
import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from hil.bus.canif import check_up, open_error

REPO = Path(__file__).resolve().parents[3]
HIL = str(Path(sys.executable).with_name("hil"))


def _host_has_can() -> bool:
    try:
        socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW).close()
    except OSError:
        return False
    return True


def _one_line(stderr: str, prog: str) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, stderr
    assert lines[0].startswith(f"{prog}: cannot open CAN interface "), stderr
    return lines[0]


@pytest.mark.parametrize("code, words", [
    (errno.EAFNOSUPPORT, ["the kernel has no CAN", "scripts/with-vcan CMD", "modprobe vcan",
                          "ip link add dev vcan0 type vcan"]),
    (errno.ENODEV, ["there is no interface 'vcan0'", "ip link add dev vcan0 type vcan",
                    "ip link set vcan0 up", "scripts/with-vcan CMD"]),
    (errno.ENETDOWN, ["the interface is down", "sudo ip link set vcan0 up"]),
])
def test_the_cause_and_the_remedy(code: int, words: list[str]) -> None:
    # python-can wraps the OSError: the errno is looked for along the chain
    try:
        try:
            raise OSError(code, os.strerror(code))
        except OSError as inner:
            raise RuntimeError("Could not access SocketCAN device") from inner
    except RuntimeError as wrapped:
        line = open_error("vcan0", wrapped)
    assert line.startswith("cannot open CAN interface 'vcan0': ")
    assert "\n" not in line
    for w in words:
        assert w in line


def test_another_error_keeps_its_own_words() -> None:
    assert open_error("can0", OSError(errno.EPERM, "Operation not permitted")) == \
        "cannot open CAN interface 'can0': [Errno 1] Operation not permitted"


def test_an_up_interface_and_an_unknown_name_pass_check_up() -> None:
    check_up("lo")                 # up
    check_up("no-such-iface-x")    # the bind will say ENODEV


@pytest.mark.skipif(_host_has_can(), reason="this kernel has CAN: the guest's tests cover it")
@pytest.mark.parametrize("argv, prog, status", [
    ([HIL, "run", "cdrw", "--no-plots", "--quiet"], "hil", 1),
    ([HIL, "live", "--seconds", "1"], "hil", 1),
    ([str(REPO / "scripts/diag"), "--iface", "vcan0", "--seconds", "1"], "diag", 2),
])
def test_on_a_kernel_without_can(tmp_path: Path, argv: list[str], prog: str, status: int) -> None:
    if "run" in argv:
        argv = [*argv, "--out", str(tmp_path / "o")]
    r = subprocess.run(argv, capture_output=True, text=True, timeout=120, cwd=REPO)
    assert r.returncode == status
    line = _one_line(r.stderr, prog)
    assert "the kernel has no CAN" in line and "scripts/with-vcan CMD" in line
    assert not (tmp_path / "o").exists()


@pytest.mark.vcan
@pytest.mark.parametrize("argv, prog, status", [
    ([HIL, "run", "cdrw", "--no-plots", "--quiet", "--channel", "IFACE"], "hil", 1),
    ([HIL, "live", "--seconds", "1", "--iface", "IFACE"], "hil", 1),
    ([str(REPO / "scripts/diag"), "--iface", "IFACE", "--seconds", "1"], "diag", 2),
])
def test_in_the_guest_a_missing_or_down_interface(tmp_path: Path, argv: list[str], prog: str,
                                                   status: int) -> None:
    down = "hiltdown0"
    subprocess.run(["ip", "link", "add", "dev", down, "type", "vcan"], check=True)
    try:
        for iface, words in (("vcan9", "ip link add dev vcan9 type vcan"),
                             (down, f"the interface is down; bring it up: sudo ip link set {down} up")):
            cmd = [a.replace("IFACE", iface) for a in argv]
            if "run" in cmd:
                cmd += ["--out", str(tmp_path / iface)]
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=REPO)
            assert r.returncode == status, r.stderr
            assert words in _one_line(r.stderr, prog)
            assert not (tmp_path / iface).exists()
    finally:
        subprocess.run(["ip", "link", "del", "dev", down], check=True)


def test_an_installed_package_names_its_own_launcher(monkeypatch: pytest.MonkeyPatch) -> None:
    # without the clone (an installed package), scripts/with-vcan does not exist: hil-vcan does
    from hil.io import paths
    monkeypatch.setattr(paths, "source_tree", lambda: None)
    line = open_error("vcan0", OSError(errno.EAFNOSUPPORT, os.strerror(errno.EAFNOSUPPORT)))
    assert "hil-vcan CMD" in line and "scripts/with-vcan" not in line
    line = open_error("vcan0", OSError(errno.ENODEV, os.strerror(errno.ENODEV)))
    assert "hil-vcan CMD" in line and "scripts/with-vcan" not in line
    # and so do the CLI's messages that name it (hil.cli.many: --workers with an ASC log)
    from hil.cli.many import parallel_options
    from hil.cli.parser import build
    from hil.cli.usage import UsageError
    args = build().parse_args(["campaign", "cdrw", "--workers", "2", "--log-format", "asc"])
    with pytest.raises(UsageError, match=r"fly the sequential form for one: hil-vcan hil campaign") as e:
        parallel_options(args)
    assert "scripts/with-vcan" not in str(e.value)
    monkeypatch.setenv("WITH_VCAN_UML", "1")                   # inside the launcher's guest
    args = build().parse_args(["campaign", "cdrw", "--workers", "2"])
    with pytest.raises(UsageError, match=r"cannot inside hil-vcan's guest: run the command without hil-vcan"):
        parallel_options(args)
