#!/usr/bin/env python3
"""Finding the keys and options of a case: each scenario is one specification.

  check_keys.py SCENARIO IBVALVE MPIEXEC SOURCE_DIR WORK_DIR [MODEL]

Scenarios:
  markdown
      `ibvalve keys` prints a Markdown table of the keys every model has (each once) and one per model
      (a heading per model, the keys with type, unit, default, allowed values, typical range, meaning);
      `ibvalve keys lumped` only the lumped one; on 2 ranks the output is the same (rank 0 prints).
  skeleton MODEL
      `ibvalve keys MODEL --format toml` is a case file: with its example waveform file next to it,
      `ibvalve run` validates it and takes its first step (--stop-after-steps 1), exit 0.
  recommended
      `ibvalve keys aortic-valve --format toml` writes the recommended case: every key
      examples/aortic_valve/default.toml sets has the same value in the skeleton (the waveform file by
      name), but for the case's name, its checkpoint cadence and its fit data (files of the repository;
      NOT_IN_THE_SKELETON says why); and every default of `ibvalve mesh aortic-valve` is the skeleton's
      mesh.* value.
  bare-set
      `--set key=WORD` for a string key is the word (`--set model=lumped`, `--set
      report.closure_rule=area`), the run goes on and config.toml holds the word.
  warning
      fluid.density 1060 (kg/m^3 written as g/mL): one warning line naming the key, the value and the
      typical range; the run goes on (exit 0).
  warnings-kept
      The same warning on 2 ranks is kept: once in log.txt, in run.json's "warnings" and in a warnings
      box of report.md and report.html (none without a warning); with --strict it is an error: exit 2,
      "error: " and the same message, no run folder; `ibvalve check --strict` the same.
  config-presets
      The lumped run's config.toml writes the Windkessel preset's values (not "(not set)"), numbers in
      their shortest form, file paths relative to the run folder (no path of the machine); run as a
      case file it gives the same timeseries.csv byte for byte.
  petsc-example
      The example `ibvalve --help` gives for PETSc options (-- -fluid_stokes_ksp_converged_reason), run
      on a small duct flow, prints a line per Stokes solve saying why it converged; `ibvalve run --help`
      lists the prefixes too.
Prints what it checked; exits 1 on the first failure.
"""
import html
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tomllib

MODELS = ["lumped", "ibfe", "fluid", "aortic-valve"]


def fail(message, output=None):
    if output is not None:
        print(output)
    print(f"FAIL: {message}")
    sys.exit(1)


class Runner:
    def __init__(self, ibvalve, mpiexec):
        self.ibvalve, self.mpiexec = ibvalve, mpiexec

    def __call__(self, *args, ranks=1, cwd=None):
        command = [self.mpiexec, "--oversubscribe", "-n", str(ranks), self.ibvalve] + [str(a) for a in args]
        p = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, text=True, cwd=cwd,
                           timeout=600)
        return p.returncode, p.stdout, p.stderr


def expect_ok(result, what):
    code, out, err = result
    if code != 0:
        fail(f"{what}: exit code {code}", f"--- stdout:\n{out}--- stderr:\n{err}")
    return out, err


def markdown(run, source, work):
    out, _ = expect_ok(run("keys"), "ibvalve keys")
    for model in MODELS:
        if f"## Model `{model}`" not in out:
            fail(f"no table for the {model} model", out)
    rows = [line for line in out.splitlines() if line.startswith("| `model` |")]
    if len(rows) != 1:
        fail(f"the common key `model` is listed {len(rows)} times, expected once", out)
    viscosity = [line for line in out.splitlines() if line.startswith("| `fluid.viscosity` |")]
    if not viscosity or not all("cP" in line and "typical" in line for line in viscosity):
        fail("fluid.viscosity rows without their unit and typical range", "\n".join(viscosity))
    header = "| key | type | unit | default | allowed | meaning |"
    if out.count(header) != 1 + len(MODELS):
        fail("expected one table for the common keys and one per model", out)
    print(f"ok: ibvalve keys: the common keys once, a table for each of {', '.join(MODELS)}")
    lumped, _ = expect_ok(run("keys", "lumped"), "ibvalve keys lumped")
    if "## Model `lumped`" not in lumped or "## Model `fluid`" in lumped or "| `valve.annulus_radius` |" not in lumped:
        fail("ibvalve keys lumped: not the lumped table alone", lumped)
    print("ok: ibvalve keys lumped: the common and the lumped keys only")
    two, _ = expect_ok(run("keys", ranks=2), "ibvalve keys on 2 ranks")
    if two != out:
        fail("ibvalve keys prints differently on 2 ranks (rank 0 alone should print)", two)
    print("ok: the same output on 2 ranks")


