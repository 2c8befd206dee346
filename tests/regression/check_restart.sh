#!/bin/sh
# Restart reproduces an uninterrupted run, on the lumped default case:
#   1. the whole run (2 cycles, 16000 steps, checkpoints every 2000 steps);
#   2. the same run stopped after 7300 steps (a stop checkpoint between the periodic ones), restarted
#      and stopped again after 5000 more, then a torn checkpoint file is planted as the newest (a crash
#      while writing), and the last restart must skip it and go on from the last good one to the end;
#   3. timeseries.csv and metrics.json of 2 must equal those of 1 exactly (compare_runs.py --rtol 0 --atol 0).
#   check_restart.sh IBVALVE MPIEXEC PYTHON SOURCE_DIR RANKS
set -eu
ibvalve=$1 mpiexec=$2 python=$3 source=$4 ranks=$5
case_file=$source/examples/lumped/default.toml
common="--set time.cycles=2 --set checkpoint.every=2000 --set report.plots=false -q"
whole=restart_whole_np$ranks split=restart_split_np$ranks
rm -rf "$whole" "$split"
# shellcheck disable=SC2086
"$mpiexec" --oversubscribe -n "$ranks" "$ibvalve" run "$case_file" -o "$whole" --overwrite $common
# shellcheck disable=SC2086
"$mpiexec" --oversubscribe -n "$ranks" "$ibvalve" run "$case_file" -o "$split" --overwrite $common --stop-after-steps 7300
[ ! -e "$split/report" ] || { echo "FAIL: a stopped run wrote a report"; exit 1; }
ls "$split/checkpoints"
"$mpiexec" --oversubscribe -n "$ranks" "$ibvalve" run --restart "$split" --stop-after-steps 5000 -q
ls "$split/checkpoints"
[ -e "$split/checkpoints/step_000012300.h5" ] || { echo "FAIL: no stop checkpoint at step 12300"; exit 1; }
[ ! -e "$split/checkpoints/step_000006000.h5" ] || { echo "FAIL: old checkpoints are not pruned (keep = 2)"; exit 1; }
echo "not an HDF5 file: a checkpoint torn by a crash" > "$split/checkpoints/step_000013000.h5"
"$mpiexec" --oversubscribe -n "$ranks" "$ibvalve" run --restart "$split" > "$split.out" 2>&1 || { cat "$split.out"; exit 1; }
grep -q "restarting from .*step_000012300.h5" "$split/log.txt" || { echo "FAIL: did not skip the torn checkpoint"; cat "$split/log.txt"; exit 1; }
"$python" "$source/tests/regression/compare_runs.py" --rtol 0 --atol 0 "$whole" "$split" --series-only
# run.json keeps where the run came from and lists both restarts, each with its build and ranks.
"$python" -c 'import json, sys; r = json.load(open(sys.argv[1])); assert r["case_file"].endswith(".toml") and len(r["restarts"]) == 2 and all(x["commit"] and x["ranks"] == int(sys.argv[2]) for x in r["restarts"]), r' "$split/run.json" "$ranks" || { echo "FAIL: run.json does not record the two restarts"; exit 1; }
cp "$whole/report/metrics.json" "$whole/metrics.json"
"$python" "$source/tests/regression/compare_runs.py" --rtol 0 --atol 0 "$whole" "$split"
