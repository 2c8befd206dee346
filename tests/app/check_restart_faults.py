#!/usr/bin/env python3
"""Runs that survive faults and mistakes: each scenario is one specification.

  check_restart_faults.py SCENARIO IBVALVE MPIEXEC RANKS CASE WORK_DIR [--set key=value ...]

Scenarios (CASE is a case file of any model; the lumped one runs in a second):
  signal-term, signal-int
      A run that receives SIGTERM (SIGINT) while it runs finishes its step, writes a checkpoint, keeps
      its output, prints one line saying where it stopped and how to continue, and exits with 143
      (130). The signal reaches one rank only (the last one): the ranks agree on it and stop together.
      `--restart` then continues it to a timeseries.csv identical byte for byte to the uninterrupted
      run's.
  mpiexec-ctrl-c
      SIGINT to mpiexec, as a Ctrl-C in its terminal gives it: Open MPI passes it on as SIGTERM and
      exits with 1; the ranks stop as above, the line says "SIGTERM from mpiexec (a Ctrl-C or a SIGTERM
      to mpiexec ...)" and gives the restart command with mpiexec and its options, which, run as
      printed, continues to the uninterrupted series.
  overwrite
      `run -o DIR --overwrite` of case B into the folder of an earlier run of case A (checkpoints,
      report) removes A's outputs first: B's checkpoints are the only ones, B's own survive pruning,
      and `--restart` continues B to B's uninterrupted series.
  foreign-case, foreign-model
      A newer checkpoint of another case (other valve parameters), or of another model, planted in a
      run folder: the restart refuses it, exit 2, one error line naming the file (and the key that
      differs, or the model), nothing cut or written.
  corrupt, torn
      The newest checkpoint with one bit of its state flipped (corrupt) or cut in half (torn): the
      restart passes over it with one warning line naming it (no HDF5 error stack), continues from
      the one before, and the series equals the uninterrupted run's.
  step-override
      `--restart DIR --set time.step=...` with a step other than the checkpoint's: exit 2, one error
      line naming time.step; config.toml stays byte for byte what it was.
  rejected-set
      Overrides a restart rejects leave config.toml byte for byte as it was, and the folder still
      restarts afterwards to the uninterrupted series: an override of the case (a valve parameter),
      a restart ending before the checkpoint (time.cycles=1 for a lumped run stopped after its first
      cycle: --stop above 8000), and a value out of range.
  lengthen
      A run that reached its end with checkpoint.every > 0 wrote a checkpoint at its last step (as
      well as every `every` steps), so `--restart DIR --set time.end=LONGER` (--longer) continues the
      finished run, to the series of a run that was that long from the start.
  fields-not-a-folder
      A stopped run whose fields/ was replaced by a regular file: the restart, on rank 0 creating the
      folder, fails on every rank (exit 3, an error line naming the path), in time: no rank is left
      waiting for rank 0.
Prints what it checked; exits 1 on the first failure.
"""
import argparse
import os
import pathlib
import shlex
import shutil
import signal
import subprocess
import sys
import time

FAIL = 1


def fail(message, output=None):
    if output is not None:
        print(output)
    print(f"FAIL: {message}")
    sys.exit(FAIL)


def add_run_arguments(parser):
    """The arguments every fault script takes and Runner reads: IBVALVE MPIEXEC RANKS CASE WORK [--set ...]."""
    parser.add_argument("ibvalve")
    parser.add_argument("mpiexec")
    parser.add_argument("ranks")
    parser.add_argument("case")
    parser.add_argument("work")
    parser.add_argument("--set", action="append", default=[], help="overrides of every run of CASE")


class Runner:
    def __init__(self, args):
        self.launch = [args.mpiexec, "--oversubscribe", "-n", args.ranks, args.ibvalve, "run"]
        self.case = args.case
        self.sets = [f"--set={s}" for s in args.set]

    def command(self, folder, *extra, restart=False):
        if restart:
            return self.launch + ["--restart", str(folder)] + list(extra)
        return self.launch + [self.case, "-o", str(folder)] + self.sets + list(extra)

    def run(self, folder, *extra, restart=False, expect=0):
        command = self.command(folder, *extra, restart=restart)
        print("+", " ".join(command), flush=True)
        result = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        output = result.stdout + result.stderr
        if result.returncode != expect:
            fail(f"exit code {result.returncode}, expected {expect}", output)
        return result


