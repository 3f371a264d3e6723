#!/usr/bin/env python3
"""Collections benchmark (issue 24; not a test): objects per hour per core for a mixed collection of
a few hundred model files, facet thumbs against f3d (one `f3d --output` per file under Xvfb, as its
thumbnailer runs) and, on the glTF files, Google's <model-viewer> in headless Chromium; facet on a
Dask cluster of 1 and 2 workers (facet.distributed) beside them.

The collection: every OBJ, glTF/GLB, STL, PLY and OFF file of Debian's assimp-testmodels and of
libcgal-demo's meshes (some of them broken on purpose: every renderer meets the same ones), and
generated models (OBJ+MTL with a PNG texture, GLB with an embedded texture, binary STL and PLY, OFF)
from 4,000 to 400,000 triangles. "Per core" is by CPU time (user + system of every process of the
run: facet and its workers, f3d and the X server's share, node and Chromium's processes, the Dask
workers and what they started), which the machine's other load changes far less than wall time;
wall times are given beside. Objects per hour count the files attempted, rendered or failed. Rounds
interleave the renderers; the tables give medians. facet is also run on each format alone, against
f3d's time on those files.

    scripts/setup --peers                       # once: chromium, node and <model-viewer>'s npm packages
    build/release/tests/python/venv/bin/python bench/collection_bench.py --data /tmp/facet-collection
                                                # 3 rounds at 256 and 512: about 1.5 h on 2 busy cores
    python3 bench/collection_bench.py --rounds 1 --sizes 256 --skip dask --limit 40   # a quick check
    python3 bench/collection_bench.py --data /tmp/facet-collection --rounds 2 --limit 60 \
        --skip dask,model-viewer,formats        # the f3d ratio on a fixed sample: about 3 min when quiet

The Dask rows need the facet package importable (the test venv has it: `ctest -R Python.InstallWheel`);
without it, or without Dask, they are left out, saying so. <model-viewer> (bench/model_viewer_thumbs.mjs
drives it) needs Debian's chromium, node and the npm packages pinned in bench/peers/package-lock.json,
which `scripts/setup --peers` installs (into ~/.cache/facet/peers, found by default); without them it
is left out, saying so.
"""
import argparse
import ctypes
import json
import math
import os
import re
import shutil
import signal
import statistics
import struct
import subprocess
import sys
import tarfile
import tempfile
import time
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ASSIMP_MODELS = Path("/usr/share/assimp/models")
CGAL_DATA = Path("/usr/share/doc/libcgal-dev/data.tar.gz")
EXTENSIONS = {".obj", ".gltf", ".glb", ".stl", ".ply", ".off"}
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")
PEERS_LOCK = ROOT / "bench" / "peers" / "package-lock.json"
PEERS_HINT = "scripts/setup --peers installs them"


def peers_dir() -> Path:
    """Where `scripts/setup --peers` puts the npm peers (scripts/lib/peers.sh)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "facet" / "peers"


def has_peer_modules(folder: Path) -> bool:
    return all((folder / "node_modules" / m).is_dir() for m in ("@google/model-viewer", "puppeteer-core"))


def model_viewer_problem(folder: Path, given: bool):
    """Why <model-viewer> cannot be measured with this folder (None: it can). A folder given by hand
    is used as it is; the default one must hold the repository's lock, not an older install."""
    if not shutil.which("node") or not Path("/usr/bin/chromium").exists():
        return f"node or /usr/bin/chromium missing: {PEERS_HINT}"
    if not has_peer_modules(folder):
        return f"no @google/model-viewer and puppeteer-core in {folder}/node_modules: {PEERS_HINT}"
    lock = folder / "package-lock.json"
    if not given and (not lock.is_file() or lock.read_bytes() != PEERS_LOCK.read_bytes()):
        return f"{folder} holds another bench/peers/package-lock.json's packages: run scripts/setup --peers again"
    return None


# ---- the collection -------------------------------------------------------------------------

