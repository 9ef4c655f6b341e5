#!/bin/sh
# t910_outdir.sh: output folders and processes. peristatic replaces only a
# folder it wrote itself, holding nothing but its own files, and refuses
# anything else untouched; a second writer of one folder is refused; the
# commit exchanges the folders atomically, and a kill in the rename window
# of the fallback is repaired at the next start; SIGINT/SIGTERM end a run
# (and the workers of griffith -j) cleanly, and a killed sweep's workers
# die with it; gnuplot runs without a shell and the case name cannot
# inject commands or keys; --resume reads summary.txt defensively; a stalled
# run says what it saw; no nan or inf in the outputs.
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
# the case name reaches griffith.gp's title and summary.txt: a name that
# would run a command in gnuplot or add a key is refused
sed 's/^name: .*/name: "x'"'"' . system('"'"'touch PWNED'"'"') . '"'"'"/' "$D/sweep.yaml" > "$T/pwn.yaml"
expect 1 "t910_tmp/pwn.yaml:3: name may hold only letters, digits, spaces and . _ + - (got 'x' . system('touch PWNED') . '')" -- griffith -q -o "$T/pwn" "$T/pwn.yaml"
sed 's/^name: .*/name: "b\\nfractured: yes"/' "$D/sweep.yaml" > "$T/nl.yaml"
expect 1 "t910_tmp/nl.yaml:3: name may hold only letters, digits, spaces and . _ + - (got 'b?fractured: yes')" -- run -q -o "$T/nl" "$T/nl.yaml"
sed 's/^name: .*/name: -rf/' "$D/sweep.yaml" > "$T/dash.yaml"
expect 1 "name must not start with '.' or '-' (got '-rf')" -- run -q -o "$T/dash" "$T/dash.yaml"
if [ -z "$(find . -name PWNED)" ] && [ ! -e "$T/pwn" ] && [ ! -e "$T/nl" ]; then
  ok "names that would inject a gnuplot command or a summary key: refused, nothing run or written"
else
  ko "a name with a quote or a line break was not refused cleanly"
fi
# a name taken from the file name is not checked: griffith.gp quotes it
pwnf="$T/x' . system('touch PWNED') . '.yaml"
grep -v '^name:' "$D/sweep.yaml" > "$pwnf"
if $P griffith -q -o "$T/pwnf" "$pwnf" &&
   grep -qF "set title 'Griffith check: x'' . system(''touch PWNED'') . '' (slope" "$T/pwnf/griffith.gp" &&
   [ -z "$(find . -name PWNED)" ]; then
  ok "a quote in the name from the file name is doubled in griffith.gp's title: gnuplot runs nothing"
else
  ko "griffith.gp with a quote in the case name: $(grep title "$T/pwnf/griffith.gp")"
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
touch "$T/legacy/particles_0001.vtk" "$T/legacy/arms_0001.vtk"
if $P run -q -o "$T/legacy" "$D/box.yaml" && $P run -q -o "$T/empty" "$D/box.yaml" &&
   grep -q "^case: outdir-box" "$T/legacy/summary.txt" && [ ! -e "$T/legacy/particles_0001.vtk" ] &&
   [ -f "$T/empty/summary.txt" ]; then
  ok "a folder of an earlier version (summary.txt of ours, legacy .vtk field files, no marker) and an empty folder are replaced"
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
cp -r "$srcdir/doc/results/griffith-small-disk" "$T/small"
chmod -R u+w "$T/small"
if $P run -q -o "$T/small" "$D/box.yaml" && grep -q "^case: outdir-box" "$T/small/summary.txt" &&
   [ ! -e "$T/small/griffith.csv" ]; then
  ok "(a copy of) doc/results/griffith-small-disk counts as ours: replaced"
else
  ko "a copy of doc/results/griffith-small-disk was not taken as ours"
