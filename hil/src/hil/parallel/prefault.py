"""A forked process's memory made its own before it works: a warm rig's spare command process
(hil.parallel.forked) breaks its copy-on-write sharing with the loop while it waits.

After a fork, the first write to each page the child shares with its parent faults, and the
kernel copies the page.  In the User-Mode Linux guest a fault is a round trip through the host
(29 us a page, measured); a command wrote about 4,000 of them (0.1 s of a 0.3 s command),
mostly reference counts and allocations in pages of the loop's objects.
MADV_POPULATE_WRITE (Linux 5.14) copies them ahead, inside the kernel, at about 3 us a page:
the whole private writable memory (about 130 MB after the commands' imports) in 0.1 s of the
spare's wait, a chunk at a time, stopping when its command comes.  The cost: the spare's memory
is its own (the guest has 1 GB; one spare at a time).
"""
from __future__ import annotations

import ctypes
import errno
import select
from collections.abc import Iterator
from pathlib import Path

MADV_POPULATE_WRITE = 23
#: the bytes populated between two looks for the command
CHUNK = 1 << 20

_libc = ctypes.CDLL(None, use_errno=True)
_libc.madvise.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int]
_libc.madvise.restype = ctypes.c_int


def private_writable(maps: Path = Path("/proc/self/maps")) -> Iterator[tuple[int, int]]:
    """(start, end) of this process's private writable mappings (its heap, the allocators'
    arenas, the libraries' data): what a fork shares copy-on-write."""
    for line in maps.read_text().splitlines():
        fields = line.split()
        if fields[1].startswith("rw") and fields[1].endswith("p"):
            start, end = (int(x, 16) for x in fields[0].split("-"))
            yield start, end


def populate(stop_fd: int) -> int:
    """This process's private writable pages made its own (MADV_POPULATE_WRITE), until
    stop_fd is readable: how many bytes.  None on a kernel without the advice; a mapping the
    kernel refuses to populate (one without pages to give: a guard) is left as it is."""
    done = 0
    for start, end in private_writable():
        for at in range(start, end, CHUNK):
            if select.select([stop_fd], [], [], 0)[0]:
                return done
            n = min(CHUNK, end - at)
            if _libc.madvise(at, n, MADV_POPULATE_WRITE) != 0:
                if ctypes.get_errno() == errno.EINVAL and not done:
                    return 0                  # a kernel without MADV_POPULATE_WRITE
                break
            done += n
    return done
