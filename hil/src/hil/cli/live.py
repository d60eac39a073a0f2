"""`hil live`: a dashboard of the bus while a run flies; with --plot, a chart of chosen
signals in the browser as well (hil.rig.liveplot); with --log, that chart of a recorded bus
log; with --follow OUT, of the log a run flying into OUT records (across scripts/with-vcan's
guest boundary: the chart on the host, the run in the guest)."""
from __future__ import annotations

import argparse
import logging
import threading
import time

from hil.bus import load
from hil.bus.canif import check_up, open_error
from hil.cli.usage import UsageError
from hil.rig import live, liveplot
from hil.rig.link import LinkError


def run(args: argparse.Namespace) -> int:
    logging.getLogger("can").addHandler(logging.NullHandler())  # its errors: our one line below
    spec = load()
    chart = None
    if args.plot or args.log is not None or args.follow is not None:
        try:
            chart = liveplot.Chart(spec, [s for s in args.signals.split(",") if s.strip()])
        except ValueError as e:
            raise UsageError(str(e)) from None
        if args.log is not None:
            from hil.bus.logio import read_frames
            chart.load(read_frames(args.log))
        try:
            server, url = liveplot.serve(chart, args.port)
        except OSError as e:
            raise UsageError(f"--port {args.port}: {e.strerror}") from None
        if args.log is not None:   # the log's chart, served until the time is up
            _served(url, args.seconds)
            threading.Event().wait(args.seconds)
            server.shutdown()
            return 0
        if args.follow is not None:   # a run's log as its recorder writes it
            _served(url, args.seconds)
            out = args.follow
            liveplot.follow(lambda: liveplot.growing_log(out), chart, time.monotonic() + args.seconds)
            server.shutdown()
            return 0
    try:
        check_up(args.iface)
        live.run(args.iface, args.seconds, spec, force_rich=args.rich,
                 also=chart.add if chart is not None else None,
                 ready=(lambda: _served(url, args.seconds)) if chart is not None else None)
    except OSError as e:
        raise LinkError(open_error(args.iface, e)) from None
    return 0


def _served(url: str, seconds: float) -> None:
    """The first line: where the chart is (once it has its data source: a reader may load it)."""
    print(f"live chart: {url} (for {seconds:g} s)", flush=True)
