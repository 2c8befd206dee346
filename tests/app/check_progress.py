#!/usr/bin/env python3
"""Progress lines, diagnostics.csv, the valve's end time and its time-step line.

    check_progress.py SCENARIO IBVALVE MPIEXEC RANKS CASE RUN_DIR [--set KEY=VALUE ...]

Scenarios:
  terminal     the run under mpiexec with its output on a pseudo-terminal (as in an interactive shell):
               the progress line is redrawn in place (carriage return, erase line) and shows step/total,
               the time a step, the ETA, the fluid's solver iterations, max|u| and the CFL number;
  pipe         the same run with its output in a pipe: plain progress lines, no carriage returns;
  diagnostics  a run with checkpoints every 3 steps stopped after 7, its newest checkpoint (step 7)
               removed, restarted from step 6 to the end: diagnostics.csv holds every step exactly once,
               in order, with its columns; the progress line names the stop of --stop-after-steps;
  valve-end    CASE is the aortic-valve case: a run with --set time.end stopped by --stop-after-steps
               (a checkpoint, no report), restarted to its end: the report is written, the first step
               says dt is within the stability estimate and which limit binds; with a coaptation step
               the progress line's end time is time.end.
Prints what it checked; exits 1 on the first failure.
"""
import argparse
import csv
import os
import pathlib
import pty
import shutil
import subprocess
import sys


def fail(message):
    sys.exit("FAIL: " + message)


def command(args, extra):
    base = [args.mpiexec, "--oversubscribe", "-n", str(args.ranks), args.ibvalve, "run"]
    return base + extra + [s for kv in args.set for s in ("--set", kv)]


def run_piped(cmd, expect=0):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            stdin=subprocess.DEVNULL)
    if result.returncode != expect:
        fail(f"exit {result.returncode} (expected {expect}) from {' '.join(cmd)}:\n{result.stdout}")
    return result.stdout


def run_on_terminal(cmd):
    """Runs `cmd` with stdout and stderr on a new pseudo-terminal; returns everything written there."""
    controller, terminal = pty.openpty()
    process = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=terminal, stderr=terminal)
    os.close(terminal)
    output = b""
    while True:
        try:
            chunk = os.read(controller, 65536)
        except OSError:  # EIO once every writer has closed the terminal
            break
        if not chunk:
            break
        output += chunk
    os.close(controller)
    code = process.wait()
    text = output.decode(errors="replace")
    if code != 0:
        fail(f"exit {code} from {' '.join(cmd)}:\n{text}")
    return text


def check_line_content(text, steps):
    for piece in (f"step 1/{steps}  t = ", " s/step  ETA ", "fluid it ", "max|u| ", " cm/s, CFL "):
        if piece not in text:
            fail(f"the progress line lacks {piece!r}:\n{text}")


def read_diagnostics(run_dir):
    with open(run_dir / "diagnostics.csv", newline="") as f:
        rows = [row for row in csv.reader(f) if row and not row[0].startswith("#")]
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


def scenario_terminal(args, run_dir):
    text = run_on_terminal(command(args, [str(args.case), "-o", str(run_dir), "--overwrite"]))
    if "\r\x1b[Kstep 1/12" not in text:
        fail("under mpiexec on a terminal the progress line is not redrawn in place "
             f"(no carriage return + erase before it):\n{text!r}")
    check_line_content(text, 12)
    print(f"on a terminal through mpiexec -n {args.ranks}: the progress line is redrawn in place "
          f"({text.count(chr(13) + chr(27) + '[K')} redraws) with step/total, s/step, ETA, fluid iterations, "
          "max|u|, CFL")


def scenario_pipe(args, run_dir):
    text = run_piped(command(args, [str(args.case), "-o", str(run_dir), "--overwrite",
                                    "--set", "log.progress_interval=1e-9"]))
    if "\r" in text:
        fail(f"a carriage return in piped output:\n{text!r}")
    lines = [line for line in text.splitlines() if line.startswith("step ")]
    if len(lines) != 12:
        fail(f"{len(lines)} plain progress lines, expected one a step (12) with a tiny interval:\n{text}")
    check_line_content(text, 12)
    print(f"in a pipe: {len(lines)} plain progress lines, no carriage return")


