#!/usr/bin/env python3
"""Compares a run folder's timeseries.csv and report/metrics.json with a stored reference.

  compare_runs.py REFERENCE RUN [--rtol R] [--atol A] [--metrics-rtol R] [--series-only]

REFERENCE holds timeseries.csv and metrics.json (as scripts/refresh-regression-reference stores them);
RUN is a run folder. A time-series column passes when

    max_i |run_i - ref_i| <= atol + rtol * max_i |ref_i|

(the difference measured against the column's scale, so a column that crosses zero is not judged by
its smallest values); a metric passes when |run - ref| <= atol + metrics_rtol * |ref|. Both files
must have the same columns, row count and metric names. Prints a table of every column's and metric's
largest absolute and relative difference, then exits 1 if anything fails. --rtol 0 --atol 0 asks for
identical numbers (a restarted run against an uninterrupted one).
"""
import argparse
import csv
import json
import math
import sys
from pathlib import Path


def read_series(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, data = rows[0], rows[1:]
    columns = {name: [float(r[i]) for r in data] for i, name in enumerate(header)}
    return header, columns, len(data)


def read_metrics(path):
    doc = json.loads(Path(path).read_text())
    out = {}
    for key, entry in doc.get("metrics", {}).items():
        value = entry.get("value") if isinstance(entry, dict) else entry
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = float(value)
    return out


def argument_parser():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reference", type=Path)
    parser.add_argument("run", type=Path)
    parser.add_argument("--rtol", type=float, default=1e-6, help="time series: relative to the column's scale")
    parser.add_argument("--atol", type=float, default=1e-12)
    parser.add_argument("--metrics-rtol", type=float, default=None, help="metrics (default: --rtol)")
    parser.add_argument("--series-only", action="store_true", help="do not compare metrics.json")
    return parser


def metrics_tolerance(args):
    """The metrics' relative tolerance: --metrics-rtol, else --rtol."""
    return args.rtol if args.metrics_rtol is None else args.metrics_rtol


def main():
    args = argument_parser().parse_args()
    metrics_rtol = metrics_tolerance(args)
    failures = []

    ref_header, ref, ref_rows = read_series(args.reference / "timeseries.csv")
    run_header, run, run_rows = read_series(args.run / "timeseries.csv")
    if ref_header != run_header:
        failures.append(f"columns differ: reference {ref_header}, run {run_header}")
    if ref_rows != run_rows:
        failures.append(f"row counts differ: reference {ref_rows}, run {run_rows}")
    print(f"time series: {ref_rows} rows; pass when max|diff| <= {args.atol:g} + {args.rtol:g} * max|ref|")
    print(f"  {'column':28s} {'max |diff|':>12s} {'rel. to scale':>14s}")
    for name in ref_header:
        if name not in run or ref_rows != run_rows:
            continue
        a, b = ref[name], run[name]
        if not all(math.isfinite(x) for x in b):
            failures.append(f"column {name}: not finite")
            continue
        diff = max((abs(x - y) for x, y in zip(a, b)), default=0.0)
        scale = max((abs(x) for x in a), default=0.0)
        rel = diff / scale if scale > 0 else (0.0 if diff == 0 else math.inf)
        ok = diff <= args.atol + args.rtol * scale
        print(f"  {name:28s} {diff:12.3e} {rel:14.3e} {'ok' if ok else 'FAIL'}")
        if not ok:
            failures.append(f"column {name}: max |diff| {diff:.3e} (scale {scale:.3e})")

    if not args.series_only:
        ref_m = read_metrics(args.reference / "metrics.json")
        run_m = read_metrics(args.run / "report" / "metrics.json")
        print(f"metrics: pass when |diff| <= {args.atol:g} + {metrics_rtol:g} * |ref|")
        for key in sorted(set(ref_m) | set(run_m)):
            if key not in run_m or key not in ref_m:
                failures.append(f"metric {key}: only in {'reference' if key in ref_m else 'run'}")
                continue
            diff = abs(run_m[key] - ref_m[key])
            rel = diff / abs(ref_m[key]) if ref_m[key] != 0 else (0.0 if diff == 0 else math.inf)
            ok = math.isfinite(run_m[key]) and diff <= args.atol + metrics_rtol * abs(ref_m[key])
            print(f"  {key:40s} ref {ref_m[key]:14.6g} run {run_m[key]:14.6g} rel {rel:10.3e} {'ok' if ok else 'FAIL'}")
            if not ok:
                failures.append(f"metric {key}: {run_m[key]!r} vs reference {ref_m[key]!r}")

    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
