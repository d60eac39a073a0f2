"""The applications fcc flies, behind one interface (application.Application): each says its
bus (hil.bus.apps: its sensor and output frames, from the DBC), its scenario sections, its
step period, the options fcc takes for it, the design a device configured over the bus asks
for, its driver, and where its evaluation and figures are; `registry` lists them, so that the
rig iterates over the registered applications instead of choosing between two (cdrw, missile).

Adding a third application (tests/python/apps/test_third_application.py registers one, the
probe, and flies it on the host fcc's probe build; docs/extending.md has the checklist):

1. the DBC: a choice of FccApp and a value of SIM_TICK.app / FCC_ACK.app (the same place), its
   sensor nodes (BU_) and the frames they send to FCC with its FccApp, its output frames and
   their authenticator (SecOC_Pdus, FccApp); `dbc/generate` -- hil.bus.apps derives its lists
   from FccApp alone;
2. fcc: its C module with a const fcc_app_ops_t (firmware/app/fcc_app.h), its instance in
   fcc_node_t and its line in fcc_node.c's k_apps, its source in firmware/app/CMakeLists.txt;
3. hil.scenario.file: its SECTIONS entry ([plant] and [sensors] option classes, [lqg] or
   none), DEFAULT_DURATION, a default scenario in hil/scenarios/;
4. hil.sim: its simulation and an AppDriver (frames_for_step, end_step);
5. hil.apps: an Application subclass (step_period, peak_bytes, driver, fcc_args,
   design_request, the evaluation and figures hooks) registered in hil.apps.registry;
6. its evaluation (hil.runs.evaluate calls the hook for an application other than the
   shipped two: its block of summary.json) and its figures (hil.plots).

Room 7: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets; its
evaluation and figures live in the rooms above (results, plots, runs) and are named here as
"module:function", resolved when used (as hil.targets.registry names its devices).
"""
