"""The rig: fly the simulated aircraft against the device under test over SocketCAN (or any
python-can bus).

* config    -- RigConfig: the run's configuration, one object for the session and the flights
* session   -- RigSession: the bus recorder, the device under test (hil.targets), the
               simulator's socket, the bus key
* errors    -- RigError, FccTimeout, FccDied (with `hil`'s exit status)
* status    -- fcc's heartbeat counters
* link      -- CanLink: the simulator's raw CAN socket (or a python-can bus), kernel time stamps
* recorder  -- the bus recorder: candump or canrec
* lockstep  -- LockstepRunner: tick, wait for FCC_ACK, integrate (deterministic)
* realtime  -- RealtimeRunner: both sides on their own clocks
* timesync  -- the bus's time master (realtime)
* txsched   -- the time-triggered transmitter (realtime; a process of its own)
* simtime   -- bus.log in simulated time (lockstep), the wall-clock log beside it
* flight    -- one flight: fcc's command line, the session, the drivers, fly
* live      -- `hil live`'s view of the bus

Room 8: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets, hil.apps.
"""
