"""Fault models (sensor, frame, bus level) and scenario files.

Public API:
    load_scenario(path) / load_default_scenario("cdrw"|"missile") -> Scenario
    parse_fault_spec("spike:signal=alpha,start=4,duration=0.1,magnitude=0.2", aircraft) -> Fault
    Scenario.active_faults(t, level=None), .sensor_faults / .frame_faults / .bus_faults
    SensorFaultInjector(faults, seed).apply(t, {"alpha": .., "q": ..}) -> faulted readings
    FaultTimeline(faults).update(t) -> start/end FaultEvents (kept in .log)
    ScenarioError: every validation error (one line: file, fault, field, reason)
"""
from hil.faults.inject import FaultEvent, FaultTimeline, SensorFaultInjector
from hil.faults.model import (BUS_KINDS, FRAME_KINDS, KINDS, SENSOR_KINDS, BadCrc, Bias, BusFault,
                              CounterFreeze, CounterJump, Drift, Dropout, Fault, Flood, FrameDelay,
                              FrameDuplicate, FrameFault, FrameLoss, FrameReplay, NoiseBurst,
                              OutOfRange, Scale, SensorFault, Silence, Spike, Stuck, WrongDlc)
from hil.faults.scenario import (AIRCRAFT, Scenario, default_scenario_text, fault_from_table,
                                 load_default_scenario, load_scenario, loads_scenario,
                                 parse_fault_spec, scenario_from_dict, with_extra_faults,
                                 with_fault_start)
from hil.faults.schema import ScenarioError

__all__ = [
    "AIRCRAFT", "BUS_KINDS", "FRAME_KINDS", "KINDS", "SENSOR_KINDS", "BadCrc", "Bias", "BusFault",
    "CounterFreeze", "CounterJump", "Drift", "Dropout", "Fault", "FaultEvent", "FaultTimeline",
    "Flood", "FrameDelay", "FrameDuplicate", "FrameFault", "FrameLoss", "FrameReplay",
    "NoiseBurst", "OutOfRange", "Scale", "Scenario", "ScenarioError", "SensorFault",
    "SensorFaultInjector", "Silence", "Spike", "Stuck", "WrongDlc", "default_scenario_text",
    "fault_from_table", "load_default_scenario", "load_scenario", "loads_scenario",
    "parse_fault_spec", "scenario_from_dict", "with_extra_faults", "with_fault_start",
]
