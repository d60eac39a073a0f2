"""The device under test: `host` (fcc, the Linux build, a child process), `qemu_m4f` (the
Cortex-M4F image under QEMU, its SLCAN UART routed to the rig's bus: board, bootcfg; the image
cross-built by m4f_image) and
`external` (whatever answers on the bus), each a `Device` (device) that owns how it starts,
stops, is described when it dies, and its bus key and trip; `registry` names them for
`--target`.

Room 6: may import hil.util, hil.io, hil.bus (the test key), hil.scenario, hil.sim.
"""
