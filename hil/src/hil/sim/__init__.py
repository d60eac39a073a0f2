"""The simulated aircraft and what they put on the bus: the CDRW UAV in stall (seed 1: cdrw,
its prior model cdrw_prior, the offline flight cdrw_flight and its per-user cache
cdrw_cache) and the missile in gusts (seed 2: missile, its offline runs with a scipy LQG
reference missile_runs, the covariance analysis missile_cov), their sensors, fault injection
(sensor_faults: readings; frame_faults: frames and the bus), the drivers that turn a flight
into frames step by step (drivers), and the sid_replay CSV of a flight (sid_csv).

Room 5: may import hil.util, hil.io, hil.bus, hil.scenario.
"""
