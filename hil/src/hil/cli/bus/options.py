"""`hil bus`'s command line (hil.cli.parser adds it): its subcommands and their options."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from hil.cli.argtypes import bitrate, nonnegative


def add_bus(sub: argparse._SubParsersAction[Any], parser_class: type[argparse.ArgumentParser]) -> None:
    """`hil bus COMMAND`: the bus's own tools, one module each in hil.cli.bus."""
    b = sub.add_parser("bus", help="the bus's timing from the DBC: `hil bus wcrt`")
    bsub = b.add_subparsers(dest="bus_command", required=True, parser_class=parser_class, metavar="COMMAND")
    w = bsub.add_parser("wcrt", help="every cyclic frame's worst-case response time (Davis et al. "
                        "2007; a FIFO-queued node's frames by hil.bus.wcrt's derivation) and the bus "
                        "utilisation, from the DBC",
                        epilog="exit status: 0 every frame meets its deadline; 1 a frame misses it "
                        "or has no bound; 2 bad command line, DBC or scenario")
    w.add_argument("--bitrate", type=bitrate, metavar="BIT/S",
                   help="the bus's bit rate, e.g. 125k, 250k, 500k, 1M or 500000 (default: the "
                        "DBC's Baudrate, else 500000)")
    w.add_argument("--scenario", type=Path, metavar="FILE",
                   help="take the periods of a scenario's aircraft from it: the missile's frames "
                        "at its [lqg] period, the CDRW's at its [plant] dt")
    w.add_argument("--jitter", type=nonnegative, default=0.0, metavar="S",
                   help="queuing jitter of every frame, in s (default 0)")
    w.add_argument("--fifo", metavar="NODE",
                   help="the DBC node whose frames wait in one FIFO (default: the rig's, fcc, "
                        "a SocketCAN node: FCC); `none`: every node priority-queued")
    w.add_argument("--json", action="store_true", help="print the result as one JSON object")
    w.add_argument("--dbc", type=Path, metavar="PATH",
                   help="the DBC (default $FCC_HIL_DBC, else the one shipped with hil)")
