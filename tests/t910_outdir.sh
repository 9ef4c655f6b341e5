#!/bin/sh
# t910_outdir.sh: output folders and processes. peristatic replaces only a
# folder it wrote itself and refuses anything else untouched; a second
# writer of one folder is refused; a kill in the commit's rename window is
# repaired at the next start; SIGINT/SIGTERM end a run (and the workers of
# griffith -j) cleanly, and a killed sweep's workers die with it; gnuplot
# runs without a shell; a stalled run says what it saw; no nan or inf in
# the outputs.
srcdir=${srcdir:-.}
D="$srcdir/tests/data/outdir"
P=./peristatic
T=t910_tmp
OMP_THREAD_LIMIT=${OMP_THREAD_LIMIT:-1}
export OMP_THREAD_LIMIT
. "$srcdir/tests/cli_lib.sh"
# wait_for FILE [LINES]: until FILE exists with at least LINES lines (~30 s at most)
wait_for() {
  n=0
  while [ $n -lt 300 ]; do
    if [ -f "$1" ] && [ "$(wc -l < "$1")" -ge "${2:-0}" ]; then return 0; fi
    sleep 0.1
    n=$((n + 1))
  done
  return 1
}
# gone PID...: every process has ended (or is a zombie) within ~3 s
gone() {
  n=0
  while [ $n -lt 30 ]; do
    alive=0
    for p in "$@"; do
      case "$(ps -o stat= -p "$p" 2>/dev/null)" in "" | Z*) ;; *) alive=1 ;; esac
    done
    [ $alive -eq 0 ] && return 0
    sleep 0.1
    n=$((n + 1))
  done
  return 1
}
# children PID: the pids of its child processes
children() { ps -o pid= --ppid "$1" 2>/dev/null; }
rm -rf "$T"
mkdir -p "$T"

# 1. no shell: an output folder whose name is a shell command stays a name
inj="$T/x';touch INJECTED;'"
if $P griffith -q -o "$inj" "$D/sweep.yaml" && [ -f "$inj/griffith.gp" ] &&
   [ ! -e INJECTED ] && [ -z "$(find "$T" -name INJECTED)" ]; then
  ok "griffith -o \"x';touch INJECTED;'\": no command ran, griffith.gp is in that folder"
else
  ko "griffith with a quote in the output folder's name"
fi
if command -v gnuplot >/dev/null 2>&1; then
  if head -c 4 "$inj/griffith.png" 2>/dev/null | grep -q PNG; then
    ok "gnuplot (without a shell) plotted griffith.png in a folder named with quotes"
  else
    ko "griffith.png missing in a folder named with quotes (gnuplot present)"
  fi
fi
if grep -rnE '(^|[^_[:alnum:]])(system|popen)\(' "$srcdir/src" >/dev/null; then
  ko "src/ calls system() or popen()"
else
  ok "src/ calls neither system() nor popen()"
fi

# 2. only a folder of ours is replaced; anything else is refused untouched
mkdir -p "$T/p"
echo x > "$T/p/thesis.tex"
expect 3 "t910_tmp/p is a folder peristatic did not write.*move t910_tmp/p away" -- run -q -o "$T/p" "$D/box.yaml"
expect 3 "t910_tmp/p is a folder peristatic did not write" -- griffith -q -o "$T/p" "$D/sweep.yaml"
expect 3 "t910_tmp/p is a folder peristatic did not write" -- griffith --resume -q -o "$T/p" "$D/sweep.yaml"
if [ "$(cat "$T/p/thesis.tex")" = x ] && [ "$(ls -A "$T/p")" = thesis.tex ] &&
   [ ! -e "$T/p.partial" ] && [ ! -e "$T/p.old" ] && [ ! -e "$T/p.lock" ]; then
  ok "a folder that is not ours is left as it was (no .partial, .old or .lock beside it)"
else
  ko "a folder that is not ours was changed"
