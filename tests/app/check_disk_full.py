#!/usr/bin/env python3
"""A run whose disk fills: the run folder on a small tmpfs, sized so that it fills
at one chosen write.

  check_disk_full.py WHEN IBVALVE MPIEXEC RANKS CASE WORK_DIR --every E --at STEP [--set key=value ...]

WHEN is the write that fills the disk:
  rows        the rows of timeseries.csv, around step STEP (the lumped case: 8000 steps a second, a row
              a step);
  checkpoint  the checkpoint of step STEP (a multiple of E);
  fields      the field file of step STEP (at a multiple of the steps in output.fields_interval).
The tmpfs holds what the uninterrupted run (on the real disk, first) has written before that write,
page by page, and half of the file that write makes (rows: nothing more, the series fills it). Asserts:
the run stops in time (no rank left waiting: a timeout is a failure) with exit 3 and one error line
naming the file of that write and "No space left on device"; the series ends with a whole row; no
checkpoint of that step and no temporary file is left; no report was written. The folder, copied to
the real disk, then restarts (`--restart`) from its newest checkpoint to a series identical byte for
byte to the uninterrupted run's.

The tmpfs is mounted in a mount namespace of its own (`unshare -m` as root, `unshare -rm` otherwise);
where neither may mount, the test is skipped (exit 77).
Prints what it checked; exits 1 on the first failure.
"""
import argparse
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from check_restart_faults import Runner, add_run_arguments, checkpoints, error_lines, fail, same_series  # noqa: E402

SKIP = 77
PAGE = 4096
TIMEOUT = 120

# Runs in the new mount namespace: mounts the tmpfs, runs the command, copies the run folder out.
IN_NAMESPACE = """
size=$1; mnt=$2; copy=$3; shift 3
mount -t tmpfs -o "size=$size" ibvalve_disk_full "$mnt" || exit 77
"$@"; code=$?
cp -a "$mnt/run" "$copy"
exit $code
"""


def unshare():
    return ["unshare", "-m"] if os.geteuid() == 0 else ["unshare", "-rm"]


def can_mount(work):
    point = work / "probe_mount"
    point.mkdir()
    command = unshare() + ["sh", "-c", f"mount -t tmpfs -o size=64k ibvalve_probe {point}"]
    result = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, text=True)
    return result.returncode == 0, (result.stderr.strip() or "mount failed")


