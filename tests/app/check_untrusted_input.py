#!/usr/bin/env python3
"""Files and case data a user may have been sent: each scenario is one specification.

  check_untrusted_input.py SCENARIO IBVALVE MPIEXEC RANKS CASE WORK_DIR

CASE is the lumped case (examples/lumped/default.toml; a run takes about a second).
Scenarios:
  report-planted-modules
      `ibvalve report RUN_DIR` on a run folder whose report/ and report/cycle_1/ hold planted json.py,
      matplotlib.py and numpy.py (each would write a marker file when imported): none of them runs (the
      plot script is run isolated, with no shell between), and the report is still made (metrics.json,
      report.md, report.html; the plots when matplotlib is there).
  waveform-content
      A readable file that is not a waveform table (a planted file of secret lines, /etc/passwd) given
      as lv_pressure.file: exit 2, one error line naming FILE:LINE and what was expected, no line (or
      comma-separated field) of the file in the output, no run folder.
  petsc-options
      petsc.options in a case file that would write or read a file, draw, or reach beyond ibvalve's
      solvers (-log_view :TARGET, a bare -log_view, -options_file FILE, -malloc_dump FILE, -draw_type
      tikz, -fluid_stokes_ksp_view_mat binary, -prefix_push, a quote inside a token, which PETSc does
      not honour there): exit 2, one error line naming the case file's line, petsc.options and the
      option, TARGET neither created nor truncated, no run folder. Solver settings and monitors to the
      terminal under ibvalve's solver prefixes pass.
  report-period
      `ibvalve report` takes the period from the run's config.toml (0.8 s for the lumped case); a
      --period other than the run's cycle (0.0096 s: RF of hundreds of %) prints one warning line
      naming both; a period holding only a few rows of the series, or longer than the series, is
      refused (exit 2, one error line naming --period) and writes nothing.
  input-files
      Files a run or a command reads, and folders it writes:
      - a sparse 100 MiB waveform table is refused at once (exit 2, naming the file and its limit);
      - a FIFO named as the newest checkpoint is passed over by --restart (a warning naming it),
        which continues from the one before;
      - a timeseries.csv with a column named twice is refused by `report` and `compare` (exit 2,
        naming the file, the line and the column), not read as the one column;
      - a metrics.json holding 1e999, and `compare -o /proc/...`, are bad input (exit 2 naming the
        file or folder), not internal errors.
Prints what it checked; exits 1 on the first failure.
"""
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys


def fail(message, output=None):
    if output is not None:
        print(output)
    print(f"FAIL: {message}")
    sys.exit(1)


class Runner:
    def __init__(self, ibvalve, mpiexec, ranks):
        self.prefix = [mpiexec, "--oversubscribe", "-n", str(ranks), ibvalve]

    def __call__(self, *args, cwd=None, timeout=240):
        try:
            p = subprocess.run(self.prefix + [str(a) for a in args], stdin=subprocess.DEVNULL,
                               capture_output=True, text=True, cwd=cwd, timeout=timeout)
        except subprocess.TimeoutExpired:
            fail(f"no answer within {timeout} s: {' '.join(str(a) for a in args)}")
        return p.returncode, p.stdout, p.stderr


def one_error_line(code, out, err, expected_code=2):
    shown = f"--- stdout:\n{out}--- stderr:\n{err}"
    if code != expected_code:
        fail(f"exit code {code}, expected {expected_code}", shown)
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    if len(lines) != 1:
        fail(f"{len(lines)} error lines, expected one", shown)
    return lines[0]


def lumped_case(case, work, extra_top=""):
    """The lumped case with its waveform path made absolute, and `extra_top` lines before the tables."""
    text = pathlib.Path(case).read_text()
    text = re.sub(r'"(\.\./waveforms/[^"]+)"',
                  lambda m: json.dumps(str((pathlib.Path(case).parent / m.group(1)).resolve())), text)
    first_table = text.index("\n[")
    text = text[:first_table] + "\n" + extra_top + text[first_table:]
    return text


