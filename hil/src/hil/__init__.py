"""Hardware-in-the-loop simulator for the fcc flight computer.

One room per concern, lowest first; a module imports its own room and the rooms before it
(tests/python/test_imports.py keeps it so, with no cycle between modules):

    util       rounding, progress bars, child processes
    io         the run directory, CSV/JSON, where the tools are
    bus        DBC, codec, E2E, SecOC, logs, the protocol's numbers
    scenario   scenario files, options, fault descriptions
    sim        plants, sensors, fault injection, the drivers that make frames
    targets    the device under test: host, qemu-m4f, external
    rig        the session, link, recorder, lockstep, realtime, time sync, one flight
    results    a flight's results, metrics, report tables
    reference  the numpy reference of the identification
    plots      the papers' figures
    runs       the commands that fly: run, campaign, sweep, demo, replay
    parallel   campaigns on many rigs (Dask)
    bench      the benchmarks' Python (scripts/bench.d)
    cli        `hil` (nothing imports it)
"""


def __getattr__(name: str) -> str:
    """hil.__version__: the installed distribution's version (hil/pyproject.toml, the one place
    it is written), looked up when asked: importlib.metadata costs 0.1 s in the UML guest."""
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version
        try:
            return version("hil")
        except PackageNotFoundError:
            return "unknown (not installed)"
    raise AttributeError(f"module 'hil' has no attribute {name!r}")
