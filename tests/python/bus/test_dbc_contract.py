"""The DBC as the one source of who sends and who consumes each frame, and of SIM_EVENT.kind's
codes -- checked against the code that must follow it, so that the two changes that once
failed in silence fail here:

- a frame added to the DBC for fcc that nothing produces or nothing takes (it was dropped by a
  ``default: break;``): every frame sent to FCC has a producer in the simulator and a consumer
  in fcc (an input slot of its application, a handler of the node's, or an authenticator; the
  C side's own check is tests/c/test_app_node.c, test_every_frame_sent_to_fcc_is_taken);
- a frame fcc sends that nothing in the rig reads (an output no evaluation looks at): every
  frame fcc sends has a reader in the rig (recorder, results, verify) or is declared diagnostic
  in the DBC (FccDiagnostic);
- a fault kind inserted among its siblings (it renumbered the codes on the bus): the codes come
  from the DBC's value table, every kind has one and every code a kind, and the codes released
  never change.
"""
from __future__ import annotations

import ast
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from hil.bus import dbc, protocol
from hil.bus.apps import bus_app
from hil.bus.cgen import generate
from hil.scenario.faults import KINDS, WIRE_KINDS
from hil.sim.drivers import SIGNAL_FRAMES

DBC = Path(__file__).resolve().parents[3] / "dbc" / "fcc_hil.dbc"
NODE_C = Path("firmware/app/fcc_node.c")
#: SIM_EVENT.kind as released: a code once on the bus never changes (new kinds are appended)
RELEASED_KIND_CODES = {
    "spike": 1, "bias": 2, "stuck": 3, "dropout": 4, "noise_burst": 5, "drift": 6, "scale": 7,
    "loss": 8, "delay": 9, "duplicate": 10, "replay": 11, "bad_crc": 12, "counter_freeze": 13,
    "counter_jump": 14, "wrong_dlc": 15, "out_of_range": 16, "flood": 17, "silence": 18}
#: the simulator's sources that name the frames it sends
SIM_SOURCES = ("hil/src/hil/sim", "hil/src/hil/rig", "hil/src/hil/bus")
#: the rig's parts that read fcc's frames: the session and recorder, the results, verify
READER_SOURCES = ("hil/src/hil/rig", "hil/src/hil/results", "hil/src/hil/verify", "hil/src/hil/runs")
#: an output of fcc's that nothing reads (the orphan-output tests add it)
ORPHAN_OUTPUT = """BO_ 1802 FCC_SPARE_COUNTS: 8 FCC
 SG_ spare : 0|16@1+ (1,0) [0|65535] "" SIM

"""
#: the application input whose copy the orphan-frame tests add (another missile sensor, at the
#: first free identifier after the missile's inputs: the last of them)
ORPHAN = """BO_ {id} MSL_AIRSPEED: 8 MSL_ACCEL
 SG_ crc : 0|8@1+ (1,0) [0|255] "" FCC
 SG_ counter : 8|4@1+ (1,0) [0|15] "" FCC
 SG_ step : 16|16@1+ (1,0) [0|65535] "" FCC
 SG_ v : 32|32@1- (0.001,0) [-4000|4000] "ft/s" FCC

"""


# ---- the checks -----------------------------------------------------------------------------

def sent_to_fcc(spec: dbc.BusSpec) -> list[dbc.MessageSpec]:
    return [m for m in spec.messages
            if dbc.FCC_NODE in m.receivers and dbc.FCC_NODE not in m.senders]


def _string_constants(root: Path) -> set[str]:
    names: set[str] = set()
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                names.add(node.value)
    return names


def producer_gaps(spec: dbc.BusSpec, repo: Path) -> list[str]:
    """Frames the DBC sends to FCC that the simulator does not send: an application's input
    must carry a sensor signal of hil.sim.drivers.SIGNAL_FRAMES; the rig's own frames are sent
    by name (a string in its sources); authenticators are made from their SecOC_Pdus."""
    sensors = {frame for frame, _ in SIGNAL_FRAMES.values()}
    named = set().union(*(_string_constants(repo / d) for d in SIM_SOURCES))
    gaps = []
    for m in sent_to_fcc(spec):
        if not (m.name in sensors if m.app else m.is_authenticator or m.name in named):
            gaps.append(f"{m.name}: sent to FCC by the DBC, sent by no part of the simulator")
    return gaps