def error_lines(result):
    return [line for line in result.stderr.splitlines() if line.startswith("error:")]


def one_error_line(result, *words):
    lines = error_lines(result)
    if len(lines) != 1:
        fail(f"{len(lines)} error lines, expected one", result.stdout + result.stderr)
    for word in words:
        if word not in lines[0]:
            fail(f"the error line does not name {word}: {lines[0]}")
    print(f"one error line: {lines[0]}")
    return lines[0]


def checkpoints(folder):
    return sorted(p.name for p in (folder / "checkpoints").glob("step_*.h5"))


def same_series(whole, continued, what):
    a, b = (whole / "timeseries.csv").read_bytes(), (continued / "timeseries.csv").read_bytes()
    if a != b:
        x, y = a.decode().splitlines(), b.decode().splitlines()
        for i, (p, q) in enumerate(zip(x, y)):
            if p != q:
                fail(f"{what}: timeseries.csv differs first at line {i + 1}:\n  whole: {p}\n  {what}: {q}")
        fail(f"{what}: timeseries.csv has {len(x)} lines uninterrupted, {len(y)} {what}")
    print(f"{what}: timeseries.csv identical byte for byte to the uninterrupted run's "
          f"({sum(1 for line in a.decode().splitlines() if not line.startswith('#')) - 1} rows)")


def data_rows(folder):
    path = folder / "timeseries.csv"
    # The header and the '#' units line are not rows.
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")] if path.exists() else []
    return max(len(lines) - 1, 0)


def processes_of(launcher):
    """The ibvalve processes mpiexec started, by rank (Open MPI starts them as its children)."""
    ranks = {}
    for entry in pathlib.Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            if parent != launcher:
                continue
            environment = (entry / "environ").read_bytes().split(b"\0")
        except (OSError, IndexError, ValueError):
            continue
        for variable in environment:
            if variable.startswith(b"OMPI_COMM_WORLD_RANK="):
                ranks[int(variable.split(b"=")[1])] = int(entry.name)
    return ranks


def run_until_rows(runner, work, after_rows):
    """Runs the case whole, then starts it again in `split` and waits for `after_rows` rows there: the
    moment a signal scenario sends its signal. Returns the two folders and the running launcher."""
    whole, split = work / "whole", work / "split"
    runner.run(whole, "-q")
    command = runner.command(split, "-q")
    print("+", " ".join(command), flush=True)
    launcher = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while data_rows(split) < after_rows:
        if launcher.poll() is not None or time.time() > deadline:
            out, err = launcher.communicate()
            fail(f"the run ended or stalled before {after_rows} rows, before the signal", out + err)
        time.sleep(0.01)
    return whole, split, launcher


def signal_scenario(runner, work, which, ranks, after_rows):
    code = 128 + which
    name = signal.Signals(which).name
    whole, split, launcher = run_until_rows(runner, work, after_rows)
    processes = processes_of(launcher.pid)
    if len(processes) != ranks:
        launcher.kill()
        fail(f"found {len(processes)} ibvalve processes of mpiexec, expected {ranks}")
    last = max(processes)
    os.kill(processes[last], which)
    print(f"sent {name} to rank {last} (pid {processes[last]}) after {data_rows(split)} rows")
    out, err = launcher.communicate(timeout=120)
    if launcher.returncode != code:
        fail(f"exit code {launcher.returncode} after {name}, expected {code}", out + err)
    stopped = [line for line in out.splitlines() if line.startswith(f"stopped by {name} after step ")]
    if len(stopped) != 1 or f"ibvalve run --restart {split}" not in stopped[0]:
        fail("no one line saying where the run stopped and how to continue", out + err)
    print(f"exit {code}, {stopped[0]}")
    if error_lines(subprocess.CompletedProcess([], 0, out, err)):
        fail("a signal stop printed an error line", err)
    saved = checkpoints(split)
    step = int(stopped[0].split(" after step ")[1].split()[0])
    if f"step_{step:09d}.h5" not in saved:
        fail(f"no checkpoint of step {step} among {saved}")
    if data_rows(split) == 0 or (split / "report").exists():
        fail("the stopped run did not keep its series, or wrote a report")
    result = runner.run(split, restart=True)
    if f"restarting from {split / 'checkpoints' / f'step_{step:09d}.h5'}" not in result.stdout:
        fail("the restart did not continue from the signal's checkpoint", result.stdout)
    same_series(whole, split, "stopped by " + name + " and restarted")


