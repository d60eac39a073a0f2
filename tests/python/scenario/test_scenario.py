"""Scenario files: the embedded defaults, loading, and one clear error line per mistake."""
from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from hil.scenario.schema import ScenarioError
from hil.scenario.sensor_options import SIGNALS
from hil.scenario.faults import Spike
from hil.scenario.file import (load_default_scenario, load_scenario, loads_scenario,
                               with_extra_faults, with_fault_start)
from hil.scenario.cdrw_params import DEFAULT_PARAMS

REPO = Path(__file__).resolve().parents[3]

GOOD_CDRW = """
aircraft = "cdrw"
duration = 7.0
seed = 3
[plant]
process_noise = [0.002, 0.001]
[plant.maneuver]
pull_deg = 5.0
[plant.params]
tau1 = 0.4
[sensors]
distribution = "triangular"
[[faults]]
kind = "spike"
signal = "alpha"
start = 4.0
duration = 0.1
magnitude = 0.15
[[faults]]
kind = "bad_crc"
frame = "CDRW_AOA"
start = 2
duration = 1
"""


def test_embedded_cdrw_default_has_the_papers_fault():
    sc = load_default_scenario("cdrw")
    assert (sc.aircraft, sc.duration, sc.seed, sc.name) == ("cdrw", 7.0, 1, "cdrw_default")
    assert sc.lqg is None and sc.plant.dt == 0.02
    assert sc.plant.params == DEFAULT_PARAMS
    assert sc.sensors.bound == (0.02, 0.02)
    faults = sc.sensor_faults
    assert {f.signal for f in faults} == {"alpha", "q"}
    for f in faults:                                   # ~4 s, 0.1 s long (seed 1, Fig. 8)
        assert isinstance(f, Spike) and f.start == 4.0 and f.duration == 0.1
    assert sc.active_faults(4.05) == faults and sc.active_faults(4.1) == ()
    assert sc.active_faults(4.05, level="frame") == ()


def test_embedded_missile_default():
    sc = load_default_scenario("missile")
    assert sc.aircraft == "missile" and sc.duration >= 5.0
    assert (sc.lqg.period, sc.lqg.bits, sc.lqg.closed_loop) == (0.1, 8, True)
    assert (sc.plant.q0, sc.plant.alpha0, sc.plant.substeps) == (0.1, 0.0, 8)
    assert (sc.sensors.var_gyro, sc.sensors.var_acc) == (0.8, 0.8)


def test_defaults_are_package_data():
    pyproject = tomllib.loads((REPO / "hil/pyproject.toml").read_text())
    assert "scenarios/*.toml" in pyproject["tool"]["setuptools"]["package-data"]["hil"]
    for name in ("cdrw_default.toml", "missile_default.toml"):
        assert (REPO / "hil/src/hil/scenarios" / name).is_file()


