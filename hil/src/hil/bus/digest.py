"""python -m hil.bus.digest DBC OUT.json: the DBC's specification digested for a fast start
(hil.bus.dbc reads it instead of parsing the DBC with cantools; dbc/generate writes it)."""
from __future__ import annotations

import sys
from pathlib import Path

from hil.bus.dbc import write_spec_file


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 2:
        print("usage: python -m hil.bus.digest DBC OUT.json", file=sys.stderr)
        return 2
    write_spec_file(Path(args[0]), Path(args[1]))
    print(f"generated {args[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
