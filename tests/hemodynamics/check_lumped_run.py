"""Checks of the lumped end-to-end run (run by CTest with Debian's python3).

usage: check_lumped_run.py report RUN_DIR      the run covers full cycles; the metrics are in
                                               physiological ranges; report.html exists, references
                                               existing PNGs and shows metrics.json's values; each of
                                               the 4 cycles has its report in report/cycle_N/
       check_lumped_run.py compare OUT_DIR     comparison files exist, fit error reported missing
       check_lumped_run.py converged RUN RUN_HALF_DT
                                               the metrics of the run and of the run at half the
                                               time step agree to 1e-4 relative (time convergence)
       check_lumped_run.py density RUN DENSITY IBVALVE
                                               the run's own report and `IBVALVE report RUN` take
                                               the EOA's density from fluid.density (DENSITY): one
                                               density for the run and its report
"""
import csv
import json
import math
import os
import re
import sys


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def check_report(run):
    with open(os.path.join(run, "timeseries.csv")) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    header = rows[0]
    for name in ("t", "Q_valve", "Q_outlet", "P_LV", "P_Ao", "P_Wk", "P_nlv", "P_nao", "orifice_area"):
        if name not in header:
            fail(f"timeseries.csv lacks column {name}")
    t_end = float(rows[-1][header.index("t")])
    if t_end < 0.8 - 1e-9:
        fail(f"the run does not cover a full cycle (ends at {t_end} s)")

    report = os.path.join(run, "report")
    with open(os.path.join(report, "metrics.json")) as f:
        doc = json.load(f)
    m = {k: v["value"] for k, v in doc["metrics"].items()}
    # Physiological ranges for an adult aortic valve at rest.
    ranges = {"forward_volume": (40.0, 130.0), "regurgitant_fraction": (0.5, 25.0),
              "transvalvular_pressure_gradient": (0.5, 20.0), "effective_orifice_area": (1.0, 5.0),
              "peak_forward_flow": (200.0, 800.0), "systolic_aortic_pressure": (90.0, 150.0),
              "diastolic_aortic_pressure": (50.0, 95.0), "energy_loss": (0.0, 200.0)}
    for key, (lo, hi) in ranges.items():
        v = m.get(key)
        if v is None or not (lo <= v <= hi):
            fail(f"{key} = {v} outside the physiological range [{lo}, {hi}]")
        print(f"{key} = {v:.4g} in [{lo}, {hi}]")

    html_path = os.path.join(report, "report.html")
    if not os.path.exists(html_path):
        fail("report.html missing")
    html = open(html_path).read()
    pngs = set(re.findall(r'href="([^"]+\.png)"', html))
    if len(pngs) < 4:
        fail(f"report.html references {len(pngs)} PNGs, expected 4")
    for png in pngs:
        path = os.path.join(report, png)
        if not os.path.exists(path) or open(path, "rb").read(8) != b"\x89PNG\r\n\x1a\n":
            fail(f"{png} referenced by report.html is not a PNG beside it")
    cells = re.findall(r'<tr data-key="([a-z_]+)">.*?data-value="([^"]+)"', html)
    if len(cells) != len(m):
        fail(f"report.html shows {len(cells)} metrics, metrics.json has {len(m)}")
    for key, text in cells:
        value = None if text == "null" else float(text)
        if value != m[key]:
            fail(f"{key}: report.html shows {value}, metrics.json has {m[key]}")
    md = open(os.path.join(report, "report.md")).read()
    for png in pngs:
        if f"({png})" not in md:
            fail(f"report.md does not show {png}")
    # Provenance: the run's record (case file, the build that ran it) and its inputs reach the report.
    record = json.load(open(os.path.join(run, "run.json")))
    provenance = json.load(open(os.path.join(report, "metrics.json")))["provenance"]
    if provenance.get("run") != record:
        fail("metrics.json's provenance does not carry run.json")
    if not record.get("case_file", "").endswith(".toml") or not record.get("commit"):
        fail(f"run.json lacks the case file or the commit: {record}")
    if provenance["inputs"].get("windkessel.compliance") is None:
        fail("metrics.json's provenance lacks the case's inputs (windkessel.compliance)")
    # Inputs in their shortest exact form with their unit: 0.6, not 0.59999999999999998; 0, not -0.0.
    for key, shown in (("valve.max_area_fraction", "0.6"), ("windkessel.distal_pressure", "0 mmHg"),
                       ("time.step", "0.0001 s"), ("windkessel.compliance", "1.75 mL/mmHg")):
        if provenance["inputs"].get(key) != shown:
            fail(f"metrics.json's provenance shows {key} as {provenance['inputs'].get(key)!r}, not {shown!r}")
        if f"| `{key}` | {shown} |" not in md:
            fail(f"report.md does not show {key} as {shown}")
    for text in (record["case_file"], record["commit"], "`windkessel.compliance`"):
        if text not in md:
            fail(f"report.md does not show {text}")
    # One report per cycle, counted from 1: report/cycle_N/ for each of the run's 4 cycles, report/ the
    # reported (last) one's, whose cycle-to-cycle table holds every cycle.
    for n in range(1, 5):
        cycle_doc = json.load(open(os.path.join(report, f"cycle_{n}", "metrics.json")))
        if cycle_doc["cycle"] != {"number": n, "of": 4}:
            fail(f"report/cycle_{n}/metrics.json is of cycle {cycle_doc['cycle']}")
        title = f"<title>ibvalve report: {os.path.basename(os.path.normpath(run))}, cycle {n} of 4</title>"
        if title not in open(os.path.join(report, f"cycle_{n}", "report.html")).read():
            fail(f"report/cycle_{n}/report.html lacks the title {title}")
    last = json.load(open(os.path.join(report, "cycle_4", "metrics.json")))
    if doc["cycle"] != {"number": 4, "of": 4} or doc["metrics"] != last["metrics"]:
        fail("report/metrics.json is not the last cycle's")
    if [row["cycle"] for row in doc["cycles"]] != [1, 2, 3, 4] or "Cycle 4 against cycle 3" not in doc["periodicity"]:
        fail(f"the last cycle's table of cycles is wrong: {doc['cycles']}, {doc['periodicity']}")
    print(f"report.html: {len(pngs)} PNGs, {len(cells)} metrics equal to metrics.json; provenance: "
          f"commit {record['commit']}, {len(provenance['inputs'])} inputs; cycles 1-4 each in report/cycle_N/; "
          f"{doc['periodicity']}")