fi
echo y > "$T/f"
expect 3 "t910_tmp/f is a file, not a folder" -- run -q -o "$T/f" "$D/box.yaml"
ln -s p "$T/l"
expect 3 "t910_tmp/l is a symbolic link" -- run -q -o "$T/l" "$D/box.yaml"
if [ "$(cat "$T/f")" = y ] && [ -L "$T/l" ] && [ "$(cat "$T/p/thesis.tex")" = x ]; then
  ok "a file and a symbolic link named by -o are left as they were"
else
  ko "a file or a symbolic link named by -o was changed"
fi
mkdir -p "$T/q.partial" "$T/r.old"
echo z > "$T/q.partial/notes"
echo z > "$T/r.old/notes"
expect 3 "t910_tmp/q.partial is a folder peristatic did not write" -- run -q -o "$T/q" "$D/box.yaml"
expect 3 "t910_tmp/r.old is a folder peristatic did not write" -- run -q -o "$T/r" "$D/box.yaml"
echo data > "$T/s.lock"
expect 3 "t910_tmp/s.lock is not a peristatic lock file" -- run -q -o "$T/s" "$D/box.yaml"
if [ "$(cat "$T/q.partial/notes")" = z ] && [ "$(cat "$T/r.old/notes")" = z ] &&
   [ "$(cat "$T/s.lock")" = data ] && [ ! -e "$T/q" ] && [ ! -e "$T/r" ] && [ ! -e "$T/s" ]; then
  ok "DIR.partial, DIR.old and DIR.lock that are not ours are left as they were"
else
  ko "DIR.partial, DIR.old or DIR.lock that are not ours were changed"
fi
if $P run -q -o "$T/own" "$D/box.yaml" && $P run -q -o "$T/own" "$D/box.yaml" &&
   grep -q "^peristatic output folder" "$T/own/.peristatic" &&
   [ ! -e "$T/own.old" ] && [ ! -e "$T/own.partial" ] && [ ! -e "$T/own.lock" ]; then
  ok "a folder of ours (.peristatic marker) is replaced; no .old, .partial or .lock is left"
else
  ko "a second run into a folder of ours"
fi
mkdir -p "$T/legacy" "$T/empty"
printf 'case: an-older-version\n' > "$T/legacy/summary.txt"
touch "$T/legacy/particles_0001.vtk"
if $P run -q -o "$T/legacy" "$D/box.yaml" && $P run -q -o "$T/empty" "$D/box.yaml" &&
   grep -q "^case: outdir-box" "$T/legacy/summary.txt" && [ ! -e "$T/legacy/particles_0001.vtk" ] &&
   [ -f "$T/empty/summary.txt" ]; then
  ok "a folder of an earlier version (summary.txt of ours, no marker) and an empty folder are replaced"
else
  ko "an earlier version's folder or an empty folder"
fi
# the committed paper sweep (no marker: recognised by its griffith.csv)
cp -r "$srcdir/doc/results/griffith-paper" "$T/paper"
chmod -R u+w "$T/paper"
if $P griffith --resume -q -o "$T/paper" "$srcdir/data/cases/paper-griffith.yaml" &&
   [ "$(cut -d, -f1-7 "$T/paper/griffith.csv")" = "$(cut -d, -f1-7 "$srcdir/doc/results/griffith-paper/griffith.csv")" ]; then
  ok "griffith --resume on (a copy of) doc/results/griffith-paper reuses its runs"
else
  ko "griffith --resume on a copy of doc/results/griffith-paper"
fi

# 3. one writer per folder: a second run or sweep is refused at once
$P run -q -t 1 -o "$T/busy" "$D/box_slow.yaml" &
bg=$!
if wait_for "$T/busy.partial/history.csv" 3; then
  expect 3 "t910_tmp/busy is being written by another peristatic process (pid $bg)" -- run -q -o "$T/busy" "$D/box.yaml"
  expect 3 "t910_tmp/busy is being written by another peristatic process (pid $bg)" -- griffith -q -o "$T/busy" "$D/sweep.yaml"
