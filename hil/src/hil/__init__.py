"""Hardware-in-the-loop simulator for the fcc flight computer."""
from . import guestmem as _guestmem

# First thing, before the imports and the flight data: in the UML guest fresh pages are slow.
_guestmem.prefault_heap()
