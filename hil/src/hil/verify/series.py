"""A flight's time series, by name, for the windowed expectations (hil.verify.window).

    bus.MESSAGE.signal   a DBC signal, decoded from the run's bus log: one sample per frame the
                         rig and fcc acted on (authenticated: a forged frame is no sample; a
                         secured frame at its authenticator's time), t from the flight's start
                         (its first authenticated SIM_CONTROL reset)
    cdrw.COLUMN          the CDRW's record, one sample per step (cdrw.csv): the simulator's
                         truth, the readings, fcc's estimates, bounds and fault flag
    missile.COLUMN       the missile's closed-loop record, one sample per step
                         (missile_T<period>_b<bits>.csv): truth, readings, the D/A code
    open_loop.COLUMN     the same flight open loop (missile_T<period>_open.csv)

A signal is an expression in the expectations' language (hil.verify.expr) over the series of
one time base -- one CSV, or one DBC message -- evaluated sample by sample:
``abs(cdrw.alpha_true - cdrw.azkf_alpha_hat)``,
``cdrw.azkf_alpha_lo <= cdrw.alpha_true <= cdrw.azkf_alpha_hi`` (1 inside, 0 outside).
Every name is checked when the suite is loaded (SeriesError: one line).
"""
from __future__ import annotations

import ast
import functools
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hil.bus import load as load_dbc
from hil.bus.logio import read_frames, run_log
from hil.bus.protocol import COMMAND_RESET, SIM_CONTROL_ID
from hil.bus.secoc import KeyFileError, read_key_file
from hil.io.output import read_csv
from hil.results.buslog import BusAuth, authentic_frames
from hil.runs.replay import ReplayError, recorded_key
from hil.util.errors import HilError
from hil.verify.expr import Expectation, ExpressionError, dotted, parse

#: the CDRW's per-step record, as cdrw.csv has it (hil.results.flight.cdrw_record joined with
#: fcc's outputs, '<filter>_<signal>' of the identification frames: hil.results.buslog.sid_arrays)
SID_OUTPUTS = (
    "alpha_hat", "q_hat", "order", "fault", "degraded", "alpha_lo", "alpha_hi", "q_lo", "q_hi",
    "a11", "a12", "a21", "a22", "b1", "b2", "rho", "gain_norm")
CDRW_COLUMNS = (
    "t", "alpha_true", "q_true", "X_true", "de", "alpha_meas", "q_meas", "de_meas", "alpha_ff",
    "q_ff", "fault", "rho_true", "rho_static", "a11_true", "a12_true", "a21_true", "a22_true",
    "b1_true", "b2_true", "acked", "degraded",
    *(f"{f}_{s}" for f in ("azkf", "zkf", "kf") for s in SID_OUTPUTS))
#: the missile's per-step record (hil.results.flight.missile_result), closed and open loop
MISSILE_COLUMNS = (
    "t", "q", "alpha_T", "w_g", "q_g", "n_a", "q_g_ff", "n_a_ff", "fault", "code", "u", "cmd_ok",
    "degraded", "saturated", "q_hat", "alpha_T_hat", "w_g_hat")
OPEN_LOOP_COLUMNS = (
    "t", "q", "alpha_T", "w_g", "q_g", "n_a", "code", "u")
#: each CSV source: the aircraft the case must fly, its columns, its file's pattern
CSV_SOURCES: dict[str, tuple[str, tuple[str, ...], str]] = {
    "cdrw": ("cdrw", CDRW_COLUMNS, "cdrw.csv"),
    "missile": ("missile", MISSILE_COLUMNS, "missile_T*_b*[0-9].csv"),
    "open_loop": ("missile", OPEN_LOOP_COLUMNS, "missile_T*_open.csv"),
}


class SeriesError(HilError, ValueError):
    """A signal that is not one (one line)."""


@dataclass(frozen=True)
class Series:
    """Samples x at times t (s from the flight's start), in time order."""

    t: np.ndarray
    x: np.ndarray


