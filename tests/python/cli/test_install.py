"""`pip install` of the hil wheel into a fresh virtualenv outside the clone works as a new user
finds it: the data ship inside the package (the DBC, a copy of dbc/fcc_hil.dbc, the one source;
the test key; the vcan launcher), every firmware program comes from the documented option or
environment variable (hil.io.paths), a missing one is one line before anything flies, and from
another directory it flies: `hil-vcan hil run cdrw`, `hil campaign cdrw --workers 2` (each
worker's guest started by the packaged launcher) and `--target qemu-m4f`.  Installing the wheel
beside other compatible numpy/python-can/cantools keeps them."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from conftest import REPO, build_dir

from hil.bus import dbc

UML = Path(os.environ.get("WITH_VCAN_UML_DIR") or REPO / ".uml")
needs_rig = pytest.mark.skipif(not (UML / "linux.uml").exists() and not Path("/sys/class/net/vcan0").exists(),
                               reason="needs User-Mode Linux (scripts/setup) or a kernel with vcan")
#: the variables that would point the installed hil back into the clone
CLONE_VARS = ("FCC_BUILD_DIR", "FCC_M4F_BUILD_DIR", "FCC_HIL_FCC", "FCC_HIL_DBC", "PYTHONPATH")

PROBE = """
import json, sys
import hil, hil.cli
from hil.bus import dbc
from hil.bus.secoc import TEST_KEY_FILE, read_key_file
from hil.io import paths
print(json.dumps({"pkg": hil.__file__, "version": hil.__version__, "dbc": str(dbc.default_path()),
                  "dbc_text": dbc.default_path().read_text(), "messages": len(dbc.load().messages),
                  "digested": "cantools" not in sys.modules, "key": read_key_file(TEST_KEY_FILE).hex(),
                  "fcc": str(paths.fcc_binary()), "tree": str(paths.source_tree()),
                  "with_vcan": paths.with_vcan()}))
"""


def _pip(python: Path, *args: str, timeout: float = 900) -> subprocess.CompletedProcess[str]:
    r = subprocess.run([str(python), "-m", "pip", *args], capture_output=True, text=True, timeout=timeout)
    assert r.returncode == 0, r.stderr[-2000:]
    return r


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    in_tree_build = REPO / "hil" / "build"     # setuptools builds there; not left behind
    had_build = in_tree_build.exists()
    try:
        _pip(Path(sys.executable), "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(out),
             str(REPO / "hil"), timeout=300)
    finally:
        if not had_build:
            shutil.rmtree(in_tree_build, ignore_errors=True)
    (whl,) = out.glob("hil-*.whl")
    return whl


#: a user's own versions inside hil's ranges, older than hil/constraints.txt's: the install keeps them
USERS_OWN = {"numpy": "2.3.5", "python-can": "4.6.0", "cantools": "45.0.0"}


def installed_versions(venv: Path) -> dict[str, str]:
    r = _pip(venv / "bin" / "python", "list", "--format", "json", timeout=120)
    return {p["name"].lower(): p["version"] for p in json.loads(r.stdout)}


@pytest.fixture(scope="module")
def venv(wheel: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A fresh virtualenv outside the clone, the user's own numpy, python-can and cantools in it
    first, then the wheel (the rest at hil/constraints.txt's versions, from the pip cache where
    scripts/setup left them)."""
    root = tmp_path_factory.mktemp("venv")
    subprocess.run([sys.executable, "-m", "venv", str(root)], check=True, timeout=300)
    py = root / "bin" / "python"
    _pip(py, "install", "-q", "--no-compile", *(f"{k}=={v}" for k, v in USERS_OWN.items()))
    pins = [line for line in (REPO / "hil" / "constraints.txt").read_text().splitlines()
            if line.split("==")[0].lower() not in USERS_OWN]
    constraints = root / "constraints.txt"
    constraints.write_text("\n".join(pins) + "\n")
    report = root / "plan.json"
    _pip(py, "install", "-q", "--no-compile", "-c", str(constraints), "--report", str(report), str(wheel))
    planned = {i["metadata"]["name"].lower() for i in json.loads(report.read_text())["install"]}
    assert "hil" in planned and not planned & set(USERS_OWN), planned   # none up- or downgraded
    return root


@pytest.fixture(scope="module")
def venv_parallel(venv: Path, wheel: Path) -> Path:
    """The same virtualenv with the [parallel] extra added (after the test that wants it absent)."""
    _pip(venv / "bin" / "python", "install", "-q", "--no-compile", "-c", str(venv / "constraints.txt"),
         f"{wheel}[parallel]")
    return venv


def user_env(venv: Path, **extra: str) -> dict[str, str]:
    """A user's shell: the venv's bin first on PATH, nothing that points into the clone."""
    env = {k: v for k, v in os.environ.items() if k not in CLONE_VARS}
    env["PATH"] = f"{venv / 'bin'}:/usr/sbin:/usr/bin:/sbin:/bin"
    env["WITH_VCAN_UML_DIR"] = str(UML)
    env.update(extra)
    return env