fi
# ours by its signature, but holding a file of someone else's: refused
mkdir -p "$T/paper2"
echo important > "$T/paper2/thesis.tex"
printf 'case: notes\n' > "$T/paper2/summary.txt"
expect 3 "t910_tmp/paper2 holds files peristatic did not write (thesis.tex): .*move them out or choose another output folder" -- run -q -o "$T/paper2" "$D/box.yaml"
$P run -q -o "$T/keep" "$D/box.yaml"
cp "$D/box.yaml" "$T/keep/box.yaml"
expect 3 "t910_tmp/keep holds files peristatic did not write (box.yaml)" -- run -q -o "$T/keep" "$T/keep/box.yaml"
$P griffith -q -o "$T/gkeep" "$D/sweep.yaml"
echo n > "$T/gkeep/delta_c500/notes.txt"
echo n > "$T/gkeep/a.txt"
echo n > "$T/gkeep/b.txt"
echo n > "$T/gkeep/c.txt"
expect 3 "t910_tmp/gkeep holds files peristatic did not write (a.txt, b.txt, c.txt, ...)" -- griffith -q -o "$T/gkeep" "$D/sweep.yaml"
rm "$T"/gkeep/?.txt
expect 3 "t910_tmp/gkeep holds files peristatic did not write (delta_c500/notes.txt)" -- griffith --resume -q -o "$T/gkeep" "$D/sweep.yaml"
mkdir -p "$T/k2.partial" "$T/k3.old"
touch "$T/k2.partial/.peristatic" "$T/k2.partial/thesis.tex" "$T/k3.old/.peristatic" "$T/k3.old/thesis.tex"
expect 3 "t910_tmp/k2.partial holds files peristatic did not write (thesis.tex)" -- run -q -o "$T/k2" "$D/box.yaml"
expect 3 "t910_tmp/k3.old holds files peristatic did not write (thesis.tex)" -- run -q -o "$T/k3" "$D/box.yaml"
if [ "$(cat "$T/paper2/thesis.tex")" = important ] && [ -f "$T/keep/box.yaml" ] &&
   [ -f "$T/gkeep/delta_c500/notes.txt" ] && [ -f "$T/k2.partial/thesis.tex" ] &&
   [ -f "$T/k3.old/thesis.tex" ] && [ ! -e "$T/paper2.partial" ] && [ ! -e "$T/k2" ] && [ ! -e "$T/k3" ]; then
  ok "a folder with our marker or signature that holds other files (DIR, DIR.partial, DIR.old, a run folder): left as it was"
else
  ko "a folder of ours holding someone else's files was changed"
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

# a claim left in a finished sweep's folder (empty: its worker was killed
# before it wrote its pid; or naming a pid since reused) is stale: the
# sweep holds the lock, so it removes every claim before it starts
$P griffith -q -o "$T/claim" "$D/sweep.yaml"
rm -rf "$T/claim/delta_c500"
: > "$T/claim/delta_c500.claim"
echo 1 > "$T/claim/delta_c1000.claim"
out=$($P griffith --resume -o "$T/claim" "$D/sweep.yaml" 2>&1)
if [ $? -eq 0 ] && printf '%s' "$out" | grep -q "delta = c/1000: reusing" &&
   [ -f "$T/claim/delta_c500/summary.txt" ] && [ "$(wc -l < "$T/claim/griffith.csv")" -eq 3 ] &&
   [ -z "$(find "$T/claim" -name '*.claim')" ]; then
  ok "griffith --resume with stale claims (an empty one, one naming pid 1): removed, the run redone, the sweep completes"
else
  ko "griffith --resume with stale claims: $out"
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
touch "$T/win.old/.peristatic" "$T/win.partial/.peristatic" "$T/win.partial/particles_0099.vtu" \
  "$T/win.partial/arms.pvd" "$T/win.partial/arms_0099.vtu.tmp"
out=$($P run -v -o "$T/win" "$D/box.yaml" 2>&1)
if printf '%s' "$out" | grep -q "removing t910_tmp/win.old, left over" && [ ! -e "$T/win.old" ] &&
   [ ! -e "$T/win.partial" ] && [ ! -e "$T/win/particles_0099.vtu" ] && grep -q "^case: outdir-box" "$T/win/summary.txt"; then
  ok "a leftover DIR.old (ours) is removed (said at -v), an old DIR.partial (ours) replaced"
else
  ko "leftover DIR.old / DIR.partial: $out"
fi
# an empty DIR (a script's mkdir -p after the kill) beside DIR.old: DIR.old
# holds the only results and is restored
cp "$T/win/summary.txt" "$T/win.summary"
mv "$T/win" "$T/win.old"
mkdir "$T/win"
out=$($P run -q -o "$T/win" "$D/soft_plane_stress.yaml" 2>&1)
if printf '%s' "$out" | grep -q "t910_tmp/win was an empty folder and t910_tmp/win.old held its results.*restored t910_tmp/win" &&
   cmp -s "$T/win.summary" "$T/win/summary.txt" && [ ! -e "$T/win.old" ]; then
  ok "an empty DIR beside DIR.old (ours, with results): DIR.old restored (and said so)"
else
  ko "an empty DIR beside DIR.old: $out"
fi
# a complete result left in DIR.partial by a kill before its commit: said
# when it is replaced (an interrupted or stalled one is not)
rm -rf "$T/win.partial"
cp -r "$T/win" "$T/win.partial"
out=$($P run -q -o "$T/win" "$D/box.yaml" 2>&1)
out2=$($P run -q -o "$T/win" "$D/soft_plane_stress.yaml" 2>&1)
out3=$($P run -q -o "$T/win" "$D/box.yaml" 2>&1)
if printf '%s' "$out" | grep -q "replacing t910_tmp/win.partial, the output of an earlier run that did not complete its commit" &&
   ! printf '%s' "$out3" | grep -q "replacing"; then
  ok "a complete result in DIR.partial is reported when it is replaced; a stalled run's is not"