def png_bytes(width, height, seed):
    """A small RGB checker PNG (zlib only)."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)
        for x in range(width):
            on = ((x // 8) + (y // 8) + seed) % 2
            rows += bytes((200 if on else 40, (x * 4 + seed * 30) % 256, (y * 4) % 256))
    chunk = lambda kind, data: struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(bytes(rows), 6)) + chunk(b"IEND", b""))


def surface(kind, n, seed):
    """A UV sphere or torus of 4 n^2 triangles, bumped: positions, normals, uvs, triangles. The seam's
    and the poles' vertices repeat their positions exactly, as a modeller's export does (split for
    the uvs), not within a rounding error."""
    pos, nrm, uv, tris = [], [], [], []
    rows, cols = n, 2 * n
    for i in range(rows + 1):
        v = i / rows
        for j in range(cols + 1):
            u = j / cols
            a = 2 * math.pi * (j % cols) / cols
            if kind == "sphere":
                b = math.pi * v
                bump = 1 + 0.08 * math.sin(5 * a + seed) * math.sin(4 * b + seed * 0.7)
                d = (0.0, 1.0 if i == 0 else -1.0, 0.0) if i in (0, rows) else \
                    (math.sin(b) * math.cos(a), math.cos(b), math.sin(b) * math.sin(a))
                p = tuple(bump * c for c in d) if i not in (0, rows) else d
            else:
                b = 2 * math.pi * (i % rows) / rows
                bump = 1 + 0.08 * math.sin(5 * a + seed) * math.sin(4 * b + seed * 0.7)
                d = (math.cos(b) * math.cos(a), math.sin(b), math.cos(b) * math.sin(a))
                p = ((1 + 0.35 * bump * math.cos(b)) * math.cos(a), 0.35 * bump * math.sin(b),
                     (1 + 0.35 * bump * math.cos(b)) * math.sin(a))
            pos.append(p)
            nrm.append(d)
            uv.append((u * 2, v * 2))
    for i in range(rows):
        for j in range(cols):
            a, b = i * (cols + 1) + j, (i + 1) * (cols + 1) + j
            tris += [(a, b, a + 1), (a + 1, b, b + 1)]
    return pos, nrm, uv, tris


def write_obj(path, mesh, seed):
    pos, nrm, uv, tris = mesh
    png = path.with_suffix(".png")
    png.write_bytes(png_bytes(64, 64, seed))
    path.with_suffix(".mtl").write_text(f"newmtl m\nKd 1 1 1\nmap_Kd {png.name}\n")
    with open(path, "w") as f:
        f.write(f"mtllib {path.with_suffix('.mtl').name}\nusemtl m\n")
        f.writelines(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in pos)
        f.writelines(f"vt {u:.6f} {v:.6f}\n" for u, v in uv)
        f.writelines(f"vn {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in nrm)
        f.writelines(f"f {a+1}/{a+1}/{a+1} {b+1}/{b+1}/{b+1} {c+1}/{c+1}/{c+1}\n" for a, b, c in tris)


def write_stl(path, mesh):
    pos, _, _, tris = mesh
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *pos[k]) for k in t) + b"\0\0")


def write_ply(path, mesh):
    pos, _, _, tris = mesh
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(pos)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(b"".join(struct.pack("<3f", *p) for p in pos))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in tris))


def write_off(path, mesh):
    pos, _, _, tris = mesh
    with open(path, "w") as f:
        f.write(f"OFF\n{len(pos)} {len(tris)} 0\n")
        f.writelines(f"{x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in pos)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in tris)


def write_glb(path, mesh, seed):
    pos, nrm, uv, tris = mesh
    blobs = [b"".join(struct.pack("<3f", *p) for p in pos), b"".join(struct.pack("<3f", *n) for n in nrm),
             b"".join(struct.pack("<2f", *t) for t in uv), b"".join(struct.pack("<3I", *t) for t in tris),
             png_bytes(64, 64, seed)]
    views, data = [], b""
    for blob in blobs:
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(blob)})
        data += blob + b"\0" * (-len(blob) % 4)
    lo = [min(p[k] for p in pos) for k in range(3)]
    hi = [max(p[k] for p in pos) for k in range(3)]
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                    "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
        "textures": [{"source": 0, "sampler": 0}], "samplers": [{}],
        "images": [{"bufferView": 4, "mimeType": "image/png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": len(uv), "type": "VEC2"},
            {"bufferView": 3, "componentType": 5125, "count": 3 * len(tris), "type": "SCALAR"}],
        "bufferViews": views, "buffers": [{"byteLength": len(data)}]}
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(data)))
        f.write(struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(data), b"BIN\0") + data)


def build_collection(root: Path, generated: int) -> list:
    """The collection's files under root (copies, so that each has a folder of its own with its
    textures), returned in a fixed order."""
    files = []
    if ASSIMP_MODELS.is_dir():
        for src in sorted(ASSIMP_MODELS.rglob("*")):
            if src.is_file() and src.suffix.lower() in EXTENSIONS:
                files.append(src)  # read in place: their textures and buffers sit beside them
    if CGAL_DATA.exists():
        with tarfile.open(CGAL_DATA) as tar:
            for m in tar.getmembers():
                if m.isfile() and Path(m.name).suffix.lower() in EXTENSIONS and m.name.startswith("data/meshes/"):
                    m.name = m.name[len("data/meshes/"):]
                    tar.extract(m, root / "cgal")
                    files.append(root / "cgal" / m.name)
    writers = [("obj", write_obj), ("glb", write_glb), ("stl", write_stl), ("ply", write_ply), ("off", write_off)]
    for i in range(generated):
        ext, writer = writers[i % len(writers)]
        n = int(round(math.sqrt(1000 * 100 ** ((i % 17) / 16))))  # 4 n^2 triangles: 4,000 .. 400,000
        mesh = surface("sphere" if i % 2 else "torus", max(n, 8), i)
        path = root / "generated" / f"g{i:03d}" / f"model.{ext}"
        path.parent.mkdir(parents=True, exist_ok=True)
        writer(path, mesh, i) if ext in ("obj", "glb") else writer(path, mesh)
        files.append(path)
    return files


def collection(root: Path, generated: int) -> list:
    """build_collection's files, built once per folder (its list, files-N.txt, written last)."""
    listing = root / f"files-{generated}.txt"
    if listing.exists():
        return [Path(line) for line in listing.read_text().splitlines()]
    files = build_collection(root, generated)
    listing.write_text("".join(f"{f}\n" for f in files))
    return files


