#!/usr/bin/env python3
"""A large batch under faults (issue 25): N inputs, some bad, killed at random moments, then a full disk.

  bench/batch_faults.py [--spheremap build/spheremap] [--inputs 200] [--bad 20] [--kills 30] [--seed 1]
                        [--jobs 2] [--work /tmp/batch-faults] [--tmpfs-mb 8]

1. Writes the inputs: generated meshes (`spheremap generate`, several shapes and sizes), the smallest
   structures of ../shared/data/pdb/misc when that folder exists (--structures of them), and --bad bad files
   of ten kinds (empty, garbage, open, NaN, index out of range, truncated PLY, not gzip, truncated gzip, genus 1,
   no atoms).
2. Maps them once without faults: the reference summary.
3. Maps them again into a second folder, SIGKILLing (seeded random moments) the batch itself or one of the
   children it forked, --kills times, each run with --retry-errors; then one run to the end.
4. As root: maps them into a tmpfs of --tmpfs-mb MB (the disk fills up), then grows the tmpfs and runs again
   with --retry-errors.
Checks after 3 and 4: summary.csv and summary.jsonl equal to the reference's but for the timing columns;
surface.ply and sphere.ply of every complete input byte-identical to the reference's; no temporary
(".tmp-") file left; every bad input a failed row and every good one not. Prints the figures; exit 1 if a
check fails.
"""
import argparse
import csv
import gzip
import io
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def is_timing(column):
    return column.startswith("seconds_") or column == "peak_rss_mb"


def csv_without_timings(path):
    rows = list(csv.reader(io.StringIO(path.read_text())))
    keep = [not is_timing(c) for c in rows[0]]
    return [[v for v, k in zip(row, keep) if k] for row in rows]


def jsonl_without_timings(path):
    out = []
    for line in path.read_text().splitlines():
        row = json.loads(line)
        out.append({k: (None if is_timing(k) else v) for k, v in row.items()})
    return out


def generate(spheremap, shape, path, *options):
    subprocess.run([spheremap, "generate", shape, "-o", str(path), *map(str, options)], check=True,
                   stdout=subprocess.DEVNULL)


def good_meshes(spheremap, folder, count, rng):
    """count generated meshes of several shapes and sizes (a few hundred to a few thousand vertices)."""
    makers = [
        lambda: ("icosphere", ["--level", rng.choice([1, 2, 3])]),
        lambda: ("ellipsoid", ["--level", rng.choice([2, 3]), "--stretch", rng.choice([0.3, 2, 4])]),
        lambda: ("dumbbell", ["--separation", rng.choice([2.5, 3]), "--neck", rng.choice([0.3, 0.5]),
                              "--rings", rng.randint(20, 60), "--segments", rng.randint(10, 24)]),
        lambda: ("cube", ["--n", rng.randint(3, 12)]),
        lambda: ("tube-u", ["--rings", rng.randint(8, 24), "--segments", rng.randint(4, 8)]),
        lambda: ("stacked", ["--vertices", rng.randint(40, 300), "--nesting", rng.choice([0.0, 0.3])]),
        lambda: ("spiky", ["--level", 1, "--spikes", rng.randint(2, 8)]),
    ]
    for k in range(count):
        shape, options = makers[k % len(makers)]()
        generate(spheremap, shape, folder / f"good-{k:03d}-{shape}.ply", *options)


def small_structures(count):
    misc = ROOT.parent / "shared" / "data" / "pdb" / "misc"
    if not misc.is_dir():
        print(f"note: {misc} absent: no structures among the inputs, meshes only")
        return []
    files = sorted((p for p in misc.iterdir() if p.suffix in (".pdb", ".cif")), key=lambda p: p.stat().st_size)
    return files[:count]


