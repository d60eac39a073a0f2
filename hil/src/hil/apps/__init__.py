"""The applications fcc flies, behind one interface (application.Application): each says its
bus (hil.bus.apps: its sensor and output frames, from the DBC), its scenario sections, the
options fcc takes for it, its driver, and where its evaluation and figures are; `registry`
lists them, so that the rig iterates over the registered applications instead of choosing
between two (cdrw, missile).  Adding one: docs/extending.md's checklist.

Room 7: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets; its
evaluation and figures live in the rooms above (results, plots, runs) and are named here as
"module:function", resolved when used (as hil.targets.registry names its devices).
"""