def skeleton(run, source, work, model):
    work.mkdir(parents=True, exist_ok=True)
    out, _ = expect_ok(run("keys", model, "--format", "toml"), f"ibvalve keys {model} --format toml")
    case = work / f"{model}.toml"
    case.write_text(out)
    shutil.copy(source / "examples/waveforms/lv_pressure_typeA.csv", work / "lv_pressure_typeA.csv")
    run_dir = work / "run"
    if run_dir.exists():
        shutil.rmtree(run_dir)
    expect_ok(run("run", case, "-o", run_dir, "--stop-after-steps", "1", cwd=work),
              f"ibvalve run on the {model} skeleton")
    print(f"ok: the {model} skeleton ({len(out.splitlines())} lines) is a case file: validated, first step taken")


def flattened(table, prefix=""):
    """{dotted key: value} of a TOML table."""
    out = {}
    for key, value in table.items():
        if isinstance(value, dict):
            out.update(flattened(value, f"{prefix}{key}."))
        else:
            out[prefix + key] = value
    return out


# What default.toml sets otherwise than the skeleton: the case's name; how often a run of its length
# checkpoints (a cadence of the machine and the run, the same default for every model); and the fit data
# (the repository's sample files, named from examples/aortic_valve).
NOT_IN_THE_SKELETON = {"name", "checkpoint.every", "leaflets.fit_data"}


def recommended(run, source, work):
    out, _ = expect_ok(run("keys", "aortic-valve", "--format", "toml"), "ibvalve keys aortic-valve --format toml")
    skeleton = flattened(tomllib.loads(out))
    case = flattened(tomllib.loads((source / "examples/aortic_valve/default.toml").read_text()))
    differ = []
    for key, value in case.items():
        if key in NOT_IN_THE_SKELETON:
            continue
        mine = skeleton.get(key)
        if key.endswith(".file"):
            value, mine = pathlib.Path(value).name, mine and pathlib.Path(mine).name
        if mine != value:
            differ.append(f"{key}: default.toml {value!r}, skeleton {mine!r}")
    if differ:
        fail("the skeleton is not default.toml's case:\n  " + "\n  ".join(differ))
    print(f"ok: the skeleton holds default.toml's {len(case) - len(NOT_IN_THE_SKELETON)} settings")
    help_text, _ = expect_ok(run("mesh", "aortic-valve", "--help"), "ibvalve mesh aortic-valve --help")
    options = re.findall(r"--([a-z-]+) (?:INT|FLOAT)=(\S+)", help_text)  # "--tube-length FLOAT=5"
    checked = 0
    for option, default in options:
        key = "mesh." + option.replace("-", "_")
        if key not in skeleton:
            continue  # the generator's own (leaflet_through, tube_through)
        if float(default) != float(skeleton[key]):
            fail(f"ibvalve mesh aortic-valve --{option} defaults to {default}, the skeleton's {key} is {skeleton[key]}")
        checked += 1
    if checked < 10:
        fail(f"only {checked} mesh options matched to keys", help_text)
    print(f"ok: the {checked} options of ibvalve mesh aortic-valve default to the skeleton's mesh.* values")


def lumped_case(source, work):
    """The lumped example with its waveform path made absolute, written into `work`."""
    work.mkdir(parents=True, exist_ok=True)
    text = (source / "examples/lumped/default.toml").read_text()
    text = re.sub(r'"\.\./waveforms/([^"]+)"',
                  lambda m: f'"{(source / "examples/waveforms" / m.group(1)).resolve()}"', text)
    case = work / "lumped.toml"
    case.write_text(text)
    return case


