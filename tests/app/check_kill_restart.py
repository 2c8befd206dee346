#!/usr/bin/env python3
"""kill -9 at random moments of a checkpointed run (issue 20): a node failure must lose nothing that
was checkpointed.

  check_kill_restart.py IBVALVE MPIEXEC RANKS CASE WORK_DIR --every E [--kills N] [--seed S] [--set ...]

Runs CASE once uninterrupted (checkpoint.every = E), then N times (default 20): starts it, waits for
its first checkpoint on disk and then a random time (reproducible: --seed, printed; a new one is
drawn when none is given), sends SIGKILL to every rank at once (mpiexec's children, as a node failure
would end them) and, once they are gone, `--restart`s the folder. Asserts for each: the restart continues from the newest checkpoint on disk
when the ranks died (every checkpoint file there is complete: no warning about a torn one), and the
restarted timeseries.csv equals the uninterrupted run's byte for byte. Every third kill is aimed at a
checkpoint write (sent when a checkpoint's temporary file first appears); a kill counts as inside a
write when such a temporary file is there after the ranks died. The random wait is drawn from the
time between the first checkpoint and the end of a run timed on its own; a kill after the run's last
checkpoint is drawn again from a window shrunk by a third, so that a machine busier or idler than
during the timing run still lands its kills. Prints what it checked and the time it took; exits 1 on
the first failure.
"""
import argparse
import os
import pathlib
import random
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from check_restart_faults import Runner, add_run_arguments, checkpoints, fail, processes_of, same_series  # noqa: E402


def temporaries(folder):
    directory = folder / "checkpoints"
    if not directory.is_dir():
        return []
    return [p.name for p in directory.iterdir() if not re.fullmatch(r"step_\d{9}\.h5", p.name)]


def one_kill(runner, folder, ranks, delay, aim_at_write, last):
    shutil.rmtree(folder, ignore_errors=True)
    command = runner.command(folder, "-q")
    launcher = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
    # Ranks are found before the wait, so the kill itself is immediate.
    deadline = time.time() + 60
    processes = {}
    while len(processes) < ranks:
        if launcher.poll() is not None or time.time() > deadline:
            fail("the run ended or did not start before the kill")
        processes = processes_of(launcher.pid)
    # The wait starts at the first checkpoint on disk: the start-up's length (MPI, PETSc, FFTW plans)
    # varies most with the machine's load and is not part of the window.
    while not checkpoints(folder):
        if launcher.poll() is not None:
            return None
        time.sleep(0.001)
    start = time.time()
    if aim_at_write:
        # The first temporary checkpoint file after `delay`: a kill while a checkpoint is written.
        while time.time() - start < delay or not temporaries(folder):
            if launcher.poll() is not None:
                return None
    else:
        time.sleep(delay)
    for pid in processes.values():
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    launcher.communicate(timeout=60)
    if launcher.returncode == 0:
        return None  # it finished before the kill
    saved = checkpoints(folder)
    if not saved or saved[-1] == last:
        return None  # killed after its last checkpoint: nothing to continue
    return saved[-1], bool(temporaries(folder))


def timeline(runner, folder, ranks):
    """Seconds from the ranks' start to the run's first checkpoint and to its end, in a run of its own:
    the window in which a kill has something to lose and something to continue."""
    shutil.rmtree(folder, ignore_errors=True)
    launcher = subprocess.Popen(runner.command(folder, "-q"), stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 60
    while len(processes_of(launcher.pid)) < ranks:
        if launcher.poll() is not None or time.time() > deadline:
            fail("the timing run ended or did not start")
    start = time.time()
    first = None
    while launcher.poll() is None:
        if first is None and checkpoints(folder):
            first = time.time() - start
        time.sleep(0.002)
    end = time.time() - start
    if launcher.returncode != 0 or first is None:
        fail(f"the timing run exited with {launcher.returncode} or wrote no checkpoint")
    return first, end


def main():
    parser = argparse.ArgumentParser()
    add_run_arguments(parser)
    parser.add_argument("--every", type=int, required=True, help="checkpoint.every")
    parser.add_argument("--kills", type=int, default=20)
    parser.add_argument("--seed", type=int, default=None)
    args = parser.parse_args()
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(1 << 31)
    print(f"seed {seed} (repeat with --seed {seed})", flush=True)
    chance = random.Random(seed)
    work = pathlib.Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    began = time.time()
    args.set.append(f"checkpoint.every={args.every}")
    runner = Runner(args)
    whole = work / "whole"
    start = time.time()
    runner.run(whole, "-q")
    length = time.time() - start
    print(f"the uninterrupted run took {length:.2f} s", flush=True)
    ranks = int(args.ranks)
    inside, kill, draws = 0, 0, 0
    folder = work / "killed"
    # Kill moments are drawn after the first checkpoint, within the rest of a run timed on its own.
    first, end = timeline(runner, folder, ranks)
    print(f"from the ranks' start: first checkpoint at {first:.2f} s, end at {end:.2f} s", flush=True)
    window = end - first
    while kill < args.kills:
        draws += 1
        if draws > 5 * args.kills:
            fail(f"only {kill} of {draws} kills landed between the first checkpoint and the end")
        aim = kill % 3 == 2
        delay = chance.uniform(0.0, window)
        outcome = one_kill(runner, folder, ranks, delay, aim, checkpoints(whole)[-1])
        if outcome is None:
            window *= 2.0 / 3.0  # the kill came after the run's last checkpoint: it ran faster than timed
            continue
        kill += 1
        newest, in_write = outcome
        inside += in_write
        result = runner.run(folder, restart=True)
        if "warning:" in result.stdout + result.stderr:
            fail("the restart passed over a checkpoint: one that was on disk was not complete",
                 result.stdout + result.stderr)
        expected = folder / "checkpoints" / newest
        if f"restarting from {expected}" not in result.stdout:
            fail(f"kill {kill}: the restart did not continue from the newest checkpoint {newest}", result.stdout)
        aimed = " (aimed at a write)" if aim else ""
        print(f"kill {kill}: {delay:.3f} s after the first checkpoint{aimed}, newest checkpoint {newest}"
              f"{', inside a checkpoint write' if in_write else ''}", flush=True)
        same_series(whole, folder, f"kill {kill}, restarted")
    print(f"{args.kills} kills ({draws - args.kills} drawn again), {inside} inside a checkpoint write; "
          f"{time.time() - began:.0f} s in all")
    print("PASS")


if __name__ == "__main__":
    main()
