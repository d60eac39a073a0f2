"""What a command leaves: the Outcome (summary and tables), the run directory's common files
(faults.log, the missile's CSVs), the finished bus log and the figures.

run directory
    summary.json      deterministic results (the seed decides them; hil.results.report)
    run_info.json     wall-clock times, fcc command line, step execution times
    bus.log           the whole bus, candump log format (candump -L / -l)
    fcc.log           fcc's stdout/stderr (event lines, final counter block); qemu-m4f: the
                      image's log UART; external: the command line the device should run
    qemu.log, bootcfg.bin   qemu-m4f: QEMU's own messages, the image's boot configuration
    faults.log        every injected fault's start and end, with its time
    cdrw.csv, missile_T0.100_b8.csv, missile_T0.100_b8_fine.csv, campaign.csv ...
    *.png             the papers' figures (hil.plots)
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hil.apps.registry import application
from hil.bus import load
from hil.io.output import write_csv
from hil.io.rundir import atomic_write_text
from hil.results.flight import MissileResult
from hil.results.report import summary_tables
from hil.results.verdict import lines as verdict_lines
from hil.rig.config import RigConfig
from hil.rig.simtime import finish_bus_log
from hil.scenario.file import Scenario


@dataclass
class Outcome:
    """What a command produced: the summary (as written) and the text tables to print."""

    out_dir: Path
    summary: dict[str, Any]
    tables: list[str] = field(default_factory=list)


def write_missile(out: Path, res: MissileResult) -> None:
    write_csv(out / f"missile_{res.tag}.csv", res.series)
    write_csv(out / f"missile_{res.tag}_fine.csv", res.fine)


def write_fault_log(out: Path, flights: Sequence[tuple[str, Sequence[dict[str, Any]]]]) -> None:
    """faults.log: every fault start and end, with its time, one line each."""
    lines = []
    for label, events in flights:
        for ev in events:
            lines.append(f"{label}t={ev['t']:8.3f} s  {ev['action']:5s}  [{ev['level']}] {ev['spec']}")
    atomic_write_text(out / "faults.log", "\n".join(lines) + ("\n" if lines else ""))


def step_periods(scenarios: Sequence[Scenario]) -> dict[int, float]:
    """Each application's step period (s) in these scenarios, by SIM_TICK.app."""
    return {application(sc.aircraft).code: application(sc.aircraft).step_period(sc) for sc in scenarios}


def finish(cfg: RigConfig, out: Path, summary: dict[str, Any], periods: dict[int, float] | None) -> Outcome:
    """The bus log finished and the report."""
    if periods is not None:   # None: no bus log in `out` (flights on several rigs, hil.parallel)
        finish_bus_log(out, cfg.mode, periods, cfg.log_format, load().baudrate)
    return report_outcome(cfg, out, summary)


def report_outcome(cfg: RigConfig, out: Path, summary: dict[str, Any]) -> Outcome:
    """The summary's verdict line and tables and, unless off, the figures of the run directory."""
    tables = [*verdict_lines(summary), *summary_tables(summary)]
    if cfg.plots:
        from hil.plots import plot_run_dir  # (its multiprocessing: the figures only)
        names = [p.name for p in plot_run_dir(out)]
        if names:
            tables.append(f"plots: {', '.join(names)}")
    return Outcome(out, summary, tables)
