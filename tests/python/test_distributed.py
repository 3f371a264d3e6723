"""facet.distributed: a collection rendered on a real Dask cluster on the loopback interface (a
`dask scheduler` and two `dask worker` processes, started with this environment's Python so that
they import the installed package), one worker killed with SIGKILL while tasks run; then every
object has exactly one line in the log and the outputs are byte for byte those of one `facet
thumbs --manifest` run of the same manifest. A second call with resume=True renders nothing
again. The cluster test skips, saying why, only when Dask's distributed is not installed; every
process it starts is stopped, within bounded time, whatever happens."""
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

import facet.distributed as fd

TIMEOUT = 120  # seconds for any one step (starting the cluster, a run); the machine may be busy


def model_obj(n: int) -> str:
    a, b = 0.5 + 0.07 * (n % 11), 0.3 + 0.05 * (n % 7)
    return (f"v 0 0 0\nv {a} 0 0\nv 0 {b} 0\nv 0.1 0.2 {1.5 + 0.1 * (n % 5)}\n"
            "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n")


def make_collection(root: Path, count: int) -> Path:
    """`count` models under root/models and a JSON Lines manifest of them, with per-object sizes,
    views and passes (a folder of files each), ids that need encoding, a missing file and a duplicate id."""
    lines = []
    for i in range(count):
        (root / "models").mkdir(parents=True, exist_ok=True)
        (root / "models" / f"m{i}.obj").write_text(model_obj(i))
        entry = {"id": f"set/obj-{i}", "path": f"models/m{i}.obj"}
        if i % 4 == 0:
            entry["size"] = 20
        if i % 8 == 5:
            entry.update(views="orbit:2", passes=["color", "depth"])
        lines.append(json.dumps(entry))
    lines.insert(3, json.dumps({"id": "missing", "path": "models/none.obj"}))
    lines.insert(7, json.dumps({"id": "set/obj-1", "path": "models/m2.obj"}))
    manifest = root / "objects.jsonl"
    manifest.write_text("\n".join(lines) + "\n")
    return manifest


def read_log(path: Path):
    text = path.read_text()
    assert text.endswith("\n"), "the log ends in a torn line"
    return [json.loads(line) for line in text.splitlines()]


def files(folder: Path):
    """Every file and folder under `folder` (relative), a file with its bytes."""
    return {str(p.relative_to(folder)): p.read_bytes() if p.is_file() else None for p in folder.rglob("*")}


