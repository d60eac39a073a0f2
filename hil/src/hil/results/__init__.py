"""What a flight gave: fcc's outputs read back from the bus log (buslog), a flight's time
series and figures of merit (flight, metrics: the papers' error integrals and Table 5's
intervals), the identification's rows as arrays (sidrows) and Tables 4-5 from sid_replay
(rowtables), the seed-2 figures' data (figures), a realtime run's timing (timing) and
summary.json as text tables (report).

Room 9: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets, hil.apps, hil.rig
(the session's status counters).
"""