def bare_set(run, source, work):
    case = lumped_case(source, work)
    expect_ok(run("run", case, "-o", work / "run", "--overwrite", "--set", "model=lumped", "--set",
                  "report.closure_rule=area", "--set", "name=bare words", "--set", "time.cycles=1",
                  "--set", "report.plots=false"), "a run with bare-word overrides")
    config = (work / "run/config.toml").read_text()
    for line in ["model = 'lumped'", "closure_rule = 'area'", "name = 'bare words'"]:
        if not any(l.startswith(line) for l in config.splitlines()):
            fail(f"config.toml has no line {line}", config)
    print("ok: --set model=lumped, report.closure_rule=area and name=bare words are strings; the run went on")


def warning(run, source, work):
    case = lumped_case(source, work)
    out, err = expect_ok(run("run", case, "-o", work / "run", "--overwrite", "--set", "fluid.density=1060",
                             "--set", "time.cycles=1", "--set", "report.plots=false"),
                         "a run with fluid.density = 1060")
    lines = [l for l in err.splitlines() if l.startswith("warning:")]
    pattern = (r"^warning: command line \(--set fluid.density=1060\):1: fluid.density: 1060 g/mL is outside "
               r"the typical 0.5 to 2 g/mL \(.*kg/m\^3\)$")
    if len(lines) != 1 or not re.match(pattern, lines[0]):
        fail("expected one warning line for fluid.density", err)
    print(f"ok: one warning, the run went on: {lines[0]}")
    _, err = expect_ok(run("run", case, "-o", work / "run", "--overwrite", "--set", "time.cycles=1",
                           "--set", "report.plots=false"), "the lumped case")
    if "warning:" in err:
        fail("a warning for the example's own values", err)
    print("ok: no warning for the example's values")


def warnings_kept(run, source, work):
    case = lumped_case(source, work)
    settings = ["--set", "time.cycles=1", "--set", "report.plots=false"]
    out, err = expect_ok(run("run", case, "-o", work / "run", "--overwrite", "--set", "fluid.density=1060",
                             *settings, ranks=2), "a run with fluid.density = 1060 on 2 ranks")
    lines = [l[len("warning: "):] for l in err.splitlines() if l.startswith("warning:")]
    if len(lines) != 1 or "fluid.density: 1060 g/mL is outside the typical" not in lines[0]:
        fail("expected one warning line for fluid.density", err)
    message = lines[0]
    log = (work / "run/log.txt").read_text()
    if log.count("warning: " + message) != 1:
        fail("log.txt does not keep the warning once", log)
    record = json.loads((work / "run/run.json").read_text())
    if record.get("warnings") != [message]:
        fail(f"run.json's warnings are {record.get('warnings')}, not [{message!r}]")
    md = (work / "run/report/report.md").read_text()
    page = (work / "run/report/report.html").read_text()
    if "The run's warnings" not in md or f"> - {message}" not in md:
        fail("report.md has no warnings box with the warning", md[:3000])
    if 'id="warnings"' not in page or f"<li>{html.escape(message, quote=False)}</li>" not in page:
        fail("report.html has no warnings box with the warning", page[:3000])
    print(f"ok: the warning is in log.txt, run.json and both report pages: {message}")
    expect_ok(run("run", case, "-o", work / "plain", "--overwrite", *settings), "the lumped case")
    if 'id="warnings"' in (work / "plain/report/report.html").read_text():
        fail("a warnings box in the report of a run without warnings")
    if json.loads((work / "plain/run.json").read_text()).get("warnings", []) != []:
        fail("run.json of a run without warnings lists some")
    print("ok: no warnings box without a warning")
    for command in (["run", case, "-o", work / "strict"], ["check", case]):
        code, out, err = run(*command, "--strict", "--set", "fluid.density=1060", *settings, ranks=2)
        said = [l for l in err.splitlines() if l.startswith(("error:", "warning:"))]  # not mpiexec's lines
        if code != 2 or said != ["error: " + message]:
            fail(f"{command[0]} --strict: expected exit 2 and the line 'error: {message}', got exit {code}",
                 f"--- stdout:\n{out}--- stderr:\n{err}")
    if (work / "strict").exists():
        fail("run --strict left a run folder")
    print("ok: with --strict the warning is an error: exit 2, the same message, nothing written")


