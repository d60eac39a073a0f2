"""hil's diagnostics: records of the logging module under the logger "hil" (each module takes
``logging.getLogger(__name__)``), shown on stderr as ``hil: MESSAGE``.

What shows is chosen once, by the command line (configure(), from hil.cli): warnings always;
``-v``/``--verbose`` adds the info records (what was found where: the scenario, the programs,
fcc's command line, the cross-build's steps); ``--debug`` adds the debug records, each with its
time since start and its module.  Python's own warnings (numpy's, matplotlib's) go the same way.

The one-line errors and the tables are not log records: they are the CLI's contract with its
user (stderr's last line, stdout), printed as they are whatever the level.
"""
from __future__ import annotations

import logging
import sys

ROOT = "hil"
#: a record as the user sees it, by level shown (the debug form says when and where)
FORMATS = {logging.DEBUG: "hil: %(relativeCreated)7.0f ms %(name)s: %(message)s",
           logging.INFO: "hil: %(message)s", logging.WARNING: "hil: %(message)s"}


class _Stderr(logging.StreamHandler):
    """Writes to sys.stderr as it is when a record comes (pytest's capture replaces it)."""

    def __init__(self) -> None:
        super().__init__(sys.stderr)

    @property
    def stream(self) -> object:
        return sys.stderr

    @stream.setter
    def stream(self, _value: object) -> None:
        pass


def level(verbose: int, debug: bool) -> int:
    """The lowest level shown: --debug, else -v (once or more), else warnings only."""
    if debug:
        return logging.DEBUG
    return logging.INFO if verbose else logging.WARNING


def configure(verbose: int = 0, debug: bool = False) -> None:
    """Show hil's records at this verbosity on stderr (again and again: main() per call)."""
    shown = level(verbose, debug)
    logger = logging.getLogger(ROOT)
    for old in [h for h in logger.handlers if isinstance(h, _Stderr)]:
        logger.removeHandler(old)
    handler = _Stderr()
    handler.setFormatter(logging.Formatter(FORMATS[shown]))
    logger.addHandler(handler)
    logger.setLevel(shown)
    logger.propagate = False            # once, not again through a handler of the root's
    logging.captureWarnings(True)
    warnings = logging.getLogger("py.warnings")
    warnings.handlers = [handler]
    warnings.propagate = False
