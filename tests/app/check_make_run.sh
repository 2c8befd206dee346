#!/usr/bin/env bash
# `make run`, read without building anything (make -n):
#   check_make_run.sh SOURCE_DIR
# - the run folder follows the case: RUN_CASE=examples/lumped/default.toml runs in runs/lumped_default,
#   not in the default case's runs/aortic_valve_default; RUN_DIR=... still chooses;
# - make prints no "Entering directory" lines (neither it nor the make that `cmake --build` starts);
# - build.configure.log is not tracked by git (the configure log is written under the build folder);
# - the build's output goes to build/build.log, shown only when the build fails.
set -u
source=$1
fail() { echo "FAIL: $*"; exit 1; }
cd "$source" || fail "no $source"
lumped=$(make -n run RUN_CASE=examples/lumped/default.toml 2>&1)
echo "$lumped" | grep -q -- "run examples/lumped/default.toml -o runs/lumped_default --overwrite" ||
  fail "the lumped case does not run in runs/lumped_default:"$'\n'"$lumped"
default=$(make -n run 2>&1)
echo "$default" | grep -q -- "-o runs/aortic_valve_default --overwrite" ||
  fail "the default case does not run in runs/aortic_valve_default:"$'\n'"$default"
chosen=$(make -n run RUN_CASE=examples/lumped/default.toml RUN_DIR=runs/mine 2>&1)
echo "$chosen" | grep -q -- "-o runs/mine --overwrite" || fail "RUN_DIR is not used:"$'\n'"$chosen"
# The make that `cmake --build` starts inherits MAKEFLAGS: without --no-print-directory there it prints
# "make[1]: Entering directory" around the build.
make -pn run 2>/dev/null | grep -q '^MAKEFLAGS = .*--no-print-directory' ||
  fail "the Makefile does not pass --no-print-directory on to sub-makes (MAKEFLAGS)"
# `make run` builds quietly: the build's output goes to build/build.log (shown when the build fails),
# not 75 lines on the terminal before the run's own.
echo "$default" | grep -q -- "cmake --build build .*> build/build.log 2>&1 ||" ||
  fail "make run does not send the build's output to build/build.log:"$'\n'"$default"
echo "$default" | grep -q "cat build/build.log" || fail "make run does not show a failed build's output:"$'\n'"$default"
echo "$lumped" | grep -q "configure.log" && { echo "$lumped" | grep -q "build/configure.log" ||
  fail "the configure log is not written under the build folder:"$'\n'"$lumped"; }
if command -v git >/dev/null && git rev-parse --git-dir >/dev/null 2>&1; then
  [ -z "$(git ls-files build.configure.log)" ] || fail "build.configure.log is tracked by git"
fi
echo "PASS"
