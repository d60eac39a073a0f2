"""A DBC file as hil reads it: a regular file of bounded size (hil.util.bounded), parsed by
cantools (strict), and whatever is wrong with it one line naming the file (DbcError): an empty
or binary file, a truncated one, a parser's complaint, a message or signal hil needs missing.
The bus layer's own checks of what was parsed are hil.bus.dbc's.
"""
from __future__ import annotations

import logging
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from hil.util.bounded import UnfitFile, read_bounded
from hil.util.errors import InputError

if TYPE_CHECKING:
    from cantools.database.can import Database

#: a DBC larger than this is no bus's (the project's is 36 kB; a vehicle's a few MB)
DBC_MAX_BYTES = 16 << 20
#: how much of a parser's complaint the one line quotes
_QUOTE_CHARS = 160
#: cantools' parser per file suffix, and the encoding it reads it in (as cantools.load_file)
_FORMATS = {".dbc": ("dbc", "cp1252"), ".sym": ("sym", "cp1252"), ".kcd": ("kcd", "utf-8"),
            ".arxml": ("arxml", "utf-8"), ".cdd": ("cdd", "utf-8")}


class DbcError(InputError, ValueError):
    """A DBC hil cannot use: unreadable, not a CAN database, or one the bus layer does not
    support (one line naming the file; the command line's exit status 2)."""


class DbcMissing(DbcError, KeyError):
    """A message or signal hil needs is not in the DBC (a KeyError too, for who looks one up)."""

    def __str__(self) -> str:
        return str(self.args[0])


def read_dbc(path: Path) -> bytes:
    """The DBC's bytes: a regular file, bounded (DbcError: one line why not)."""
    try:
        return read_bounded(path, DBC_MAX_BYTES, "DBC")
    except UnfitFile as e:
        raise DbcError(str(e)) from None
    except OSError as e:
        raise DbcError(f"DBC {path}: {(e.strerror or str(e)).lower()}") from None


@lru_cache(maxsize=8)
def parse_dbc(path: Path) -> Database:
    """cantools' Database of the DBC, from a bounded read (DbcError: one line why not)."""
    import cantools  # slow to import (python-can with it): only when the DBC must be parsed
    fmt, encoding = _FORMATS.get(path.suffix.lower(), (None, "utf-8"))
    try:
        text = read_dbc(path).decode(encoding)
    except UnicodeDecodeError as e:
        raise DbcError(f"{path}: not a DBC: byte {e.start} is not {encoding} text") from None
    if not text.strip():
        raise DbcError(f"{path}: an empty file, not a DBC")
    # cantools logs what strict parsing lets pass (two messages on one identifier: refused
    # below, in one line); its parser's own complaints about a file, whatever their class,
    # are one line too (a parser of a user's file: MemoryError and RecursionError included)
    log = logging.getLogger("cantools")
    level = log.level
    log.setLevel(logging.ERROR)
    try:
        db = cantools.database.load_string(text, database_format=fmt, strict=True)
    except Exception as e:  # noqa: BLE001 - see above
        raise DbcError(f"{path}: not a DBC this rig reads: {_quote(e, fmt)}") from None
    finally:
        log.setLevel(level)
    if not isinstance(db, cantools.database.can.Database):  # e.g. a diagnostics (.cdd) file
        raise DbcError(f"{path}: not a CAN database")
    return db


def _quote(e: Exception, fmt: str | None) -> str:
    """A parser's complaint, printable and short (a binary file's bytes are neither), without
    cantools' `DBC: "..."` around it."""
    text = str(e).splitlines()[0] if str(e).strip() else type(e).__name__
    if fmt and text.startswith(f'{fmt.upper()}: "') and text.endswith('"'):
        text = text[len(fmt) + 3:-1]
    text = "".join(c if c.isprintable() else "?" for c in text)
    return text if len(text) <= _QUOTE_CHARS else text[:_QUOTE_CHARS] + "..."
