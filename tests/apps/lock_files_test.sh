#!/usr/bin/env bash
# Output folders on a file system without flock (flock refused with
# ENOLCK by a preloaded library, as on Lustre mounted noflock): the refusal
# is said once, the lock is taken with O_EXCL files that are removed at
# the end, a second writer and a stale lock (its holder killed) are
# refused naming their holder, --break-lock clears a stale one, and the
# shards of an audit share the folder.
#   lock_files_test.sh <wearscar> <flock_refused.so> <source dir> <scratch>
set -euo pipefail
wearscar=$1 shim=$2 src=$3 scratch=$4
rm -rf "$scratch"
mkdir -p "$scratch"
fail() { echo "FAILED: $*"; exit 1; }
# (an ASan build wants its runtime first; the shim only replaces flock)
export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0
run() { LD_PRELOAD=$shim "$wearscar" "$@"; }
force=$src/samples/data/B-RT-R.force.csv
out=$scratch/fuse

run force "$force" -o "$out" --no-figures --no-lugre --quiet 2> "$scratch/said" ||
  fail "force without flock: $(cat "$scratch/said")"
grep -q "$out: the file system refuses flock (No locks available; a Lustre or NFS mount without locks?): locking with files created with O_EXCL" "$scratch/said" ||
  fail "the refusal not said: $(cat "$scratch/said")"
test ! -e "$out/.wearscar.lock.held" || fail "the lock file left after the run"
test -f "$out/cycles.csv" || fail "no cycles.csv"
echo "no flock: said, locked with a file, removed at the end"

# A live holder (this shell) and a stale one (a process that has ended).
echo "$(hostname) $$ $(date +%s)" > "$out/.wearscar.lock.held"
status=0; run force "$force" -o "$out" --no-figures --no-lugre --quiet 2> "$scratch/said" || status=$?
test $status = 2 || fail "a live holder: exit $status"
grep -q "another wearscar is writing into this folder: $out/.wearscar.lock.held (wearscar pid $$ on $(hostname) since" "$scratch/said" ||
  fail "a live holder: $(cat "$scratch/said")"
sh -c 'exit 0' & dead=$!; wait $dead
echo "$(hostname) $dead 1700000000" > "$out/.wearscar.lock.held"
status=0; run force "$force" -o "$out" --no-figures --no-lugre --quiet 2> "$scratch/said" || status=$?
test $status = 2 || fail "a stale lock: exit $status"
grep -q "a stale lock: $out/.wearscar.lock.held (wearscar pid $dead on $(hostname) since 2023-11-14 22:13:20 UTC) is no longer running (killed?); expected no lock (--break-lock removes it)" "$scratch/said" ||
  fail "a stale lock: $(cat "$scratch/said")"
run force "$force" -o "$out" --no-figures --no-lugre --quiet --break-lock 2> /dev/null ||
  fail "--break-lock did not clear the stale lock"
test ! -e "$out/.wearscar.lock.held" || fail "the lock file left after --break-lock"
echo "a live holder and a stale lock refused, named; --break-lock clears the stale one"

# Shards at once share the folder; the merge is one at a time.
samples=$src/samples/data
audit=$scratch/audit
pids=()
for i in 1 2 3; do
  run audit "$samples" -o "$audit" --shard "$i/3" -j 1 --no-figures --quiet 2>> "$scratch/shards" &
  pids+=($!)
done
for pid in "${pids[@]}"; do wait "$pid" || fail "a shard failed: $(cat "$scratch/shards")"; done
run audit --merge "$audit" --no-figures --quiet 2> /dev/null || fail "the merge failed"
test "$(wc -l < "$audit/summary.csv")" = 13 || fail "the shards' summary: $(wc -l < "$audit/summary.csv") lines"
ls -a "$audit" | grep -q '^\.wearscar\.\(merge\.\)\?lock\.\(held\|shard\)' &&
  fail "lock files left: $(ls -a "$audit")"
# A shard killed leaves its file: an unsharded audit is then refused as
# stale until --break-lock.
echo "$(hostname) $dead 1700000000" > "$audit/.wearscar.lock.shard-$(hostname)-$dead"
status=0; run audit "$samples" -o "$audit" --no-figures --quiet 2> "$scratch/said" || status=$?
test $status = 2 || fail "an audit over a killed shard's lock: exit $status"
grep -q "a stale lock: $audit/.wearscar.lock.shard-" "$scratch/said" || fail "$(cat "$scratch/said")"
run audit "$samples" -o "$audit" --no-figures --quiet --break-lock 2> /dev/null || fail "--break-lock on the audit"
echo "three shards at once without flock: 12 rows; a killed shard's lock stale until --break-lock"
