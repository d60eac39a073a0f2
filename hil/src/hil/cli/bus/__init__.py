"""`hil bus COMMAND`: the bus's own tools, one module per command (as hil.cli has one per
subcommand); run(args) imports only the chosen one."""
from __future__ import annotations

import argparse
import importlib


def run(args: argparse.Namespace) -> int:
    return int(importlib.import_module(f"hil.cli.bus.{args.bus_command}").run(args))
