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
# drop_columns FILE NAME...: the CSV FILE without the columns NAME... (by
# header), e.g. history.csv without wall_s, whose value no two runs share
drop_columns() {
  f=$1
  shift
  awk -F, -v names=" $* " 'NR == 1 { for (i = 1; i <= NF; i++) if (index(names, " " $i " ")) w[i] = 1 }
    { s = ""; for (i = 1; i <= NF; i++) if (!(i in w)) s = s (s == "" ? "" : ",") $i; print s }' "$f"
}
# the closing line and the exit status of the script
summary() {
  echo "$pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
# series_ok DIR [partial]: the time series of DIR's field files.
# particles.pvd and arms.pvd (well-formed, by xmllint when it is
# installed) list the same steps (partial: a killed run's arms.pvd may
# lack the last step of particles.pvd, written first) at strictly
# increasing timesteps, each NAME_NNNN.vtu of its timestep, every one
# there and passing tests/vtu_dump's strict reader;
# with particles.csv in DIR, the last particles file's displacement is
# that of particles.csv to its printed digits. The first failure is in
# $why (temporary files under ${T:-.}).
V=./tests/vtu_dump
series_ok() {
  why=""
  tmp=${T:-.}/series
  for k in particles arms; do
    pvd="$1/$k.pvd"
    if [ ! -f "$pvd" ]; then why="no $pvd"; return 1; fi
    if command -v xmllint >/dev/null 2>&1 && ! xmllint --noout "$pvd" 2>"$tmp.err"; then
      why="$pvd: not well-formed: $(head -1 "$tmp.err")"; return 1
    fi
    sed -n 's/.*<DataSet timestep="\([^"]*\)".* file="\([^"]*\)".*/\1 \2/p' "$pvd" > "$tmp.$k"
    if [ "$(grep -c "<DataSet" "$pvd")" -ne "$(wc -l < "$tmp.$k")" ] || [ ! -s "$tmp.$k" ]; then
      why="$pvd: no DataSet, or one without timestep and file"; return 1
    fi
    if ! awk -v k="$k" 'NR > 1 && $1 + 0 <= last + 0 { exit 1 }
                        $2 != sprintf("%s_%04d.vtu", k, $1) { exit 1 } { last = $1 }' "$tmp.$k"; then
      why="$pvd: timesteps not increasing, or a file not of its step"; return 1
    fi
    while read -r t f; do
      if [ ! -f "$1/$f" ] || ! $V "$1/$f" > "$tmp.dump" 2> "$tmp.err"; then
        why="$pvd lists $f (timestep $t): missing or unreadable: $(cat "$tmp.err")"; return 1
      fi
    done < "$tmp.$k"
  done
  if [ "$(cut -d' ' -f1 "$tmp.particles")" != "$(cut -d' ' -f1 "$tmp.arms")" ] &&
     { [ "$2" != partial ] ||
       [ "$(sed '$d' "$tmp.particles" | cut -d' ' -f1)" != "$(cut -d' ' -f1 "$tmp.arms")" ]; }; then
    why="particles.pvd and arms.pvd list different steps"; return 1
  fi
  [ -f "$1/particles.csv" ] || return 0
  last=$(tail -n 1 "$tmp.particles" | cut -d' ' -f2)
  $V "$1/$last" > "$tmp.dump"
  # the dump's displacement block against the CSV's ux, uy[, uz] columns
  if ! awk -F'[, ]' '
    FILENAME == ARGV[1] {
      if ($1 == "VECTORS") { on = ($2 == "displacement"); i = 0; next }
      if ($1 == "SCALARS" || $1 == "CELL_DATA" || $1 == "FIELD") { on = 0; next }
      if (on) { for (c = 1; c <= 3; c++) u[i, c] = $c; i++ }
      next }
    FNR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; dim = ("uz" in col) ? 3 : 2; next }
    { n++
      for (c = 1; c <= dim; c++) {
        want = $(col[c == 1 ? "ux" : c == 2 ? "uy" : "uz"])
        got = sprintf("%.10g", u[$(col["id"]), c])
        if (got == "-0") got = "0"; if (want == "-0") want = "0"
        if (got != want) { printf "particle %s u%d: vtu %s, csv %s\n", $1, c, got, want; bad = 1; exit 1 } } }
    END { if (!bad && n != i) { printf "%d particles in the CSV, %d in the vtu\n", n, i; exit 1 } }' \
    "$tmp.dump" "$1/particles.csv" > "$tmp.err"; then
    why="$last: displacement differs from particles.csv: $(cat "$tmp.err")"; return 1
  fi
  return 0
}
