"""Campaigns flown by many rigs at once, on one machine or a Dask cluster (issue 15), and a
warm rig for the shell's commands (issue 40).

* flights -- what one flight is, flown inside a rig: its own fcc, candump and bus
* files   -- the files between the host side of a rig and the loop inside it
* server  -- the loop inside a worker's rig (a UML guest with its own vcan0, or a vcanK):
             flight requests in, results out, through files
* guest   -- the host side of a worker's rig: boots it once, hands it flights, restarts it
             when it dies or hangs
* engine  -- Dask distributed: a local cluster of N workers or a running cluster's scheduler,
             one progress bar, a failed task's finished flights kept and the rest flown
             elsewhere, each failure's cause, results merged in flight order
* runs    -- `hil campaign/sweep --workers/--scheduler`: the flights, the merged run directory

A warm rig (`hil rig up`, `--rig`) is one such rig kept up for the shell's commands:

* warm    -- its state file and a command flown on it from the host shell (the client)
* keeper  -- the host process that boots it, watches its clients and stops it
* warmup  -- its loop readied once: the commands' modules, the CDRW flight, a child forked
* forked  -- a command inside it: a child forked from the loop, cancelled when its client dies

Every flight gets everything it depends on (scenario, fault time, seed) from the coordinator,
so the merged results are the same for any number of workers and any order of completion.

Room 13: may import every room below it (hil.util to hil.runs); Dask is imported only by the
commands that use it.
"""
