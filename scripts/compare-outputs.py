#!/usr/bin/env python3
"""Usage: scripts/compare-outputs.py BEFORE AFTER

Compares two output folders (for instance two scripts/output-snapshot.sh runs): PLY files byte for byte,
JSON and JSON-lines files equal but for timings and memory (timings_seconds, seconds, seconds_*,
peak_rss_mb), CSV files equal but for those columns, .txt and .err files byte for byte, and the same
files on both sides. Prints each difference and a count; exits 1 if there is any.
"""
import csv
import filecmp
import json
import os
import sys

VOLATILE = ("timings_seconds", "peak_rss_mb", "seconds")


def files(root):
    return {os.path.relpath(os.path.join(d, f), root) for d, _, fs in os.walk(root) for f in fs}


def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if k not in VOLATILE and not k.startswith("seconds_")}
    if isinstance(value, list):
        return [strip(x) for x in value]
    return value


def csv_rows(path):
    with open(path, newline="", encoding="utf-8") as f:
        return [{k: v for k, v in r.items() if k not in VOLATILE and not k.startswith("seconds_")}
                for r in csv.DictReader(f)]


def same(a, b, name):
    if name.endswith(".ply"):
        return filecmp.cmp(a, b, shallow=False)
    if name.endswith(".json"):
        return strip(json.load(open(a))) == strip(json.load(open(b)))
    if name.endswith(".jsonl"):
        return [strip(json.loads(l)) for l in open(a)] == [strip(json.loads(l)) for l in open(b)]
    if name.endswith(".csv"):
        return csv_rows(a) == csv_rows(b)
    if name.endswith((".txt", ".err")):
        return filecmp.cmp(a, b, shallow=False)
    return True  # other files (pictures, logs) are not part of the comparison


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    before, after = sys.argv[1], sys.argv[2]
    fa, fb = files(before), files(after)
    differences = 0
    for name in sorted(fa ^ fb):
        print("only in", before if name in fa else after, ":", name)
        differences += 1
    counts = {}
    for name in sorted(fa & fb):
        kind = os.path.splitext(name)[1] or "(none)"
        counts[kind] = counts.get(kind, 0) + 1
        if not same(os.path.join(before, name), os.path.join(after, name), name):
            print("differs:", name)
            differences += 1
    print("compared", dict(sorted(counts.items())), "- differences:", differences)
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
