"""Helpers of no concern of their own: rounding as the firmware rounds, progress bars, child
processes that die with the rig.

Room 1 of hil (tests/python/test_imports.py keeps the order): imports nothing of hil.
"""