def node_handlers(repo: Path) -> set[str]:
    """The frames fcc_node.c's handler table (k_handlers) takes."""
    text = (repo / NODE_C).read_text(encoding="utf-8")
    table = re.search(r"k_handlers\[FCC_MSG_COUNT\] = \{(.*?)\};", text, re.S)
    assert table, f"{NODE_C}: no k_handlers table"
    return set(re.findall(r"\[FCC_MSG_(\w+)\]\s*=\s*handle_\w+", table.group(1)))


def consumer_gaps(spec: dbc.BusSpec, repo: Path) -> list[str]:
    """Frames the DBC sends to FCC that fcc takes in no way: not an application's input (the
    generated input tables: their size checked against the slots when fcc is compiled, see
    test_an_orphan_input_stops_the_firmware_build), not in the node's handler table, not an
    authenticator."""
    handled = node_handlers(repo)
    return [f"{m.name}: sent to FCC by the DBC, taken by nothing in fcc"
            for m in sent_to_fcc(spec)
            if not (m.app or m.is_authenticator or m.name.upper() in handled)]


def sent_by_fcc(spec: dbc.BusSpec) -> list[dbc.MessageSpec]:
    return [m for m in spec.messages if m.senders == (dbc.FCC_NODE,)]


def reader_gaps(spec: dbc.BusSpec, repo: Path) -> list[str]:
    """Frames fcc sends that no part of the rig reads and the DBC does not declare diagnostic
    (FccDiagnostic): read is named in the rig's readers (READER_SOURCES), or one of an
    application's output group (its frames and their authenticator: hil.results.buslog
    verifies and decodes every one of them)."""
    named = set().union(*(_string_constants(repo / d) for d in READER_SOURCES))
    outputs = {f for app in spec.apps for a in [bus_app(spec, app)]
               for f in (*a.output_frames, a.output_auth) if f}
    return [f"{m.name}: sent by fcc, read by no part of the rig, not declared {dbc.DIAGNOSTIC_ATTRIBUTE}"
            for m in sent_by_fcc(spec) if not (m.diagnostic or m.name in named or m.name in outputs)]


def with_orphan_output(tmp_path: Path, diagnostic: bool) -> Path:
    """A copy of the DBC with one more frame sent by fcc (declared diagnostic, or not)."""
    text = DBC.read_text(encoding="utf-8").replace("BO_ 1808 SIM_EVENT:", ORPHAN_OUTPUT + "BO_ 1808 SIM_EVENT:", 1)
    if diagnostic:
        text = text.replace('BA_ "FccApp" BO_ 48 2;', 'BA_ "FccApp" BO_ 48 2;\nBA_ "FccDiagnostic" BO_ 1802 1;', 1)
    out = tmp_path / "fcc_hil.dbc"
    out.write_text(text, encoding="utf-8")
    return out


def with_orphan(tmp_path: Path, app: str | None) -> Path:
    """A copy of the DBC with one more frame sent to FCC (of application app, or of none)."""
    spec = dbc.load(DBC)
    taken = {m.frame_id for m in spec.messages}
    frame_id = next(i for i in range(spec.app_inputs("missile")[-1].frame_id + 1, 0x800) if i not in taken)
    text = DBC.read_text(encoding="utf-8")
    text = text.replace("BO_ 80 CDRW_AOA:", ORPHAN.format(id=frame_id) + "BO_ 80 CDRW_AOA:", 1)
    if app is not None:
        choice = ["none", *spec.apps].index(app)
        text = text.replace('BA_ "FccApp" BO_ 64 2;',
                            f'BA_ "FccApp" BO_ 64 2;\nBA_ "FccApp" BO_ {frame_id} {choice};', 1)
    out = tmp_path / "fcc_hil.dbc"   # the name: the generated C's prefix
    out.write_text(text, encoding="utf-8")
    return out


def with_kind_inserted(tmp_path: Path) -> Path:
    """A copy of the DBC with a fault kind inserted after SPIKE, its siblings renumbered (what
    numbering by position did)."""
    spec = dbc.load(DBC)
    names = [n for n, _ in sorted(protocol.fault_kind_codes(spec).items(), key=lambda kv: kv[1])]
    names.insert(1, "intermittent")
    pairs = " ".join(f'{i + 1} "{n.upper()}"' for i, n in reversed(list(enumerate(names))))
    text = re.sub(r"VAL_ 1808 kind .*;", f'VAL_ 1808 kind {pairs} 0 "NONE" ;',
                  DBC.read_text(encoding="utf-8"))
    out = tmp_path / "fcc_hil.dbc"
    out.write_text(text, encoding="utf-8")
    return out


