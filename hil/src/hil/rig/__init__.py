"""The rig: fly the simulated aircraft against the fcc firmware over SocketCAN.

* session   -- RigSession: the bus recorder (candump), fcc, the simulator's socket
* targets   -- the device under test: host fcc, qemu-m4f (qemu: the M4F image + slcand + can-gw),
               external (whatever answers on the bus)
* apps      -- CdrwDriver / MissileDriver: one aircraft, step by step
* inject    -- FrameInjector: frame- and bus-level faults on the simulator's frames
* lockstep  -- LockstepRunner: tick, wait for FCC_ACK, integrate (deterministic)
* realtime  -- RealtimeRunner: both sides on their own clocks
* buslog    -- fcc's outputs read back from bus.log
* results   -- time series and figures of merit of a flight
* runs      -- the CLI commands: run_flight, run_campaign, run_sweep, run_demo
* report    -- summary.json as text tables
* output    -- CSV and JSON files of a run directory
* rundir    -- atomic writes; the staged run directory (published when done, kept when failed)
* bench     -- scripts/bench.d/rig

Nothing is imported here: each module is imported by name (a command imports only what it
uses).
"""