else
  ko "the first run into t910_tmp/busy did not start"
fi
wait $bg
rc=$?
if [ $rc -eq 0 ] && grep -q "^case: outdir-box-slow" "$T/busy/summary.txt" && [ ! -e "$T/busy.lock" ]; then
  ok "the first writer finished undisturbed and removed its lock"
else
  ko "the first writer (exit $rc) was disturbed or left its lock"
fi

# 4. kill -9 of griffith -j's parent: its workers die with it; --resume
# then takes over the dead workers' claims and completes
$P griffith -q -j 2 -o "$T/orphan" "$D/sweep_slow.yaml" 2>/dev/null &
bg=$!
wait_for "$T/orphan.partial/job-2.log"
sleep 0.3
workers=$(children $bg)
kill -9 $bg
wait $bg 2>/dev/null
if [ "$(echo $workers | wc -w)" -eq 2 ] && gone $workers; then
  ok "kill -9 of the parent of griffith -j 2: both workers ended within 3 s"
else
  ko "kill -9 of the parent of griffith -j 2 left workers ($workers) running"
  kill -9 $workers 2>/dev/null
fi
if $P griffith --resume -q -j 2 -o "$T/orphan" "$D/sweep_slow.yaml" &&
   [ "$(wc -l < "$T/orphan/griffith.csv")" -eq 5 ] && [ ! -e "$T/orphan.partial" ] &&
   [ -z "$(find "$T/orphan" -name '*.claim')" ]; then
  ok "griffith --resume -o DIR after the kill: continues in DIR.partial, all 4 runs, DIR in place"
else
  ko "griffith --resume after killing the sweep"
fi

# 5. the commit's rename window: DIR missing and DIR.old of ours is
# restored; DIR.old beside DIR is a leftover and removed; an old
# DIR.partial of ours is replaced
$P run -q -o "$T/win" "$D/box.yaml"
cp "$T/win/summary.txt" "$T/win.summary"
mv "$T/win" "$T/win.old"
out=$($P run -q -o "$T/win" "$D/soft_plane_stress.yaml" 2>&1)
if printf '%s' "$out" | grep -q "restored t910_tmp/win" && cmp -s "$T/win.summary" "$T/win/summary.txt" &&
   [ ! -e "$T/win.old" ]; then
  ok "DIR missing, DIR.old ours: restored (and said so), then kept by the failed run"
else
  ko "DIR.old was not restored: $out"
fi
mkdir -p "$T/win.old" "$T/win.partial"
touch "$T/win.old/.peristatic" "$T/win.partial/.peristatic" "$T/win.partial/stale.vtk"
out=$($P run -v -o "$T/win" "$D/box.yaml" 2>&1)
if printf '%s' "$out" | grep -q "removing t910_tmp/win.old, left over" && [ ! -e "$T/win.old" ] &&
   [ ! -e "$T/win.partial" ] && [ ! -e "$T/win/stale.vtk" ] && grep -q "^case: outdir-box" "$T/win/summary.txt"; then
  ok "a leftover DIR.old (ours) is removed (said at -v), an old DIR.partial (ours) replaced"
else
  ko "leftover DIR.old / DIR.partial: $out"
fi