def lumped_run(run, case, directory, *extra):
    code, out, err = run("run", case, "-o", directory, "--overwrite", "--set", "time.cycles=2",
                         "--set", "report.plots=false", *extra)
    if code != 0:
        fail(f"the lumped run exited with {code}", out + err)


def report_planted_modules(run, case, work):
    directory = work / "run"
    lumped_run(run, case, directory)
    marker_dir = work / "markers"
    marker_dir.mkdir()
    report = directory / "report"
    # Planted beside the script, in the cycle's folder where it runs, and in report/ itself.
    for folder in (report, report / "cycle_1"):
        folder.mkdir(exist_ok=True)
        for module in ("json", "matplotlib", "numpy", "os"):
            marker = marker_dir / f"{module}.ran"
            (folder / f"{module}.py").write_text(
                f"open({str(marker)!r}, 'w').write('planted {module}.py ran')\n")
    for name in ("metrics.json", "report.md", "report.html"):
        (report / name).unlink(missing_ok=True)
    code, out, err = run("report", directory, cwd=report)
    ran = sorted(p.name for p in marker_dir.iterdir())
    if ran:
        fail(f"planted modules ran: {', '.join(ran)} (exit {code})", out + err)
    for name in ("metrics.json", "report.md", "report.html"):
        if not (report / name).is_file():
            fail(f"report/{name} was not written (exit {code})", out + err)
    plotted = sorted(p.name for p in report.glob("*.png"))
    if code == 0:
        if len(plotted) != 4:
            fail(f"exit 0 but {len(plotted)} plots: {plotted}", out + err)
    elif code == 3:
        # Only a Python without matplotlib may fail, with one line naming the plotting failure.
        line = one_error_line(code, out, err, 3)
        if "matplotlib" not in line:
            fail("plotting failed for another reason than a missing matplotlib", out + err)
        print(f"note: no matplotlib here ({line})")
    else:
        fail(f"exit code {code}", out + err)
    print(f"ok: no planted module ran; report written, {len(plotted)} plots (exit {code})")


def leaked_lines(path, output):
    """Lines and comma-separated fields (8 characters or more) of `path` that appear in `output`."""
    found = []
    for line in pathlib.Path(path).read_text(errors="replace").splitlines():
        pieces = [line.strip()] + [field.strip() for field in line.split(",")]
        for piece in pieces:
            if len(piece) >= 8 and piece in output:
                found.append(piece)
    return found


def waveform_content(run, case, work):
    secret = work / "secret.txt"
    secret.write_text("alice:SECRET-first-line:1000\nbob:SECRET-second-line:1001\n"
                      "carol,SECRET-third-field,1002\n")
    files = [secret]
    if os.access("/etc/passwd", os.R_OK):
        files.append(pathlib.Path("/etc/passwd"))
    for file in files:
        directory = work / f"run_{file.name}"
        code, out, err = run("run", case, "-o", directory, "--set", f"lv_pressure.file={json.dumps(str(file))}")
        line = one_error_line(code, out, err)
        if not re.match(rf"^error: {re.escape(str(file))}:[0-9]+: .*expected", line):
            fail(f"the error line does not name {file}:LINE and what was expected: {line}")
        leaked = leaked_lines(file, out + err)
        if leaked:
            fail(f"the output echoes {len(leaked)} line(s) of {file}: {leaked[0]!r}", out + err)
        if directory.exists():
            fail(f"{directory} was created")
        print(f"ok: {line}")