@dataclass(frozen=True)
class Signal:
    """A checked signal expression: its text, its tree, the names it reads and their base
    ('cdrw', 'missile', 'open_loop' or 'bus.MESSAGE')."""

    exp: Expectation
    base: str

    @property
    def text(self) -> str:
        return self.exp.text


@functools.lru_cache(maxsize=1)
def bus_signals() -> dict[str, tuple[str, ...]]:
    """Each DBC message's signals, by message name."""
    return {m.name: tuple(s.name for s in m.signals) for m in load_dbc().messages}


def _base(name: str) -> str:
    """The time base a series name belongs to (SeriesError: an unknown name)."""
    head, _, rest = name.partition(".")
    if head in CSV_SOURCES:
        if rest not in CSV_SOURCES[head][1]:
            raise SeriesError(f"unknown series {name!r} ({head}: {', '.join(CSV_SOURCES[head][1])})")
        return head
    if head == "bus":
        msg, _, sig = rest.partition(".")
        if msg not in bus_signals():
            raise SeriesError(f"unknown series {name!r}: no DBC message {msg!r}")
        if sig not in bus_signals()[msg]:
            raise SeriesError(f"unknown series {name!r} ({msg}'s signals: {', '.join(bus_signals()[msg])})")
        return f"bus.{msg}"
    raise SeriesError(f"unknown series {name!r} (bus.MESSAGE.signal, {', '.join(f'{s}.COLUMN' for s in CSV_SOURCES)})")


def signal(text: str, aircraft: Collection[str]) -> Signal:
    """A signal expression, checked: in the language, every name a series, all of one time
    base, its aircraft flown in this case (SeriesError: one line)."""
    try:
        exp = parse(text)
    except ExpressionError as e:
        raise SeriesError(str(e)) from None
    if not exp.fields:
        raise SeriesError(f"{text!r}: names no series")
    bases = {_base(n) for n in exp.fields}
    if len(bases) > 1:
        raise SeriesError(f"{text!r}: series of different time bases ({', '.join(sorted(bases))}): "
                          "one CSV or one DBC message per signal")
    (base,) = bases
    need = CSV_SOURCES[base][0] if base in CSV_SOURCES else None
    if need is not None and need not in aircraft:
        raise SeriesError(f"{text!r}: needs a {need} flight, this case flies {', '.join(aircraft)}")
    return Signal(exp, base)


# ---- evaluation, sample by sample ------------------------------------------------------------
_FUNCTIONS: dict[str, Callable[..., np.ndarray]] = {
    "abs": np.abs, "min": lambda *a: functools.reduce(np.minimum, a),
    "max": lambda *a: functools.reduce(np.maximum, a)}
_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide}
_COMPARE = {ast.Lt: np.less, ast.LtE: np.less_equal, ast.Gt: np.greater, ast.GtE: np.greater_equal,
            ast.Eq: np.equal, ast.NotEq: np.not_equal}


def evaluate(node: ast.expr, columns: Mapping[str, np.ndarray]) -> np.ndarray:
    """The expression over arrays of equal length (a comparison, and/or/not: 1.0 or 0.0; a
    division by zero: inf or nan, which no band holds)."""
    name = dotted(node)
    if name is not None:
        return np.asarray(columns[name], dtype=float)
    if isinstance(node, ast.Constant):
        assert isinstance(node.value, (int, float))   # (all the language admits)
        return np.asarray(float(node.value))
    with np.errstate(divide="ignore", invalid="ignore"):
        if isinstance(node, ast.BinOp):
            return np.asarray(_BINARY[type(node.op)](evaluate(node.left, columns), evaluate(node.right, columns)))
        if isinstance(node, ast.UnaryOp):
            v = evaluate(node.operand, columns)
            return (v == 0).astype(float) if isinstance(node.op, ast.Not) else -v
        if isinstance(node, ast.BoolOp):
            vals = [evaluate(v, columns) != 0 for v in node.values]
            op = np.logical_and if isinstance(node.op, ast.And) else np.logical_or
            return functools.reduce(op, vals).astype(float)
        if isinstance(node, ast.Compare):
            sides = [evaluate(s, columns) for s in (node.left, *node.comparators)]
            held = [_COMPARE[type(op)](a, b) for op, a, b in zip(node.ops, sides, sides[1:])]
            return functools.reduce(np.logical_and, held).astype(float)
    assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)   # all the language has
    return np.asarray(_FUNCTIONS[node.func.id](*(evaluate(a, columns) for a in node.args)))


