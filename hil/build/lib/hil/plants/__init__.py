"""The simulated aircraft: the CDRW UAV in stall (seed 1) and the missile in gusts (seed 2).

Modules: cdrw_params (every CDRW number, documented), cdrw (nonlinear plant, trim, true
linearisation), missile (plant, exact discretisation, D/A), options (scenario options),
cdrw_flight (offline flight generator + sid_replay CSV), missile_runs (offline open/closed
loop with a scipy LQG reference).  Import the module you need; this package imports nothing
so that hil.sensors and hil.faults can depend on it without cycles.
"""
