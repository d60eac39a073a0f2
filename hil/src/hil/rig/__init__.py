"""The rig: fly the simulated aircraft against the fcc firmware over SocketCAN.

* session   -- RigSession: candump -L recorder, the fcc process, the simulator's socket
* apps      -- CdrwDriver / MissileDriver: one aircraft, step by step
* inject    -- FrameInjector: frame- and bus-level faults on the simulator's frames
* lockstep  -- LockstepRunner: tick, wait for FCC_ACK, integrate (deterministic)
* realtime  -- RealtimeRunner: both sides on their own clocks
* buslog    -- fcc's outputs read back from bus.log
* results   -- time series and figures of merit of a flight
* runs      -- the CLI commands: run_flight, run_campaign, run_sweep, run_demo
"""
from .runs import RigConfig, run_campaign, run_demo, run_flight, run_sweep, summary_tables
from .session import FccDied, FccTimeout, RigError, RigSession

__all__ = ["FccDied", "FccTimeout", "RigConfig", "RigError", "RigSession", "run_campaign",
           "run_demo", "run_flight", "run_sweep", "summary_tables"]
