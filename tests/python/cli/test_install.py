"""`pip install ./hil` (not editable) works away from the source tree: the DBC ships inside
the package (a copy of dbc/fcc_hil.dbc, the one source), fcc is found through --fcc or
$FCC_HIL_FCC, and `hil --version` answers."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

from conftest import REPO, build_dir

from hil.bus import dbc

PROBE = """
import json, sys
import hil, hil.cli
from hil.bus import dbc
from hil.io import paths
print(json.dumps({"pkg": hil.__file__, "dbc": str(dbc.default_path()),
                  "dbc_text": dbc.default_path().read_text(), "messages": len(dbc.load().messages),
                  "digested": "cantools" not in sys.modules,
                  "fcc": str(paths.fcc_binary()), "repo": str(paths.REPO)}))
"""


def test_packaged_dbc_is_the_source_dbc() -> None:
    assert dbc.PACKAGED_DBC.read_bytes() == (REPO / "dbc" / "fcc_hil.dbc").read_bytes()


def test_wheel_runs_outside_the_tree(tmp_path: Path) -> None:
    import json

    whl_dir = tmp_path / "wheel"
    in_tree_build = REPO / "hil" / "build"     # setuptools builds there; not left behind
    had_build = in_tree_build.exists()
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                        "-q", "-w", str(whl_dir), str(REPO / "hil")], capture_output=True, text=True,
                       timeout=300)
    if not had_build:
        shutil.rmtree(in_tree_build, ignore_errors=True)
    assert r.returncode == 0, r.stderr
    (whl,) = whl_dir.glob("hil-*.whl")
    site = tmp_path / "site"
    with zipfile.ZipFile(whl) as z:
        z.extractall(site)
    assert not (site / "hil" / "data" / "fcc_hil.dbc").is_symlink()
    fcc = build_dir() / "bin" / "fcc"
    env = {k: v for k, v in os.environ.items() if k not in ("FCC_BUILD_DIR", "FCC_HIL_DBC")}
    env.update(PYTHONPATH=str(site), FCC_HIL_FCC=str(fcc))
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, cwd=tmp_path,
                         env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert Path(got["pkg"]).is_relative_to(site)
    assert got["repo"] == "None"                       # no source tree behind it
    assert got["dbc_text"] == (REPO / "dbc" / "fcc_hil.dbc").read_text()
    assert got["messages"] == len(dbc.load().messages)
    assert got["digested"], "the wheel's DBC was parsed by cantools: data/fcc_hil.spec.json missing?"
    assert got["fcc"] == str(fcc.resolve())
    v = subprocess.run([sys.executable, "-m", "hil.cli", "--version"], capture_output=True, text=True,
                       cwd=tmp_path, env=env, timeout=120)
    assert v.returncode == 0 and v.stdout.startswith("hil 0."), v
    # no fcc anywhere: one line naming the ways to give it, exit status 2
    env.pop("FCC_HIL_FCC")
    env["PATH"] = "/usr/bin:/bin"
    bad = subprocess.run([sys.executable, "-m", "hil.cli", "run", "cdrw", "--fcc", str(tmp_path / "nope")],
                         capture_output=True, text=True, cwd=tmp_path, env=env, timeout=120)
    assert bad.returncode == 2
    assert bad.stderr.strip().count("\n") == 0 and "--fcc" in bad.stderr
