#!/bin/sh
# t915_restart.sh: checkpoints and run --restart. A run stopped after k
# increments (path.max_increments, or SIGINT) and restarted from its
# checkpoint gives the uninterrupted run's history.csv (all columns but
# the wall time), particles.csv and summary.txt counts to the last bit:
# under load control with yielding and breaking arms (a small disk),
# arc-length control past a limit load (a perforated plate), dissipation
# control of softening arms (a notched plate), event control of brittle
# arms (the same plate: the restart falls between an event and the
# breaking of its arms) and path.steps with named entries' reactions (a
# box). A checkpoint of
# another case, a damaged one and a truncated one are refused (exit 1)
# with the folder left as it was; output.checkpoint: false writes none.
srcdir=${srcdir:-.}
D="$srcdir/tests/data/restart"
P=./peristatic
T=t915_tmp
OMP_THREAD_LIMIT=${OMP_THREAD_LIMIT:-1}
export OMP_THREAD_LIMIT
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T"
mkdir -p "$T"

# history.csv without its wall_s column
no_wall() { drop_columns "$1" wall_s; }
# summary.txt without times, memory and threads
counts() { grep -v '_s:\|_MiB:\|^threads:' "$1"; }
# same A B WHAT: the outputs of runs A and B are identical
same() {
  no_wall "$1/history.csv" > "$T/a.csv"
  no_wall "$2/history.csv" > "$T/b.csv"
  counts "$1/summary.txt" > "$T/a.txt"
  counts "$2/summary.txt" > "$T/b.txt"
  if cmp -s "$T/a.csv" "$T/b.csv" && cmp -s "$1/particles.csv" "$2/particles.csv" &&
     cmp -s "$T/a.txt" "$T/b.txt"; then
    ok "$3: history.csv (but wall_s), particles.csv and summary.txt's counts are the uninterrupted run's"
  else
    ko "$3: differs from the uninterrupted run ($(cmp "$T/a.csv" "$T/b.csv" 2>&1 | head -1);" \
       "$(cmp "$1/particles.csv" "$2/particles.csv" 2>&1 | head -1); $(diff "$T/a.txt" "$T/b.txt" | head -3))"
  fi
}
# cut CASE K NAME: CASE with path.max_increments K as $T/NAME.yaml
cut_case() {
  if grep -q 'max_increments:' "$1"; then
    sed "s/max_increments: [0-9]*/max_increments: $2/" "$1" > "$T/$3.yaml"
  else
    sed "s/max_load: 3.0}/max_load: 3.0, max_increments: $2}/" "$1" > "$T/$3.yaml"
  fi
}

# 1. stopped by path.max_increments at k and restarted with the full case
# (max_increments may differ): load, arc-length, dissipation and event
# control, path.steps
for c in disk:13 arc:17 soft:20 event:19 steps:5; do
  name=${c%%:*}
  k=${c#*:}
  $P run -q -t 1 -o "$T/$name-full" "$D/$name.yaml" || ko "$name: the uninterrupted run failed"
  cut_case "$D/$name.yaml" "$k" "$name-cut"
  if $P run -q -t 1 -o "$T/$name" "$T/$name-cut.yaml" &&
     [ "$(($(wc -l < "$T/$name/history.csv") - 1))" -eq "$k" ] &&
     [ -f "$T/$name/checkpoint.bin" ] && $P run -q -t 1 --restart "$T/$name" -o "$T/$name" "$D/$name.yaml"; then
    same "$T/$name-full" "$T/$name" "$name.yaml stopped at $k increments, restarted"
  else
    ko "$name.yaml: the run cut at $k increments or its restart failed"
  fi
done

# 2. a restart of a restart, into another folder, on two threads
cut_case "$D/disk.yaml" 9 disk-9
cut_case "$D/disk.yaml" 22 disk-22
if $P run -q -t 1 -o "$T/chain" "$T/disk-9.yaml" &&
   $P run -q -t 2 --restart "$T/chain" -o "$T/chain" "$T/disk-22.yaml" &&
   $P run -q -t 2 --restart "$T/chain" -o "$T/chain2" "$D/disk.yaml"; then
  same "$T/disk-full" "$T/chain2" "disk.yaml cut at 9, restarted to 22, restarted into another folder (-t 2)"
  fields_same=1
  for f in "$T"/disk-full/*.vtu "$T"/disk-full/*.pvd; do
    cmp -s "$f" "$T/chain2/${f##*/}" || fields_same=0
  done
  if [ $fields_same -eq 1 ] && [ -f "$T/chain2/particles_0020.vtu" ] &&
     [ ! -e "$T/chain2/particles_0022.vtu" ] &&
     [ "$(ls "$T/disk-full")" = "$(ls "$T/chain2")" ]; then
    ok "the restart's field files and .pvd series are the uninterrupted run's (step 20 kept, the cut run's final 22 not)"
  else
    ko "field files after a restart: $(ls "$T/chain2" | tr '\n' ' ')"
  fi