def config_presets(run, source, work):
    case = lumped_case(source, work)
    settings = ["--set", "time.cycles=1", "--set", "report.plots=false", "--set", "time.step=2e-5"]
    expect_ok(run("run", case, "-o", work / "first", "--overwrite", *settings), "the lumped run")
    config = (work / "first/config.toml").read_text()
    for key, value in [("proximal_resistance", "0.033"), ("distal_resistance", "0.79"), ("compliance", "1.75"),
                       ("initial_pressure", "85.0"), ("step", "2e-05")]:
        lines = [l for l in config.splitlines() if l.startswith(f"{key} = ")]
        if len(lines) != 1 or not lines[0].startswith(f"{key} = {value}  #"):
            fail(f"config.toml: expected {key} = {value}", config)
    windkessel = config[config.index("\n[windkessel]"):].split("\n\n")[0]
    if "(not set)" in windkessel:
        fail("config.toml leaves a Windkessel key unset", windkessel)
    if re.search(r"\d{12,}", config):
        fail("config.toml writes a number with 12 or more digits", config)
    if "from windkessel.preset = \"stergiopulos-typeA\"" not in config:
        fail("config.toml does not name the preset the values come from", config)
    print("ok: config.toml writes the preset's values (naming it) and 2e-05")
    # No path of this machine: the case's absolute waveform path is written relative to the run folder.
    for machine_path in {str(source.resolve()), str(work.resolve())}:
        if machine_path in config:
            fail(f"config.toml holds the absolute path {machine_path}", config)
    waveform = next(l for l in config.splitlines() if l.startswith("file = "))
    if not waveform.startswith("file = '../"):
        fail("config.toml does not name the waveform relative to the run folder", waveform)
    print(f"ok: config.toml holds no absolute path ({waveform.split('  #')[0]})")
    expect_ok(run("run", work / "first/config.toml", "-o", work / "second", "--overwrite"),
              "config.toml run as a case file")
    if (work / "first/timeseries.csv").read_bytes() != (work / "second/timeseries.csv").read_bytes():
        fail("config.toml run as a case gives another timeseries.csv")
    print("ok: config.toml run as a case file gives the same timeseries.csv byte for byte")


def petsc_example(run, source, work):
    out, _ = expect_ok(run("--help"), "ibvalve --help")
    match = re.search(r"e\.g\. ibvalve run case\.toml -- (.+?)  \(", out)
    if not match:
        fail("ibvalve --help gives no example of PETSc options", out)
    options = match.group(1).split()
    for prefix in ["-fluid_stokes_", "-fluid_helmholtz_", "-fluid_poisson_", "-nested_pressure_",
                   "-ib_velocity_mass_", "-fibers_"]:
        if prefix not in out:
            fail(f"ibvalve --help does not list {prefix}", out)
    run_help, _ = expect_ok(run("run", "--help"), "ibvalve run --help")
    if "-fluid_stokes_" not in run_help or "ibvalve keys" not in run_help:
        fail("ibvalve run --help lists neither the prefixes nor ibvalve keys", run_help)
    print(f"ok: --help lists the prefixes, example: {' '.join(options)}")
    out, _ = expect_ok(run("run", source / "tests/app/cases/restart_fluid.toml", "-o", work / "run", "--overwrite",
                           "--", *options), "the duct flow with the example's options")
    lines = [l for l in out.splitlines() if re.match(r"^\s*Linear fluid_stokes_ solve converged due to", l)]
    if len(lines) < 12:
        fail(f"{len(lines)} lines 'Linear fluid_stokes_ solve converged', expected one per step (12)", out)
    print(f"ok: the example prints why each Stokes solve converged ({len(lines)} lines): {lines[0].strip()}")


def main():
    scenario, ibvalve, mpiexec, source, work = sys.argv[1:6]
    run = Runner(ibvalve, mpiexec)
    source, work = pathlib.Path(source), pathlib.Path(work)
    if scenario == "skeleton":
        skeleton(run, source, work, sys.argv[6])
        return
    scenarios = {"markdown": markdown, "recommended": recommended, "bare-set": bare_set, "warning": warning,
                 "warnings-kept": warnings_kept,
                 "config-presets": config_presets, "petsc-example": petsc_example}
    scenarios[scenario](run, source, work)


if __name__ == "__main__":
    main()
