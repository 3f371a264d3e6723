"""Whole collections on a Dask cluster: the same objects, output names, results log and resume
rules as ``facet thumbs --manifest`` on one machine, rendered by the cluster's workers.

    from distributed import Client
    import facet.distributed

    client = Client("tcp://scheduler:8786")
    summary = facet.distributed.render_collection(
        client, "/data/objects.jsonl", "/data/thumbs", log="/data/thumbs.jsonl", resume=True, size=512)
    print(summary.rendered, summary.failed, summary.objects_per_second)

Each task is a few lines of the manifest, rendered on a worker by ``facet thumbs --manifest
MANIFEST --manifest-lines ...``: every object is still loaded and rendered in a facet worker
process of its own, so a file that crashes or hangs the importer costs only itself. Lines that
share an id go to one task, so that facet reports duplicates as it does on one machine. Each task
returns the log lines facet wrote for it and this process appends them to the log as tasks finish,
one ``write()`` under ``flock`` each, as facet does. A Dask worker that dies takes its running
tasks with it; Dask runs them again on another worker, and only a finished task's lines reach the
log, so every object gets one line.

The manifest, the model files and ``out_dir`` must have the same paths on every worker (a shared
file system), and every worker needs this package installed (its ``facet`` executable runs the
tasks).
"""
from __future__ import annotations

import fcntl
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import uuid
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple

__all__ = ["Summary", "render_collection", "output_stem", "shard_of"]

# Options that render_collection sets itself or that make no sense per task.
_RESERVED = {"manifest", "output", "o", "shard", "log", "resume", "manifest_lines", "print_config", "help"}


@dataclass
class Summary:
    """What became of a collection: counts of this call's objects (manifest lines)."""

    objects: int = 0          # manifest lines in the collection
    rendered: int = 0         # rendered by this call
    failed: int = 0           # failed in this call ("status": "failed" lines)
    skipped: int = 0          # done before (resume) and left alone
    seconds: float = 0.0      # wall time of the whole call
    failures: Dict[str, int] = field(default_factory=dict)  # by the log's "reason"

    @property
    def objects_per_second(self) -> float:
        """Objects rendered or failed per second of wall time."""
        done = self.rendered + self.failed
        return done / self.seconds if self.seconds > 0 else 0.0


def output_stem(object_id: str) -> str:
    """The stem of an object's output names, as facet makes it from the id (README,
    "Collections"): bytes A-Z a-z 0-9 - _ . ~ kept, every other byte and a leading '.' as %XX."""
    keep = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_.~"
    return "".join(chr(b) if b in keep and not (i == 0 and b == ord(".")) else "%%%02X" % b
                   for i, b in enumerate(object_id.encode("utf-8", "surrogateescape")))


def shard_of(object_id: str, count: int) -> int:
    """The shard of an id among ``count``, as ``facet thumbs --shard K/N`` picks it:
    fmix64(FNV-1a-64(id)) mod N."""
    mask = (1 << 64) - 1
    h = 0xCBF29CE484222325
    for b in object_id.encode("utf-8", "surrogateescape"):
        h = ((h ^ b) * 0x100000001B3) & mask
    for k in (0xFF51AFD7ED558CCD, 0xC4CEB9FE1A85EC53):
        h = ((h ^ (h >> 33)) * k) & mask
    return (h ^ (h >> 33)) % count


def _executable() -> str:
    """The facet command line installed with this package."""
    exe = Path(__file__).resolve().parent / "bin" / "facet"
    if not exe.is_file():
        raise FileNotFoundError(f"{exe}: the facet command line is not installed with this package")
    return str(exe)


def _option_args(options: Dict[str, Any]) -> List[str]:
    """``size=512, up_axis="z", background=(1, 0, 0)`` as ``--size 512 --up-axis z --background 1,0,0``."""
    args: List[str] = []
    for key, value in options.items():
        if key in _RESERVED:
            raise TypeError(f"render_collection() sets --{key.replace('_', '-')} itself; '{key}' is not an option here")
        flag = "--" + key.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            args.append(flag)
        elif isinstance(value, (list, tuple)):
            args += [flag, ",".join(str(v) for v in value)]
        else:
            args += [flag, str(value)]
    return args


_BLANK = b" \t\r\v\f"


def _manifest_lines(manifest: Path) -> List[Tuple[int, int, str]]:
    """(byte offset, line number, key) of each line facet reads as an entry; the key is the id
    the line gives facet, or for a line without a readable one its text."""
    data = manifest.read_bytes()
    lines: List[Tuple[int, int, str]] = []
    json_lines: Optional[bool] = None
    offset = 0
    for number, raw in enumerate(data.split(b"\n"), start=1):
        start, offset = offset, offset + len(raw) + 1
        text = raw.strip(_BLANK)
        if not text or text.startswith(b"#"):
            continue
        if json_lines is None:
            json_lines = text.startswith(b"{")
        key = text.decode("utf-8", "surrogateescape")
        if not json_lines:
            lines.append((start, number, key))
            continue
        try:
            entry = json.loads(text)
        except ValueError:
            entry = None
        if isinstance(entry, dict):
            object_id = entry.get("id", entry.get("path"))
            if isinstance(object_id, str) and object_id:
                key = object_id
        lines.append((start, number, key))
    return lines