def renumbered(codes: dict[str, int]) -> list[str]:
    return [f"{k}: code {codes.get(k)} on the bus, released as {c}"
            for k, c in RELEASED_KIND_CODES.items() if codes.get(k) != c]


# ---- the DBC today ------------------------------------------------------------------------

def test_every_frame_sent_to_fcc_has_a_producer_and_a_consumer(repo: Path) -> None:
    spec = dbc.load(DBC)
    assert len(sent_to_fcc(spec)) >= 14  # 5 sensors, 3 time sync, 2 control, 2 tick, event, ping
    assert producer_gaps(spec, repo) == []
    assert consumer_gaps(spec, repo) == []


def test_every_frame_fcc_sends_has_a_reader_or_is_declared_diagnostic(repo: Path) -> None:
    spec = dbc.load(DBC)
    assert len(sent_by_fcc(spec)) >= 28   # ACK, 16 application outputs and authenticators, 10 heartbeat, RIG_PONG
    assert reader_gaps(spec, repo) == []


@pytest.mark.parametrize("diagnostic", [False, True])
def test_an_output_without_a_reader_fails_unless_declared_diagnostic(repo: Path, tmp_path: Path,
                                                                    diagnostic: bool) -> None:
    spec = dbc.load(with_orphan_output(tmp_path, diagnostic))
    assert spec.by_name("FCC_SPARE_COUNTS").diagnostic is diagnostic
    assert reader_gaps(spec, repo) == ([] if diagnostic else [
        "FCC_SPARE_COUNTS: sent by fcc, read by no part of the rig, not declared FccDiagnostic"])


def test_the_applications_inputs_come_from_the_dbc() -> None:
    spec = dbc.load(DBC)
    # SIM_TICK.app's code of an application is its place among the FccApp choices (below)
    inputs = {code: tuple(m.name for m in spec.app_inputs(app)) for code, app in enumerate(spec.apps)}
    assert inputs == protocol.APP_INPUTS
    # the inputs of before keep their slots (fcc's FCC_APP_*_IN_* numbers): a new frame follows them
    assert inputs[protocol.APP_CDRW][:3] == ("CDRW_AOA", "CDRW_PITCH_RATE", "CDRW_ELEVATOR")
    assert inputs[protocol.APP_MISSILE][:2] == ("MSL_RATE_GYRO", "MSL_ACCELEROMETER")
    assert inputs[protocol.APPS["PROBE"]] == ()   # the test build's third application: no frames of its own
    # the application ids are SIM_TICK.app's: the FccApp choices in the same order
    assert dbc.load(DBC).apps == ("cdrw", "missile", "probe")


def test_fault_codes_agree_python_c_and_the_dbc(repo: Path) -> None:
    codes = protocol.fault_kind_codes(dbc.load(DBC))
    assert protocol.fault_code_mismatches(KINDS, codes) == []
    assert renumbered(codes) == []
    header = (repo / "firmware/bus/generated/fcc_bus_msgs.h").read_text(encoding="utf-8")
    in_c = {n.lower(): int(c) for n, c in re.findall(r"#define FCC_MSG_SIM_EVENT_KIND_(\w+) (\d+)u", header)}
    assert in_c == {"none": 0, **codes}
    from hil.rig.live import KIND_NAMES
    from hil.sim.frame_faults import KIND_CODES
    assert codes == KIND_CODES
    assert {c: k for k, c in codes.items()} == KIND_NAMES


# ---- the two silent failures, now loud ----------------------------------------------------

@pytest.mark.parametrize("app", [None, "missile"])
def test_an_orphan_frame_fails_the_checks(repo: Path, tmp_path: Path, app: str | None) -> None:
    spec = dbc.load(with_orphan(tmp_path, app))
    assert producer_gaps(spec, repo) == [
        "MSL_AIRSPEED: sent to FCC by the DBC, sent by no part of the simulator"]
    if app is None:
        assert consumer_gaps(spec, repo) == [
            "MSL_AIRSPEED: sent to FCC by the DBC, taken by nothing in fcc"]
    else:
        assert spec.app_inputs("missile")[-1].name == "MSL_AIRSPEED"