else
  ko "disk.yaml: a restart of a restart failed"
fi

# 3. SIGINT: the partial output holds the last checkpoint; --restart
# continues from DIR.partial
$P run -q -t 1 -o "$T/sig" "$D/disk.yaml" 2> "$T/sig.err" &
pid=$!
n=0
while [ $n -lt 300 ] && ! { [ -f "$T/sig.partial/history.csv" ] &&
      [ "$(wc -l < "$T/sig.partial/history.csv")" -ge 10 ]; }; do
  sleep 0.05
  n=$((n + 1))
done
kill -INT $pid 2>/dev/null
wait $pid
rc=$?
if [ $rc -eq 130 ] && grep -q -- "--restart $T/sig continues it" "$T/sig.err" &&
   [ -f "$T/sig.partial/checkpoint.bin" ]; then
  ok "SIGINT after $(($(wc -l < "$T/sig.partial/history.csv") - 1)) increments: exit 130, the message names --restart"
  if $P run -q -t 1 --restart "$T/sig" -o "$T/sig" "$D/disk.yaml"; then
    same "$T/disk-full" "$T/sig" "disk.yaml interrupted by SIGINT, restarted from sig.partial"
  else
    ko "the restart after SIGINT failed"
  fi
elif [ $rc -eq 0 ]; then
  ok "SIGINT: the run ended before the signal (nothing to restart)"
else
  ko "SIGINT: exit $rc, $(cat "$T/sig.err")"
fi

# 3b. output.checkpoint: false writes no checkpoint, neither on the way
# nor at the end, and changes no result
sed 's/checkpoint_every: 4}/checkpoint_every: 4, checkpoint: false}/' "$D/disk.yaml" > "$T/nockpt.yaml"
if grep -q 'checkpoint: false' "$T/nockpt.yaml" && $P run -q -t 1 -o "$T/nockpt" "$T/nockpt.yaml" &&
   [ ! -e "$T/nockpt/checkpoint.bin" ]; then
  same "$T/disk-full" "$T/nockpt" "output.checkpoint: false (no checkpoint.bin)"
else
  ko "output.checkpoint: false: the run failed or wrote a checkpoint"
fi

# 4. refusals, the folder left as it was
cut_case "$D/disk.yaml" 6 disk-6
$P run -q -t 1 -o "$T/ref" "$T/disk-6.yaml"
sed 's/E: 210.0e9/E: 200.0e9/' "$D/disk.yaml" > "$T/other.yaml"
snap() { (cd "$T/ref" && ls -lA --time-style=+%s && cat checkpoint.bin history.csv | cksum); }
snap > "$T/before"
expect 1 "checkpoint.bin was written for another case: its material settings differ" -- run -q --restart "$T/ref" -o "$T/ref" "$T/other.yaml"
sed 's/max_load: 3.0}/max_load: 3.0}\nsolver: {cg_max_iterations: 20}/' "$D/disk.yaml" > "$T/other_cg.yaml"
expect 1 "written for another case: its solver settings differ" -- run -q --restart "$T/ref" -o "$T/ref" "$T/other_cg.yaml"
snap > "$T/after"
if cmp -s "$T/before" "$T/after"; then ok "refused restarts leave the folder as it was"; else ko "a refused restart changed $T/ref"; fi
cp "$T/ref/checkpoint.bin" "$T/good.bin"
size=$(wc -c < "$T/good.bin")
printf 'X' | dd of="$T/ref/checkpoint.bin" bs=1 seek=$((size / 2)) conv=notrunc 2>/dev/null
expect 1 "checkpoint.bin is truncated or corrupt" -- run -q --restart "$T/ref" -o "$T/ref" "$D/disk.yaml"
head -c $((size - 100)) "$T/good.bin" > "$T/ref/checkpoint.bin"
expect 1 "checkpoint.bin is truncated or corrupt" -- run -q --restart "$T/ref" -o "$T/ref" "$D/disk.yaml"
head -c 20 "$T/good.bin" > "$T/ref/checkpoint.bin"
expect 1 "checkpoint.bin is truncated or corrupt" -- run -q --restart "$T/ref" -o "$T/ref" "$D/disk.yaml"
if head -c 20 "$T/good.bin" | cmp -s - "$T/ref/checkpoint.bin"; then
  ok "a refused checkpoint stays as it was"
else
  ko "a refused checkpoint changed"
fi
# named entries are not in the fingerprint, but they are history.csv's columns
sed 's/name: right/name: grip/' "$D/steps.yaml" > "$T/renamed.yaml"
expect 1 "history.csv has other columns than" -- run -q --restart "$T/steps" -o "$T/steps" "$T/renamed.yaml"
expect 1 "no-such/checkpoint.bin: cannot read" -- run -q --restart "$T/no-such" -o "$T/x" "$D/disk.yaml"
expect 1 "restart is an option of run" -- griffith -q --restart "$T/ref" "$D/disk.yaml"

rm -rf "$T"
summary
