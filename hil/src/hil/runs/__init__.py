"""The commands that fly and write a run directory, each in one rig session (one fcc): a
flight (run; its evaluation: evaluate), a campaign (campaign), a sweep (sweep), the demo
(demo), the replay of a recorded run (replay); what they leave (outcome: the Outcome, the
common files, the finished bus log, the figures) and whether the machine has the memory for a
run's results (budget).

Room 12: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets, hil.apps, hil.rig,
hil.results, hil.reference, hil.plots.
"""
