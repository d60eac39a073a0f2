"""Fresh memory, mapped ahead in the User-Mode Linux guest (scripts/with-vcan).

In the guest every page a process touches for the first time is a page fault that the UML
kernel resolves through the host (ptrace and a host mmap): 70-170 us each, measured, against
~1 us on the host.  Python's start, its imports and a flight's data touch ~15,000 pages, so a
`hil run` spent over a second in page faults.  Mapping a region ahead costs ~2 us a page
instead: populate it in the guest (MADV_POPULATE_WRITE) and make the UML kernel map it into
the host process in one go (two mprotect calls over the range).

with-vcan runs the guest's Python with PYTHONMALLOC=malloc, so that small objects come from
glibc's heap rather than from arenas mapped one by one, and sets WITH_VCAN_UML=1.
prefault_heap() then makes glibc keep a large heap (top pad, no trimming, no separate mappings
for big blocks) and maps it ahead.  Elsewhere it does nothing.
"""
from __future__ import annotations

import ctypes
import os
import sys

#: the heap mapped ahead (MiB); beyond it pages are mapped as touched.  Since the guest's side
#: of a CDRW run imports no numpy (hil.offload), 32 MiB beat 64 MiB: 1.39 vs 1.49 s beyond the
#: loop (median of 6 alternated rounds in one guest, 2026-11-23).
HEAP_MB = 32
_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3   # glibc's mallopt parameters
_MMAP_THRESHOLD_MAX = 32 << 20                                   # glibc's largest (64-bit)
_MADV_POPULATE_WRITE = 23
_PROT_READ, _PROT_READ_WRITE = 1, 3
_PAGE = 4096
_mapped = False   # once per process


def wanted() -> bool:
    """In a with-vcan UML guest, with Python's allocations going to glibc's heap."""
    return (os.environ.get("WITH_VCAN_UML") == "1" and os.environ.get("PYTHONMALLOC") == "malloc"
            and sys.platform == "linux")


def prefault_heap(megabytes: int = HEAP_MB) -> bool:
    """Grow glibc's heap by `megabytes` and map it ahead; False when not wanted or refused
    (the process then runs as it would have, only slower)."""
    global _mapped
    if _mapped or not wanted():
        return _mapped
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.malloc.restype, libc.malloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t]
        libc.free.argtypes = [ctypes.c_void_p]
        libc.sbrk.restype, libc.sbrk.argtypes = ctypes.c_void_p, [ctypes.c_ssize_t]
        libc.madvise.argtypes = libc.mprotect.argtypes = [ctypes.c_void_p, ctypes.c_size_t,
                                                          ctypes.c_int]
        size = megabytes << 20
        settings = ((_M_TRIM_THRESHOLD, 2 * size), (_M_TOP_PAD, size),
                    (_M_MMAP_THRESHOLD, _MMAP_THRESHOLD_MAX))
        if not all(libc.mallopt(param, value) == 1 for param, value in settings):
            return False
        block = libc.malloc(1 << 20)          # extends the heap by the top pad
        if not block:
            return False
        start, end = (block + _PAGE - 1) & ~(_PAGE - 1), libc.sbrk(0) & ~(_PAGE - 1)
        libc.free(block)                      # the free top of the heap, not given back
        if end - start < size // 2:           # the heap did not grow as asked: leave it
            return False
        length = end - start
        _mapped = (libc.madvise(start, length, _MADV_POPULATE_WRITE) == 0
                   and libc.mprotect(start, length, _PROT_READ) == 0
                   and libc.mprotect(start, length, _PROT_READ_WRITE) == 0)
        return _mapped
    except (OSError, AttributeError):
        return False
