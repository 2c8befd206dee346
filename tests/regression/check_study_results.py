"""The study's stored results (examples/aortic_valve/study/) recomputed from their raw series by a second
implementation of the definitions (numpy here, C++ in hemodynamics/metrics.cpp and compare.cpp).

usage: check_study_results.py STUDY_DIR

For each case in STUDY_DIR/runs/<case>/: the reported cycle's forward-flow start t_ff, pressure
crossover, orifice opening and t_bs (the latest of the three, docs/hemodynamics.md, "Phases of the
analysed cycle"), t_es, and V_F, TPG, Q_rms, EOA and T_ej, from timeseries.csv, against
report/metrics.json; then the 12-criterion ranking's totals from the cases' metrics.json against
ranking.csv. Every
figure RESULTS.md quotes is in those files. Instants agree to 1e-9 s and values to 1e-9 relative (both
implementations integrate the same piecewise-linear interpolant; the difference is round-off). Exits 1
on the first disagreement, naming the case and the figure.

Where the cases carry numerical uncertainties (an `ibvalve study` with [[uncertainty]] sources, their
variant runs kept in STUDY_DIR/uncertainty/<source>/<case>/): each source's variant is recomputed from
its own series the same way, and every metric's u_s = |variant - case| (and, for a shared source, the
signed shift) and u = sqrt(sum u_s^2) must equal metrics.json's; the ranking's totals are recomputed
with the uncertainty's ties (docs/hemodynamics.md, "Comparison": sorted neighbours within 2 sigma of
their difference chain, a chain scores as its mean) and each case's rank stability by this script's own
draws (another generator and seed), which must agree with ranking.csv's `rank_held` and with the whole
order's share in comparison.md within 4 binomial standard deviations of 10,000 draws.
"""
import csv
import json
import pathlib
import re
import sys

import numpy as np

PERIOD = 0.8


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def last_rise(t, y, i, level):
    """Where y last rose above level at or before sample i (t[0] if above from the start; None if never)."""
    j = i
    while j > 0 and not y[j] > level:
        j -= 1
    if not y[j] > level:
        return None
    while j > 0 and y[j - 1] > level:
        j -= 1
    if j == 0:
        return t[0]
    return t[j - 1] + (level - y[j - 1]) / (y[j] - y[j - 1]) * (t[j] - t[j - 1])


def integral(t, y, a, b):
    inside = (t > a) & (t < b)
    tt = np.concatenate(([a], t[inside], [b]))
    yy = np.interp(tt, t, y)
    return float(np.sum(0.5 * (yy[1:] + yy[:-1]) * np.diff(tt)))


def recompute(series_file, closed_fraction, open_fraction, density):
    d = np.genfromtxt(series_file, delimiter=",", names=True, comments="#")
    t_all = d["t"]
    cycles = int(np.floor((t_all[-1] - t_all[0]) / PERIOD * (1 + 1e-9)))
    t0 = t_all[0] + (cycles - 1) * PERIOD
    t1 = t0 + PERIOD
    # The cycle's samples with both ends interpolated, as the report takes them.
    inside = (t_all > t0) & (t_all < t1)
    t = np.concatenate(([t0], t_all[inside], [t1]))
    col = {name: np.interp(t, t_all, d[name]) for name in ("Q_valve", "P_nlv", "P_nao", "orifice_area")}
    q, gradient, area = col["Q_valve"], col["P_nlv"] - col["P_nao"], col["orifice_area"]
    i_peak = int(np.argmax(q))
    t_ff = last_rise(t, q, i_peak, 0.0)
    j = i_peak
    while j + 1 < len(q) and q[j + 1] > 0:
        j += 1
    t_es = t[j] + (0 - q[j]) / (q[j + 1] - q[j]) * (t[j + 1] - t[j])
    crossover = last_rise(t, gradient, i_peak, 0.0)
    # The orifice opening: the area normalised by its smallest value before the largest, the last
    # upward crossing of the closed fraction before it first reaches the open fraction.
    i_big = int(np.argmax(area))
    a = (area - area[: i_big + 1].min()) / (area[i_big] - area[: i_big + 1].min())
    i_open = int(np.argmax(a >= open_fraction))
    opening = last_rise(t, a, i_open, closed_fraction)
    candidates = [x for x in (t_ff, crossover, opening) if x is not None and x < t_es]
    t_bs = max(candidates)
    length = t_es - t_bs
    tpg = integral(t, gradient, t_bs, t_es) / length
    q_rms = np.sqrt(integral(t, q * q, t_bs, t_es) / length)
    return {
        "phases": {"forward_flow_start": t_ff, "pressure_crossover": crossover, "opening_start": opening,
                   "ejection_start": t_bs, "ejection_end": t_es},
        "metrics": {"forward_volume": integral(t, q, t_ff, t_es), "transvalvular_pressure_gradient": tpg,
                    "rms_forward_flow": q_rms, "effective_orifice_area": q_rms / (51.6 * np.sqrt(tpg / density)),
                    "ejection_duration": length * 1e3},
    }