def bad_inputs(spheremap, folder, count):
    """count bad files, cycling through ten kinds (each a refusal the batch must report as a failed row)."""
    scratch = folder / ".scratch.ply"
    generate(spheremap, "icosphere", scratch, "--level", 2)
    ply = scratch.read_bytes()
    scratch.unlink()
    pdb = b"".join(b"ATOM  %5d  CA  GLY A%4d    %8.3f%8.3f%8.3f  1.00  0.00           C\n" % (i + 1, i + 1, 3.8 * i,
                   (i % 2) * 1.5, 0.0) for i in range(30))
    torus = []
    n, m = 12, 8
    for i in range(n):
        for j in range(m):
            torus.append("v %d %d %d" % (i, j, (i * j) % 3))
    for i in range(n):
        for j in range(m):
            a, b = i * m + j + 1, ((i + 1) % n) * m + j + 1
            c, d = ((i + 1) % n) * m + (j + 1) % m + 1, i * m + (j + 1) % m + 1
            torus += ["f %d %d %d" % (a, b, c), "f %d %d %d" % (a, c, d)]
    kinds = [
        ("empty.stl", b""),
        ("garbage.ply", bytes(random.Random(7).randrange(256) for _ in range(4000))),
        ("open.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"),
        ("nan.obj", b"v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n"),
        ("index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n"),
        ("truncated.ply", ply[: len(ply) // 2]),
        ("notgzip.pdb.gz", pdb),
        ("truncated.pdb.gz", gzip.compress(pdb)[:-30]),
        ("torus.obj", ("\n".join(torus) + "\n").encode()),
        ("noatoms.pdb", b"HEADER    NOTHING\nREMARK   1 NO ATOMS\nEND\n"),
    ]
    for k in range(count):
        name, data = kinds[k % len(kinds)]
        (folder / f"bad-{k:02d}-{name}").write_bytes(data)


def children_of(pid):
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                fields = Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.append(int(entry))
    return found


def run(command, log):
    with open(log, "ab") as out:
        return subprocess.run(command, stdout=out, stderr=out).returncode


def check(root, reference, failures, label):
    if csv_without_timings(root / "summary.csv") != csv_without_timings(reference / "summary.csv"):
        failures.append(f"{label}: summary.csv differs from the reference's")
    if jsonl_without_timings(root / "summary.jsonl") != jsonl_without_timings(reference / "summary.jsonl"):
        failures.append(f"{label}: summary.jsonl differs from the reference's")
    compared = 0
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        if (folder / "report.json").exists():
            for file in ("surface.ply", "sphere.ply"):
                compared += 1
                if (folder / file).read_bytes() != (reference / folder.name / file).read_bytes():
                    failures.append(f"{label}: {folder.name}/{file} differs from the reference's")
    temporaries = [p for p in root.rglob("*") if ".tmp-" in p.name]
    failures += [f"{label}: temporary left: {p}" for p in temporaries]
    rows = list(csv.DictReader(io.StringIO((root / "summary.csv").read_text())))
    status_column = list(rows[0].keys())[3]
    for row in rows:
        bad = "bad-" in row[list(row.keys())[0]]
        if (row[status_column] == "error") != bad:
            failures.append(f"{label}: row {row[list(row.keys())[0]]} has status {row[status_column]}")
    return compared, len(temporaries), len(rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--spheremap", default=str(ROOT / "build" / "spheremap"))
    parser.add_argument("--inputs", type=int, default=200)
    parser.add_argument("--bad", type=int, default=20)
    parser.add_argument("--structures", type=int, default=10)
    parser.add_argument("--kills", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--work", default="/tmp/batch-faults")
    parser.add_argument("--tmpfs-mb", type=int, default=8)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    work = Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    inputs = work / "in"
    inputs.mkdir(parents=True)
    structures = small_structures(args.structures)
    for path in structures:
        shutil.copy(path, inputs / f"good-s-{path.name}")
    good_meshes(args.spheremap, inputs, args.inputs - args.bad - len(structures), rng)
    bad_inputs(args.spheremap, inputs, args.bad)
    print(f"{len(list(inputs.iterdir()))} inputs ({len(structures)} structures, {args.bad} bad) in {inputs}")
    batch = [args.spheremap, "batch", str(inputs), "--jobs", str(args.jobs), "-q"]
    log = work / "log.txt"
    failures = []

    reference = work / "reference"
    start = time.monotonic()
    code = run(batch + ["-o", str(reference)], log)
    reference_seconds = time.monotonic() - start
    print(f"reference: exit {code} in {reference_seconds:.1f} s")
    if code != 1:
        failures.append(f"reference: exit {code}, expected 1 (some inputs failed)")
    check(reference, reference, failures, "reference")

    killed = work / "killed"
    parent_kills = child_kills = finished_alone = 0
    start = time.monotonic()
    # Kill moments spread so that the batch progresses over all the runs: each run lives on average about
    # twice its share of the reference time; every other run first loses a child, then the batch itself.
    share = reference_seconds / args.kills
    for k in range(args.kills):
        process = subprocess.Popen(batch + ["-o", str(killed), "--retry-errors"], stdout=open(log, "ab"),
                                   stderr=subprocess.STDOUT)
        time.sleep(rng.uniform(0.05, 2 * share))
        children = children_of(process.pid)
        if k % 2 == 1 and children and process.poll() is None:
            os.kill(rng.choice(children), signal.SIGKILL)  # as the out-of-memory killer would
            child_kills += 1
            time.sleep(rng.uniform(0.05, share))
        if process.poll() is not None:
            finished_alone += 1
        else:
            process.kill()
            parent_kills += 1
        process.wait()
    code = run(batch + ["-o", str(killed), "--retry-errors"], log)
    killed_seconds = time.monotonic() - start
    compared_k, temporaries_k, _ = check(killed, reference, failures, "killed")
    print(f"killed: {parent_kills} kills of the batch, {child_kills} of a child, {finished_alone} runs finished "
          f"before their kill; last run exit {code}; {killed_seconds:.1f} s in all; {compared_k} PLY files "
          f"compared, {temporaries_k} temporaries")

    if os.geteuid() == 0 and shutil.which("mount"):
        full = work / "full"
        full.mkdir()
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={args.tmpfs_mb}m", "tmpfs", str(full)], check=True)
        try:
            full_log = work / "full-log.txt"
            code_full = run(batch + ["-o", str(full)], full_log)
            rows_full = list(csv.reader(io.StringIO((full / "summary.csv").read_text())))[1:] \
                if (full / "summary.csv").exists() else []
            failed = sum(1 for r in rows_full if r[3] == "error")
            no_room = sum(1 for p in full.glob("*/error.json") if "No space left" in p.read_text())
            if "internal error" in full_log.read_text():
                failures.append("full disk: an internal error in the log")
            subprocess.run(["mount", "-o", "remount,size=2g", str(full)], check=True)
            code_room = run(batch + ["-o", str(full), "--retry-errors"], log)
            compared_f, temporaries_f, _ = check(full, reference, failures, "full disk")
            written = f"{len(rows_full)} rows in its summary, {failed} failed" if rows_full else \
                "no room for its summary"
            print(f"full disk ({args.tmpfs_mb} MB tmpfs): exit {code_full}, {written}, {no_room} inputs failed "
                  f"saying no space left; with room: exit {code_room}, "
                  f"{compared_f} PLY files compared, {temporaries_f} temporaries")
        finally:
            subprocess.run(["umount", str(full)], check=False)
    else:
        print("full disk: skipped (needs root to mount a tmpfs)")

    for failure in failures:
        print("FAILED:", failure)
    print("all checks passed" if not failures else f"{len(failures)} checks failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