def check_compare(out):
    for name in ("comparison.md", "comparison.html", "metrics.csv", "ranking.csv"):
        if not os.path.exists(os.path.join(out, name)):
            fail(f"{name} missing")
    md = open(os.path.join(out, "comparison.md")).read()
    if "fit_error (missing for:" not in md:
        fail("the fit error of lumped runs is not reported as missing")
    with open(os.path.join(out, "ranking.csv")) as f:
        rows = list(csv.reader(f))
    if len(rows) != 3 or rows[0][-2:] != ["total", "rank"]:
        fail("ranking.csv: expected a header and two cases")
    totals = [float(r[-2]) for r in rows[1:]]
    if not all(math.isfinite(x) for x in totals):
        fail("ranking totals not finite")
    # The overlaid curves: one PNG per curve, each embedded in the HTML and linked from the Markdown, drawn
    # from both cases' series over their analysed cycles.
    html = open(os.path.join(out, "comparison.html")).read()
    for name in ("flow.png", "pressure_difference.png", "orifice_area.png"):
        path = os.path.join(out, name)
        if not os.path.exists(path) or open(path, "rb").read(8) != b"\x89PNG\r\n\x1a\n":
            fail(f"{name} missing or not a PNG")
        if f"]({name})" not in md:
            fail(f"comparison.md does not show {name}")
    if html.count("data:image/png;base64,") != 3:
        fail("comparison.html does not embed the three curves")
    with open(os.path.join(out, "curves.json")) as f:
        curves = json.load(f)["cases"]
    if len(curves) != 2:
        fail("curves.json: expected the two cases")
    for c in curves:
        if not os.path.exists(c["series"]) or not abs(c["cycle_end"] - c["cycle_start"] - 0.8) < 1e-9:
            fail(f"curves.json: {c['name']}: series or analysed cycle wrong: {c}")
    print("comparison files written with 3 overlaid curves; ranking totals", totals)


def check_converged(run, run_half):
    def metrics(path):
        with open(os.path.join(path, "report", "metrics.json")) as f:
            return {k: v["value"] for k, v in json.load(f)["metrics"].items()}
    a, b = metrics(run), metrics(run_half)
    worst = 0.0
    for key in ("forward_volume", "regurgitant_volume", "leakage_volume", "regurgitant_fraction",
                "transvalvular_pressure_gradient", "effective_orifice_area", "energy_loss",
                "peak_forward_flow", "opening_duration", "closing_duration"):
        change = abs(a[key] - b[key]) / abs(b[key])
        worst = max(worst, change)
        print(f"{key}: {a[key]:.8g} (dt) vs {b[key]:.8g} (dt/2), relative change {change:.2e}")
        if change > 1e-4:
            fail(f"{key} changes by {change:.2e} when the time step is halved")
    print(f"largest relative change {worst:.2e}")


def check_density(run, density, ibvalve):
    import subprocess

    density = float(density)

    def check(who):
        with open(os.path.join(run, "report", "metrics.json")) as f:
            doc = json.load(f)
        used = doc["settings"]["density_g_per_mL"]
        m = {k: v["value"] for k, v in doc["metrics"].items()}
        # EOA = Q_rms / (51.6 sqrt(TPG / rho)) over the ejection window (docs/hemodynamics.md).
        eoa = m["rms_forward_flow"] / (51.6 * math.sqrt(m["transvalvular_pressure_gradient"] / density))
        if used != density:
            fail(f"{who}: the EOA's density is {used} g/mL, not the run's fluid.density {density}")
        if abs(m["effective_orifice_area"] - eoa) > 1e-12 * eoa:
            fail(f"{who}: EOA {m['effective_orifice_area']} is not Q_rms / (51.6 sqrt(TPG / {density})) = {eoa}")
        print(f"{who}: density {used} g/mL, EOA {m['effective_orifice_area']:.6g} cm^2")

    check("the run's report")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    result = subprocess.run([ibvalve, "report", run, "--no-plots"], capture_output=True, text=True, env=env)
    if result.returncode != 0:
        fail(f"ibvalve report exited with {result.returncode}: {result.stderr}")
    check("ibvalve report")


if __name__ == "__main__":
    mode = sys.argv[1]
    if mode == "density":
        check_density(sys.argv[2], sys.argv[3], sys.argv[4])
    elif mode == "converged":
        check_converged(sys.argv[2], sys.argv[3])
    else:
        {"report": check_report, "compare": check_compare}[mode](sys.argv[2])
