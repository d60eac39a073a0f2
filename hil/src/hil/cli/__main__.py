"""`python -m hil.cli`: the `hil` program."""
from hil.cli import entry

entry()