# ---- measuring ------------------------------------------------------------------------------

def proc_cpu(pid: int, children: bool = True) -> float:
    """CPU seconds of a live process (and of the children it has waited for)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except FileNotFoundError:
        return 0.0
    ticks = int(fields[11]) + int(fields[12]) + (int(fields[13]) + int(fields[14]) if children else 0)
    return ticks / CLOCK_TICKS


def run_waited(command, env=None, timeout=None):
    """Runs a command; returns (exit status or None on timeout, wall s, CPU s of it and its waited-for
    descendants)."""
    start = time.monotonic()
    p = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                         env=env, start_new_session=True)
    deadline = None if timeout is None else start + timeout
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if deadline and time.monotonic() > deadline:
            os.killpg(p.pid, signal.SIGKILL)
            pid, status, usage = os.wait4(p.pid, 0)
            return None, time.monotonic() - start, usage.ru_utime + usage.ru_stime
        time.sleep(0.002)
    p.returncode = os.waitstatus_to_exitcode(status)
    return p.returncode, time.monotonic() - start, usage.ru_utime + usage.ru_stime


def load_average() -> float:
    return os.getloadavg()[0]


def run_facet(facet, manifest, out, size):
    shutil.rmtree(out, ignore_errors=True)
    status, wall, cpu = run_waited([facet, "thumbs", "--manifest", str(manifest), "-o", str(out), "--size", str(size),
                                    "--threads", "1", "--log", str(out) + ".jsonl"])
    lines = [json.loads(x) for x in Path(str(out) + ".jsonl").read_text().splitlines()]
    Path(str(out) + ".jsonl").unlink()
    ok = sum(1 for x in lines if x["status"] == "ok")
    return {"ok": ok, "failed": len(lines) - ok, "wall": wall, "cpu": cpu}


class Xvfb:
    """An X server of its own for f3d: Xvfb picks a free display and says which (-displayfd), so that
    it never meets another one started at the same moment (a test's, another run's)."""

    def __init__(self):
        read, write = os.pipe()
        self.p = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, pass_fds=(write,))
        os.close(write)
        with os.fdopen(read) as f:
            self.display = ":" + f.readline().strip()
        if self.display == ":":
            raise RuntimeError("Xvfb did not start")

    def cpu(self):
        return proc_cpu(self.p.pid, children=False)

    def close(self):
        self.p.kill()
        self.p.wait()


def run_f3d(files, out, size, xvfb):
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    env = dict(os.environ, DISPLAY=xvfb.display, LP_NUM_THREADS="1")  # llvmpipe on one core: a thumbnailer per core
    ok = failed = 0
    wall = cpu = 0.0
    per_file = {}
    server_before = xvfb.cpu()
    for i, f in enumerate(files):
        png = out / f"{i:04d}.png"
        status, w, c = run_waited(["f3d", f"--output={png}", f"--resolution={size},{size}", str(f)], env=env, timeout=60)
        wall, cpu = wall + w, cpu + c
        per_file[f] = c
        if status == 0 and png.exists():
            ok += 1
        else:
            failed += 1
    return {"ok": ok, "failed": failed, "wall": wall, "cpu": cpu + xvfb.cpu() - server_before, "per_file": per_file}


def descendants_cpu(root: int, seen: dict):
    """Records the CPU seconds (their own, not their children's) of `root` and every live process
    descending from it (this process is their subreaper: orphans stay in the tree)."""
    parent, own = {}, {}
    for entry in os.scandir("/proc"):
        if entry.name.isdigit():
            try:
                fields = Path(entry.path, "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            parent[int(entry.name)] = int(fields[1])
            own[int(entry.name)] = (int(fields[11]) + int(fields[12])) / CLOCK_TICKS
    for pid in own:
        p = pid
        while p > 1 and p != root:
            p = parent.get(p, 0)
        if p == root:
            seen[pid] = own[pid]


def run_model_viewer(modules, files, out, size):
    """<model-viewer> in headless Chromium (bench/model_viewer_thumbs.mjs), one browser for the list;
    its CPU is that of node and every process descending from it (the browser, its zygotes, GPU,
    renderer and utility processes), sampled until they end."""
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    listing = out / "list.json"
    listing.write_text(json.dumps([{"path": str(f), "out": str(out / f"{i:04d}.png")} for i, f in enumerate(files)]))
    env = dict(os.environ, LP_NUM_THREADS="1")
    ctypes.CDLL(None).prctl(36, 1, 0, 0, 0)  # PR_SET_CHILD_SUBREAPER: double-forked helpers stay ours
    start = time.monotonic()
    with open(out / "results.jsonl", "w") as results_file:
        p = subprocess.Popen(["node", str(ROOT / "bench" / "model_viewer_thumbs.mjs"), "--modules", str(modules), "--list",
                              str(listing), "--size", str(size)], stdin=subprocess.DEVNULL, stdout=results_file,
                             stderr=subprocess.DEVNULL, env=env, start_new_session=True)
    seen = {}
    while p.poll() is None:
        descendants_cpu(p.pid, seen)
        if time.monotonic() - start > 60 * len(files) + 120:
            os.killpg(p.pid, signal.SIGKILL)
        time.sleep(0.05)
    lines = (out / "results.jsonl").read_text().splitlines()
    results = [json.loads(x) for x in lines if x.startswith("{")]
    ok = sum(1 for x in results if x["ok"])
    return {"ok": ok, "failed": len(files) - ok, "wall": time.monotonic() - start, "cpu": sum(seen.values())}


class DaskCluster:
    def __init__(self, workers: int, tmp: Path):
        import distributed
        self.dir = Path(tempfile.mkdtemp(dir=tmp, prefix="dask-"))
        scheduler_file = self.dir / "scheduler.json"
        quiet = dict(stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        self.scheduler = subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port", "0",
                                           "--no-dashboard", "--scheduler-file", str(scheduler_file)], **quiet)
        while not scheduler_file.exists():
            time.sleep(0.05)
        self.workers = [subprocess.Popen([sys.executable, "-m", "dask", "worker", "--scheduler-file", str(scheduler_file),
                                          "--host", "127.0.0.1", "--nthreads", "1", "--no-nanny", "--no-dashboard",
                                          "--local-directory", str(self.dir / f"w{i}")], **quiet)
                        for i in range(workers)]
        self.client = distributed.Client(scheduler_file=str(scheduler_file), timeout=120)
        self.client.wait_for_workers(workers, timeout=120)

    def cpu(self):
        return sum(proc_cpu(p.pid) for p in self.workers + [self.scheduler])

    def close(self):
        self.client.close()
        for p in self.workers + [self.scheduler]:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
        shutil.rmtree(self.dir, ignore_errors=True)


def run_dask(cluster, executable, manifest, out, size):
    import resource
    import facet.distributed
    shutil.rmtree(out, ignore_errors=True)
    before = cluster.cpu()
    usage = lambda: [resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    before_self = usage()
    summary = facet.distributed.render_collection(cluster.client, manifest, out, size=size, objects_per_task=8,
                                                       executable=executable)
    # The driver: this process's Dask client, and its check of the options (facet --print-config).
    driver = sum((a.ru_utime - b.ru_utime) + (a.ru_stime - b.ru_stime) for a, b in zip(usage(), before_self))
    return {"ok": summary.rendered, "failed": summary.failed, "wall": summary.seconds,
            "cpu": cluster.cpu() - before + driver}


# ---- the run --------------------------------------------------------------------------------

LABELS = {"facet": "facet thumbs --threads 1", "f3d": "f3d --output, one per file (Xvfb, LP_NUM_THREADS=1)",
          "dask1": "facet.distributed, 1 Dask worker", "dask2": "facet.distributed, 2 Dask workers",
          "model-viewer": "<model-viewer>, headless Chromium (llvmpipe, LP_NUM_THREADS=1), one page"}


def describe(files):
    kinds = {}
    for f in files:
        kinds[f.suffix.lower()] = kinds.get(f.suffix.lower(), 0) + 1
    return f"{len(files)} files ({', '.join(f'{n} {k[1:]}' for k, n in sorted(kinds.items()))})"


def main():
    # Stopped with SIGTERM (or SIGINT, which a background job ignores): the clean-up below still runs.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--facet", default=str(ROOT / "build" / "release" / "bin" / "facet"), help="facet executable")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--sizes", default="256,512")
    parser.add_argument("--generated", type=int, default=100, help="generated models besides Debian's files")
    parser.add_argument("--data", help="keep the collection in this folder and use it again on the next run "
                                       "(it takes a few minutes to build)")
    parser.add_argument("--node-modules", help="a folder with node_modules/@google/model-viewer and puppeteer-core "
                                               "for <model-viewer> on the glTF files (default: scripts/setup --peers's, "
                                               "${XDG_CACHE_HOME:-~/.cache}/facet/peers)")
    parser.add_argument("--limit", type=int, help="every k-th file only, about this many (a quick check)")
    parser.add_argument("--skip", default="", help="comma-separated: f3d, dask, model-viewer, formats (facet on each "
                                                   "format alone)")
    parser.add_argument("--markdown", help="also write the tables here")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    skip = set(filter(None, args.skip.split(",")))
    notes = []
    node_modules = Path(args.node_modules or peers_dir())
    if "model-viewer" not in skip and args.node_modules:
        problem = model_viewer_problem(node_modules, given=True)
        if problem:  # asked for by hand: an error, not a silent gap in the tables
            parser.error(f"--node-modules {args.node_modules}: {problem}")

    tmp = Path(tempfile.mkdtemp(prefix="facet-collection-bench-"))
    clusters, xvfb = {}, None
    try:
        files = collection(Path(args.data) if args.data else tmp / "data", args.generated)
        if args.limit:
            files = files[::max(1, math.ceil(len(files) / args.limit))]
        # The whole collection, and each format alone (facet is run on each; f3d's per-file times
        # are summed by format), glTF and GLB together for <model-viewer>.
        groups = {"all": files}
        for f in files:
            kind = "gltf" if f.suffix.lower() in (".gltf", ".glb") else f.suffix.lower()[1:]
            if "formats" not in skip or (kind == "gltf" and "model-viewer" not in skip):
                groups.setdefault(kind, []).append(f)
        manifests = {}
        for name, group in groups.items():
            manifests[name] = tmp / f"{name}.jsonl"
            manifests[name].write_text("".join(json.dumps({"id": f"{files.index(f):04d}", "path": str(f)}) + "\n"
                                               for f in group))
        print(f"collection: {describe(files)}; load average {load_average():.1f}", flush=True)

        runs = [("facet", name) for name in groups]
        if "f3d" not in skip:
            if shutil.which("f3d") and shutil.which("Xvfb"):
                runs.append(("f3d", "all"))
                xvfb = Xvfb()
            else:
                notes.append("f3d: not measured (f3d or Xvfb missing)")
        if "model-viewer" not in skip:
            problem = model_viewer_problem(node_modules, given=bool(args.node_modules))
            if problem is None:
                runs.append(("model-viewer", "gltf"))
            else:
                notes.append(f"<model-viewer>: not measured ({problem})")
        if "dask" not in skip:
            try:
                import distributed  # noqa: F401
                import facet.distributed  # noqa: F401
                for n in (1, 2):
                    clusters[n] = DaskCluster(n, tmp)
                    runs.append((f"dask{n}", "all"))
            except ImportError as e:
                notes.append(f"Dask: not measured ({e}; run with the test venv's python)")

        results = {}
        for r in range(args.rounds):
            for size in sizes:
                for name, group in runs:
                    out = tmp / "out" / name
                    load = load_average()
                    if name == "facet":
                        res = run_facet(args.facet, manifests[group], out, size)
                    elif name == "f3d":
                        res = run_f3d(files, out, size, xvfb)
                    elif name == "model-viewer":
                        res = run_model_viewer(node_modules, groups[group], out, size)
                    else:
                        res = run_dask(clusters[int(name[4:])], args.facet, manifests[group], out, size)
                    res["load"] = load
                    results.setdefault((name, group, size), []).append(res)
                    print(f"round {r + 1} {name:12s} {group:4s} {size}: {res['ok']} rendered, {res['failed']} failed, "
                          f"wall {res['wall']:.1f} s, CPU {res['cpu']:.1f} s, load {load:.1f}", flush=True)

        loads = [x["load"] for v in results.values() for x in v]
        median = lambda key, name, group, size: statistics.median(x[key] for x in results[(name, group, size)])
        rate = lambda n, cpu: n / cpu * 3600 if cpu > 0 else float("nan")
        lines = [f"Collection: {describe(files)}; {args.rounds} interleaved rounds, medians; load average (1 min) "
                 f"at the start of the runs {min(loads):.1f}-{max(loads):.1f}. Objects per hour per core = files "
                 "attempted / CPU seconds x 3600.", "",
                 "| renderer | size | rendered | failed | wall s | CPU s | objects/hour/core | vs f3d |",
                 "|---|---|---|---|---|---|---|---|"]
        for size in sizes:
            f3d_rate = rate(len(files), median("cpu", "f3d", "all", size)) if ("f3d", "all") in runs else None
            for name, group in runs:
                if group != "all":
                    continue
                first = results[(name, group, size)][0]
                cpu = median("cpu", name, group, size)
                ratio = f"**{rate(len(files), cpu) / f3d_rate:.1f}x**" if f3d_rate and name != "f3d" else "-"
                lines.append(f"| {LABELS[name]} | {size} | {first['ok']} | {first['failed']} | "
                             f"{median('wall', name, group, size):.1f} | {cpu:.1f} | {rate(len(files), cpu):,.0f} | {ratio} |")
        # By format: facet run on each format alone against f3d's own CPU on those files (its X server left out).
        if ("f3d", "all") in runs and len(groups) > 1:
            lines += ["", "By format (CPU ms per file; f3d's X server left out here):", "",
                      "| format | files | size | facet | f3d | f3d / facet |", "|---|---|---|---|---|---|"]
            for size in sizes:
                for group in groups:
                    if group == "all":
                        continue
                    n = len(groups[group])
                    facet_ms = median("cpu", "facet", group, size) / n * 1000
                    f3d_ms = statistics.median(sum(x["per_file"][f] for f in groups[group])
                                               for x in results[("f3d", "all", size)]) / n * 1000
                    lines.append(f"| {group} | {n} | {size} | {facet_ms:.0f} | {f3d_ms:.0f} | {f3d_ms / facet_ms:.1f}x |")
        if ("model-viewer", "gltf") in runs:
            lines += ["", f"glTF and GLB files alone ({describe(groups['gltf'])}; <model-viewer> reads glTF 2.0 only):",
                      "", "| renderer | size | rendered | failed | wall s | CPU s | objects/hour/core | vs <model-viewer> |",
                      "|---|---|---|---|---|---|---|---|"]
            for size in sizes:
                n = len(groups["gltf"])
                mv_rate = rate(n, median("cpu", "model-viewer", "gltf", size))
                for name in ("facet", "model-viewer"):
                    first = results[(name, "gltf", size)][0]
                    cpu = median("cpu", name, "gltf", size)
                    ratio = f"**{rate(n, cpu) / mv_rate:.1f}x**" if name == "facet" else "-"
                    lines.append(f"| {LABELS[name]} | {size} | {first['ok']} | {first['failed']} | "
                                 f"{median('wall', name, 'gltf', size):.1f} | {cpu:.1f} | {rate(n, cpu):,.0f} | {ratio} |")
        lines += [""] + notes
        text = "\n".join(lines)
        print("\n" + text)
        if args.markdown:
            Path(args.markdown).write_text(text + "\n")
    finally:
        if xvfb:
            xvfb.close()
        for c in clusters.values():
            c.close()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