def hil(venv: Path, cwd: Path, *args: str, env: dict[str, str],
        timeout: float = 900) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(venv / "bin" / args[0]), *args[1:]], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=timeout, stdin=subprocess.DEVNULL)


def test_packaged_data_is_the_source_data() -> None:
    assert dbc.PACKAGED_DBC.read_bytes() == (REPO / "dbc" / "fcc_hil.dbc").read_bytes()
    from hil.bus.secoc import TEST_KEY_FILE
    assert TEST_KEY_FILE.read_bytes() == (REPO / "tests" / "keys" / "secoc_test.key").read_bytes()
    assert TEST_KEY_FILE.parent == dbc.PACKAGED_DBC.parent      # the package's data, not tests/


def test_wheel_carries_the_license_and_the_data(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        license_file = next(n for n in names if n.endswith(".dist-info/licenses/LICENSE"))
        assert z.read(license_file) == (REPO / "LICENSE").read_bytes()
        for data, source in (("hil/data/fcc_hil.dbc", "dbc/fcc_hil.dbc"),
                             ("hil/data/secoc_test.key", "tests/keys/secoc_test.key"),
                             ("hil/data/with-vcan", "scripts/with-vcan"),
                             ("hil/data/lib/uml.sh", "scripts/lib/uml.sh")):
            assert z.read(data) == (REPO / source).read_bytes(), data
        metadata = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
    requires = [line for line in metadata.splitlines() if line.startswith("Requires-Dist:")]
    assert requires and not any("==" in r.split(";")[0] for r in requires), requires  # ranges
    assert any("dask" in r and 'extra == "parallel"' in r for r in requires)
    assert not any("control" in r and "extra" not in r for r in requires)


def test_installed_hil_stands_alone(venv: Path, tmp_path: Path) -> None:
    fcc = build_dir() / "bin" / "fcc"
    env = user_env(venv, FCC_HIL_FCC=str(fcc))
    out = hil(venv, tmp_path, "python", "-c", PROBE, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert Path(got["pkg"]).is_relative_to(venv)
    assert got["tree"] == "None"                       # no source tree behind it
    assert got["dbc_text"] == (REPO / "dbc" / "fcc_hil.dbc").read_text()
    assert got["messages"] == len(dbc.load().messages)
    assert got["digested"], "the wheel's DBC was parsed by cantools: data/fcc_hil.spec.json missing?"
    assert got["key"] == bytes(range(16)).hex()
    assert got["fcc"] == str(fcc.resolve())
    assert got["with_vcan"][-1].startswith(str(venv)) and got["with_vcan"][1] == f"WITH_VCAN_UML_DIR={UML}"
    v = hil(venv, tmp_path, "hil", "--version", env=env, timeout=120)
    assert v.returncode == 0 and v.stdout == f"hil {got['version']}\n", v
    # offline study, lqg_design from the documented option, in a directory of the user's
    st = hil(venv, tmp_path, "hil", "study", "missile-rms", "--periods", "0.1", "--bits", "8", "--json",
             "--build-dir", str(build_dir()), env=env, timeout=300)
    assert st.returncode == 0, st.stderr
    assert [p["period"] for p in json.loads(st.stdout)["periods"]] == [0.1]


@pytest.mark.parametrize("args, given, missing", [
    (("run", "cdrw"), (), "fcc not found"),                       # nothing given: fcc first
    (("run", "cdrw"), ("fcc",), "bin/canrec: not an executable file"),             # then the recorder
    (("run", "cdrw"), ("fcc", "canrec"), "bin/sid_replay: not an executable file"),  # not after the flight
    (("study", "missile-rms"), (), "lqg_design not found"),
    (("study", "cdrw"), (), "sid_replay not found"),
    (("run", "cdrw", "--target", "qemu-m4f"), (), "fcc_m4f.elf not found"),
])
def test_a_missing_program_is_one_line_before_anything_flies(venv: Path, tmp_path: Path, args: tuple[str, ...],
                                                             given: tuple[str, ...], missing: str) -> None:
    env = user_env(venv)
    if given:                   # a build directory with only these programs
        (tmp_path / "partial" / "bin").mkdir(parents=True)
        for name in given:
            (tmp_path / "partial" / "bin" / name).symlink_to(build_dir() / "bin" / name)
        env["FCC_BUILD_DIR"] = str(tmp_path / "partial")
    bad = hil(venv, tmp_path, "hil", *args, "--out", "out", env=env, timeout=120) if args[0] == "run" \
        else hil(venv, tmp_path, "hil", *args, env=env, timeout=120)
    assert bad.returncode == 2, bad
    line = bad.stderr.strip()
    assert line.count("\n") == 0 and missing in line, line
    assert "$FCC_BUILD_DIR" in line or "$FCC_M4F_BUILD_DIR" in line, line   # how to give it
    assert not (tmp_path / "out").exists()                     # nothing flew, nothing written


def test_shipped_scenarios_by_name_when_installed(venv: Path, tmp_path: Path) -> None:
    """The installed package lists its scenarios and finds them by name from another
    directory; an unknown name is one line naming them (nothing flies)."""
    env = user_env(venv, FCC_BUILD_DIR=str(build_dir()))
    listed = hil(venv, tmp_path, "hil", "run", "--list-scenarios", env=env, timeout=120)
    assert listed.returncode == 0 and "cdrw_multi_fault" in listed.stdout, listed
    bad = hil(venv, tmp_path, "hil", "run", "cdrw", "cdrw_nope", "--out", "out", env=env, timeout=120)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1, bad
    assert "no scenario named 'cdrw_nope' (shipped: " in bad.stderr and "cdrw_multi_fault" in bad.stderr
    wrong = hil(venv, tmp_path, "hil", "run", "cdrw", "missile_default", "--out", "out", env=env, timeout=120)
    assert wrong.returncode == 2 and f"{venv}" in wrong.stderr and "not 'cdrw'" in wrong.stderr, wrong
    assert not (tmp_path / "out").exists()


def test_the_users_versions_stay(venv: Path) -> None:
    have = installed_versions(venv)
    assert {k: have[k] for k in USERS_OWN} == USERS_OWN
    assert "dask" not in have and "control" not in have        # extras only when asked for


def test_a_missing_extra_is_one_line(venv: Path, tmp_path: Path) -> None:
    """Without [parallel], --workers names the extra to install (before venv_parallel adds it)."""
    if "dask" in installed_versions(venv):
        pytest.skip("[parallel] already installed by an earlier test (run the module in order)")
    env = user_env(venv, FCC_BUILD_DIR=str(build_dir()))
    r = hil(venv, tmp_path, "hil", "campaign", "cdrw", "--runs", "2", "--workers", "2", env=env, timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r
    assert "pip install 'hil[parallel]'" in r.stderr


@needs_rig
def test_flies_outside_the_tree(venv_parallel: Path, tmp_path: Path) -> None:
    """The three ways a new user flies, each from a directory of theirs, every program from the
    documented variables or --build-dir."""
    from hil.targets.qemu_m4f import build_image
    venv = venv_parallel
    image = build_image()                              # cross-built in the clone if stale
    work = tmp_path / "user"
    work.mkdir()
    env = user_env(venv, FCC_BUILD_DIR=str(build_dir()))
    scenario = work / "cdrw_2s.toml"
    scenario.write_text('aircraft = "cdrw"\nduration = 2.0\nseed = 3\n\n[[faults]]\nkind = "spike"\n'
                        'signal = "alpha"\nstart = 1.0\nduration = 0.1\nmagnitude = 0.15\n')

    run = hil(venv, work, "hil-vcan", "hil", "run", "cdrw", str(scenario), "--no-plots", "--quiet",
              "--out", "run", env=env)
    assert run.returncode == 0, run.stderr[-2000:]
    assert json.loads((work / "run" / "summary.json").read_text())

    camp_env = {k: v for k, v in env.items() if k != "FCC_BUILD_DIR"}
    camp = hil(venv, work, "hil", "campaign", "cdrw", str(scenario), "--runs", "3", "--workers", "2",
               "--build-dir", str(build_dir()), "--no-plots", "--quiet", "--out", "campaign", env=camp_env)
    assert camp.returncode == 0, camp.stderr[-2000:]
    par = json.loads((work / "campaign" / "run_info.json").read_text())["parallel"]
    assert par["failed"] == 0 and len(par["flights_by_worker"]) == 2        # two guests flew
    runs = json.loads((work / "campaign" / "summary.json").read_text())["cdrw"]["runs"]
    assert [r["run"] for r in runs] == [0, 1, 2]

    named = hil(venv, work, "hil-vcan", "hil", "run", "cdrw", "cdrw_multi_fault", "--no-plots", "--quiet",
                "--out", "named", env=env)             # a shipped scenario by its name
    assert named.returncode == 0, named.stderr[-2000:]
    assert json.loads((work / "named" / "summary.json").read_text())["cdrw"]["flight"]["scenario"] == "cdrw_multi_fault"

    pil_env = {**env, "FCC_M4F_BUILD_DIR": str(image.parent.parent)}
    pil = hil(venv, work, "hil-vcan", "hil", "run", "cdrw", str(scenario), "--target", "qemu-m4f",
              "--no-plots", "--quiet", "--out", "pil", env=pil_env)
    assert pil.returncode == 0, pil.stderr[-2000:]
    assert json.loads((work / "pil" / "run_info.json").read_text())["target"] == "qemu-m4f"