def petsc_options(run, case, work):
    target = work / "target.txt"
    readable = work / "options.txt"
    readable.write_text("-SECRET_option_line 1\n")
    attempts = [
        ("-log_view", f"-log_view :{target}"),
        ("-log_view", f"-fluid_stokes_ksp_type gmres -log_view :{target}:ascii_info_detail"),
        ("-options_file", f"-options_file {readable}"),
        ("-options_file", "-options_file /etc/hostname"),
        ("-malloc_dump", f"-malloc_dump {target}"),
        ("-fluid_ksp_view", "-fluid_ksp_view binary"),
        ("-fluid_ksp_monitor", f"-fluid_ksp_monitor ascii:{target}"),
        ("-prefix_push", "-prefix_push log_ -view"),
        ("-on_error_attach_debugger", "-on_error_attach_debugger"),
        # PETSc honours a double quote only at a token's start: this is three options to PETSc, the
        # second of which writes the matrix to TARGET.
        ('-x: \'"\'', f'-x" -fluid_stokes_ksp_view_mat ascii:{target} -y"'),
        ("-fluid_stokes_ksp_view_mat binary", "-fluid_stokes_ksp_view_mat binary"),
        ("-fluid_stokes_ksp_monitor_lg_residualnorm", "-fluid_stokes_ksp_monitor_lg_residualnorm"),
        ("-fluid_stokes_ksp_type python", "-fluid_stokes_ksp_type python -fluid_stokes_ksp_python_type x.Y"),
        ("-fluid_stokes_ksp_rtol", "-fluid_stokes_ksp_rtol\t1e-8"),
        ("-draw_type", "-draw_type tikz"),
        ("-log_view", "-log_view"),
    ]
    for option, value in attempts:
        target.write_text("keep\n")
        case_file = work / "case.toml"
        case_file.write_text(lumped_case(case, work, f"petsc.options = {json.dumps(value)}\n"))
        line_number = next(i + 1 for i, line in enumerate(case_file.read_text().splitlines())
                           if line.startswith("petsc.options"))
        directory = work / "run"
        code, out, err = run("run", case_file, "-o", directory)
        line = one_error_line(code, out, err)
        expected = f"^error: {re.escape(str(case_file))}:{line_number}: petsc.options: .*{re.escape(option)}"
        if not re.match(expected, line):
            fail(f"the error line does not name {case_file}:{line_number}, petsc.options and {option}: {line}")
        if "SECRET" in out + err:
            fail(f"the output echoes {readable}", out + err)
        if target.read_text() != "keep\n":
            fail(f"{target} was written ({value})")
        if directory.exists():
            fail(f"{directory} was created ({value})")
        print(f"ok: {value!r}: {line}")
    # What stays allowed in a case file: solver settings and monitors to the terminal.
    case_file = work / "case.toml"
    allowed = "-fluid_stokes_ksp_type gmres -fluid_stokes_ksp_rtol 1e-8 -fluid_stokes_ksp_monitor"
    case_file.write_text(lumped_case(case, work, f"petsc.options = {json.dumps(allowed)}\n"))
    directory = work / "run"
    code, out, err = run("run", case_file, "-o", directory, "--set", "time.cycles=1", "--set", "report.plots=false")
    if code != 0:
        fail(f"a case with harmless PETSc options exited with {code}", out + err)
    print(f"ok: {allowed} accepted")


def report_period(run, case, work):
    directory = work / "run"
    lumped_run(run, case, directory)
    # No --period: the run's cycle (report.period of its config.toml), no warning.
    code, out, err = run("report", directory, "--no-plots")
    if code != 0 or "warning" in out + err:
        fail(f"report without --period: exit {code}", out + err)
    period = json.loads((directory / "report/metrics.json").read_text())["settings"]["period_s"]
    if period != 0.8:
        fail(f"report without --period used {period} s, not the run's 0.8 s")
    print("ok: the run's period 0.8 s, no warning")
    # A period other than the run's cycle: one warning line naming both.
    code, out, err = run("report", directory, "--no-plots", "--period", "0.0096")
    warnings = [line for line in (out + err).splitlines() if line.startswith("warning:")]
    if code != 0 or len(warnings) != 1:
        fail(f"--period 0.0096: exit {code}, {len(warnings)} warning lines (expected 0 and one)", out + err)
    if "0.0096" not in warnings[0] or "0.8" not in warnings[0]:
        fail(f"the warning does not name 0.0096 and the run's 0.8: {warnings[0]}")
    print(f"ok: {warnings[0]}")
    # Periods that do not fit the series: a few rows, or longer than the series.
    for period in ("0.0003", "5"):
        shutil.rmtree(directory / "report", ignore_errors=True)
        code, out, err = run("report", directory, "--no-plots", "--period", period)
        line = one_error_line(code, out, err)
        if "--period" not in line or period not in line:
            fail(f"the error line does not name --period {period}: {line}")
        if (directory / "report").exists():
            fail(f"--period {period}: report/ was written")
        print(f"ok: {line}")