def test_output_stem_and_shard_are_facets(facet_exe, tmp_path):
    """The helpers name outputs and pick shards exactly as `facet thumbs` does."""
    ids = ["plain", "a/b", "../x", ".hidden", "é ü", "chair-06", "%2F"]
    (tmp_path / "m.obj").write_text(model_obj(1))
    (tmp_path / "m.jsonl").write_text("".join(json.dumps({"id": i, "path": "m.obj"}) + "\n" for i in ids))
    for k in range(3):
        out = tmp_path / f"out{k}"
        r = subprocess.run([str(facet_exe), "thumbs", "--manifest", str(tmp_path / "m.jsonl"), "-o", str(out),
                            "--size", "8", "--shard", f"{k}/3"], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        expected = {fd.output_stem(i) + ".png" for i in ids if fd.shard_of(i, 3) == k}
        assert {p.name for p in out.iterdir()} == expected


class Gate:
    def __init__(self, folder: Path):
        self.executable = folder / "facet"  # what the workers run instead of facet
        self.holder = folder / "holder"      # written by the held run: its parent's pid (the worker)
        self.opened = folder / "opened"      # lets the held run go on


def gated_facet(folder: Path, facet_exe: Path, hold: int) -> Gate:
    """A stand-in for facet that runs facet, except that its run number `hold` (0 first; numbered
    atomically with mkdir) first writes its parent's pid and waits until the gate is opened, for at
    most TIMEOUT seconds."""
    folder.mkdir()
    gate = Gate(folder)
    gate.executable.write_text(f"""#!/bin/sh
n=0
while ! mkdir "{folder}/run$n" 2>/dev/null; do n=$((n + 1)); done
if [ $n -eq {hold} ]; then
    echo $PPID > "{gate.holder}.tmp" && mv "{gate.holder}.tmp" "{gate.holder}"
    i=0
    while [ ! -e "{gate.opened}" ] && [ $i -lt {TIMEOUT * 10} ]; do sleep 0.1; i=$((i + 1)); done
fi
exec "{facet_exe}" "$@"
""")
    gate.executable.chmod(0o755)
    return gate


@pytest.fixture
def cluster(tmp_path):
    """A scheduler and two workers on 127.0.0.1 (ports chosen by the system, found through the
    scheduler file), each in a session of its own so that it and anything it started can be
    killed together; yields (client, {name: worker process})."""
    distributed = pytest.importorskip(
        "distributed", reason="Dask's distributed is not installed (Debian: python3-distributed; scripts/setup installs it)")
    scheduler_file = tmp_path / "scheduler.json"
    processes = []
    logs = tmp_path / "dask-logs"
    logs.mkdir()

    def start(name, *args):
        out = open(logs / f"{name}.txt", "wb")
        p = subprocess.Popen([sys.executable, "-m", "dask", *args], stdin=subprocess.DEVNULL, stdout=out,
                             stderr=subprocess.STDOUT, start_new_session=True, cwd=tmp_path)
        out.close()
        processes.append(p)
        return p

    client = None
    try:
        start("scheduler", "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
              "--scheduler-file", str(scheduler_file))
        deadline = time.monotonic() + TIMEOUT
        while not scheduler_file.exists():
            assert time.monotonic() < deadline, "the scheduler did not start: " + (logs / "scheduler.txt").read_text()
            assert processes[0].poll() is None, "the scheduler ended: " + (logs / "scheduler.txt").read_text()
            time.sleep(0.1)
        workers = {}
        for name in ("w0", "w1"):
            workers[name] = start(name, "worker", "--scheduler-file", str(scheduler_file), "--host", "127.0.0.1",
                                  "--nthreads", "1", "--no-nanny", "--no-dashboard", "--name", name,
                                  "--local-directory", str(tmp_path / name), "--death-timeout", str(TIMEOUT))
        client = distributed.Client(scheduler_file=str(scheduler_file), timeout=TIMEOUT)
        client.wait_for_workers(2, timeout=TIMEOUT)
        yield client, workers
    finally:
        if client is not None:
            client.close(timeout=10)
        for p in processes:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        for p in processes:
            p.wait(timeout=30)
        # Nothing of ours is left: no worker, and no facet a worker started.
        for p in processes:
            assert p.poll() is not None


def test_a_collection_on_two_workers_one_killed_matches_one_machine(cluster, facet_exe, tmp_path):
    client, workers = cluster
    manifest = make_collection(tmp_path / "data", 40)

    # One machine: the reference.
    ref, ref_log = tmp_path / "ref", tmp_path / "ref.jsonl"
    r = subprocess.run([str(facet_exe), "thumbs", "--manifest", str(manifest), "-o", str(ref), "--size", "24",
                        "--log", str(ref_log)], capture_output=True, text=True)
    assert r.returncode == 1, r.stderr  # the missing file and the duplicate id
    reference = read_log(ref_log)

    # The cluster, with one worker killed while it runs a task, once a few tasks are done. The third
    # task to start is held (by a gate in front of facet) until then, however fast or slow the
    # machine: a kill timed by polling the scheduler could come after the last task.
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    gate = gated_facet(tmp_path / "gate", facet_exe, hold=2)
    result = {}

    def run():
        try:
            result["summary"] = fd.render_collection(client, manifest, out, log=log, objects_per_task=3, size=24,
                                                     executable=str(gate.executable))
        except BaseException as e:  # reported by the test thread
            result["error"] = e

    runner = threading.Thread(target=run)
    runner.start()
    deadline = time.monotonic() + TIMEOUT
    killed = None
    try:
        while killed is None:
            assert runner.is_alive(), "render_collection ended before the held task was seen"
            assert time.monotonic() < deadline, "the held task did not start, or the others did not finish"
            done = len(log.read_text().splitlines()) if log.exists() else 0
            if done >= 3 and gate.holder.exists():
                pid = int(gate.holder.read_text())  # the worker running the held task
                killed = next((name for name, p in workers.items() if p.pid == pid), None)
                assert killed is not None, f"the held task runs in {pid}, not in a worker"
                os.kill(pid, signal.SIGKILL)  # the worker alone: the task's process dies with it
            time.sleep(0.01)
    except BaseException:
        gate.opened.touch()  # the held task goes on, so that the run ends
        raise
    runner.join(TIMEOUT)
    assert not runner.is_alive(), "render_collection did not finish"
    assert "error" not in result, repr(result.get("error"))
    assert workers[killed].wait(timeout=30) == -signal.SIGKILL
    # The task's process (held before it became facet; set to die with the worker as facet is) ended
    # with it: the worker's process group is empty.
    deadline = time.monotonic() + 30
    while True:
        try:
            os.killpg(workers[killed].pid, 0)
        except ProcessLookupError:
            break
        assert time.monotonic() < deadline, "a process of the task outlived its killed worker"
        time.sleep(0.05)

    summary = result["summary"]
    good = [x for x in reference if x["status"] == "ok"]
    assert (summary.objects, summary.rendered, summary.failed, summary.skipped) == (42, len(good), 2, 0)
    assert summary.failures == {"missing": 1, "duplicate_id": 1}
    lines = read_log(log)
    ok_ids = [x["id"] for x in lines if x["status"] == "ok"]
    assert sorted(ok_ids) == sorted(x["id"] for x in good), "each object exactly once"
    assert len(ok_ids) == len(set(ok_ids))
    failed = sorted((x["line"], x["reason"], x["error"]) for x in lines if x["status"] == "failed")
    assert failed == sorted((x["line"], x["reason"], x["error"]) for x in reference if x["status"] == "failed")
    # The outputs: the same names and bytes as one machine's, and nothing else (no temporaries).
    assert files(out) == files(ref)
    for x in lines:
        for name in x["outputs"]:
            assert (out / name).is_file()

    # Again with resume: everything done is skipped; the two bad entries fail again.
    again = fd.render_collection(client, manifest, out, log=log, resume=True, objects_per_task=3, size=24)
    assert (again.rendered, again.failed, again.skipped) == (0, 2, len(good))
    assert len(read_log(log)) == len(lines) + 2
    assert files(out) == files(ref)


def test_bad_options_are_refused_before_anything_is_submitted(tmp_path):
    class NoClient:
        def submit(self, *args, **kwargs):
            raise AssertionError("nothing may be submitted")

    manifest = make_collection(tmp_path, 2)
    with pytest.raises(ValueError, match="--shading"):
        fd.render_collection(NoClient(), manifest, tmp_path / "out", shading="glossy")
    with pytest.raises(ValueError, match="resume"):
        fd.render_collection(NoClient(), manifest, tmp_path / "out", resume=True)
    with pytest.raises(TypeError, match="shard"):
        fd.render_collection(NoClient(), manifest, tmp_path / "out", shard="0/2")
    with pytest.raises(ValueError, match="none.jsonl"):
        fd.render_collection(NoClient(), tmp_path / "none.jsonl", tmp_path / "out")
    assert not (tmp_path / "out").exists()
