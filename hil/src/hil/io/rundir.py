"""Result safety: atomic file writes and the staged run directory.

Every file a run writes goes first into a new staging directory next to ``--out``
(``.NAME.partial-HOST-PID-TOKEN``: the host, the process and a random token, made with one
mkdir, which fails rather than share a directory -- PIDs repeat across fresh guests and
machines); when the run is done, that directory is renamed into place in one
step, so ``--out`` holds either the previous complete results or the new complete ones, never
a mixture.  Each file inside is itself written atomically (temporary file, rename), so even a
copy made while a run writes never sees half a CSV.  What a run wrote is on the disk before it
is published: one syncfs(2) of the staging directory's filesystem then, rather than an fsync
of every file and of its directory as it is written (11 of them in a `hil run cdrw`: 2-4 ms in
all on a quiet disk, ~60 ms beside other writers, in the UML guest); a file written anywhere
else is fsynced at once.

What ``--out`` may already be:
  * missing or empty: the staging directory is renamed onto it;
  * a complete earlier hil run (its ``.hil-run.json`` lists every file in it, and nothing else
    is there): it is swapped out and removed (only the files it lists, which hil wrote);
  * anything else (the user's own files): refused, exit 2, unless ``--force``; with
    ``--force`` the new files are moved in one by one (same names replaced), and every other
    file stays untouched.
A run that fails keeps what it had (bus.log, fcc.log, any result written) in
``NAME.failed-YYYYmmddTHHMMSS``, next to ``--out``, with a ``FAILED`` file that says why;
``--out`` itself is not touched.  A run removes only directories it made itself (its own
staging directory, the earlier run it swapped out); when another run published into the
same ``--out`` meanwhile, its results are left where they are (one line, exit 1).
"""
from __future__ import annotations

import ctypes
import json
import os
import re
import shutil
import socket
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from hil.util.bounded import read_bounded
from hil.util.errors import InputError

#: the list of files a complete hil run wrote (what makes a directory "hil's own")
MANIFEST = ".hil-run.json"
#: a manifest lists a run's files: a few kB (one larger, or not a regular file, is not hil's)
MANIFEST_MAX_BYTES = 16 << 20
#: in a failed run's directory: why it failed
FAILED = "FAILED"
_STAGE = re.compile(r"\.(.+)\.partial-[A-Za-z0-9_.-]+?-\d+-[0-9a-f]{16}")


def unique_tag() -> str:
    """HOST-PID-TOKEN: different for every process on every machine and guest."""
    host = re.sub(r"[^A-Za-z0-9_.-]", "_", socket.gethostname())[:40] or "host"
    # (os.urandom, as secrets.token_hex: secrets would load hmac and OpenSSL's libcrypto
    # before a run starts, ~20 ms in the UML guest)
    return f"{host}-{os.getpid()}-{os.urandom(8).hex()}"


class OutDirRefused(InputError):
    """--out holds files hil did not write (one line; the CLI exits 2)."""


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def atomic_write(path: Path, data: bytes) -> Path:
    """Write a whole file or nothing: a temporary file beside it, fsync, rename over it.  A
    full disk or a kill leaves the old file (or none), never a truncated one.  In a staging
    directory the fsyncs wait for its publication (make_durable)."""
    path = Path(path)
    now = published_path(path) == path   # not in a staging directory: durable at once
    tmp = path.with_name(f".{path.name}.tmp-{unique_tag()}")
    try:
        with open(tmp, "wb") as fh:
            fh.write(data)
            if now:
                fh.flush()
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            tmp.unlink()
        except OSError:
            pass
        raise
    if now:
        _fsync_dir(path.parent)
    return path


