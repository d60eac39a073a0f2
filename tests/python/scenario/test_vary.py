"""Campaigns over any scenario field (hil.scenario.vary, hil.runs.field_campaign's plan):
the keys and values are checked by the scenario file's own validator, the product and the
draws are what the campaign flies, and the CLI refuses a bad one with exit 2 naming it."""
from __future__ import annotations

import pytest

from hil.bus import load
from hil.runs.field_campaign import flights_of
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import default_scenario_text, load_default_scenario, loads_scenario
from hil.scenario.schema import ScenarioError
from hil.scenario.vary import draw_values, grid, parse_draw, parse_vary, with_fields

from rig_helpers import cli

FRAMES = {m.name for m in load().messages}


def test_a_varied_field_is_the_scenario_file_with_that_value():
    text = default_scenario_text("missile")
    sc = load_default_scenario("missile", FRAMES)
    for key, line, new_line in (("lqg.period", "period = 0.1 ", "period = 0.05 "),
                                ("lqg.bits", "bits = 8 ", "bits = 12 "),
                                ("sensors.noise_scale", "noise_scale = 1.0 ", "noise_scale = 0.5 ")):
        assert line in text
        value = parse_vary(f"{key}=" + new_line.split("=")[1].strip()).values[0]
        from_file = loads_scenario(text.replace(line, new_line), sc.source, FRAMES)
        assert with_fields(sc, {key: value}) == from_file, key
    assert with_fields(sc, {"seed": 7}) == sc.replace(seed=7)    # as `hil run --seed 7`


@pytest.mark.parametrize("key, value, message", [
    ("lqg.perod", 0.1, "lqg.perod: [lqg]: unknown field 'perod'"),
    ("lqg.period", 2.0, "[lqg]: field 'period': must be <= 1.0, got 2.0"),
    ("lqg.bits", 1, "[lqg]: field 'bits': must be >= 2, got 1"),
    ("lqg.bits", 6.5, "field 'bits': expected an integer"),
    ("seed", -1, "seed: field 'seed': must be >= 0"),
    ("duration", 0.05, "[lqg]: field 'period': 0.1 s is longer than the duration 0.05 s"),
    ("color", 1, "unknown field 'color'"),
    ("faults[0].magnitude", 1.0, "the scenario has 0 fault(s)"),
    ("plant.gust0", "windy", "must be one of stationary, got 'windy'"),
])
def test_a_bad_key_or_value_is_named(key, value, message):
    with pytest.raises(ScenarioError, match=message.replace("[", r"\[").replace("]", r"\]")
                       .replace("(", r"\(").replace(")", r"\)").replace(".", r"\.")):
        with_fields(load_default_scenario("missile", FRAMES), {key: value}, "--vary x")


def test_a_fault_and_a_nested_table_are_fields_too():
    sc = load_default_scenario("cdrw", FRAMES)
    new = with_fields(sc, {"faults[0].magnitude": 0.2, "plant.maneuver.pull_deg": 3.0})
    assert new.faults[0].magnitude == 0.2 and new.faults[1:] == sc.faults[1:]
    assert new.plant.maneuver.pull_deg == 3.0
    with pytest.raises(ScenarioError, match="a cdrw scenario has no \\[lqg\\]"):
        with_fields(sc, {"lqg.period": 0.05})


def test_parse_vary_and_draw():
    assert parse_vary("lqg.period=0.1, 0.05").values == (0.1, 0.05)
    assert parse_vary("plant.gust0=stationary,0").values == ("stationary", 0)
    assert parse_draw("plant.q0=uniform:0,0.2").describe() == "uniform:0,0.2"
    for bad in ("lqg.period", "lqg.period=", "seed=1,1"):
        with pytest.raises(ScenarioError, match="--vary"):
            parse_vary(bad)
    for bad in ("seed=normal:0,1", "seed=integers:0.5,3", "q0=uniform:1,0", "q0=uniform:1"):
        with pytest.raises(ScenarioError, match="--draw"):
            parse_draw(bad)


def test_grid_is_the_product_first_axis_outermost():
    assert grid([("a", (1, 2)), ("b", ("x", "y", "z"))]) == [
        {"a": a, "b": b} for a in (1, 2) for b in ("x", "y", "z")]
    assert grid([]) == [{}]
    with pytest.raises(ScenarioError, match="varied twice"):
        grid([("a", (1,)), ("a", (2,))])


def test_draws_are_the_seed_s_and_each_key_its_own_stream():
    q0 = parse_draw("plant.q0=uniform:0,0.2")
    seeds = parse_draw("seed=integers:0,5")
    both = draw_values([q0, seeds], 20, 4)
    alone = draw_values([q0], 20, 4)
    assert [d["plant.q0"] for d in both] == [d["plant.q0"] for d in alone]   # a new --draw: the same q0
    assert draw_values([q0, seeds], 20, 4) == both and draw_values([q0], 20, 5) != alone
    assert all(0 <= d["plant.q0"] < 0.2 and 0 <= d["seed"] <= 5 and isinstance(d["seed"], int) for d in both)


def test_the_plan_every_combination_with_table_5_s_fault_times():
    sc = load_default_scenario("cdrw", FRAMES)
    plan = flights_of(sc, 3, 9, [parse_vary("plant.q0=0,0.01")], [parse_draw("sensors.de_bound=uniform:0.001,0.002")])
    assert [(k["flight"], k["combination"], k["run"]) for k, _ in plan] == [
        (0, 0, 0), (1, 0, 1), (2, 0, 2), (3, 1, 0), (4, 1, 1), (5, 1, 2)]
    starts = campaign_fault_times(sc, 3, 9)
    for key, flight in plan:
        assert key["fault_start"] == float(starts[key["run"]]) == min(f.start for f in flight.faults)
        assert flight.plant.q0 == key["plant.q0"] and flight.sensors.de_bound == key["sensors.de_bound"]
    assert plan[0][0]["sensors.de_bound"] == plan[3][0]["sensors.de_bound"]   # the same draws


@pytest.mark.parametrize("argv, named", [
    (["--vary", "lqg.perod=0.1,0.05"], "unknown field 'perod'"),
    (["--vary", "lqg.bits=8,40"], "--vary lqg.bits=40: lqg.bits: [lqg]: field 'bits': must be <= 16, got 40"),
    (["--draw", "seed=uniform:0,3"], "field 'seed': expected an integer"),
    (["--draw", "seed=gauss:0,3"], "--draw 'seed=gauss:0,3'"),
    (["--vary", "seed=1,2", "--draw", "seed=integers:0,3"], "a key varied twice"),
    (["--keep-logs", "--workers", "2"], "--keep-logs: the rigs of --workers/--scheduler keep no bus log"),
])
def test_the_cli_refuses_a_bad_key_or_value_exit_2(tmp_path, capsys, argv, named):
    rc, out, err = cli(capsys, "campaign", "missile", "--runs", "2", "--out", str(tmp_path / "c"), *argv)
    assert rc == 2 and named in err and err.count("\n") == 1, err
    assert not (tmp_path / "c").exists()