else
  ko "DIR.partial with a complete result: $out / $out3"
fi
# the commit exchanges DIR and DIR.partial in one step: DIR is never
# missing (renameat2 RENAME_EXCHANGE; no rename of DIR to DIR.old)
if strace -o /dev/null true 2>/dev/null; then
  strace -f -e trace=rename,renameat,renameat2 -o "$T/strace.log" $P run -q -o "$T/win" "$D/box.yaml"
  if grep -q 'renameat2(AT_FDCWD, "t910_tmp/win.partial", AT_FDCWD, "t910_tmp/win", RENAME_EXCHANGE) = 0' "$T/strace.log" &&
     ! grep -q '"t910_tmp/win", [A-Z_]*"t910_tmp/win.old"' "$T/strace.log" &&
     grep -q "^case: outdir-box" "$T/win/summary.txt" && [ ! -e "$T/win.old" ] && [ ! -e "$T/win.partial" ]; then
    ok "the commit exchanges DIR.partial and DIR atomically (renameat2 RENAME_EXCHANGE); nothing left beside DIR"
  else
    ko "the commit did not exchange the folders: $(cat "$T/strace.log")"
  fi
fi
# an earlier tree that cannot be removed after the exchange: a warning,
# the new results are in DIR (exit 0); the next run removes the leftover
if [ "$(id -u)" -eq 0 ]; then
  lockit() { chattr +i "$1" 2>/dev/null; }
  unlockit() { chattr -i "$1" 2>/dev/null; }
else
  lockit() { chmod a-w "$(dirname "$1")"; }
  unlockit() { chmod u+w "$(dirname "$1")"; }
fi
if lockit "$T/win/history.csv"; then
  out=$($P run -q -o "$T/win" "$D/box.yaml" 2>&1)
  rc=$?
  unlockit "$T/win.old/history.csv"
  if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "warning: .*cannot remove.*the results are in t910_tmp/win" &&
     [ -d "$T/win.old" ] && $P run -q -o "$T/win" "$D/box.yaml" && [ ! -e "$T/win.old" ]; then
    ok "an earlier tree that cannot be removed after the swap: a warning, exit 0; the next run removes it"
  else
    ko "an unremovable earlier tree: exit $rc, $out"
  fi
  unlockit "$T/win/history.csv"
fi

