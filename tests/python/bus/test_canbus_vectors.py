"""canbus's frame-length vectors (tests/vectors/canbus/frame_bits.txt) are what
hil.bus.busload.frame_bits counts today: regenerated into a temporary directory, they must
equal the committed file, which tests/c/test_canbus.c checks the C count against."""
from __future__ import annotations

import importlib.util
from pathlib import Path

VEC = Path(__file__).resolve().parents[2] / "vectors" / "canbus"


def test_vectors_are_up_to_date(repo: Path, tmp_path: Path) -> None:
    spec = importlib.util.spec_from_file_location("gen_canbus_vectors",
                                                  repo / "tests" / "gen_canbus_vectors.py")
    assert spec is not None and spec.loader is not None
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    paths = gen.generate(tmp_path)
    assert [p.name for p in paths] == ["frame_bits.txt"]
    for path in paths:
        assert path.read_text() == (VEC / path.name).read_text(), (
            f"tests/vectors/canbus/{path.name} is stale: run tests/gen_canbus_vectors.py")


def test_vectors_cover_every_class() -> None:
    """11- and 29-bit identifiers, DLC 0-8, data and remote frames: each class present."""
    classes = set()
    for line in (VEC / "frame_bits.txt").read_text().splitlines():
        if line.startswith("#"):
            continue
        width, remote, _ident, dlc, _data, bits = line.split()
        assert int(bits) > 0
        classes.add((width, remote, int(dlc)))
    assert classes == {(w, r, d) for w in ("11", "29") for r in ("0", "1") for d in range(9)}