def test_load_file_with_overrides(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(GOOD_CDRW)
    sc = load_scenario(path, known_frames={"CDRW_AOA"})
    assert sc.source == str(path) and sc.seed == 3
    assert sc.plant.process_noise == (0.002, 0.001)
    assert sc.plant.maneuver.pull_deg == 5.0 and sc.plant.maneuver.pull_ramp == 1.0
    assert sc.plant.params.tau1 == 0.4 and sc.plant.params.tau2 == DEFAULT_PARAMS.tau2
    assert sc.sensors.distribution == "triangular"
    assert [f.level for f in sc.faults] == ["sensor", "frame"]
    assert sc.frame_faults[0].frame == "CDRW_AOA" and sc.bus_faults == ()


def test_missile_defaults_fill_in():
    sc = loads_scenario('aircraft = "missile"\n[lqg]\nperiod = 0.05\nbits = 6\n[plant]\ngust0 = "stationary"')
    assert sc.duration == 10.0 and sc.lqg.period == 0.05 and sc.lqg.bits == 6
    assert sc.plant.gust0 == "stationary" and sc.plant.substeps == 8


def test_with_fault_start_and_extra_faults():
    sc = load_default_scenario("cdrw")
    moved = with_fault_start(sc, 5.5)
    assert [f.start for f in moved.faults] == [5.5, 5.5]
    assert [f.duration for f in moved.faults] == [0.1, 0.1]
    more = with_extra_faults(sc, ["stuck:signal=de,start=1,duration=0.5"])
    assert len(more.faults) == 3 and more.faults[-1].signal == "de"
    with pytest.raises(ScenarioError, match="unknown signal 'n_a'"):
        with_extra_faults(sc, ["bias:signal=n_a,start=1,duration=1,magnitude=1"])


BAD = [
    # (text, message fragment); every message starts with the file name
    ('aircraft = "cdrw"\n[[faults]]\nkind = "spik"\nsignal = "alpha"\nstart = 4\nduration = 0.1',
     "faults[0]: field 'kind': unknown fault kind 'spik' (did you mean 'spike'? `hil faults` lists them)"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "spike"\nsignal = "alpha"\nstart = 4\nduration = -0.1\nmagnitude = 1',
     "faults[0] (spike): field 'duration': must be > 0.0, got -0.1"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "bias"\nsignal = "beta"\nstart = 4\nduration = 1\nmagnitude = 1',
     "faults[0] (bias): field 'signal': unknown signal 'beta' for aircraft cdrw"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "spike"\nsignal = "q"\nstart = "4 s"\nduration = 1\nmagnitude = 1',
     "faults[0] (spike): field 'start': expected a number, got string '4 s'"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "spike"\nsignal = "q"\nstart = 4\nduration = 1\nmagnitude = 1\nsize = 2',
     "faults[0] (spike): unknown field 'size'"),
    ('aircraft = "cdrw"\n[[faults]]\nkind = "spike"\nsignal = "q"\nstart = 9\nduration = 1\nmagnitude = 1',
     "faults[0] (spike): field 'start': 9.0 s is not before the end of the run (7.0 s)"),
    ('aircraft = "cdrw"\n[[faults]]\nsignal = "q"', "faults[0]: missing field 'kind'"),
    ('aircraft = "cdrw"\nduration = -7', "field 'duration': must be > 0.0, got -7.0"),
    ('aircraft = "cdrw"\nseed = 1.5', "field 'seed': expected an integer, got number 1.5"),
    ('aircraft = "cdrw"\nsead = 1', "unknown key 'sead'"),
    ('aircraft = "plane"', "key 'aircraft': must be one of cdrw, missile, got 'plane'"),
    ('duration = 7.0', "missing key 'aircraft'"),
    ('aircraft = "cdrw"\n[plant]\nprocess_noise = [0.1]',
     "[plant]: field 'process_noise': expected an array of 2 values, got 1"),
    ('aircraft = "cdrw"\n[plant]\nprocess_noise = [0.1, -1]',
     "[plant]: field 'process_noise'[1]: must be >= 0.0, got -1.0"),
    ('aircraft = "cdrw"\n[plant.maneuver]\npull = 5', "[plant]: field 'maneuver': unknown field 'pull'"),
    ('aircraft = "cdrw"\n[plant.params]\ntau1 = 0', "[plant]: field 'params': CDRW parameter tau1 must be > 0"),
    ('aircraft = "cdrw"\n[plant.params]\nC_Lalpha = 3', "field 'params': unknown field 'C_Lalpha'"),
    ('aircraft = "cdrw"\n[sensors]\ndistribution = "gauss"', "[sensors]: distribution must be one of"),
    ('aircraft = "cdrw"\n[sensors]\nbounds = [0.1, 0.1]',
     "[sensors]: unknown field 'bounds' (allowed: distribution, bound, de_bound)"),
    ('aircraft = "cdrw"\n[lqg]\nbits = 8', "section [lqg] is only for aircraft = \"missile\""),
    ('aircraft = "missile"\n[lqg]\nbits = 40', "[lqg]: field 'bits': must be <= 16, got 40"),
    ('aircraft = "missile"\n[lqg]\nperiod = "fast"', "[lqg]: field 'period': expected a number, got string 'fast'"),
    ('aircraft = "missile"\n[plant]\nsubsteps = 4', "[plant]: field 'substeps': must be >= 8, got 4"),
    ('aircraft = "missile"\n[plant]\ngust0 = "windy"',
     "[plant]: field 'gust0': must be one of stationary, got 'windy'"),
    ('aircraft = "missile"\n[[faults]]\nkind = "spike"\nsignal = "alpha"\nstart = 1\nduration = 1\nmagnitude = 1',
     f"unknown signal 'alpha' for aircraft missile (signals: {', '.join(SIGNALS['missile'])})"),
    ('aircraft = "missile"\nfaults = 3', "key 'faults': expected an array of tables"),
    ('aircraft = "missile"\n[plant]\ngust0 = true',
     "[plant]: field 'gust0': expected a number or a string, got boolean True"),
    ('aircraft = "cdrw"\n[plant]\ndt = 0.02\n[plant]\ndt = 0.01', "not valid TOML"),
    ('aircraft = "cdrw"\nfaults = ' + "[" * 100_000, "not valid TOML: nested too deeply"),
]


@pytest.mark.parametrize("text, message", BAD)
def test_bad_scenarios_give_one_clear_line_naming_file_fault_and_field(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}: "), msg
    assert message in msg, msg
    assert "\n" not in msg


def test_missing_file():
    with pytest.raises(ScenarioError, match=r"nope\.toml: cannot read scenario"):
        load_scenario("/nonexistent/nope.toml")


def test_gust0_choices_and_inf_duration_in_toml():
    sc = loads_scenario('aircraft = "missile"\n[plant]\ngust0 = "stationary"\n'
                        '[[faults]]\nkind = "silence"\nstart = 1\nduration = inf')
    assert math.isinf(sc.faults[0].duration)
