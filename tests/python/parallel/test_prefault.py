"""hil.parallel.prefault: a forked process's private writable memory made its own ahead of its
work (a warm rig's spare), its contents unchanged, its parent's untouched, and the work not
kept waiting: populating stops as soon as the command's pipe is readable."""
from __future__ import annotations

import os

import pytest

from hil.parallel.prefault import populate, private_writable

SIZE = 8 << 20
PAGE = os.sysconf("SC_PAGE_SIZE")


def minor_faults() -> int:
    return int(open("/proc/self/stat").read().rsplit(")", 1)[1].split()[7])


def test_private_writable_mappings_hold_this_processs_data():
    data = bytearray(SIZE)
    address = id(data)   # (the object's header: its buffer is further, in the same kind of mapping)
    assert any(start <= address < end for start, end in private_writable())


def test_a_forked_child_owns_its_pages_after_populating_and_its_parent_keeps_its_own():
    data = bytearray(b"x" * SIZE)
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:        # the child: exit 0 when populated, unchanged, and its writes fault no more
        code = 1
        try:
            done = populate(r)
            if done == 0:
                code = 3                                   # a kernel without the advice
            else:
                before = minor_faults()
                for at in range(0, SIZE, PAGE):
                    data[at] = ord("y")
                faults = minor_faults() - before
                code = 0 if done >= SIZE and faults < SIZE // PAGE // 8 else 2
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    code = os.waitstatus_to_exitcode(status)
    if code == 3:
        pytest.skip("the kernel has no MADV_POPULATE_WRITE (Linux 5.14)")
    assert code == 0
    assert data == b"x" * SIZE                             # the parent's copy is its own
    os.close(r)
    os.close(w)


def test_populating_stops_when_the_command_has_come():
    r, w = os.pipe()
    os.write(w, b"command")
    assert populate(r) == 0
    os.close(r)
    os.close(w)
