#!/usr/bin/env bash
# `wearscar watch` following tests while a replayer (replay.py) writes them
# as a tribometer's software does (blocks flushed at 50x real time, each
# cut inside a row): every cycle reported once, the verdict alert on S-RL-R
# and the hook run for it, the
# final products those of `wearscar fuse` on the finished file (but for
# the date), a file truncated for a new test followed from its start, a
# writer killed mid-row, Ctrl-C, and a test written as a file per block
# (--pattern), with its clock continuing or starting again in each. (How soon each cycle is reported, and
# the watch's CPU and memory: scripts/measure-watch.)
#   watch_test.sh <wearscar> <source dir> <scratch dir>
set -euo pipefail
wearscar=$1 src=$2 scratch=$3
rm -rf "$scratch"
mkdir -p "$scratch"
cd "$scratch"
replay() { python3 "$src/tests/apps/replay.py" "$@"; }
fail() { echo "FAILED: $*"; exit 1; }
# Waits (up to 60 s) until the watch has reported a cycle into $1: what
# follows must not race a loaded machine.
wait_for_a_cycle() {
  for _ in $(seq 600); do
    [ "$(wc -l < "$1" 2> /dev/null || echo 0)" -ge 2 ] && return 0
    sleep 0.1
  done
  fail "no cycle reported into $1 within 60 s"
}
# The products of a watch (DIR $1) and of fuse (DIR $2): the same files, the
# same bytes but for result.json's and the page's date.
same_products() {
  for f in "$2"/*; do
    name=$(basename "$f")
    [ -f "$1/$name" ] || fail "$1 lacks $name"
    if [ "$name" = report.html ]; then  # the page says when it was made
      undated() { sed -E 's/[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:]{8}Z/DATE/g' "$1"; }
      cmp -s <(undated "$f") <(undated "$1/$name") ||
        fail "$1/report.html differs from fuse's: $(diff <(undated "$f") <(undated "$1/$name") | head -5)"
    elif [ "$name" = result.json ]; then
      cmp -s <(grep -v '"date_utc"' "$f") <(grep -v '"date_utc"' "$1/$name") ||
        fail "$1/result.json differs from fuse's: $(diff <(grep -v date_utc "$f") <(grep -v date_utc "$1/$name") | head -5)"
    else
      cmp -s "$f" "$1/$name" || fail "$1/$name differs from fuse's"
    fi
  done
}
"$wearscar" simulate --case S-RL-R --case B-RT-R --cycles 120 --formats csv \
  -o sim > /dev/null

# 1. S-RL-R written at 50x real time (2.4 s).
replay sim/S-RL-R.force.csv live.csv replay.log --speed 50 &
writer=$!
"$wearscar" watch live.csv -o out --idle 3 --no-figures \
  --on-alert 'echo "$WEARSCAR_ALERT $WEARSCAR_CYCLE" >> alerts.txt' \
  > watch.txt 2> watch.err || fail "watch: $(tail -3 watch.err)"
wait $writer
cmp -s live.csv sim/S-RL-R.force.csv || fail "the replayer wrote another file"
test "$(tail -n +2 out/live/cycles.csv | wc -l)" = 120 ||
  fail "$(tail -n +2 out/live/cycles.csv | wc -l) cycles reported, expected 120"
grep '"kind":"verdict".*not explained by wear-scar interaction' out/events.jsonl |
  grep -q '"good":false' ||
  fail "no verdict alert (a warning): $(cat out/events.jsonl)"
grep -q '^verdict [0-9]' alerts.txt || fail "the hook did not run: $(cat alerts.txt)"
grep -q '^idle 120$' alerts.txt || fail "no idle alert: $(cat alerts.txt)"
grep -q 'has not grown for 3 s: the writer stopped' watch.err ||
  fail "idle not said: $(cat watch.err)"
"$wearscar" fuse live.csv -o fused --no-figures --quiet
same_products out fused
echo "S-RL-R: verdict alert, hook, idle end, products identical to fuse's"

# 2. A test stopped mid-row, then the file truncated and a new test written.
replay sim/B-RT-R.force.csv live2.csv r2.log --speed 50 --kill-at 40 &
writer=$!
"$wearscar" watch live2.csv -o out2 --idle 3 --no-figures > w2.txt 2> w2.err &
watcher=$!
wait $writer
wait_for_a_cycle out2/live/cycles.csv
sleep 0.5
replay sim/S-RL-R.force.csv live2.csv r3.log --speed 50
wait $watcher || fail "watch after a truncation: $(tail -3 w2.err)"
grep -q 'live2.csv: truncated' w2.err || fail "truncation not said: $(cat w2.err)"
grep -q '"kind":"restart"' out2/events.jsonl || fail "no restart event"
test "$(sed -n 2p out2/live/cycles.csv | cut -d, -f1)" = 1 ||
  fail "the new test is not numbered from cycle 1"
test "$(sed -n 2p out2/live/cycles.before-1.csv | cut -d, -f1)" = 1 ||
  fail "the first test's cycles were not kept"
"$wearscar" fuse live2.csv -o fused2 --no-figures --quiet
same_products out2 fused2
echo "truncated for a new test: said, followed from its start"

# 3. The writer killed mid-row for good: the products of what was written.
replay sim/S-RL-R.force.csv live3.csv r4.log --speed 100 --kill-at 50
"$wearscar" watch live3.csv -o out3 --idle 1 --no-figures > w3.txt 2> w3.err ||
  fail "watch of a cut file: $(tail -3 w3.err)"
grep -q 'the last row is cut and was dropped' w3.txt ||
  fail "the cut row is not said: $(cat w3.txt | head)"
"$wearscar" fuse live3.csv -o fused3 --no-figures --quiet
same_products out3 fused3
echo "killed mid-row: the cut row said, products identical to fuse's"

# 4. Ctrl-C while the test runs.
replay sim/B-RT-R.force.csv live4.csv r5.log --speed 20 &
writer=$!
"$wearscar" watch live4.csv -o out4 --idle 30 --no-figures > w4.txt 2> w4.err &
watcher=$!
wait_for_a_cycle out4/live/cycles.csv
kill -INT $watcher
wait $watcher || fail "watch after Ctrl-C: $(tail -3 w4.err)"
kill $writer 2> /dev/null || true
wait $writer 2> /dev/null || true
grep -q '^interrupted' w4.txt || fail "the interruption is not said"
test -s out4/result.json || fail "no products after Ctrl-C"
grep -q 'is still being written: the products are of its' w4.txt ||
  fail "the copy at the stop is not said: $(cat w4.txt | tail -3)"
cmp -s out4/live/live4.csv.at-stop <(head -c "$(stat -c %s out4/live/live4.csv.at-stop)" sim/B-RT-R.force.csv) ||
  fail "the copy at the stop is not the file's first bytes"
echo "Ctrl-C: the products of what was written"

# 5. A file per block (--pattern): B-RT-R (121 s) as thirteen files of 10 s of the
#    test each, the last 1 s (run_10 after run_9), each starting with the
#    header; joined, they are the blocks one after the other, and the
#    cycles those of the test's file. Then with each block's clock starting
#    at 0: the same cycles at the same times, the same products.
mkdir blocks restarting
replay sim/B-RT-R.force.csv 'blocks/run_{}.csv' r6.log --speed 50 --split 10 &
writer=$!
"$wearscar" watch blocks --pattern 'run_*.csv' -o out5 --idle 3 --no-figures \
  > w5.txt 2> w5.err || fail "watch of blocks: $(tail -3 w5.err)"
wait $writer
test "$(ls blocks | wc -l)" = 13 || fail "$(ls blocks | wc -l) blocks written, expected 13"
test "$(tail -n +2 out5/live/cycles.csv | wc -l)" = 120 ||
  fail "$(tail -n +2 out5/live/cycles.csv | wc -l) cycles reported of the blocks, expected 120"
cmp -s out5/live/blocks.joined.csv <(for k in $(seq 13); do cat "blocks/run_$k.csv"; done) ||
  fail "the blocks joined are not the blocks one after the other"
grep -q 'block run_9.csv finished; block run_10.csv started' w5.err ||
  fail "the blocks' order is not said: $(grep block w5.err | head -3)"
grep -q '"kind":"restart"' out5/events.jsonl && fail "a new block taken for a new test"
"$wearscar" fuse out5/live/blocks.joined.csv --name blocks -o fused5 --no-figures --quiet
same_products out5 fused5
"$wearscar" fuse sim/B-RT-R.force.csv -o fused-whole --no-figures --quiet
cmp -s out5/cycles.csv fused-whole/cycles.csv || fail "the blocks' cycles are not the test's"
replay sim/B-RT-R.force.csv 'restarting/run_{}.csv' r7.log --speed 50 --split 10 \
  --restart-clock &
writer=$!
"$wearscar" watch restarting --pattern 'run_*.csv' -o out6 --idle 3 --no-figures \
  > w6.txt 2> w6.err || fail "watch of restarting blocks: $(tail -3 w6.err)"
wait $writer
test "$(sed -n 2p restarting/run_2.csv | cut -d, -f1)" = 0.000000 ||
  fail "block 2's clock does not start at 0: $(sed -n 2p restarting/run_2.csv)"
# (the cycles and their times; a live mu-hat depends on what had arrived)
cmp -s <(cut -d, -f1-2 out5/live/cycles.csv) <(cut -d, -f1-2 out6/live/cycles.csv) ||
  fail "restarting clocks gave other cycles: $(diff out5/live/cycles.csv out6/live/cycles.csv | head -3)"
cmp -s out5/cycles.csv out6/cycles.csv || fail "restarting clocks gave other products"
# The folder given as "blocks/" (or "."): the joining and the specimen
# still take its name.
(cd blocks && "$wearscar" watch ./ --pattern 'run_*.csv' -o ../out9 --idle 1 \
  --no-figures --quiet > /dev/null 2>&1) || fail "watch ./ of blocks"
test -f out9/live/blocks.joined.csv || fail "$(ls out9/live)"
grep -q '"specimen": "blocks"' out9/result.json || fail "the specimen is not named for its folder"
# A folder without --pattern, and --pattern with a file: refused, the fix said.
status=0
"$wearscar" watch blocks -o out7 > /dev/null 2> w7.err || status=$?
test "$status" = 2 || fail "a folder without --pattern: exit $status, expected 2"
grep -q "blocks is a folder: give --pattern" w7.err || fail "$(cat w7.err)"
status=0
"$wearscar" watch sim/B-RT-R.force.csv --pattern 'run_*.csv' -o out8 \
  > /dev/null 2> w8.err || status=$?
test "$status" = 2 || fail "--pattern with a file: exit $status, expected 2"
grep -q "is not a folder (the blocks' folder is expected)" w8.err || fail "$(cat w8.err)"
echo "a file per block: joined into the test's file, its clock continuing or restarting"