def make_durable(root: Path) -> None:
    """Everything written under root on the disk: syncfs(2) of its filesystem, one call
    (Linux); elsewhere an fsync of each file and directory under it.  OSError when the data
    could not be written (a full disk: the files are not published)."""
    syncfs = getattr(ctypes.CDLL(None, use_errno=True), "syncfs", None)
    if syncfs is not None:
        fd = os.open(root, os.O_RDONLY | os.O_DIRECTORY)
        try:
            if syncfs(fd) != 0:
                err = ctypes.get_errno()
                raise OSError(err, os.strerror(err), str(root))
        finally:
            os.close(fd)
        return
    for dirpath, _, filenames in os.walk(root):
        for name in filenames:
            with open(os.path.join(dirpath, name), "rb") as fh:
                os.fsync(fh.fileno())
        _fsync_dir(Path(dirpath))


def atomic_write_text(path: Path, text: str, encoding: str = "utf-8") -> Path:
    return atomic_write(path, text.encode(encoding))


def _files(root: Path) -> list[str]:
    """Every file and link under root, as relative POSIX paths (directories not listed)."""
    out = []
    for dirpath, dirnames, filenames in os.walk(root):
        for name in filenames + [d for d in dirnames if os.path.islink(os.path.join(dirpath, d))]:
            out.append(Path(dirpath, name).relative_to(root).as_posix())
    return sorted(out)


