"""hil.guestmem: the heap mapped ahead in the UML guest (only there, and only once)."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest

PROBE = ("import resource, hil.guestmem as g; "
         "print(g._mapped, g.prefault_heap(), resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)")


def _probe(**env: str) -> tuple[str, str, int]:
    clean = {k: v for k, v in os.environ.items() if k not in ("WITH_VCAN_UML", "PYTHONMALLOC")}
    r = subprocess.run([sys.executable, "-c", PROBE], env={**clean, **env}, capture_output=True,
                       text=True, timeout=60, check=True)
    mapped, again, rss_kb = r.stdout.split()
    return mapped, again, int(rss_kb)


def test_nothing_happens_outside_the_guest() -> None:
    assert _probe()[:2] == ("False", "False")
    assert _probe(WITH_VCAN_UML="1")[:2] == ("False", "False")      # pymalloc's arenas: no use
    assert _probe(PYTHONMALLOC="malloc")[:2] == ("False", "False")  # not in a guest


def test_the_heap_is_mapped_once_when_importing_hil() -> None:
    mapped, again, rss_kb = _probe(WITH_VCAN_UML="1", PYTHONMALLOC="malloc")
    assert (mapped, again) == ("True", "True")      # done by `import hil`; the second call is a no-op
    from hil.guestmem import HEAP_MB
    assert rss_kb >= HEAP_MB * 1024                 # resident: populated, not just reserved


@pytest.mark.vcan
def test_the_guest_maps_the_heap_of_hil() -> None:
    """scripts/with-vcan sets the environment that makes every hil process in the guest map it."""
    if os.environ.get("WITH_VCAN_UML") != "1":
        pytest.skip("not in a UML guest (a kernel with vcan: nothing to map ahead)")
    import hil.guestmem
    assert os.environ.get("PYTHONMALLOC") == "malloc"
    assert hil.guestmem._mapped