# removing an earlier tree never enters another file system mounted in it
# (nftw FTW_MOUNT): only where this test may mount a tmpfs (root)
$P griffith -q -o "$T/mnt" "$D/sweep.yaml"
rm -rf "$T/mnt/delta_c500"/*
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs none "$T/mnt/delta_c500" 2>/dev/null; then
  echo keep > "$T/mnt/delta_c500/history.csv"
  out=$($P griffith -q -o "$T/mnt" "$D/sweep.yaml" 2>&1)
  rc=$?
  kept=$(cat "$T/mnt.old/delta_c500/history.csv" 2>/dev/null)
  umount "$T/mnt.old/delta_c500" 2>/dev/null || umount "$T/mnt/delta_c500" 2>/dev/null
  if [ $rc -eq 0 ] && [ "$kept" = keep ] && printf '%s' "$out" | grep -q "warning: t910_tmp/mnt.old: cannot remove"; then
    ok "a file system mounted inside the earlier tree is not entered: its files stay (a warning, exit 0)"
  else
    ko "a mount inside the earlier tree: exit $rc, kept '$kept', $out"
  fi
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
# kill -9 during a run that writes fields: DIR.partial's particles.pvd and
# arms.pvd list the files written so far (steps 5 and 10 at least: the
# history row of step 11 follows step 10's files), all there and readable;
# arms.pvd may lack the last step when the kill fell between the two
rm -rf "$T/k9.partial"
$P run -q -t 1 -o "$T/k9" "$D/box_fields.yaml" 2>/dev/null &
bg=$!
wait_for "$T/k9.partial/history.csv" 12
kill -9 $bg
wait $bg 2>/dev/null
if series_ok "$T/k9.partial" partial && [ "$(head -n 2 "$T/series.particles" | cut -d' ' -f1 | tr '\n' ' ')" = "5 10 " ]; then
  ok "kill -9 of a run: DIR.partial's .pvd files list steps $(cut -d' ' -f1 "$T/series.particles" | tr '\n' ' ')(files that exist and read)"
else
  ko "kill -9 of a run: the time series in DIR.partial: $why"
fi
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

# a signal during the set-up (before any output): run and griffith end
# with 143 and write nothing; info takes the default action (it looks at
# no flag)
$P griffith -q -o "$T/bsig" "$D/big_setup.yaml" 2> "$T/bsig.err" &
bg=$!
sleep 0.3
kill -TERM $bg
wait $bg
rc=$?
if [ $rc -eq 143 ] && grep -q "big_setup.yaml: interrupted by SIGTERM during the set-up; nothing was written" "$T/bsig.err" &&
   [ ! -e "$T/bsig" ] && [ ! -e "$T/bsig.partial" ] && [ ! -e "$T/bsig.lock" ]; then
  ok "SIGTERM during the set-up: exit 143, 'interrupted by SIGTERM during the set-up; nothing was written', no folder"
else
  ko "SIGTERM during the set-up: exit $rc, $(cat "$T/bsig.err")"
fi
$P info "$D/big_setup.yaml" > "$T/info.out" 2> "$T/info.err" &
bg=$!
sleep 0.3
kill -TERM $bg
wait $bg 2>/dev/null
rc=$?
if [ $rc -eq 143 ] && [ ! -s "$T/info.err" ] && ! grep -q "^pattern_s" "$T/info.out"; then
  ok "SIGTERM during info: it ends at once (the default action; no handler that nothing checks)"
else
  ko "SIGTERM during info: exit $rc, $(cat "$T/info.err")"
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
# no earlier results to speak of when DIR does not exist
out=$($P run -q -o "$T/nopeak" "$D/no_peak.yaml" 2>&1)
if [ ! -e "$T/nopeak" ] && printf '%s' "$out" | grep -q "(this run's partial output is in t910_tmp/nopeak.partial)" &&
   ! printf '%s' "$out" | grep -q "earlier results"; then
  ok "a failed run into a new DIR does not speak of earlier results in DIR"
else
  ko "a failed run into a new DIR: $out"
fi
if grep -q "^sigma_failure_Pa: n/a" "$T/nopeak.partial/summary.txt" &&
   ! grep -qiE 'nan|inf' "$T/nopeak.partial/summary.txt" "$T/nopeak.partial/history.csv" "$T/soft.partial/summary.txt"; then
  ok "no settled peak: summary.txt says n/a, no nan or inf"
else
  ko "nan or inf in summary.txt or history.csv"
fi

# 8. --resume reads summary.txt defensively: a value out of range, a NaN
# delta and an over-long line are no match (the run is redone), CRLF line
# ends read as LF
$P griffith -q -o "$T/rd" "$D/sweep.yaml"
reuse_of() { # reuse_of EDIT: griffith --resume after EDIT of delta_c500/summary.txt; 1 when reused
  cp "$T/rd/delta_c500/summary.txt" "$T/rd.summary"
  eval "$1"
  out=$($P griffith --resume -o "$T/rd" "$D/sweep.yaml" 2>&1) || { echo "failed: $out"; return; }
  printf '%s' "$out" | grep -q "delta = c/500: reusing" && echo 1 || echo 0
}
f="$T/rd/delta_c500/summary.txt"
r1=$(reuse_of "sed -i 's/^particles: .*/particles: 1e300/' $f")
r2=$(reuse_of "sed -i 's/^delta_m: .*/delta_m: n\/a/' $f")
# (fgets reads 511 characters at a time: the tail of this line would read as particles: 12)
r3=$(reuse_of "{ printf 'case: %0505d%s\\n' 0 'particles: 12'; cat $T/rd.summary; } > $f")
row=$(grep '^0.002,' "$T/rd/griffith.csv" | cut -d, -f1-5)
r4=$(reuse_of "sed -i 's/\$/\r/' $f")
if [ "$r1" = 0 ] && [ "$r2" = 0 ]; then
  ok "--resume: particles: 1e300 (out of range) and delta_m: n/a (NaN) are no match: the run is redone"
else
  ko "--resume: particles: 1e300 reused ($r1), delta_m: n/a reused ($r2)"
fi
if [ "$r4" = 1 ] && [ "$(grep '^0.002,' "$T/rd/griffith.csv" | cut -d, -f1-5)" = "$row" ]; then
  ok "--resume: a summary.txt with CRLF line ends is reused and read right (fractured: yes stays yes)"
else
  ko "--resume with CRLF: reused $r4, row $(grep '^0.002,' "$T/rd/griffith.csv") (want $row)"
fi
if [ "$r3" = 1 ]; then
  ok "--resume: the tail of an over-long line is not read as a key"
else
  ko "--resume with an over-long line: reused $r3"
fi

# 9. paths: an output folder too long for what is written inside it is
# refused before anything is created
long="$T/long/$(printf '%0950d' 0)"
expect 1 "output directory 't910_tmp/long/0000.*is too long (964 characters; at most 900" -- run -q -o "$long" "$D/box.yaml"
if [ ! -e "$T/long" ]; then
  ok "a too-long -o: nothing created"
else
  ko "a too-long -o created folders"
fi

rm -rf "$T"
rm -f INJECTED
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
