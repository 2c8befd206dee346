#!/usr/bin/env python3
"""The aortic-valve run takes its coaptation step inside the window and time.step outside it.

  check_step_schedule.py IBVALVE MPIEXEC SOURCE_DIR WORK_DIR

immersed_tube.toml (a fixed step) for 14 steps with time.step 3e-5 s, time.coaptation_step 1.5e-5 s over
[1.5e-4, 2.4e-4] s: the rows of timeseries.csv (one a step) are 5 steps of 3e-5 s, 6 of 1.5e-5 s and
then steps of (0.8 - 2.4e-4) / round((0.8 - 2.4e-4) / 3e-5) s (each part of the 0.8 s cycle holds a
whole number of steps), each within 1e-12 s. Exits 1 on the first row that is not.
"""
import csv
import pathlib
import subprocess
import sys


def main():
    ibvalve, mpiexec, source, work = sys.argv[1:5]
    run = pathlib.Path(work) / "schedule"
    command = [mpiexec, "--oversubscribe", "-n", "1", ibvalve, "run",
               str(pathlib.Path(source) / "examples/aortic_valve/immersed_tube.toml"), "-o", str(run), "--overwrite",
               "-q", "--stop-after-steps", "14", "--set", "output.every=1", "--set", "report.plots=false",
               "--set", "time.step=3e-5", "--set", "time.coaptation_step=1.5e-5", "--set", "time.coaptation_window=[1.5e-4, 2.4e-4]",
               "--set", 'petsc.options="-fluid_fftw_planner estimate"']
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        print(result.stdout)
        sys.exit(f"FAIL: exit code {result.returncode}")
    rows = [r for r in csv.reader(open(run / "timeseries.csv")) if r and not r[0].startswith(("t", "#"))]
    times = [float(r[0]) for r in rows]
    rest = 0.8 - 2.4e-4
    expected = [1.5e-4 / 5] * 5 + [9e-5 / 6] * 6 + [rest / round(rest / 3e-5)] * 3
    steps = [b - a for a, b in zip(times, times[1:])]
    print("steps (s):", " ".join(f"{s:.6g}" for s in steps))
    if len(steps) != len(expected):
        sys.exit(f"FAIL: {len(steps)} steps in the series, expected {len(expected)}")
    for n, (got, want) in enumerate(zip(steps, expected), start=1):
        if abs(got - want) > 1e-12:
            sys.exit(f"FAIL: step {n} is {got:.12g} s, expected {want:g} s")
    print(f"ok: 5 steps of 3e-5 s, 6 of 1.5e-5 s inside the window, 3 of {expected[-1]:.6g} s")


if __name__ == "__main__":
    main()
