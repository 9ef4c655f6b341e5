# cli_lib.sh: helpers of the command-line tests (t9xx_*.sh source it after
# setting P, the peristatic to run). Each check prints one "PASS: ..." or
# "FAIL: ..." line; the script ends with summary, "N passed, N failed".
pass=0
fail=0
ok() { echo "PASS: $1"; pass=$((pass + 1)); }
ko() { echo "FAIL: $1"; fail=$((fail + 1)); }
# expect CODE PATTERN -- ARGS: exit status CODE and stderr matching PATTERN
expect() {
  code=$1
  pat=$2
  shift 3
  out=$($P "$@" 2>&1 >/dev/null)
  rc=$?
  if [ "$rc" -eq "$code" ] && printf '%s' "$out" | grep -q -- "$pat"; then
    ok "peristatic $* -> exit $rc, '$pat'"
  else
    ko "peristatic $* -> exit $rc (want $code), message: $out (want '$pat')"
  fi
}
# no_hang SECONDS CODE PATTERN -- ARGS: as expect, under timeout(1): a guard
# against a hang (an input that used to take minutes), set far above the
# command's normal time; not a speed test (exit 124 when it fires)
no_hang() {
  secs=$1
  shift
  P_plain=$P
  P="timeout $secs $P"
  expect "$@"
  P=$P_plain
}
# the closing line and the exit status of the script
summary() {
  echo "$pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