def mpiexec_ctrl_c_scenario(runner, work, ranks, after_rows):
    """SIGINT to mpiexec, as a Ctrl-C in its terminal gives it: Open MPI passes it on to the ranks as
    SIGTERM; the stopped line says so and gives the whole restart command, mpiexec and its options
    included, which, run as printed, continues to the uninterrupted series."""
    whole, split, launcher = run_until_rows(runner, work, after_rows)
    os.kill(launcher.pid, signal.SIGINT)
    print(f"sent SIGINT to mpiexec (pid {launcher.pid}) after {data_rows(split)} rows")
    out, err = launcher.communicate(timeout=120)
    # Open MPI 4.1's mpiexec sends the ranks SIGCONT, then SIGTERM a grace later, then SIGKILL a grace
    # after that (odls_base_sigkill_timeout, 1 s): a run whose steps end within the first grace writes
    # its report when the SIGTERM comes, and is killed in it. The case must outlast the grace.
    if data_rows(split) == data_rows(whole):
        fail("the run had taken its last step when mpiexec's SIGTERM came, a grace after the SIGINT: "
             "the case is too short for this test", out + err)
    # Open MPI's mpiexec, aborting the job it was signalled to stop, exits with 1 whatever the ranks do.
    if launcher.returncode != 1:
        fail(f"mpiexec's exit code {launcher.returncode}, expected Open MPI's 1", out + err)
    stopped = [line for line in out.splitlines() if line.startswith("stopped by SIGTERM from mpiexec (")]
    if len(stopped) != 1:
        fail("no one line saying mpiexec's SIGTERM (a Ctrl-C or a SIGTERM to it) stopped the run", out + err)
    restart = stopped[0].split("; continue with: ")[1]
    expected = shlex.join(runner.launch + ["--restart", str(split)])  # mpiexec OPTIONS IBVALVE run
    if restart != expected:
        fail(f"the restart command is\n  {restart}\nnot mpiexec's as it was given:\n  {expected}")
    print(f"mpiexec exit 1; {stopped[0]}")
    result = subprocess.run(shlex.split(restart), stdin=subprocess.DEVNULL, capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"the printed restart command: exit {result.returncode}", result.stdout + result.stderr)
    same_series(whole, split, "stopped by Ctrl-C to mpiexec and restarted with the printed command")


def overwrite_scenario(runner, work, steps_b, every):
    folder, reference = work / "folder", work / "reference_b"
    case_b = ["--set=valve.max_area_fraction=0.5", f"--set=checkpoint.every={every}"]
    runner.run(folder, "-q", f"--set=checkpoint.every={every}")  # case A, whole: checkpoints and report
    old = checkpoints(folder)
    print(f"case A left {old} and report/: {(folder / 'report').exists()}")
    runner.run(reference, "-q", *case_b)
    runner.run(folder, "-q", "--overwrite", *case_b, f"--stop-after-steps={steps_b}")
    found = checkpoints(folder)
    expected = [f"step_{steps_b - every:09d}.h5", f"step_{steps_b:09d}.h5"]
    if found != expected:
        fail(f"after --overwrite with case B stopped at step {steps_b}: checkpoints {found}, expected {expected}")
    if (folder / "report").exists():
        fail("case A's report/ is still in the folder")
    print(f"--overwrite: the folder holds case B's checkpoints only {found}, no report of case A")
    result = runner.run(folder, restart=True)
    if f"step_{steps_b:09d}.h5" not in result.stdout:
        fail("the restart did not continue case B's checkpoint", result.stdout)
    same_series(reference, folder, "case B restarted")