def _manifest(path: Path) -> set[str] | None:
    try:
        doc = json.loads(read_bounded(path / MANIFEST, MANIFEST_MAX_BYTES, "run manifest"))
        files = doc["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not isinstance(files, list) or not all(isinstance(f, str) for f in files):
        return None
    return set(files)


def users_files(path: Path) -> list[Path]:
    """The files in a run directory that hil did not write (not in its manifest; all of them
    when it has none): never overwritten."""
    listed = _manifest(path) or set()
    return [path / f for f in _files(path) if f not in listed | {MANIFEST}]


def is_own_run(path: Path) -> bool:
    """A directory that holds exactly what a complete hil run listed in its manifest."""
    listed = _manifest(path)
    return listed is not None and set(_files(path)) <= listed | {MANIFEST}


def check_out_dir(out: Path, force: bool) -> None:
    """Refuse an --out that exists with files hil did not write (unless force)."""
    if out.exists() and not out.is_dir():
        raise OutDirRefused(f"--out {out}: exists and is not a directory")
    if force or not out.is_dir() or is_own_run(out):
        return
    foreign = [f for f in _files(out) if f not in (_manifest(out) or set()) | {MANIFEST}]
    if foreign:
        raise OutDirRefused(f"--out {out}: not empty and not a hil run directory ({len(foreign)} "
                            f"other file(s), e.g. {foreign[0]}); choose another --out, or "
                            f"--force to add the results (other files are kept)")


def _write_manifest(stage: Path, command: str) -> None:
    doc = {"tool": "hil", "command": command, "complete": True,
           "files": [f for f in _files(stage) if f != MANIFEST]}
    atomic_write_text(stage / MANIFEST, json.dumps(doc, indent=1) + "\n")


def note_written(run_dir: Path, paths: list[Path]) -> None:
    """Files added to a published hil run later (figures drawn by `hil report`): listed in
    its manifest, so the directory stays hil's own."""
    listed = _manifest(run_dir)
    if listed is None:
        return
    doc = json.loads((run_dir / MANIFEST).read_text(encoding="utf-8"))
    doc["files"] = sorted(listed | {Path(p).resolve().relative_to(run_dir.resolve()).as_posix()
                                    for p in paths})
    atomic_write_text(run_dir / MANIFEST, json.dumps(doc, indent=1) + "\n")


def _merge_into(stage: Path, out: Path) -> None:
    """--force: each staged file is added to out; a namesake hil did not write (not in out's
    manifest) is the user's: refused (one line, nothing moved, the results stay in stage)."""
    listed = _manifest(out) or set()
    theirs = [rel for rel in _files(stage)
              if rel not in listed | {MANIFEST} and os.path.lexists(out / rel)]
    if theirs:
        raise OutDirRefused(f"--out {out}: {theirs[0]} is not hil's (not in its {MANIFEST}); "
                            f"--force never overwrites a user's file; the results are in {stage}")
    for rel in _files(stage):
        dst = out / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        if dst.is_dir() and not dst.is_symlink():
            raise OutDirRefused(f"--out {out}: {rel} is a directory, the run has a file there")
        os.replace(stage / rel, dst)
    shutil.rmtree(stage, ignore_errors=True)


def _publish(stage: Path, out: Path, force: bool) -> None:
    if out.is_dir() and any(out.iterdir()):
        if is_own_run(out):
            old = out.with_name(f".{out.name}.old-{unique_tag()}")
            os.rename(out, old)   # old: made by this rename, so this run's to remove
            try:
                os.rename(stage, out)
            except OSError:  # another run published meanwhile: its results stay
                _lost_race(old, out, stage)
            shutil.rmtree(old, ignore_errors=True)  # only what the earlier run wrote
        elif force:
            listed = _manifest(out)
            _merge_into(stage, out)
            if listed is not None:  # the files of the run added to what hil wrote before
                doc = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
                doc["files"] = sorted(listed | set(doc.get("files", [])))
                atomic_write_text(out / MANIFEST, json.dumps(doc, indent=1) + "\n")
        else:  # a foreign file appeared during the run
            raise OutDirRefused(f"--out {out}: files appeared in it during the run; the results "
                                f"are in {stage}")
    else:
        try:
            os.rename(stage, out)  # replaces an empty directory
        except OSError:  # another run published into out meanwhile: its results stay
            _lost_race(None, out, stage)
    _fsync_dir(out.parent)


def _lost_race(old: Path | None, out: Path, stage: Path) -> None:
    if old is not None:  # the earlier run this one swapped out (and would have removed)
        shutil.rmtree(old, ignore_errors=True)
    raise OutDirRefused(f"--out {out}: another run published into it while this one ran; "
                        f"this run's complete results are in {stage}")


def published_path(path: Path) -> Path:
    """Where a path inside a staging directory will be once the run is published (for
    anything that names it for later, e.g. deferred plots)."""
    parts = list(Path(path).parts)
    for i, part in enumerate(parts):
        m = _STAGE.fullmatch(part)
        if m:
            parts[i] = m[1]
    return Path(*parts)


def failed_dir(out: Path) -> Path:
    stamp = time.strftime("%Y%m%dT%H%M%S")
    cand = out.with_name(f"{out.name}.failed-{stamp}")
    i = 1
    while cand.exists():
        i += 1
        cand = out.with_name(f"{out.name}.failed-{stamp}-{i}")
    return cand


@contextmanager
def staged_run(out: Path, command: str, *, force: bool = False) -> Iterator[Path]:
    """The directory to write a run into; published to out when the block ends normally.
    On an exception whatever was written is kept in NAME.failed-TIME (see module doc) and
    the exception gets a note (PEP 678) saying where; a failure before any file was written
    leaves nothing."""
    out = Path(out)
    check_out_dir(out, force)
    out.parent.mkdir(parents=True, exist_ok=True)
    stage = out.with_name(f".{out.name}.partial-{unique_tag()}")
    stage.mkdir()   # atomic, and fails if it exists: the directory is this run's alone
    try:
        yield stage
    except BaseException as e:
        if not _files(stage):  # failed before writing anything: nothing to keep
            shutil.rmtree(stage, ignore_errors=True)
            raise
        kept = failed_dir(out)
        first = str(e).splitlines()[0] if str(e) else type(e).__name__
        try:
            atomic_write_text(stage / FAILED, f"hil {command} failed: {first}\n")
            make_durable(stage)
            os.rename(stage, kept)
        except OSError:
            kept = stage
        what = "bus log and partial results" if (kept / "bus.log").is_file() else "partial results"
        e.add_note(f"{what} kept in {kept}")
        raise
    _write_manifest(stage, command)
    make_durable(stage)
    _publish(stage, out, force)
