"""`ibvalve convergence` on synthetic run folders (run by CTest with Debian's python3).

usage: check_convergence_command.py IBVALVE CHECK_CONVERGENCE

Writes three run folders of the study's grids (h = 1/16, 1/8 and 3/16 cm; the 1/8 cm one as a 1/4 cm
level 0 with nested.ratios = [2]): a config.toml and a report/metrics.json whose metrics follow
phi(h) = phi0 + C h^p (p = 2, 1.3 and 0.8, one with phi = 0 on the finest grid), oscillate, diverge,
stay unchanged, or are missing in a run. Then:
- `ibvalve convergence` given the folders out of order writes convergence.json, .csv and .md whose
  figures are the closed forms': p, phi_ext = phi0, GCI = 1.25 |phi1 - phi0| / |phi1| and 1.25 |C| h1^p in
  the unit, the classes, the conservative uncertainty 3 max|phi_i - phi1| where the grids do not
  converge monotonically, the metrics left out and why, names escaped in the Markdown;
- one run, two runs on the same grid, a run with cells that are not cubes, a run without metrics and a
  run without config.toml each exit with 2 and one error line naming the file (and key), and no output
  folder is made;
- CHECK_CONVERGENCE (scripts/check-convergence, the independent recomputation) passes on the output
  and fails, naming the metric, when one figure of convergence.json is moved by 1e-7 relative.
Prints what it checked; exits 1 on the first failure. The run folders stay in convergence_work/ for the
next tests (the 2-rank run and the recomputation).
"""
import json
import math
import pathlib
import shutil
import subprocess
import sys

H = {"h1_16": 1 / 16, "h1_8": 1 / 8, "h3_16": 3 / 16}
GRIDS = {  # run -> [fluid] and [nested] tables of its config.toml
    "h1_16": "[fluid]\ncells = [60, 60, 85]\nlower = [-1.875, -1.875, -0.03125]\nupper = [1.875, 1.875, 5.28125]\n",
    "h1_8": "[fluid]\ncells = [15, 15, 22]\nlower = [-1.875, -1.875, -0.0625]\nupper = [1.875, 1.875, 5.4375]\n"
            "[nested]\nratios = [2]\n",
    "h3_16": "[fluid]\ncells = [20, 20, 29]\nlower = [-1.875, -1.875, -0.09375]\nupper = [1.875, 1.875, 5.34375]\n",
}
# key -> (unit, symbol, phi0, C, p) of phi0 + C h^p
MANUFACTURED = {
    "forward_volume": ("mL", "V_F", 70.0, 40.0, 2.0),
    "regurgitant_volume": ("mL", "V_R", 5.0, -8.0, 1.3),
    "transvalvular_pressure_gradient": ("mmHg", "TPG", 12.0, 30.0, 0.8),  # R = 1.11, still monotone
    "closing_duration": ("ms", "T_c", -100.0 * (1 / 16) ** 2, 100.0, 2.0),  # 0 on the finest grid
    "odd_metric": ("a|b", "<x>", 3.0, 1.0, 2.0),  # a unit and symbol the Markdown must escape
}
# key -> (unit, class, values on h1_16, h1_8, h3_16)
OTHERS = {
    "energy_loss": ("mJ", "oscillatory", [250.0, 260.0, 245.0]),
    "effective_orifice_area": ("cm^2", "divergent", [1.30, 1.34, 1.36]),
    "leakage_volume": ("mL", "unchanged", [0.5, 0.5, 0.5]),
}


def fail(message, output=""):
    print(output)
    print(f"FAIL: {message}")
    sys.exit(1)


def run(*args):
    p = subprocess.run([str(a) for a in args], stdin=subprocess.DEVNULL, capture_output=True, text=True,
                       timeout=240)
    return p.returncode, p.stdout + p.stderr, p.stderr


def write_run(folder, name, grid, metrics):
    (folder / "report").mkdir(parents=True)
    (folder / "config.toml").write_text(f"model = 'aortic-valve'\nname = '{name}'\n\n{grid}")
    (folder / "report" / "metrics.json").write_text(json.dumps({"ibvalve_metrics": 1, "metrics": metrics}, indent=1))


def metrics_of(run_name):
    h = H[run_name]
    metrics = {}
    for key, (unit, symbol, phi0, c, p) in MANUFACTURED.items():
        metrics[key] = {"value": phi0 + c * h ** p, "unit": unit, "symbol": symbol}
    for key, (unit, _, values) in OTHERS.items():
        metrics[key] = {"value": values[list(H).index(run_name)], "unit": unit}
    if run_name != "h3_16":
        metrics["fit_error"] = {"value": 0.1, "unit": "1"}  # missing in one run: left out
    metrics["rms_forward_flow"] = {"value": None if run_name == "h1_8" else 300.0, "unit": "mL/s"}
    return metrics


