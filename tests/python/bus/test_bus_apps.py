"""Which frames belong to which application comes from the DBC (hil.bus.apps): every frame a
sensor node sends is one application's sensor frame, every output frame one application's,
and the lists the rest of hil uses are these."""
from __future__ import annotations

import dataclasses

from hil.bus import SIM_NODES
from hil.bus.apps import BUS_APPS, RIG_NODES, SENSOR_APP, bus_app, output_frames, sensor_frames
from hil.bus.dbc import PACKAGED_DBC, BusSpec, load
from hil.bus.protocol import APPS
from hil.results.buslog import OUTPUT_AUTH
from hil.scenario.catalog import SIGNAL_UNITS
from hil.scenario.file import AIRCRAFT, SENSOR_FRAMES
from hil.scenario.sensor_options import SIGNALS
from hil.sim.drivers import SIGNAL_FRAMES

SPEC = load(PACKAGED_DBC)


def test_the_applications_are_sim_ticks() -> None:
    assert sorted(a.code for a in BUS_APPS.values()) == sorted(APPS.values())
    assert tuple(BUS_APPS) == ("cdrw", "missile", "probe")   # the FccApp choices, in order
    assert AIRCRAFT == ("cdrw", "missile")   # the probe is the test build's: no scenario section
    assert BUS_APPS["probe"].sensor_frames == () and BUS_APPS["probe"].output_auth == ""


def test_every_sensor_nodes_frame_is_one_applications() -> None:
    """No orphan: a frame a sensor node sends that no application claims fails here."""
    sent_by_sensors = {m.name for m in SPEC.messages if set(m.senders) - set(RIG_NODES)}
    claimed = [f for a in BUS_APPS.values() for f in a.sensor_frames]
    assert sorted(claimed) == sorted(sent_by_sensors) and len(set(claimed)) == len(claimed)
    assert {n for m in SPEC.messages if m.name in sent_by_sensors for n in m.senders} | {"SIM"} \
        == set(SIM_NODES)


def test_the_lists_of_before_are_kept() -> None:
    """The frames and signals of before keep their places (a scenario's signal names, fcc's
    input slots); a new sensor frame adds to them (the lists are the DBC's: the test above)."""
    assert sensor_frames("cdrw")[:3] == ("CDRW_AOA", "CDRW_PITCH_RATE", "CDRW_ELEVATOR")
    assert sensor_frames("missile")[:2] == ("MSL_RATE_GYRO", "MSL_ACCELEROMETER")
    assert (SIGNALS["cdrw"][:3], SIGNALS["missile"][:2], SIGNALS["probe"]) == (("alpha", "q", "de"), ("q_g", "n_a"), ())
    assert SIGNAL_FRAMES["de"] == ("CDRW_ELEVATOR", "delta_e")
    assert SIGNAL_UNITS.items() >= {"alpha": "rad", "q": "rad/s", "de": "rad", "q_g": "rad/s", "n_a": "ft/s^2"}.items()
    assert output_frames("missile") == ("MSL_ELEV_CMD", "MSL_STATE_EST")
    assert len(output_frames("cdrw")) == 12 and all(f.startswith("SID_") for f in output_frames("cdrw"))
    assert OUTPUT_AUTH == {0: "SID_OUT_AUTH", 1: "MSL_ELEV_CMD_AUTH"}


def test_every_list_of_hil_is_the_dbcs() -> None:
    for app in BUS_APPS.values():
        assert SENSOR_FRAMES[app.name] == app.sensor_frames
        assert {SENSOR_APP[SPEC.by_name(f).frame_id] for f in app.sensor_frames} <= {app.code}
        for name, frame, sig in app.sensor_signals:
            assert SIGNAL_FRAMES[name] == (frame, sig)
            assert SPEC.by_name(frame).signal(sig).unit == SIGNAL_UNITS[name]
    fcc_outputs = {m.name for m in SPEC.messages if m.senders == ("FCC",)}
    assert {f for a in BUS_APPS.values() for f in a.output_frames} <= fcc_outputs


def test_a_dbc_with_another_sensor_frame_gives_it_to_its_application() -> None:
    """The lists follow the DBC: a spec with a third missile sensor frame lists it."""
    gyro = SPEC.by_name("MSL_RATE_GYRO")
    taken = {m.frame_id for m in SPEC.messages}
    free = next(i for i in range(SPEC.app_inputs("missile")[-1].frame_id + 1, 0x800) if i not in taken)
    extra = dataclasses.replace(gyro, name="MSL_AIRSPEED", frame_id=free, senders=("MSL_PITOT",))
    spec = BusSpec(SPEC.path, tuple(sorted((*SPEC.messages, extra), key=lambda m: m.frame_id)),
                   (*SPEC.nodes, "MSL_PITOT"), SPEC.baudrate, SPEC.apps)
    assert bus_app(spec, "missile").sensor_frames == (*sensor_frames("missile"), "MSL_AIRSPEED")
    assert bus_app(spec, "cdrw").sensor_frames == sensor_frames("cdrw")
