#!/usr/bin/env python3
"""kill -9 at random moments of a checkpointed run: a node failure must lose nothing that
was checkpointed.

  check_kill_restart.py IBVALVE MPIEXEC RANKS CASE WORK_DIR --every E [--kills N] [--seed S] [--set ...]

Runs CASE once uninterrupted (checkpoint.every = E), then N times (default 20): starts it, waits for
a checkpoint drawn at random to be on disk and then a random part of the time between two checkpoints
(reproducible: --seed, printed; a new one is drawn when none is given), sends SIGKILL to every rank at
once (mpiexec's children, as a node failure would end them) and, once they are gone, `--restart`s the
folder. Asserts for each: the restart continues from the newest checkpoint on disk when the ranks died
(every checkpoint file there is complete: no warning about a torn one), and the restarted
timeseries.csv equals the uninterrupted run's byte for byte. Every third kill is aimed at a checkpoint
write (sent when a checkpoint's temporary file first appears); a kill counts as inside a write when
such a temporary file is there after the ranks died. The kill is placed by the run's progress (which
checkpoint is on disk), not by the time since its start, so a machine busier or idler than during the
timing run still lands its kills; a kill that lands after the last checkpoint is drawn again, and the
reasons are printed when too few land. Prints what it checked and the time it took; exits 1 on the
first failure.
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


def one_kill(runner, folder, ranks, after, delay, aim_at_write, last):
    """Starts the run, waits for checkpoint `after` on disk and then `delay` seconds (or, aimed at a
    write, for the next temporary checkpoint file after them) and kills every rank. Returns the newest
    checkpoint and whether a write was cut, or the reason the kill has nothing to continue."""
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
        time.sleep(0.001)
    # The wait starts at a checkpoint on disk, not at the ranks' start: how far a run has come in a
    # given time varies with the machine's load, which checkpoint it has written does not.
    # Older checkpoints are deleted (checkpoint.keep): `after` or a newer one.
    while not checkpoints(folder) or checkpoints(folder)[-1] < after:
        if launcher.poll() is not None:
            return f"the run ended (exit {launcher.returncode}) before {after} was on disk"
        time.sleep(0.001)
    start = time.time()
    if aim_at_write:
        while time.time() - start < delay or not temporaries(folder):
            if launcher.poll() is not None:
                return "the run ended before a checkpoint write came"
            time.sleep(0.0002)
    else:
        time.sleep(delay)
    for pid in processes.values():
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    launcher.communicate(timeout=60)
    if launcher.returncode == 0:
        return "the run finished before the kill"
    saved = checkpoints(folder)
    if not saved or saved[-1] == last:
        return "the kill came after the run's last checkpoint"
    return saved[-1], bool(temporaries(folder))


def timeline(runner, folder, ranks):
    """The checkpoints of a run of its own in the order they appeared, and the mean seconds between
    two of them: a kill is placed after one of them, within about one interval."""
    shutil.rmtree(folder, ignore_errors=True)
    launcher = subprocess.Popen(runner.command(folder, "-q"), stdin=subprocess.DEVNULL,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    seen = {}
    while launcher.poll() is None:
        for name in checkpoints(folder):
            seen.setdefault(name, time.time())
        time.sleep(0.001)
    if launcher.returncode != 0 or len(seen) < 3:
        fail(f"the timing run exited with {launcher.returncode} or wrote fewer than 3 checkpoints")
    names = sorted(seen)
    interval = (seen[names[-1]] - seen[names[0]]) / (len(names) - 1)
    return names, interval


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
    names, interval = timeline(runner, folder, ranks)
    print(f"{len(names)} checkpoints, {interval * 1000:.1f} ms apart in a run of its own", flush=True)
    missed = {}
    while kill < args.kills:
        draws += 1
        if draws > 2 * args.kills:
            fail(f"only {kill} of {draws} kills landed before the run's last checkpoint: "
                 + "; ".join(f"{n} x {why}" for why, n in missed.items()))
        aim = kill % 3 == 2
        # After a checkpoint drawn from all but the last two, within about one interval: the kill
        # has something checkpointed to continue and something not yet checkpointed to lose.
        after = chance.choice(names[:-2])
        delay = chance.uniform(0.0, interval)
        outcome = one_kill(runner, folder, ranks, after, delay, aim, names[-1])
        if isinstance(outcome, str):
            missed[outcome] = missed.get(outcome, 0) + 1
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
        print(f"kill {kill}: {delay * 1000:.1f} ms after {after}{aimed}, newest checkpoint {newest}"
              f"{', inside a checkpoint write' if in_write else ''}", flush=True)
        same_series(whole, folder, f"kill {kill}, restarted")
    print(f"{args.kills} kills ({draws - args.kills} drawn again), {inside} inside a checkpoint write; "
          f"{time.time() - began:.0f} s in all")
    print("PASS")


if __name__ == "__main__":
    main()