def close(a, b, rtol, what):
    if a is None or b is None or not math.isclose(a, b, rel_tol=rtol, abs_tol=rtol * 1e-3):
        fail(f"{what}: {a}, expected {b} (within {rtol:g} relative)")


def check_json(doc):
    if [g["run"] for g in doc["grids"]] != ["h1_16", "h1_8", "h3_16"]:
        fail(f"grids not sorted finest first: {doc['grids']}")
    if [g["spacing_cm"] for g in doc["grids"]] != [1 / 16, 1 / 8, 3 / 16]:
        fail(f"spacings {[g['spacing_cm'] for g in doc['grids']]}, expected 1/16, 1/8, 3/16 exactly")
    close(doc["monotone_bound"], math.log(2) / math.log(1.5), 1e-15, "monotone_bound")
    h1, h2, h3 = H["h1_16"], H["h1_8"], H["h3_16"]
    metrics = doc["metrics"]
    for key, (unit, symbol, phi0, c, p) in MANUFACTURED.items():
        m = metrics[key]
        if m["class"] != "monotone" or m["rule"] != "richardson" or m["unit"] != unit or m["symbol"] != symbol:
            fail(f"{key}: {m['class']}, {m['rule']}, unit {m['unit']}, symbol {m['symbol']}")
        close(m["p"], p, 1e-10, f"{key}: p")
        close(m["R"], (h2 ** p - h1 ** p) / (h3 ** p - h2 ** p), 1e-12, f"{key}: R")
        if abs(m["phi_ext"] - phi0) > 1e-12 * (abs(phi0) + abs(c)):
            fail(f"{key}: phi_ext {m['phi_ext']}, expected phi0 = {phi0}")
        phi1 = phi0 + c * h1 ** p
        close(m["gci_in_unit"], 1.25 * abs(c) * h1 ** p, 1e-11, f"{key}: GCI in the unit")
        if phi1 == 0.0:
            if m["gci"] is not None or m["e_a"] is not None:
                fail(f"{key}: phi1 = 0, yet relative figures {m['gci']}, {m['e_a']}")
        else:
            close(m["gci"], 1.25 * abs(phi1 - phi0) / abs(phi1), 1e-11, f"{key}: GCI")
        print(f"ok: {key}: p = {m['p']!r} (exact {p}), phi_ext - phi0 = {m['phi_ext'] - phi0:.1e}, "
              f"GCI {m['gci_in_unit']:.6g} {unit}")
    for key, (unit, kind, values) in OTHERS.items():
        m = metrics[key]
        expected_u = 0.0 if kind == "unchanged" else 3 * max(abs(values[1] - values[0]), abs(values[2] - values[0]))
        if m["class"] != kind or m["p"] is not None or m["phi_ext"] is not None or m["values"] != values:
            fail(f"{key}: class {m['class']}, p {m['p']}, phi_ext {m['phi_ext']}, values {m['values']}")
        close(m["gci_in_unit"], expected_u, 1e-12, f"{key}: conservative uncertainty")
        print(f"ok: {key}: {kind}, uncertainty {m['gci_in_unit']:.6g} {unit}, no p or phi_ext")
    if set(metrics) != set(MANUFACTURED) | set(OTHERS):
        fail(f"metrics studied: {sorted(metrics)}")
    left = " ".join(doc["left_out"])
    if len(doc["left_out"]) != 2 or "fit_error (missing or not a finite number in: h3_16)" not in left \
            or "rms_forward_flow (missing or not a finite number in: h1_8)" not in left:
        fail(f"left out: {doc['left_out']}")
    print(f"ok: left out: {doc['left_out']}")


