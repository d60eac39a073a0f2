"""`hil-vcan CMD...`: run CMD where a virtual CAN interface vcan0 exists, from an installed hil.

The same launcher as the clone's scripts/with-vcan (the script ships in the package, built from
that file: hil.io.paths.with_vcan), with its options (`hil-vcan --help`).  Where the host
kernel has no vcan, an installed hil keeps the User-Mode Linux kernel in $WITH_VCAN_UML_DIR
(default ~/.cache/hil/uml) and provisions it there on first use, as scripts/setup does for the
clone (scripts/lib/uml.sh: Debian's user-mode-linux >= 7; needs apt-get and patchelf).
Exit status: the command's; 125 the kernel could not be provisioned or booted; 2 bad options.

Room 14 (cli): imports hil.io only.
"""
from __future__ import annotations

import os
import subprocess
import sys
from typing import NoReturn

from hil.io import paths

#: provisions the kernel unless the host has vcan or it is there already (scripts/setup's rule)
_PROVISION = r'''
source "$1"
prog=hil-vcan dir=$(uml_dir)
[ -e /sys/class/net/vcan0 ] || modprobe -q vcan 2>/dev/null || uml_ready "$dir" && exit 0
echo "hil-vcan: no vcan in this kernel: installing Debian's user-mode-linux >= 7 into $dir (once)" >&2
uml_provision "$dir"
'''


def _provisioned() -> bool:
    """The packaged launcher's kernel is there (or not needed); False: one line already said why."""
    env = {**os.environ, "WITH_VCAN_UML_DIR": str(paths.uml_dir())}
    script = paths.DATA / "lib" / "uml.sh"
    return subprocess.run(["bash", "-c", _PROVISION, "hil-vcan", str(script)], env=env).returncode == 0


def entry() -> NoReturn:
    argv = [*paths.with_vcan(), *sys.argv[1:]]
    asks_help = any(a in ("-h", "--help") for a in sys.argv[1:2])
    if paths.source_tree() is None and not asks_help and not _provisioned():
        sys.exit(125)
    os.execvp(argv[0], argv)