def scenario_diagnostics(args, run_dir):
    first = run_piped(command(args, [str(args.case), "-o", str(run_dir), "--overwrite", "--stop-after-steps", "7",
                                     "--set", "checkpoint.every=3", "--set", "checkpoint.keep=3",
                                     "--set", "log.progress_interval=1e-9"]))
    if "ETA " not in first or "(stop at step 7)" not in first:
        fail(f"the progress line does not name the stop at step 7:\n{first}")
    columns, rows = read_diagnostics(run_dir)
    if [int(r[0]) for r in rows] != list(range(1, 8)):
        fail(f"diagnostics.csv of the stopped run has steps {[r[0] for r in rows]}, expected 1..7")
    newest = run_dir / "checkpoints" / "step_000000007.h5"
    if not newest.exists():
        fail(f"no {newest}")
    newest.unlink()  # the restart continues from step 6: the row of step 7 is taken again
    second = run_piped(command(args, ["--restart", str(run_dir), "--set", "log.progress_interval=1e-9"]))
    if "step 7/12" not in second or "(stop at" in second:
        fail(f"the restarted run's progress lines:\n{second}")
    columns, rows = read_diagnostics(run_dir)
    steps = [int(r[0]) for r in rows]
    if steps != list(range(1, 13)):
        fail(f"diagnostics.csv after the restart from step 6 has steps {steps}, expected 1..12 once each")
    expected = ["step", "t", "wall_step", "fluid_iterations", "fluid_residual", "max_velocity", "cfl"]
    if columns[:len(expected)] != expected:
        fail(f"diagnostics.csv columns {columns}, expected {expected} first")
    index = {c: i for i, c in enumerate(columns)}
    for r in rows:
        if not (r[index["wall_step"]] > 0 and r[index["fluid_iterations"]] >= 1 and r[index["max_velocity"]] > 0):
            fail(f"diagnostics.csv row {r}: wall time, iterations and max|u| should be positive")
        if abs(r[index["cfl"]] - r[index["max_velocity"]] * 0.002 / 0.125) > 1e-9 * r[index["cfl"]]:
            fail(f"diagnostics.csv row {r}: cfl is not max|u| dt / h (dt 0.002 s, h 0.125 cm)")
    series = (run_dir / "timeseries.csv").read_text().splitlines()[0]
    if "wall" in series:
        fail(f"timeseries.csv has a wall-time column: {series}")
    print(f"diagnostics.csv: steps 1..12 once each after a restart from step 6 (columns {', '.join(columns)}); "
          "the progress line named the stop at step 7")


def scenario_valve_end(args, run_dir):
    # At the step the time-step line is checked against (the default case's is 4e-5 s).
    end = ["--set", "time.step=2e-5", "--set", "time.end=0.0003", "--set", "output.every=1", "--set", "report.plots=false",
           "--set", "output.fields_interval=0", "--set", "log.progress_interval=1e-9"]
    first = run_piped(command(args, [str(args.case), "-o", str(run_dir), "--overwrite", "--stop-after-steps", "5"]
                              + end))
    if (run_dir / "report").exists():
        fail("--stop-after-steps wrote a report: it is a stop, not the run's end")
    if "stopped after step 5 of 15" not in first:
        fail(f"the stopped run does not say it stopped after step 5 of 15:\n{first}")
    wording = ("ib: dt = 2e-05 s is within the stable time step estimate 4.04e-05 s of the explicit IB/FE "
               "coupling: the structure's inertial limit 2/omega binds (the viscous-regime limit 2 mu/E, "
               "2.51e-08 s, holds only where viscosity dominates, which it does not here)")
    if wording not in first:
        fail(f"the first step's time-step line is not\n  {wording}\n:\n{first}")
    if "viscous limit 2.51e-08 s)" in first:
        fail(f"the bare viscous limit is still printed:\n{first}")
    second = run_piped(command(args, ["--restart", str(run_dir)]))
    metrics = run_dir / "report" / "metrics.json"
    if not metrics.exists():
        fail(f"the run to time.end = 0.0003 s wrote no {metrics}:\n{second}")
    if "report of the run's 0.0003 s" not in second:
        fail(f"the summary does not name the short run's report:\n{second}")
    columns, rows = read_diagnostics(run_dir)
    if [int(r[0]) for r in rows] != list(range(1, 16)):
        fail(f"diagnostics.csv has steps {[r[0] for r in rows]}, expected 1..15")
    for c in ("fluid_iterations", "structure_iterations", "smallest_J", "max_velocity", "cfl"):
        if c not in columns:
            fail(f"diagnostics.csv has no column {c}: {columns}")
    smallest = [float(r[columns.index("smallest_J")]) for r in rows]
    if not all(0.99 < j <= 1.0 for j in smallest):
        fail(f"the valve's smallest quadrature-point J over its first 15 steps from rest is {smallest}, expected just below 1")
    print("aortic valve, time.end = 0.0003 s (15 steps): stopped after 5 without a report, restarted to its end "
          "with a report; the first step says dt is within the estimate and the inertial limit binds; "
          "diagnostics.csv steps 1..15")
    # With a coaptation step the steps differ: the progress line's end is the run's time.end, not its steps
    # times the cycle's mean step (20 steps here: 0.0004 s).
    schedule = ["--set", "time.coaptation_step=1e-5", "--set", "time.coaptation_window=[0.0001, 0.0002]"]
    third = run_piped(command(args, [str(args.case), "-o", str(run_dir), "--overwrite", "--stop-after-steps", "2"]
                              + end + schedule))
    if "step 1/20  t = 2e-05 s / 0.0003 s" not in third:
        fail(f"the progress line of a run to time.end = 0.0003 s with a coaptation step does not end at 0.0003 s:\n{third}")
    print("with a coaptation step over [0.0001, 0.0002] s: 20 steps, the progress line ends at 0.0003 s")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scenario", choices=["terminal", "pipe", "diagnostics", "valve-end"])
    parser.add_argument("ibvalve")
    parser.add_argument("mpiexec")
    parser.add_argument("ranks", type=int)
    parser.add_argument("case", type=pathlib.Path)
    parser.add_argument("run_dir", type=pathlib.Path)
    parser.add_argument("--set", action="append", default=[])
    args = parser.parse_args()
    if args.run_dir.exists():
        shutil.rmtree(args.run_dir)
    args.run_dir.parent.mkdir(parents=True, exist_ok=True)
    {"terminal": scenario_terminal, "pipe": scenario_pipe, "diagnostics": scenario_diagnostics,
     "valve-end": scenario_valve_end}[args.scenario](args, args.run_dir)


if __name__ == "__main__":
    main()