def _tasks(lines: Sequence[Tuple[int, int, str]], per_task: int) -> List[List[Tuple[int, int]]]:
    """Lines grouped by key (in order of first appearance), the groups packed into tasks of about
    ``per_task`` lines; a group is never split."""
    groups: Dict[str, List[Tuple[int, int]]] = {}
    for offset, number, key in lines:
        groups.setdefault(key, []).append((offset, number))
    tasks: List[List[Tuple[int, int]]] = []
    current: List[Tuple[int, int]] = []
    for group in groups.values():
        current += group
        if len(current) >= per_task:
            tasks.append(current)
            current = []
    if current:
        tasks.append(current)
    return tasks


def _finished_lines(log: Path) -> Dict[str, str]:
    """The latest "ok" line of each id in a results log (complete lines only)."""
    finished: Dict[str, str] = {}
    if not log.exists():
        return finished
    with open(log, "rb") as f:
        for raw in f:
            if not raw.endswith(b"\n"):
                break  # a torn last line: facet skips it too
            try:
                record = json.loads(raw)
            except ValueError:
                continue
            if isinstance(record, dict) and record.get("status") == "ok" and isinstance(record.get("id"), str):
                finished[record["id"]] = raw.decode("utf-8")
    return finished


class _LogAppender:
    """Appends lines to a results log as facet does: one write() each, under an exclusive flock,
    a torn last line (a writer killed mid-line) cut off first."""

    def __init__(self, path: Path):
        path.parent.mkdir(parents=True, exist_ok=True)
        self.fd = os.open(path, os.O_RDWR | os.O_APPEND | os.O_CREAT | os.O_CLOEXEC, 0o644)
        if os.fstat(self.fd).st_size > 0 and os.pread(self.fd, 1, 0) != b"{":
            os.close(self.fd)
            raise ValueError(f"{path}: is not a facet results log (its first line is not a JSON object)")

    def append(self, lines: Iterable[str]) -> None:
        data = "".join(lines).encode("utf-8")
        if not data:
            return
        fcntl.flock(self.fd, fcntl.LOCK_EX)
        try:
            size = os.fstat(self.fd).st_size
            if size > 0 and os.pread(self.fd, 1, size - 1) != b"\n":
                start = max(0, size - (1 << 20))
                tail = os.pread(self.fd, size - start, start)
                newline = tail.rfind(b"\n")
                if newline >= 0 or start == 0:
                    os.ftruncate(self.fd, start + newline + 1 if newline >= 0 else 0)
            os.write(self.fd, data)
        finally:
            fcntl.flock(self.fd, fcntl.LOCK_UN)

    def close(self) -> None:
        os.close(self.fd)


_TEMPORARY = re.compile(r"^(.*)\.tmp[0-9]+$")


def _remove_temporaries(out_dir: Path, names: set) -> None:
    """Removes the temporaries (NAME.tmpDIGITS) of outputs in ``names`` that killed workers left:
    files, and the staging folders of objects with views or passes; one pass over the folder, which
    the tasks leave to this process."""
    try:
        entries = list(os.scandir(out_dir))
    except FileNotFoundError:
        return
    for entry in entries:
        m = _TEMPORARY.match(entry.name)
        if m and m.group(1) in names:
            try:
                if entry.is_dir(follow_symlinks=False):
                    shutil.rmtree(entry.path, ignore_errors=True)
                else:
                    os.unlink(entry.path)
            except FileNotFoundError:
                pass


def _render_task(executable: Optional[str], manifest: str, out_dir: str, lines: List[Tuple[int, int]],
                 previous: List[str], args: List[str], resume: bool) -> List[str]:
    """On a worker: renders a task's manifest lines with facet thumbs and returns the log lines it
    wrote. ``previous`` are the log's earlier "ok" lines of these ids, which --resume reads."""
    exe = executable or _executable()
    with tempfile.TemporaryDirectory(prefix="facet-task-") as tmp:
        log = os.path.join(tmp, "log.jsonl")
        before = "".join(previous).encode("utf-8")
        with open(log, "wb") as f:
            f.write(before)
        command = [exe, "thumbs", "--manifest", manifest, "-o", out_dir, "--log", log,
                   "--manifest-lines", ",".join(f"{offset}:{number}" for offset, number in lines)]
        command += (["--resume"] if resume else []) + args
        # facet dies with this worker (a worker that is killed must not leave it rendering).
        setpriv = shutil.which("setpriv")
        if setpriv:
            command = [setpriv, "--pdeathsig", "KILL", "--"] + command
        done = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if done.returncode not in (0, 1):
            message = done.stderr.decode("utf-8", "replace").strip()
            raise RuntimeError(f"facet thumbs ended with status {done.returncode}: {message[-2000:]}")
        with open(log, "rb") as f:
            f.seek(len(before))
            written = f.read().decode("utf-8")
    return [line + "\n" for line in written.split("\n") if line]