def stopped_run(runner, folder, every, stop):
    runner.run(folder, "-q", f"--set=checkpoint.every={every}", f"--stop-after-steps={stop}")
    return checkpoints(folder)


def unchanged(folder, before, what):
    now = (folder / "config.toml").read_bytes()
    if now != before:
        fail(f"{what}: config.toml changed")
    print(f"{what}: config.toml byte for byte as before")


def foreign_scenario(runner, work, args, every, stop, foreign_case):
    folder, other = work / "folder", work / "other"
    stopped_run(runner, folder, every, stop)
    if foreign_case:
        runner.run(other, "-q", "--set=valve.max_area_fraction=0.5", f"--set=checkpoint.every={every}",
                   f"--stop-after-steps={stop + every}")
    else:
        other_runner = Runner(args)
        other_runner.case, other_runner.sets = args.foreign, []
        other_runner.run(other, "-q", "--set=checkpoint.every=1", "--stop-after-steps=2")
    source = sorted((other / "checkpoints").glob("step_*.h5"))[-1]
    planted = folder / "checkpoints" / f"step_{stop + every:09d}.h5"
    shutil.copy(source, planted)
    print(f"planted {source} as {planted}")
    before_config = (folder / "config.toml").read_bytes()
    before_series = (folder / "timeseries.csv").read_bytes()
    result = runner.run(folder, restart=True, expect=2)
    one_error_line(result, str(planted), *(["valve.max_area_fraction"] if foreign_case else ["model"]))
    unchanged(folder, before_config, "refused foreign checkpoint")
    if (folder / "timeseries.csv").read_bytes() != before_series:
        fail("timeseries.csv was cut for a refused checkpoint")


