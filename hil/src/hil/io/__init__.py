"""Files of a run: the staged run directory and atomic writes (rundir), CSV and JSON (output),
where the repository's tools are (paths: the fcc build, lqg_design, sid_replay, canrec).

Room 2: may import hil.util.
"""
