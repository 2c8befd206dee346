#!/bin/sh
# Bad input to `ibvalve run` (lumped), `ibvalve report` and `ibvalve study` must exit with code 2 and one line on
# stderr naming the file. usage: check_exit_codes.sh IBVALVE SOURCE_DIR
ibvalve="$1"
source_dir="$2"
work="exit_codes_work"
rm -rf "$work" && mkdir -p "$work"
status=0

expect_two() {
  what="$1"
  shift
  "$@" > "$work/out.txt" 2> "$work/err.txt"
  code=$?
  lines=$(grep -c . "$work/err.txt")
  if [ "$code" -ne 2 ] || [ "$lines" -ne 1 ]; then
    echo "FAIL: $what: exit $code, $lines stderr line(s):"
    cat "$work/err.txt"
    status=1
  else
    echo "ok: $what: exit 2: $(cat "$work/err.txt")"
  fi
}

case="$source_dir/examples/lumped/default.toml"
expect_two "unknown key" "$ibvalve" run "$case" --set valve.bogus=1 -o "$work/r1"
expect_two "out of range" "$ibvalve" run "$case" --set windkessel.compliance=-1 -o "$work/r2"
expect_two "period mismatch" "$ibvalve" run "$case" --set report.period=1.0 -o "$work/r3"
expect_two "cycle 0 (cycles count from 1)" "$ibvalve" run "$case" --set report.cycle=0 -o "$work/r4"
[ -e "$work/r1" ] && { echo "FAIL: a run folder was created for bad input"; status=1; }

mkdir -p "$work/missing_column" "$work/bad_line" "$work/no_series"
printf 't,Q_valve,P_LV,P_Ao,P_nlv\n0,1,2,3,4\n0.1,1,2,3,4\n0.2,1,2,3,4\n' > "$work/missing_column/timeseries.csv"
printf 't,Q_valve,P_LV,P_Ao,P_nlv,P_nao\n0,1,2,3,4,5\n0.1,1,2,oops,4,5\n' > "$work/bad_line/timeseries.csv"
expect_two "missing column" "$ibvalve" report "$work/missing_column"
expect_two "bad CSV line" "$ibvalve" report "$work/bad_line"
expect_two "no time series" "$ibvalve" report "$work/no_series"
expect_two "report --cycle 0 (cycles count from 1)" "$ibvalve" report "$work/bad_line" --cycle 0
expect_two "not a folder" "$ibvalve" compare "$work/does_not_exist"
printf 'base = "%s"\nleave_out = ["fit_eror"]\n[[case]]\nname = "a"\n' "$case" > "$work/study.toml"
expect_two "a study leaving out no criterion" "$ibvalve" study "$work/study.toml" -o "$work/study"
grep -q "leave_out: 'fit_eror' is no ranking criterion" "$work/err.txt" ||
  { echo "FAIL: the study's error does not name leave_out's criterion"; status=1; }
[ -e "$work/study" ] && { echo "FAIL: a study folder was created for bad input"; status=1; }
exit $status