# 6. SIGINT / SIGTERM: the run ends with a message, the partial output in
# DIR.partial, DIR untouched
$P run -q -o "$T/sig" "$D/box.yaml"
cp "$T/sig/summary.txt" "$T/sig.summary"
for s in INT TERM; do
  rm -rf "$T/sig.partial" # wait_for must see this run's history
  $P run -q -t 1 -o "$T/sig" "$D/box_slow.yaml" 2> "$T/sig.err" &
  bg=$!
  wait_for "$T/sig.partial/history.csv" 3
  kill -$s $bg
  wait $bg
  rc=$?
  want=130
  [ $s = TERM ] && want=143
  if [ $rc -eq $want ] && grep -q "interrupted by SIG$s at load factor [0-9.]*; the partial output is in t910_tmp/sig.partial, earlier results in t910_tmp/sig are untouched" "$T/sig.err" &&
     cmp -s "$T/sig.summary" "$T/sig/summary.txt" &&
     grep -q "^stop_reason: interrupted by SIG$s" "$T/sig.partial/summary.txt" &&
     [ "$(wc -l < "$T/sig.partial/history.csv")" -ge 3 ] && [ ! -e "$T/sig.old" ] && [ ! -e "$T/sig.lock" ]; then
    ok "SIG$s: exit $rc (128 + signal), 'interrupted by SIG$s at load factor', DIR untouched, DIR.partial has history and summary"
  else
    ko "SIG$s during a run: exit $rc, $(cat "$T/sig.err")"
  fi
done
# a sweep: the parent passes SIGTERM on, the workers end their runs, and
# --resume -o DIR continues and completes
$P griffith -q -j 2 -o "$T/gsig" "$D/sweep_slow.yaml" 2> "$T/gsig.err" &
bg=$!
wait_for "$T/gsig.partial/job-2.log"
sleep 0.3
workers=$(children $bg)
kill -TERM $bg
wait $bg
rc=$?
if [ $rc -eq 143 ] && grep -q "griffith interrupted by SIGTERM" "$T/gsig.err" &&
   grep -q "griffith --resume -o t910_tmp/gsig CASE" "$T/gsig.err" && gone $workers &&
   cat "$T"/gsig.partial/job-*.log | grep -q "interrupted by SIGTERM at load factor"; then
  ok "SIGTERM to griffith -j 2: the workers ended their runs (interrupted), the parent says how to resume"
else
  ko "SIGTERM to griffith -j 2: exit $rc, $(cat "$T/gsig.err")"
fi
if $P griffith --resume -q -j 2 -o "$T/gsig" "$D/sweep_slow.yaml" &&
   [ "$(wc -l < "$T/gsig/griffith.csv")" -eq 5 ] && [ ! -e "$T/gsig.partial" ]; then
  ok "griffith --resume after SIGTERM completes the sweep"
else
  ko "griffith --resume after SIGTERM"
fi

# 7. a stall says what was seen; a model that softens is not sent to
# smaller steps; no nan or inf in summary.txt and history.csv
expect 2 "no arm can break (delta is infinite); the boundary stress was falling over the last converged increments; the tangent turned indefinite. The model itself softens: the fibre model in plane stress with nu = 0.2 < 1/3" -- run -q -o "$T/soft" "$D/soft_plane_stress.yaml"
out=$($P run -q -o "$T/soft" "$D/soft_plane_stress.yaml" 2>&1)
if printf '%s' "$out" | grep -q "will not help" && ! printf '%s' "$out" | grep -q "Try a smaller" &&
   grep -q "^stop_reason: .*as the model softened, no arm broken" "$T/soft.partial/summary.txt"; then
  ok "softening: the advice says smaller steps will not help; stop_reason says no arm broke"
else
  ko "softening advice: $out"
fi
expect 2 "Newton diverged at load factor .*Try a smaller path.load_step" -- run -q -o "$T/nopeak" "$D/no_peak.yaml"
if grep -q "^sigma_failure_Pa: n/a" "$T/nopeak.partial/summary.txt" &&
   ! grep -qiE 'nan|inf' "$T/nopeak.partial/summary.txt" "$T/nopeak.partial/history.csv" "$T/soft.partial/summary.txt"; then
  ok "no settled peak: summary.txt says n/a, no nan or inf"
else
  ko "nan or inf in summary.txt or history.csv"
fi

rm -rf "$T"
rm -f INJECTED
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
