#!/usr/bin/env python3
"""Why the handle repair changes more than 1% of some surfaces: one Markdown row per structure whose
outer area changed by more than the threshold, from the report.json files of a `spheremap batch` run.

    bench/repair_changes.py runs/g0.5 [more run folders ...] [--threshold 1.0]

Per structure: atoms, outer area before the repair, genus before, number of closures, the net change,
the single largest closure (kind, Å², % of the area), how many closures each change more than the
threshold by themselves, and the sums of the cuts and of the fills. A structure where one closure alone
exceeds the threshold cannot meet it with one closure per handle; one where no closure does, only sums
many small ones.
"""
import argparse
import json
import pathlib


def rows(run, threshold):
    for report_path in sorted(pathlib.Path(run).glob("*/report.json")):
        report = json.loads(report_path.read_text())
        structure = report.get("structure") or {}
        repair = structure.get("topology_repair") or {}
        if not repair or abs(repair.get("area_changed_percent", 0)) <= threshold:
            continue
        area = repair["area_before"]
        changes = repair["changes"]
        largest = max(changes, key=lambda c: abs(c["area_change"]))
        alone = sum(1 for c in changes if 100 * abs(c["area_change"]) / area > threshold)
        cuts = sum(c["area_change"] for c in changes if c["kind"] == "cut")
        fills = sum(c["area_change"] for c in changes if c["kind"] == "fill")
        yield (f"| {report_path.parent.name} | {structure['atoms']} | {area:.0f} | {repair['genus_before']} | "
               f"{len(changes)} | {repair['area_changed_percent']:+.2f} | {largest['kind']} {largest['area_change']:+.0f} "
               f"({100 * largest['area_change'] / area:+.2f}%) | {alone} | {100 * cuts / area:+.2f} | {100 * fills / area:+.2f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+", help="folders written by spheremap batch")
    parser.add_argument("--threshold", type=float, default=1.0, help="percent of the outer area (default 1)")
    args = parser.parse_args()
    for run in args.runs:
        print(f"\n{run}\n")
        print("| structure | atoms | area before (Å²) | genus | closures | net change % | largest closure Å² (%) | "
              "closures above threshold alone | cuts sum % | fills sum % |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for row in rows(run, args.threshold):
            print(row)


if __name__ == "__main__":
    main()