# The ranking's criteria and which way is better (docs/hemodynamics.md, "Comparison").
CRITERIA = [("fit_error", -1), ("max_orifice_area", 1), ("opening_duration", -1), ("closing_duration", -1),
            ("forward_volume", 1), ("regurgitant_volume", -1), ("strain_variation", -1),
            ("stress_variation", -1), ("regurgitant_fraction", -1), ("transvalvular_pressure_gradient", -1),
            ("effective_orifice_area", 1), ("energy_loss", -1)]


TIE_TOLERANCE = 1e-3  # criteria spreading less than this of their largest value tie at 1
TIE_COVERAGE = 2.0    # neighbours within 2 standard uncertainties of their difference tie
DRAWS = 10000


def scaled(values, better):
    lo, hi = values.min(), values.max()
    if hi - lo <= TIE_TOLERANCE * max(abs(lo), abs(hi)):
        return np.ones_like(values)
    return (values - lo) / (hi - lo) if better > 0 else (hi - values) / (hi - lo)


def difference_sigma(a, b):
    """Standard uncertainty of a - b: own parts in quadrature, each shared source by shift_a - shift_b."""
    names = set(a["shared"]) | set(b["shared"])
    return np.sqrt(a["own"] ** 2 + b["own"] ** 2
                   + sum((a["shared"].get(n, 0.0) - b["shared"].get(n, 0.0)) ** 2 for n in names))


def chained(entries):
    """The values with each chain of sorted neighbours closer than TIE_COVERAGE sigma set to its mean."""
    order = sorted(range(len(entries)), key=lambda i: entries[i]["value"])
    out = np.array([e["value"] for e in entries])
    first = 0
    while first < len(order):
        last = first
        while last + 1 < len(order):
            a, b = entries[order[last + 1]], entries[order[last]]
            if a["value"] - b["value"] > TIE_COVERAGE * difference_sigma(a, b):
                break
            last += 1
        members = order[first:last + 1]
        out[members] = np.mean([entries[i]["value"] for i in members])
        first = last + 1
    return out


def ranks_of(totals):
    """Rank 1 for the largest total; equal totals share the best of their places."""
    return np.array([1 + np.sum(totals > t) for t in totals])


def uncertain_entry(metric):
    shared = dict(metric.get("uncertainty_shared", {}))
    u = metric.get("uncertainty", 0.0)
    own = np.sqrt(max(u * u - sum(v * v for v in shared.values()), 0.0))
    return {"value": metric["value"], "own": own, "shared": shared}


def ranking_check(study, cases, docs):
    """Totals (with the uncertainty's ties) against ranking.csv; rank stability by draws of our own."""
    entries = {key: [uncertain_entry(docs[c]["metrics"][key]) for c in cases] for key, _ in CRITERIA
               if all(key in docs[c]["metrics"] for c in cases)}
    totals = sum(scaled(chained(entries[key]), better) for key, better in CRITERIA if key in entries)
    ranks = ranks_of(totals)
    rows = {row["case"]: row for row in csv.DictReader(open(study / "ranking.csv"))}
    for i, c in enumerate(cases):
        if abs(float(rows[c]["total"]) - totals[i]) > 1e-9:
            fail(f"ranking.csv: {c} total {rows[c]['total']}, recomputed {totals[i]}")
    print("ok: ranking totals " + ", ".join(f"{c} {totals[i]:.3f}" for i, c in enumerate(cases)))
    if "rank_held" not in next(iter(rows.values())):
        return
    rng = np.random.default_rng(7)
    n = len(cases)
    sharing = np.array([np.sum(ranks == r) for r in ranks])
    shared_names = sorted({name for key in entries for e in entries[key] for name in e["shared"]})
    z = {name: rng.standard_normal(DRAWS) for name in shared_names}
    drawn_totals = np.zeros((DRAWS, n))
    for key, better in CRITERIA:
        if key not in entries:
            continue
        drawn = np.empty((DRAWS, n))
        for i, e in enumerate(entries[key]):
            drawn[:, i] = e["value"] + e["own"] * rng.standard_normal(DRAWS)
            for name, shift in e["shared"].items():
                drawn[:, i] += z[name] * shift
        for d in range(DRAWS):
            drawn_totals[d] += scaled(drawn[d], better)
    held = np.zeros(n)
    whole = 0
    for d in range(DRAWS):
        r = ranks_of(drawn_totals[d])
        same = (r >= ranks) & (r < ranks + sharing)
        held += same
        whole += bool(same.all())
    held /= DRAWS
    for i, c in enumerate(cases):
        stored = float(rows[c]["rank_held"])
        bound = 4 * np.sqrt(max(held[i] * (1 - held[i]), 1e-4) / DRAWS)
        if abs(stored - held[i]) > bound:
            fail(f"ranking.csv: {c} holds its rank in {stored:.4f} of the draws, recomputed {held[i]:.4f}")
    page = (study / "comparison.md").read_text()
    match = re.search(r"the whole order holds in (\d+) %", page)
    if not match:
        fail("comparison.md does not say how often the whole order holds")
    share = whole / DRAWS
    if abs(int(match.group(1)) / 100 - share) > 0.005 + 4 * np.sqrt(max(share * (1 - share), 1e-4) / DRAWS):
        fail(f"comparison.md: the whole order holds in {match.group(1)} %, recomputed {100 * share:.1f} %")
    print("ok: rank held " + ", ".join(f"{c} {held[i]:.3f}" for i, c in enumerate(cases))
          + f"; the whole order {100 * share:.1f} %")


