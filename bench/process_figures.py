"""Runs one command as a whole process for the bench scripts: its output, wall time and the peak
resident memory of its largest process (MiB)."""
import re
import subprocess
import sys
import time

# Each run in its own small Python process, which reports the peak resident memory of its largest
# descendant (getrusage of the children it waited for: mpiexec and, through it, the ranks).
WRAPPER = """
import resource, subprocess, sys
code = subprocess.run(sys.argv[1:]).returncode
print("PEAK_KIB", resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
sys.exit(code)
"""


def run(command, env):
    start = time.monotonic()
    result = subprocess.run([sys.executable, "-c", WRAPPER, *command], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=env)
    wall = time.monotonic() - start
    if result.returncode != 0:
        print(result.stdout)
        sys.exit(f"{' '.join(command)}: exit code {result.returncode}")
    peak = re.search(r"PEAK_KIB (\d+)", result.stdout)
    return result.stdout, wall, int(peak.group(1)) / 1024.0 if peak else float("nan")