def _compile(repo: Path, generated: Path, source: str) -> subprocess.CompletedProcess[str]:
    """fcc's source compiled (syntax only) against the C generated into `generated`."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler")
    includes = [f"-I{generated}", *(f"-I{d}" for d in sorted((repo / "firmware").iterdir())
                                     if d.is_dir())]
    return subprocess.run([cc, "-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror",
                           "-fsyntax-only", *includes, str(repo / source)],
                          capture_output=True, text=True, check=False)


def test_an_orphan_input_stops_the_firmware_build(repo: Path, tmp_path: Path) -> None:
    """A sensor frame added to an application in the DBC, regenerated: the application's
    source no longer compiles until its input slots follow (it is not ignored)."""
    path = with_orphan(tmp_path, "missile")
    out = tmp_path / "generated"
    r = subprocess.run([sys.executable, "-m", "cantools", "generate_c_source",
                        "--no-floating-point-numbers", "-o", str(out), str(path)],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    generate(path, out)
    inputs = len(dbc.load(DBC).app_inputs("missile")) + 1
    assert f"#define FCC_BUS_APP_MISSILE_N_INPUTS {inputs}u" in (out / "fcc_bus_msgs.h").read_text()
    refused = _compile(repo, out, "firmware/app/fcc_app_msl.c")
    assert refused.returncode != 0 and "fcc_app_msl_inputs_are_the_dbcs" in refused.stderr
    # the same source against the DBC of today compiles: the refusal is the orphan's
    assert _compile(repo, repo / "firmware/bus/generated", "firmware/app/fcc_app_msl.c").returncode == 0


def test_a_fault_kind_in_the_middle_fails_the_checks(tmp_path: Path) -> None:
    # in the registry: the codes do not move (they are the DBC's), the new kind has none
    registry = list(KINDS)
    registry.insert(1, "intermittent")
    assert protocol.fault_code_mismatches(registry, protocol.FAULT_KIND_CODES) == [
        "fault kind 'intermittent' has no code in SIM_EVENT.kind's value table (append one)"]
    # in the DBC, renumbering its siblings: 17 released codes moved
    codes = protocol.fault_kind_codes(dbc.load(with_kind_inserted(tmp_path)))
    assert len(renumbered(codes)) == 17
    # appended instead: every released code stays, and the registry with it agrees
    appended = {**protocol.FAULT_KIND_CODES, "intermittent": max(protocol.FAULT_KIND_CODES.values()) + 1}
    assert renumbered(appended) == []
    assert protocol.fault_code_mismatches(registry, appended) == []


def test_a_code_without_a_kind_or_given_twice_is_named() -> None:
    free = max(protocol.FAULT_KIND_CODES.values()) + 1   # (a code no kind has, whatever the kinds)
    codes = {**protocol.FAULT_KIND_CODES, "gone": free, "twice": 1}
    assert protocol.fault_code_mismatches(KINDS, codes) == [
        f"SIM_EVENT.kind code {free} (gone) names no fault kind",
        "SIM_EVENT.kind code 1 (twice) names no fault kind",
        "SIM_EVENT.kind code 1 given to both spike and twice"]


def _dict_keys(path: Path, name: str) -> set[str]:
    """The string keys of the dict literal assigned to name in a Python source."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if (isinstance(node, ast.AnnAssign | ast.Assign) and isinstance(node.value, ast.Dict)
                and name in [t.id for t in (node.targets if isinstance(node, ast.Assign) else [node.target])
                             if isinstance(t, ast.Name)]):
            return {k.value for k in node.value.keys if isinstance(k, ast.Constant)}
    raise AssertionError(f"{path}: no dict {name}")


def test_the_fault_matrix_covers_every_kind(repo: Path) -> None:
    """Every fault kind has a cell in the fault matrix (tests/python/rig/test_fault_matrix.py,
    flown under vcan) and a row in its table in docs/reliability.md; but the wire kinds,
    canbus's, which fly on the wire-time bus only (tests/python/bus/test_canbus_faults.py)."""
    kinds = set(KINDS) - set(WIRE_KINDS)
    assert _dict_keys(repo / "tests/python/rig/test_fault_matrix.py", "CASES") == kinds
    doc = (repo / "docs/reliability.md").read_text(encoding="utf-8")
    table = doc.split("## Fault matrix", 1)[1].split("| fault class |", 1)[1].split("\n\n", 1)[0]
    rows = {line.split("|")[1].strip() for line in table.splitlines()[2:] if line.startswith("|")}
    assert rows == kinds