def render_collection(client: Any, manifest: os.PathLike | str, out_dir: os.PathLike | str, *,
                      log: Optional[os.PathLike | str] = None, resume: bool = False, objects_per_task: int = 8,
                      executable: Optional[str] = None, progress: bool = False, **options: Any) -> Summary:
    """Renders every object of ``manifest`` into ``out_dir`` on the Dask cluster of ``client``.

    Parameters
    ----------
    client : distributed.Client
        The cluster's client. Its workers need this package and the same paths as this process.
    manifest : path
        A ``facet thumbs`` manifest (README, "Collections"): a text file of paths, or JSON Lines
        with ``path``, ``id`` and per-object options. Relative paths are relative to its folder.
    out_dir : path
        Where the outputs go, named by the ids exactly as ``facet thumbs --manifest`` names them.
    log : path, optional
        The results log (``facet thumbs --log``'s format) to append one line per object to.
    resume : bool
        Skip the objects the log has done with the same options (``--resume``; needs ``log``).
    objects_per_task : int
        Manifest lines per Dask task (lines sharing an id stay together).
    executable : str, optional
        The facet executable on the workers (default: the one installed with this package there).
    progress : bool
        Print a line per finished task on stderr.
    **options
        ``facet thumbs`` options: ``size=512``, ``up_axis="z"``, ``shading="flat"``,
        ``background=(1, 1, 1)``, ``timeout=30``, ... (``threads``: per task, default 1, as each
        Dask worker thread runs a task).

    Returns
    -------
    Summary
        Counts of rendered, failed and skipped objects, failures by reason, and the time.

    Raises
    ------
    ValueError
        When facet refuses the options or the manifest (its message), or ``resume`` without ``log``.
    """
    start = time.monotonic()
    if objects_per_task < 1:
        raise ValueError(f"objects_per_task must be 1 or more, got {objects_per_task}")
    if resume and log is None:
        raise ValueError("resume=True needs log=, the log it resumes from")
    manifest_path = Path(manifest).resolve()
    out_path = Path(out_dir).resolve()
    options.setdefault("threads", 1)
    args = _option_args(options)
    # facet checks the options and the manifest once, here, the way it will on the workers.
    check = subprocess.run([_executable(), "thumbs", "--manifest", str(manifest_path), "-o", str(out_path),
                            "--print-config"] + args, stdin=subprocess.DEVNULL, capture_output=True, text=True)
    if check.returncode != 0:
        raise ValueError(check.stderr.strip() or f"facet thumbs refused the options (status {check.returncode})")

    lines = _manifest_lines(manifest_path)
    tasks = _tasks(lines, objects_per_task)
    log_path = Path(log).resolve() if log is not None else None
    previous = _finished_lines(log_path) if (resume and log_path) else {}
    key_of = {(offset, number): key for offset, number, key in lines}
    # The thumbnails NAME.png, and the folders NAME of objects with views or passes.
    outputs = {name for _, _, key in lines for name in (output_stem(key), output_stem(key) + ".png")}
    _remove_temporaries(out_path, outputs)
    appender = _LogAppender(log_path) if log_path else None

    import distributed  # here: facet.distributed's helpers and its checks need no Dask

    summary = Summary(objects=len(lines))
    failures: Counter = Counter()
    run = uuid.uuid4().hex[:12]
    futures = []
    for i, task in enumerate(tasks):
        earlier = [previous[key_of[line]] for line in task if key_of[line] in previous]
        futures.append(client.submit(_render_task, executable, str(manifest_path), str(out_path), task, earlier, args,
                                     resume, key=f"facet-render-{run}-{i}", pure=False))
    try:
        for done, future in enumerate(distributed.as_completed(futures), start=1):
            written = future.result()
            for line in written:
                record = json.loads(line)
                if record.get("status") == "ok":
                    summary.rendered += 1
                else:
                    summary.failed += 1
                    failures[record.get("reason") or "failed"] += 1
            if appender:
                appender.append(written)
            if progress:
                print(f"facet.distributed: [{done}/{len(futures)} tasks] {summary.rendered} rendered, "
                      f"{summary.failed} failed", file=sys.stderr, flush=True)
    finally:
        if appender:
            appender.close()
        for future in futures:
            future.cancel()
    _remove_temporaries(out_path, outputs)
    summary.skipped = summary.objects - summary.rendered - summary.failed
    summary.failures = dict(failures)
    summary.seconds = time.monotonic() - start
    return summary