def input_files(run, case, work):
    # A waveform table of 100 MiB, sparse (no disk used): named with its limit in seconds, not read.
    sparse = work / "sparse.csv"
    with open(sparse, "w") as f:
        f.write("t,p\n")
        f.truncate(100 << 20)
    code, out, err = run("run", case, "-o", work / "sparse_run",
                         "--set", f"lv_pressure.file={json.dumps(str(sparse))}", timeout=30)
    line = one_error_line(code, out, err)
    if str(sparse) not in line or "MiB" not in line:
        fail(f"the error line does not name {sparse} and its limit: {line}")
    print(f"ok: {line}")
    # A FIFO under the newest checkpoint's name: passed over, not opened.
    stopped = work / "stopped"
    code, out, err = run("run", case, "-o", stopped, "--set", "time.cycles=1", "--set", "report.plots=false",
                         "--stop-after-steps", "3000")
    if code != 0:
        fail(f"the stopped run exited with {code}", out + err)
    fifo = stopped / "checkpoints" / "step_000999999.h5"
    os.mkfifo(fifo)
    code, out, err = run("run", "--restart", stopped, timeout=60)
    if code != 0:
        fail(f"--restart with a FIFO checkpoint exited with {code}", out + err)
    warnings = [l for l in (out + err).splitlines() if l.startswith("warning:") and str(fifo) in l]
    if len(warnings) != 1 or "not a regular file" not in warnings[0]:
        fail("--restart did not warn once that the FIFO is not a regular file", out + err)
    print(f"ok: {warnings[0]}")

    directory = work / "run"
    lumped_run(run, case, directory)
    # A column named twice: the report and the comparison refuse the series, naming file, line, column.
    twice = work / "twice"
    shutil.copytree(directory, twice)
    series = (twice / "timeseries.csv").read_text().split("\n", 1)
    header = series[0].split(",")
    header[header.index("Q_outlet")] = "Q_valve"
    (twice / "timeseries.csv").write_text(",".join(header) + "\n" + series[1])
    shutil.rmtree(twice / "report")
    for args in (("report", twice, "--no-plots"),
                 ("compare", twice, directory, "-o", work / "twice_cmp", "--no-plots")):
        code, out, err = run(*args)
        line = one_error_line(code, out, err)
        if f"{twice / 'timeseries.csv'}:1:" not in line or "'Q_valve'" not in line:
            fail(f"{args[0]}: the error line does not name timeseries.csv:1 and 'Q_valve': {line}")
        print(f"ok: {args[0]}: {line}")

    # A number beyond a double in metrics.json.
    huge = work / "huge"
    shutil.copytree(directory, huge)
    metrics = huge / "report" / "metrics.json"
    metrics.write_text(re.sub(r'"value": [-0-9.eE+]+', '"value": 1e999', metrics.read_text(), count=1))
    code, out, err = run("compare", huge, directory, "-o", work / "huge_cmp", "--no-plots")
    line = one_error_line(code, out, err)
    if str(metrics) not in line:
        fail(f"the error line does not name {metrics}: {line}")
    print(f"ok: {line}")
    # An output folder that cannot be made.
    code, out, err = run("compare", directory, "-o", "/proc/ibvalve/comparison", "--no-plots")
    line = one_error_line(code, out, err)
    if "/proc/ibvalve/comparison: cannot create the output folder" not in line:
        fail(f"the error line does not name /proc/ibvalve/comparison: {line}")
    print(f"ok: {line}")


def main():
    scenario, ibvalve, mpiexec, ranks, case, work = sys.argv[1:7]
    work = pathlib.Path(work).resolve()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    run = Runner(ibvalve, mpiexec, int(ranks))
    scenarios = {"report-planted-modules": report_planted_modules, "waveform-content": waveform_content,
                 "petsc-options": petsc_options, "report-period": report_period, "input-files": input_files}
    scenarios[scenario](run, pathlib.Path(case).resolve(), work)


if __name__ == "__main__":
    main()
