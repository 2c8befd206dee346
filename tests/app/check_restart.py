#!/usr/bin/env python3
"""Restart reproduces the uninterrupted run for a grid-based run model.

  check_restart.py IBVALVE MPIEXEC RANKS CASE WORK_DIR --every E --stop S [--steps N] [--set key=value ...]

1. The whole run: CASE with checkpoint.every = E, to its end (or uninterrupted for its first N steps,
   then stopped: a case longer than a test, such as a cardiac cycle).
2. The same case stopped by --stop-after-steps S (a stop checkpoint at S), then `--restart` to the end
   (or to step N).
3. Both on RANKS ranks. Then, bit for bit:
   - timeseries.csv of 2 equals that of 1 byte for byte (every printed digit);
   - every checkpoint both runs wrote after step S (the restarted run's own) holds the same datasets
     with the same bits: the whole state (fluid, structure, outlet) continued exactly, not only what
     the time series prints;
   - every field file (fields/*.h5) both wrote holds the same bits, and each XDMF series
     (fields_fluid.xdmf, fields_structure.xdmf) is the same text.
With --from K instead of --stop: the whole run's own folder, copied and cut back to its checkpoint at
step K, is restarted to the end and compared the same way. Both halves then run in different processes
with FFTW plans timed in the first (the default -fluid_fftw_planner measure): the restart must load
those plans (<run>/fftw_wisdom.txt) to compute the same bits.
Prints what it compared; exits 1 on the first difference.
"""
import argparse
import pathlib
import shutil
import subprocess
import sys

import h5py
import numpy as np


def run(command):
    print("+", " ".join(command), flush=True)
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        print(result.stdout)
        sys.exit(f"FAIL: exit code {result.returncode}")
    return result.stdout


def datasets(path):
    found = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, item: found.__setitem__(name, item[()]) if isinstance(item, h5py.Dataset) else None)
        attributes = dict(f.attrs)
    return found, attributes


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def compare_h5(first, second, label):
    a, a_attributes = datasets(first)
    b, b_attributes = datasets(second)
    if sorted(a) != sorted(b):
        sys.exit(f"FAIL: {label}: different datasets {sorted(set(a) ^ set(b))}")
    values = 0
    for name in sorted(a):
        if not same_bits(a[name], b[name]):
            difference = np.max(np.abs(np.asarray(a[name], float) - np.asarray(b[name], float)))
            sys.exit(f"FAIL: {label}: {name} differs (largest difference {difference:.3e})")
        values += np.asarray(a[name]).size
    for key in a_attributes:
        if key in b_attributes and not same_bits(a_attributes[key], b_attributes[key]):
            sys.exit(f"FAIL: {label}: attribute {key} differs")
    return len(a), values


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("ibvalve")
    parser.add_argument("mpiexec")
    parser.add_argument("ranks")
    parser.add_argument("case")
    parser.add_argument("work")
    parser.add_argument("--every", type=int, required=True, help="checkpoint.every of both runs")
    parser.add_argument("--stop", type=int, help="--stop-after-steps of the split run")
    parser.add_argument("--from", dest="start", type=int, help="restart a copy of the whole run from step K")
    parser.add_argument("--steps", type=int, default=0, help="compare the first N steps only")
    parser.add_argument("--set", action="append", default=[], help="extra overrides of both runs")
    args = parser.parse_args()

    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    whole, split = work / "whole", work / "split"
    launch = [args.mpiexec, "--oversubscribe", "-n", args.ranks, args.ibvalve, "run"]
    overrides = [f"--set=checkpoint.every={args.every}"] + [f"--set={s}" for s in args.set]
    until = [f"--stop-after-steps={args.steps}"] if args.steps else []
    run(launch + [args.case, "-o", str(whole), "-q"] + overrides + until)
    if args.start is not None:
        # The whole run's folder as it was at its checkpoint of step K: later checkpoints gone.
        args.stop = args.start
        shutil.copytree(whole, split)
        for p in (split / "checkpoints").glob("step_*.h5"):
            if int(p.stem[5:]) > args.start:
                p.unlink()
        for p in (split / "fields").glob("*_*.h5") if (split / "fields").is_dir() else []:
            if int(p.stem.rsplit("_", 1)[1]) > args.start:
                p.unlink()  # field files are named <what>_<step>.h5
    else:
        run(launch + [args.case, "-o", str(split), "-q", f"--stop-after-steps={args.stop}"] + overrides)
    stop_checkpoint = split / "checkpoints" / f"step_{args.stop:09d}.h5"
    if not stop_checkpoint.exists():
        sys.exit(f"FAIL: the stopped run left no checkpoint {stop_checkpoint}")
    stopped_rows = 0
    if args.start is None:
        stopped_rows = sum(1 for line in (split / "timeseries.csv").read_text().splitlines()
                           if not line.startswith("#"))
    until = [f"--stop-after-steps={args.steps - args.stop}"] if args.steps else []
    output = run(launch + ["--restart", str(split)] + until)
    if "FFTW did not accept" in output:
        sys.exit("FAIL: the restart could not load the run's FFTW plans:\n" + output)
    if f"restarting from {stop_checkpoint}" not in output:
        sys.exit("FAIL: the restart did not start from the stop checkpoint:\n" + output)

    series_whole = (whole / "timeseries.csv").read_bytes()
    series_split = (split / "timeseries.csv").read_bytes()
    if series_whole != series_split:
        a, b = series_whole.decode().splitlines(), series_split.decode().splitlines()
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                sys.exit(f"FAIL: timeseries.csv differs first at line {i + 1}:\n  whole: {x}\n  split: {y}")
        sys.exit(f"FAIL: timeseries.csv has {len(a)} lines whole, {len(b)} split")
    rows = sum(1 for line in series_whole.decode().splitlines() if not line.startswith("#")) - 1
    if args.start is None:
        print(f"timeseries.csv: {rows} rows identical byte for byte ({stopped_rows - 1} written before the stop)")
    else:
        print(f"timeseries.csv: {rows} rows identical byte for byte (cut back to step {args.start} and rewritten)")

    later = sorted(p.name for p in (split / "checkpoints").glob("step_*.h5")
                   if int(p.stem[5:]) > args.stop and (whole / "checkpoints" / p.name).exists())
    if not later:
        sys.exit("FAIL: no checkpoint after the stop in both runs to compare (choose --every and --stop)")
    for name in later:
        count, values = compare_h5(whole / "checkpoints" / name, split / "checkpoints" / name, name)
        print(f"checkpoint {name}: {count} datasets, {values} values identical bit for bit")

    fields = sorted(p.name for p in (whole / "fields").glob("*.h5")) if (whole / "fields").is_dir() else []
    for name in fields:
        if not (split / "fields" / name).exists():
            sys.exit(f"FAIL: the restarted run has no fields/{name}")
        compare_h5(whole / "fields" / name, split / "fields" / name, "fields/" + name)
    if fields:
        print(f"fields: {len(fields)} files identical bit for bit")
    # One XDMF series per part (fields_fluid.xdmf, and fields_structure.xdmf with a structure), each
    # taken over from the stopped run's file and continued.
    series = sorted(p.name for p in whole.glob("fields_*.xdmf"))
    if fields and "fields_fluid.xdmf" not in series:
        sys.exit("FAIL: the run wrote field files but no fields_fluid.xdmf")
    for name in series:
        if not (split / name).exists():
            sys.exit(f"FAIL: the restarted run has no {name}")
        if (whole / name).read_text() != (split / name).read_text():
            sys.exit(f"FAIL: {name} differs")
        print(f"{name}: identical")
    print("PASS")


if __name__ == "__main__":
    main()