def pages(size):
    return -(-size // PAGE)


def step_of(name):
    found = re.search(r"_(\d+)\.h5$", name)
    return int(found.group(1)) if found else None


def series_bytes(whole, rows):
    """Bytes of timeseries.csv with its header and first `rows` data rows."""
    lines = (whole / "timeseries.csv").read_bytes().splitlines(keepends=True)
    return sum(len(line) for line in lines[: rows + 1])


def rows_at(whole, step):
    """Data rows of timeseries.csv up to and including the row of `step`: by its column `step`, or,
    without one (the lumped model), one row a step from step 0."""
    lines = (whole / "timeseries.csv").read_text().splitlines()
    columns = lines[0].split(",")
    if "step" not in columns:
        return min(step + 1, len(lines) - 1)
    for i, line in enumerate(lines[1:], start=1):
        if float(line.split(",")[columns.index("step")]) > step:
            return i - 1
    return len(lines) - 1


def budget(whole, when, at, every, keep=2):
    """Bytes, in whole pages, of what the uninterrupted run has on disk just before the write `when` of
    step `at` (files rewritten atomically counted twice: old and new exist together), plus half of
    what that write adds."""
    total = 0
    for name in ("config.toml", "log.txt"):
        total += pages((whole / name).stat().st_size)
    for series in whole.glob("fields_*.xdmf"):
        total += 2 * pages(series.stat().st_size)
    for wisdom in (whole / "fftw_wisdom").glob("*"):
        total += 2 * pages(wisdom.stat().st_size)
    field_files = sorted((whole / "fields").glob("*.h5")) if (whole / "fields").exists() else []
    field_size = pages(field_files[0].stat().st_size) if field_files else 0
    saved = sorted((whole / "checkpoints").glob("step_*.h5"))
    checkpoint_size = pages(saved[0].stat().st_size)
    if when == "rows":
        # The fill comes in the rows between two checkpoints; the checkpoint before it briefly had its
        # predecessors beside it.
        total += (keep + 1) * checkpoint_size + len(field_files) * field_size
        return (total + pages(series_bytes(whole, rows_at(whole, at)))) * PAGE
    # Per step the run writes its row, then its field file, then its checkpoint.
    total += pages(series_bytes(whole, rows_at(whole, at)))
    before = [f for f in field_files if step_of(f.name) < at or (when == "checkpoint" and step_of(f.name) == at)]
    total += len(before) * field_size
    total += min(keep, (at - 1) // every) * checkpoint_size
    half = (checkpoint_size if when == "checkpoint" else field_size) // 2
    return (total + half) * PAGE


def whole_rows_only(folder):
    text = (folder / "timeseries.csv").read_bytes()
    if not text.endswith(b"\n"):
        fail("timeseries.csv ends with a torn row (no line end)")
    lines = text.decode().splitlines()
    width = len(lines[0].split(","))
    torn = [i + 1 for i, line in enumerate(lines) if len(line.split(",")) != width]
    if torn:
        fail(f"timeseries.csv has torn rows at lines {torn[:5]}")
    print(f"timeseries.csv ends with a whole row ({len(lines) - 1} rows)")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("when", choices=["rows", "checkpoint", "fields"])
    add_run_arguments(parser)
    parser.add_argument("--every", type=int, required=True, help="checkpoint.every")
    parser.add_argument("--at", type=int, required=True, help="the step whose write fills the disk")
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    ok, why = can_mount(work)
    if not ok:
        print(f"SKIP: cannot mount a tmpfs in a mount namespace here ({' '.join(unshare())}: {why})")
        sys.exit(SKIP)

    args.set.append(f"checkpoint.every={args.every}")
    runner = Runner(args)
    whole = work / "whole"
    runner.run(whole, "-q")
    size = budget(whole, args.when, args.at, args.every)
    # The copy lies as deep as the run on the tmpfs: its config.toml names the files relative to it.
    mount, copy = work / "disk", work / "copied" / "run"
    mount.mkdir()
    copy.parent.mkdir()
    command = unshare() + ["sh", "-c", IN_NAMESPACE, "sh", str(size), str(mount), str(copy)]
    command += runner.command(mount / "run", "-q")
    print(f"+ (a {size} byte tmpfs at {mount}) " + " ".join(runner.command(mount / "run", "-q")), flush=True)
    process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = process.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        out, err = process.communicate()
        fail(f"the run on the full disk hung ({TIMEOUT} s): a rank waits for another", out + err)
    result = subprocess.CompletedProcess(command, process.returncode, out, err)
    output = out + err
    if result.returncode == SKIP:
        print(f"SKIP: the tmpfs could not be mounted: {output}")
        sys.exit(SKIP)
    if result.returncode != 3:
        fail(f"exit code {result.returncode} on the full disk, expected 3", output)
    if args.when == "rows":
        named = "timeseries.csv"
    elif args.when == "checkpoint":
        named = f"checkpoints/step_{args.at:09d}.h5"
    else:
        named = f"_{args.at:06d}.h5"
    lines = [line for line in error_lines(result) if "No space left on device" in line]
    if len(lines) != 1 or named not in lines[0] or str(mount / "run") not in lines[0]:
        fail(f"expected one error line naming {named} and 'No space left on device'", output)
    print(f"exit 3, one error line: {lines[0]}")
    whole_rows_only(copy)
    saved = checkpoints(copy)
    leftovers = [p.name for p in (copy / "checkpoints").iterdir() if not re.fullmatch(r"step_\d{9}\.h5", p.name)]
    if leftovers:
        fail(f"files other than complete checkpoints left in checkpoints/: {leftovers}")
    if args.when == "checkpoint" and f"step_{args.at:09d}.h5" in saved:
        fail(f"the checkpoint of step {args.at} is there though it could not be written")
    if (copy / "report").exists():
        fail("a report was written for a run that could not finish its series")
    if not saved:
        fail("no checkpoint to restart from was kept")
    print(f"kept the checkpoints {saved}, no temporary file, no report")
    restarted = runner.run(copy, restart=True)
    newest = copy / "checkpoints" / saved[-1]
    if f"restarting from {newest}" not in restarted.stdout:
        fail(f"the restart did not continue from the newest checkpoint {newest}", restarted.stdout)
    same_series(whole, copy, "copied off the full disk and restarted")
    print("PASS")


if __name__ == "__main__":
    main()
