#!/usr/bin/env bash
# Runs a command and checks how it ended, as a user would see it:
#   expect_exit.sh CODE REGEX [--absent PATH] -- COMMAND...
# passes when the exit code is CODE, exactly one line of stderr starts with "error:" (one clear
# message, from rank 0 only) and that line matches the extended regex REGEX, and PATH (a run folder
# that bad input must not create) does not exist afterwards. CODE 0 checks stdout against REGEX.
set -u
expected_code=$1
regex=$2
shift 2
absent=""
if [ "$1" = "--absent" ]; then
  absent=$2
  shift 2
fi
[ "$1" = "--" ] && shift
[ -n "$absent" ] && rm -rf "$absent"
out=$(mktemp)
err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT
"$@" >"$out" 2>"$err"
code=$?
fail() {
  echo "FAIL: $*"
  echo "--- command: $*"
  echo "--- stdout:"; cat "$out"
  echo "--- stderr:"; cat "$err"
  exit 1
}
[ "$code" -eq "$expected_code" ] || fail "exit code $code, expected $expected_code"
if [ "$expected_code" -eq 0 ]; then
  grep -Eq -- "$regex" "$out" || fail "stdout does not match: $regex"
else
  n=$(grep -c '^error:' "$err")
  [ "$n" -eq 1 ] || fail "$n error lines, expected exactly one"
  grep '^error:' "$err" | grep -Eq -- "$regex" || fail "the error line does not match: $regex"
fi
if [ -n "$absent" ] && [ -e "$absent" ]; then fail "$absent was created"; fi
echo "ok: exit $code"
exit 0