def damaged_scenario(runner, work, every, stop, torn):
    import h5py
    import numpy as np

    whole, folder = work / "whole", work / "folder"
    runner.run(whole, "-q", f"--set=checkpoint.every={every}")
    saved = stopped_run(runner, folder, every, stop)
    newest = folder / "checkpoints" / saved[-1]
    if torn:
        size = newest.stat().st_size
        with open(newest, "r+b") as f:
            f.truncate(size // 2)
        print(f"cut {newest} to {size // 2} of {size} bytes")
    else:
        with h5py.File(newest, "r") as f:
            names = []
            f.visititems(lambda n, item: names.append(n) if isinstance(item, h5py.Dataset) else None)
            dataset = f[names[0]]
            offset, value = dataset.id.get_offset(), np.asarray(dataset[()]).ravel()[0]
        with open(newest, "r+b") as f:
            f.seek(offset)
            byte = f.read(1)[0]
            f.seek(offset)
            f.write(bytes([byte ^ 0x01]))  # the lowest bit of the dataset's first value
        with h5py.File(newest, "r") as f:
            flipped = np.asarray(f[names[0]][()]).ravel()[0]
        print(f"flipped one bit of {names[0]} in {newest}: {value!r} -> {flipped!r}")
    result = runner.run(folder, restart=True)
    warnings = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    if len(warnings) != 1 or str(newest) not in warnings[0]:
        fail("expected one warning line naming the skipped checkpoint", result.stdout + result.stderr)
    if "HDF5-DIAG" in result.stdout + result.stderr:
        fail("HDF5 printed a diagnostic stack", result.stderr)
    print(f"one warning line: {warnings[0]}")
    if f"restarting from {folder / 'checkpoints' / saved[-2]}" not in result.stdout:
        fail(f"the restart did not continue from the one before, {saved[-2]}", result.stdout)
    same_series(whole, folder, "restarted past the " + ("torn" if torn else "corrupt") + " checkpoint")


def step_override_scenario(runner, work, every, stop, step):
    folder = work / "folder"
    stopped_run(runner, folder, every, stop)
    before = (folder / "config.toml").read_bytes()
    result = runner.run(folder, f"--set=time.step={step}", restart=True, expect=2)
    one_error_line(result, "time.step")
    unchanged(folder, before, f"--set time.step={step} refused")


def rejected_set_scenario(runner, work, every, stop):
    whole, folder = work / "whole", work / "folder"
    runner.run(whole, "-q", f"--set=checkpoint.every={every}")
    stopped_run(runner, folder, every, stop)
    before = (folder / "config.toml").read_bytes()
    for override, named in (("valve.max_area_fraction=0.5", "valve.max_area_fraction"),
                            ("time.cycles=1", "nothing to continue"),
                            ("valve.max_area_fraction=7", "valve.max_area_fraction")):
        result = runner.run(folder, f"--set={override}", restart=True, expect=2)
        one_error_line(result, named)
        unchanged(folder, before, f"--set {override} refused")
    runner.run(folder, "-q", restart=True)
    same_series(whole, folder, "restarted after the refused overrides")


def lengthen_scenario(runner, work, every, longer, last_step):
    finished, reference = work / "finished", work / "longer"
    runner.run(finished, "-q", f"--set=checkpoint.every={every}")
    last = f"step_{last_step:09d}.h5"
    if last not in checkpoints(finished):
        fail(f"the finished run wrote no checkpoint of its last step {last_step}: {checkpoints(finished)}")
    print(f"the finished run's checkpoints: {checkpoints(finished)}")
    runner.run(reference, "-q", f"--set=checkpoint.every={every}", f"--set={longer}")
    result = runner.run(finished, f"--set={longer}", restart=True)
    if f"restarting from {finished / 'checkpoints' / last}" not in result.stdout:
        fail("the lengthened run did not continue from the last step's checkpoint", result.stdout)
    same_series(reference, finished, "finished, then lengthened")


def fields_not_a_folder_scenario(runner, work, every, stop):
    folder = work / "folder"
    stopped_run(runner, folder, every, stop)
    shutil.rmtree(folder / "fields")
    (folder / "fields").write_text("not a folder\n")
    command = runner.command(folder, restart=True)
    print("+", " ".join(command), flush=True)
    try:
        result = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        fail("the restart hung (60 s): a rank waits for rank 0")
    if result.returncode != 3:
        fail(f"exit code {result.returncode}, expected 3", result.stdout + result.stderr)
    lines = error_lines(result)
    if not lines or f"{folder / 'fields'}: cannot create the folder" not in lines[0]:
        fail("no error line naming the fields folder", result.stdout + result.stderr)
    print(f"exit 3: {lines[0]}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scenario")
    add_run_arguments(parser)
    parser.add_argument("--every", type=int, default=1000, help="checkpoint.every")
    parser.add_argument("--stop", type=int, default=5000, help="--stop-after-steps of the stopped runs")
    parser.add_argument("--after-rows", type=int, default=200, help="signal once the series has this many rows")
    parser.add_argument("--foreign", help="a case file of another model (foreign-model)")
    parser.add_argument("--step", default="2e-4", help="the time.step a restart must refuse")
    parser.add_argument("--longer", help="lengthen: the override of a longer run, e.g. time.end=0.032")
    parser.add_argument("--last-step", type=int, help="lengthen: the finished run's last step")
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    runner = Runner(args)
    s = args.scenario
    if s in ("signal-term", "signal-int"):
        signal_scenario(runner, work, signal.SIGTERM if s == "signal-term" else signal.SIGINT, int(args.ranks),
                        args.after_rows)
    elif s == "mpiexec-ctrl-c":
        mpiexec_ctrl_c_scenario(runner, work, int(args.ranks), args.after_rows)
    elif s == "overwrite":
        overwrite_scenario(runner, work, args.stop, args.every)
    elif s in ("foreign-case", "foreign-model"):
        foreign_scenario(runner, work, args, args.every, args.stop, s == "foreign-case")
    elif s in ("corrupt", "torn"):
        damaged_scenario(runner, work, args.every, args.stop, s == "torn")
    elif s == "step-override":
        step_override_scenario(runner, work, args.every, args.stop, args.step)
    elif s == "rejected-set":
        rejected_set_scenario(runner, work, args.every, args.stop)
    elif s == "fields-not-a-folder":
        fields_not_a_folder_scenario(runner, work, args.every, args.stop)
    elif s == "lengthen":
        lengthen_scenario(runner, work, args.every, args.longer, args.last_step)
    else:
        fail(f"unknown scenario {s}")
    print("PASS")


if __name__ == "__main__":
    main()