def check_tables(out):
    csv = (out / "convergence.csv").read_text().splitlines()
    header = "metric,symbol,unit,h1_16,h1_8,h3_16,R,class,rule,p,phi_ext,e_a,e_ext,safety_factor,gci,gci_in_unit"
    if csv[0] != header or len(csv) != 1 + len(MANUFACTURED) + len(OTHERS):
        fail("convergence.csv: header or row count", "\n".join(csv))
    row = next(line.split(",") for line in csv if line.startswith("energy_loss,"))
    if row[3:6] != ["250", "260", "245"] or row[7] != "oscillatory" or row[9] != "" or row[8] != "range":
        fail(f"convergence.csv energy_loss row: {row}")
    md = (out / "convergence.md").read_text()
    for text in ["| metric | unit | h1_16 | h1_8 | h3_16 | R | class | p | φ_ext | e_a | e_ext | GCI | GCI (unit) |",
                 "| V_F (`forward_volume`) | mL | 70.156", "| 0.125 | 2 |", "| 0.1875 | 1.5 |",
                 "ln(r21)/ln(r32) = 1.70951", "`energy_loss`: oscillatory (R < 0)", "`leakage_volume`: unchanged",
                 "`effective_orifice_area`: divergent", "&lt;x&gt; (`odd_metric`) | a\\|b |",
                 "- fit_error (missing or not a finite number in: h3_16)"]:
        if text not in md:
            fail(f"convergence.md lacks: {text}", md)
    print("ok: convergence.csv and convergence.md hold the table, the classes and the escaped names")


def refused(what, naming, out, *args):
    code, output, err = run(*args)
    errors = [line for line in err.splitlines() if line.startswith("error:")]
    if code != 2 or len(errors) != 1 or any(n not in errors[0] for n in naming):
        fail(f"{what}: exit {code}, expected 2 and one error line naming {naming}", output)
    if out.exists():
        fail(f"{what}: the output folder {out} was made")
    print(f"ok: {what}: exit 2: {errors[0]}")


def main():
    ibvalve, checker = sys.argv[1], sys.argv[2]
    work = pathlib.Path("convergence_work").resolve()
    shutil.rmtree(work, ignore_errors=True)
    for name, grid in GRIDS.items():
        write_run(work / name, name, grid, metrics_of(name))
    out = work / "out"
    code, output, _ = run(ibvalve, "convergence", work / "h1_8", work / "h3_16", work / "h1_16", "-o", out)
    if code != 0:
        fail(f"ibvalve convergence exited with {code}", output)
    check_json(json.loads((out / "convergence.json").read_text()))
    check_tables(out)

    bad = work / "bad"
    shutil.copytree(work / "h1_16", bad / "same_grid")
    write_run(bad / "stretched", "stretched", GRIDS["h1_16"].replace("[60, 60, 85]", "[60, 60, 80]"),
              metrics_of("h1_16"))
    (bad / "no_metrics").mkdir(parents=True)
    (bad / "no_metrics" / "config.toml").write_text(GRIDS["h1_8"])
    shutil.copytree(work / "h1_8" / "report", bad / "no_config" / "report")
    never = work / "never_written"
    refused("one run", ["1 run folder given", "at least two"], never, ibvalve, "convergence", work / "h1_16", "-o", never)
    refused("two runs on one grid", [str(work / "h1_16" / "config.toml"), str(bad / "same_grid" / "config.toml"),
                                     "the same grid spacing"],
            never, ibvalve, "convergence", work / "h1_16", bad / "same_grid", work / "h1_8", "-o", never)
    refused("cells that are not cubes", [f"{bad / 'stretched' / 'config.toml'}:5: fluid.cells", "not cubes"],
            never, ibvalve, "convergence", bad / "stretched", work / "h1_8", work / "h3_16", "-o", never)
    refused("a run without metrics", [str(bad / "no_metrics"), "neither report/metrics.json nor timeseries.csv"],
            never, ibvalve, "convergence", work / "h1_16", bad / "no_metrics", "-o", never)
    refused("a run without config.toml", [str(bad / "no_config" / "config.toml")],
            never, ibvalve, "convergence", work / "h1_16", bad / "no_config", "-o", never)

    runs = [work / name for name in GRIDS]
    code, output, _ = run(sys.executable, checker, out, *runs)
    if code != 0:
        fail(f"{checker} on the output exited with {code}", output)
    print(f"ok: {pathlib.Path(checker).name} recomputes the output: {output.strip().splitlines()[-1]}")
    tampered = work / "tampered"
    shutil.copytree(out, tampered)
    doc = json.loads((tampered / "convergence.json").read_text())
    doc["metrics"]["regurgitant_volume"]["p"] *= 1 + 1e-7
    (tampered / "convergence.json").write_text(json.dumps(doc))
    code, output, _ = run(sys.executable, checker, tampered, *runs)
    if code != 1 or "regurgitant_volume" not in output:
        fail(f"{checker} passed a convergence.json with p moved by 1e-7 (exit {code})", output)
    print("ok: the recomputation fails when p of regurgitant_volume is moved by 1e-7 relative")


if __name__ == "__main__":
    main()