def uncertainty_check(study, case, doc, mine, settings):
    """Each source's u_s (and shared shift) from the variant run against metrics.json's, and u."""
    sources = {}
    for source_dir in sorted((study / "uncertainty").iterdir()) if (study / "uncertainty").is_dir() else []:
        variant = source_dir / case
        vdoc = json.load(open(variant / "report" / "metrics.json"))
        vmine = recompute(variant / "timeseries.csv", *settings)
        for name, value in vmine["metrics"].items():
            stored = vdoc["metrics"][name]["value"]
            if abs(stored - value) > 1e-9 * abs(value):
                fail(f"{source_dir.name}/{case}: {name} {stored} in metrics.json, {value} recomputed")
        sources[source_dir.name] = (vdoc, vmine)
    for key, metric in doc["metrics"].items():
        if "uncertainty" not in metric:
            continue
        total = 0.0
        for name, (vdoc, vmine) in sources.items():
            shift = vdoc["metrics"][key]["value"] - metric["value"]
            if key in mine["metrics"]:  # the series' own recomputation of both
                shift_own = vmine["metrics"][key] - mine["metrics"][key]
                if abs(shift_own - shift) > 1e-8 * max(abs(metric["value"]), 1e-12):
                    fail(f"{case}: {key}'s shift from {name}: {shift} from the reports, {shift_own} recomputed")
            label = name.replace("_", " ")
            stored = metric["uncertainty_sources"].get(name, metric["uncertainty_sources"].get(label))
            if stored is None or abs(stored - abs(shift)) > 1e-12 * max(abs(metric["value"]), 1.0):
                fail(f"{case}: {key}'s uncertainty from {name} {stored} in metrics.json, |shift| {abs(shift)}")
            shared = metric.get("uncertainty_shared", {})
            signed = shared.get(name, shared.get(label))
            if signed is not None and abs(signed - shift) > 1e-12 * max(abs(metric["value"]), 1.0):
                fail(f"{case}: {key}'s shared shift from {name} {signed} in metrics.json, {shift} recomputed")
            total += shift * shift
        if abs(metric["uncertainty"] - np.sqrt(total)) > 1e-12 * max(abs(metric["value"]), 1.0):
            fail(f"{case}: {key}'s uncertainty {metric['uncertainty']} in metrics.json, {np.sqrt(total)} recomputed")
    return len(sources)


def main():
    study = pathlib.Path(sys.argv[1])
    cases = sorted(p.name for p in (study / "runs").iterdir() if p.is_dir())
    if len(cases) != 6:
        fail(f"{study}/runs holds {len(cases)} cases, the study has 6")
    docs = {}
    for case in cases:
        doc = json.load(open(study / "runs" / case / "report" / "metrics.json"))
        docs[case] = doc
        s = doc["settings"]
        settings = (s["closed_area_fraction"], s["open_area_fraction"], s["density_g_per_mL"])
        mine = recompute(study / "runs" / case / "timeseries.csv", *settings)
        for name, value in mine["phases"].items():
            stored = doc["phases"][name]
            if abs(stored - value) > 1e-9:
                fail(f"{case}: {name} {stored} in metrics.json, {value} recomputed")
        for name, value in mine["metrics"].items():
            stored = doc["metrics"][name]["value"]
            if abs(stored - value) > 1e-9 * abs(value):
                fail(f"{case}: {name} {stored} in metrics.json, {value} recomputed")
        sources = uncertainty_check(study, case, doc, mine, settings)
        print(f"ok: {case}: t_bs {mine['phases']['ejection_start'] - doc['phases']['cycle_start']:.4f} s into "
              f"the cycle ({doc['phases']['ejection_start_condition']}), TPG "
              f"{mine['metrics']['transvalvular_pressure_gradient']:.3f} mmHg, EOA "
              f"{mine['metrics']['effective_orifice_area']:.4f} cm^2; uncertainties from {sources} sources")
    ranking_check(study, cases, docs)


if __name__ == "__main__":
    main()
