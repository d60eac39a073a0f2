"""`hil bus wcrt`: every cyclic frame's worst-case response time (hil.bus.wcrt, Davis et al.
2007; the FIFO-queued node's frames, fcc's unless --fifo says otherwise, by hil.bus.wcrt's own
derivation) and the bus utilisation, from the DBC or a scenario's rates.

Exit status: 0 every frame meets its deadline; 1 (EXIT_FAILED) a frame misses it or has no
bound, the table printed first and one line on stderr; 2 a bad command line, DBC or scenario.
"""
from __future__ import annotations

import argparse
import json
import sys
from fractions import Fraction
from pathlib import Path

from hil.bus import dbc
from hil.bus.wcrt import (Frame, Response, analyse, application_periods, cyclic_frames, seconds,
                          utilisation, with_jitter, with_periods)
from hil.cli.usage import EXIT_FAILED, PROG, UsageError
from hil.rig.wirebus import FIFO_SENDERS
from hil.scenario.file import find_scenario, load_scenario
from hil.scenario.plant_options import CdrwPlantOptions

#: the bit rate of a DBC without a Baudrate attribute
DEFAULT_BITRATE = 500_000


def run(args: argparse.Namespace) -> int:
    spec = _load(dbc.default_path())
    bitrate, source = _bitrate(args.bitrate, spec)
    frames = with_jitter(cyclic_frames(spec), seconds(args.jitter))
    if args.scenario is not None:
        frames = with_periods(frames, _scenario_periods(args.scenario, frames))
    if not frames:
        raise UsageError(f"{spec.path}: no cyclic frame (GenMsgCycleTime) to analyse")
    fifo = _fifo(args.fifo, frames)
    responses = analyse(frames, bitrate, fifo)
    u = float(utilisation(frames, bitrate))
    if args.json:
        print(json.dumps(_document(bitrate, u, responses)))
    else:
        print(_table(spec.path, bitrate, source, args.jitter, u, responses, fifo))
    failed = [r for r in responses if not r.deadline_met]
    if failed:
        unbounded = sum(r.wcrt_s is None for r in failed)
        print(f"{PROG}: {len(failed)} of {len(responses)} frames miss their deadline at {bitrate} "
              f"bit/s ({unbounded} with no bound), the first {failed[0].frame.name}", file=sys.stderr)
        return EXIT_FAILED
    return 0


def _load(path: Path) -> dbc.BusSpec:
    import cantools  # its parse error's class; the send types need its parse in any case
    try:
        return dbc.load(path)
    except (OSError, ValueError, cantools.database.Error) as e:
        first = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise UsageError(f"{path}: not a DBC this rig reads ({first})") from None


def _fifo(given: str | None, frames: list[Frame]) -> tuple[str, ...]:
    """The FIFO-queued senders: --fifo (`none`: none), else the rig's."""
    if given is None:
        return FIFO_SENDERS
    if given.lower() == "none":
        return ()
    senders = {f.sender for f in frames}
    if given not in senders:
        raise UsageError(f"--fifo {given}: not a sender of a cyclic frame ({', '.join(sorted(senders))})")
    return (given,)


def _bitrate(given: int | None, spec: dbc.BusSpec) -> tuple[int, str]:
    """The bit rate and where it comes from: --bitrate, else the DBC's Baudrate, else 500000."""
    if given is not None:
        return given, "--bitrate"
    attributes = spec.db.dbc.attributes if spec.db.dbc else {}
    if "Baudrate" in attributes:
        return int(attributes["Baudrate"].value), "the DBC's Baudrate"
    return DEFAULT_BITRATE, "the DBC has no Baudrate: 500000"


def _scenario_periods(path: Path, frames: list[Frame]) -> dict[str, Fraction]:
    """The periods of the scenario's aircraft: the missile's [lqg] period, the CDRW's [plant] dt."""
    sc = load_scenario(find_scenario(str(path)))
    if sc.lqg is not None:
        period = sc.lqg.period
    else:
        assert isinstance(sc.plant, CdrwPlantOptions)
        period = sc.plant.dt
    return application_periods(frames, sc.aircraft, seconds(period))


def _document(bitrate: int, u: float, responses: list[Response]) -> dict[str, object]:
    return {"bitrate": bitrate, "utilisation": u, "frames": [
        {"id": r.frame.frame_id, "name": r.frame.name, "period_s": float(r.frame.period_s),
         "c_s": float(r.c_s), "wcrt_s": None if r.wcrt_s is None else float(r.wcrt_s),
         "deadline_met": r.deadline_met, "queue": r.queue} for r in responses]}


def _verdict(r: Response) -> str:
    return "met" if r.deadline_met else "MISSED"


def _table(path: Path, bitrate: int, source: str, jitter: float, u: float,
           responses: list[Response], fifo: tuple[str, ...]) -> str:
    queued = (f"{', '.join(fifo)} FIFO-queued (hil.bus.wcrt's derivation), the others priority-queued"
              if fifo else "every node priority-queued")
    lines = [f"{len(responses)} cyclic frames of {path.name} at {bitrate} bit/s ({source}), "
             f"queuing jitter {jitter:g} s",
             f"C: the worst-case frame time; WCRT: Davis et al. 2007, {queued}",
             f"{'id':>6}  {'name':<20} {'sender':<18} {'queue':<5} {'period ms':>9} {'C us':>7} "
             f"{'WCRT ms':>9}  deadline"]
    for r in responses:
        f = r.frame
        wcrt = "unbounded" if r.wcrt_s is None else f"{float(r.wcrt_s) * 1e3:.3f}"
        ident = f"0x{f.frame_id:08x}" if f.extended else f"0x{f.frame_id:03x}"
        lines.append(f"{ident:>6}  {f.name:<20} {f.sender:<18} {r.queue:<5} {float(f.period_s) * 1e3:9g} "
                     f"{float(r.c_s) * 1e6:7.1f} {wcrt:>9}  {_verdict(r)}")
    met = sum(r.deadline_met for r in responses)
    in_fifo = [r for r in responses if r.queue == "fifo"]
    of_fifo = (f" ({sum(r.deadline_met for r in in_fifo)} of the FIFO's {len(in_fifo)})" if in_fifo else "")
    lines.append(f"bus utilisation {u:.3f} (sum of C/T); {met} of {len(responses)} frames meet "
                 f"their deadline (= period){of_fifo}")
    return "\n".join(lines)
