#!/usr/bin/env python3
"""Markdown tables for BENCHMARKS.md from the summary.csv of `spheremap batch` runs over structures.

    bench/batch_table.py runs/g0.5/summary.csv [more summary.csv ...]

Per run folder: one row per structure (atoms, contour and mapped vertices, genus before the handle
repair, outer area changed by the repair, status, certificate, re-weighting rounds, seconds per stage,
peak memory), then a summary line: how many certified, the distribution of the repair's area change
(median, 90th percentile, max, how many above 1%), total and slowest times, largest peak memory.
"""
import csv
import statistics
import sys


def number(row, key):
    value = row.get(key, "")
    return float(value) if value not in ("", None) else None


def fmt(value, digits=2):
    return "" if value is None else f"{value:.{digits}f}"


def quantile(values, q):
    if not values:
        return None
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * (len(ordered) - 1)))]


def table(path):
    rows = list(csv.DictReader(open(path, newline="", encoding="utf-8")))
    grid = next((r["grid"] for r in rows if r.get("grid")), "?")
    print(f"\n`{path}` (grid {grid} Å):\n")
    print("| structure | atoms | contour vertices | mapped vertices | genus before | repair area change % | status | "
          "plain collapsed | re-weighting rounds | surface s | simplify s | map s | total s | peak MB |")
    print("|---|--:|--:|--:|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|")
    changes, totals, certified, peaks = [], [], 0, []
    for r in rows:
        name = "/".join(r["input"].split("/")[-2:])
        change = number(r, "repair_area_changed_percent")
        genus = number(r, "genus_before_repair")
        if genus and change is not None:
            changes.append(abs(change))
        total = number(r, "seconds_total")
        if total is not None:
            totals.append((total, name))
        peak = number(r, "peak_rss_mb")
        if peak is not None:
            peaks.append((peak, name))
        certified += r["status"] == "ok"
        contour = r.get("simplified_vertices_before") or r.get("vertices")
        status = r["status"] if r["status"] != "error" else "error: " + r["message"][:80].replace("|", "/")
        print(f"| {name} | {r['atoms']} | {contour} | {r['vertices']} | {r['genus_before_repair']} | "
              f"{fmt(change)} | {status} | {r['plain_collapsed']} | {r['reweighting_rounds']} | "
              f"{fmt(number(r, 'seconds_surface'))} | {fmt(number(r, 'seconds_simplify'))} | "
              f"{fmt(number(r, 'seconds_map'))} | {fmt(total)} | {fmt(peak, 0)} |")
    above = sum(1 for c in changes if c > 1.0)
    slowest = sorted(totals, reverse=True)[:3]
    print(f"\nSummary (grid {grid} Å): {len(rows)} structures, {certified} certified; "
          f"{len(changes)} had handles repaired: |outer area change| median {fmt(quantile(changes, 0.5))}%, "
          f"90th percentile {fmt(quantile(changes, 0.9))}%, max {fmt(max(changes) if changes else None)}%, "
          f"{above} above 1%; time per structure median {fmt(quantile([t for t, _ in totals], 0.5))} s, "
          f"sum {fmt(sum(t for t, _ in totals), 1)} s, slowest "
          + ", ".join(f"{n} {t:.1f} s" for t, n in slowest)
          + (f"; largest peak memory {max(peaks)[1]} {max(peaks)[0]:.0f} MB" if peaks else ""))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for summary in sys.argv[1:]:
        table(summary)
