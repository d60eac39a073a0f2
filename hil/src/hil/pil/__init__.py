"""Processor-in-the-loop: the Cortex-M4F image (firmware/target) under QEMU.

bootcfg  the boot configuration record the image reads instead of a command line
qemu     the QEMU command line, booting the image, and its SLCAN pty as a frame link
"""
