"""`hil verify`: requirement-based test suites run against a device under test on the bus.

A suite (TOML, ``hil/suites/*.toml`` or a user's file) lists requirements, each traced to its
source, and test cases: a flight (aircraft, faults, LQG, mode, optional attack on the bus), the
requirements it verifies and expectations over documented result fields.  A case's verdict is
pass, fail (an expectation does not hold: the measured value is shown beside the limit) or
error (the case could not run: no device, a timeout, a crash -- never a pass).

    expr     -- the expression language of expectations (a safe subset of Python's)
    fields   -- the documented result fields and how each is read from a run directory
    series   -- a run's time series by name (DBC signals from the bus log, the CSVs' columns)
    window   -- events, windows around them and the measures of a windowed expectation
    figure   -- a windowed check's evidence figure
    suite    -- loading and validating suites (before anything flies)
    attack   -- a second node that sends forged frames during a case
    runner   -- running cases and judging them
    report   -- text summary, JUnit XML, HTML report, traceability matrix

May import: every room below it (hil.scenario, hil.bus, hil.io, hil.rig, hil.runs: a flight and its
results); only hil.cli imports it.
"""
