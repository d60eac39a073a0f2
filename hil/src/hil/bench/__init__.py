"""The benchmarks' Python (scripts/bench.d/* run them; each module is `python -m hil.bench.NAME
--help`): the rig's speed (rig), realtime against lockstep (realtime), the bus recorder's share
(recorder), campaigns on several rigs (parallel), the numpy reference's identification step
(sid), the fcc image on the bus and its table (fcc_bus, fcc_table), the LQG design against scipy
and python-control (lqg), the Cortex-M4F image under QEMU (pil).  The C benchmarks measured by
callgrind stay in scripts/bench.d (shell + C).

Room 14: may import every room below it (hil.util to hil.parallel); nothing imports it.
"""