# ---- reading a run's series --------------------------------------------------------------------
class RunSeries:
    """A run directory's series, read when first asked for (each file once)."""

    def __init__(self, run_dir: Path, key_file: Path | None = None) -> None:
        """key_file: the bus key the run used if the run directory does not keep it (a target
        with a key of its own: the qemu-m4f image's published test key)."""
        self.run_dir = run_dir
        self.key_file = key_file
        self._csv: dict[str, dict[str, np.ndarray]] = {}
        self._bus: dict[str, list[tuple[float, bytes]]] | None = None
        self.t0 = 0.0

    def of(self, sig: Signal) -> Series:
        """The signal's samples (SeriesError: the run has not got them)."""
        columns = self._columns(sig.base)
        t = columns["t"]
        x = evaluate(sig.exp.tree, columns)
        return Series(t, np.broadcast_to(x, t.shape).astype(float))

    def _columns(self, base: str) -> dict[str, np.ndarray]:
        if base in CSV_SOURCES:
            return {f"{base}.{k}": v for k, v in self._csv_of(base).items()} | {"t": self._csv_of(base)["t"]}
        return self._message(base.partition(".")[2])

    def _csv_of(self, source: str) -> dict[str, np.ndarray]:
        if source not in self._csv:
            pattern = CSV_SOURCES[source][2]
            found = sorted(p for p in self.run_dir.glob(pattern) if not p.stem.endswith("_fine"))
            if len(found) != 1:
                raise SeriesError(f"{self.run_dir}: {len(found)} files {pattern} (expected one)")
            self._csv[source] = read_csv(found[0])
        return self._csv[source]

    def _frames(self) -> dict[str, list[tuple[float, bytes]]]:
        """The authenticated frames of the bus log by message name, times from the first
        SIM_CONTROL reset (its key: the one the run kept, hil.runs.replay.recorded_key)."""
        if self._bus is None:
            log = run_log(self.run_dir)
            if log is None:
                raise SeriesError(f"{self.run_dir}: no bus log")
            auth = BusAuth(self._key())
            spec = load_dbc()
            by_name: dict[str, list[tuple[float, bytes]]] = {}
            start = None
            for f in authentic_frames(read_frames(log), auth):
                if start is None and f.frame_id == SIM_CONTROL_ID and len(f.data) >= 2 \
                        and f.data[1] >> 4 == COMMAND_RESET:
                    start = f.timestamp
                msg = spec.by_id(f.frame_id)
                if msg is not None and len(f.data) == msg.length:
                    by_name.setdefault(msg.name, []).append((f.timestamp, bytes(f.data)))
            if start is None:
                raise SeriesError(f"{log}: no authenticated flight start (SIM_CONTROL reset)")
            self.t0, self._bus = start, by_name
        return self._bus

    def _key(self) -> bytes:
        try:
            return recorded_key(self.run_dir)
        except ReplayError as e:
            if self.key_file is None:
                raise SeriesError(str(e)) from None
        try:
            return read_key_file(self.key_file)
        except (KeyFileError, OSError) as e:
            raise SeriesError(f"{self.key_file}: the run's bus key cannot be read ({e})") from None

    def _message(self, name: str) -> dict[str, np.ndarray]:
        frames = self._frames().get(name, [])
        msg = load_dbc().by_name(name)
        decoded = [msg.decode(d) for _, d in frames]
        cols = {f"bus.{name}.{s}": np.array([float(v[s]) for v in decoded]) for s in bus_signals()[name]}
        return cols | {"t": np.array([t - self.t0 for t, _ in frames])}
