#!/usr/bin/env bash
# The Slurm recipe (examples/slurm/submit.sh and audit.sbatch) run as Slurm
# would run it, with a stand-in sbatch (fake_slurm/sbatch) on the bundled
# samples: arrays numbered from 0, from 1 and by steps, more tasks than
# specimens, a task killed with SIGKILL and re-run alone, a re-run of two
# tasks; each ends with the rows a single audit writes, and the merge job
# fails (exit 3) exactly while a shard is missing.
#   slurm_test.sh <wearscar> <source dir> <scratch dir>
set -euo pipefail
wearscar=$1 src=$2 scratch=$3
rm -rf "$scratch"
mkdir -p "$scratch"
export WEARSCAR=$wearscar FAKE_SLURM_DIR=$scratch/slurm
export PATH="$src/tests/apps/fake_slurm:$PATH"
samples=$src/samples/data
submit=$src/examples/slurm/submit.sh
fail() { echo "FAILED: $*"; exit 1; }
# summary.csv's rows sorted, without the date of the run (the last column).
rows() { sed 's/,[^,]*$//' "$1/summary.csv" | { read -r header; echo "$header"; sort; }; }
merge_status() { cat "$FAKE_SLURM_DIR/$(cat "$FAKE_SLURM_DIR/next").status"; }

"$wearscar" audit "$samples" -o "$scratch/single" --no-figures --quiet
rows "$scratch/single" > "$scratch/single.rows"
test "$(wc -l < "$scratch/single.rows")" -eq 13 || fail "the single audit has no 12 rows"

# Every numbering of an array, and more tasks than specimens.
for array in 0-3 1-4 0-9:3 1-16; do
  out=$scratch/audit-${array//[:]/by}
  said=$("$submit" "$samples" "$out" "$array" --partition=test --no-figures)
  grep -q "^audit: array job [0-9]* ($array), merge job [0-9]*$" <<< "$said" ||
    fail "$array: submit.sh printed: $said"
  test "$(merge_status)" = 0 || fail "$array: the merge job failed"
  rows "$out" | cmp -s - "$scratch/single.rows" ||
    fail "$array: rows differ from the single audit's: $(rows "$out" | diff - "$scratch/single.rows" | head -5)"
  shards=$(ls "$out/parts" | grep -c '^shard-')
  case $array in
    0-3|1-4|0-9:3) test "$shards" = 4 || fail "$array: $shards parts" ;;
    1-16) test "$shards" = 16 || fail "$array: $shards parts (empty ones too)" ;;
  esac
  echo "--array=$array: $shards parts, the single audit's 12 rows, merge exit 0"
done
grep -q '"first":0,"shards":4,"step":3' "$scratch/audit-0-9by3/parts/plan.json" ||
  fail "the stepped array's plan: $(cat "$scratch/audit-0-9by3/parts/plan.json")"

# A task killed mid-run: the merge job says which shard is missing and
# fails; nothing of the killed shard's part is there. Re-run alone (its
# array has one task, numbered 2), it is the same shard, and a merge
# completes the audit.
out=$scratch/audit-killed
FAKE_SLURM_KILL=2 "$submit" "$samples" "$out" 0-3 --no-figures > /dev/null
test "$(merge_status)" = 3 || fail "the merge with a shard killed exited $(merge_status)"
grep -q "1 of 4 shards missing (3)" "$FAKE_SLURM_DIR/$(cat "$FAKE_SLURM_DIR/next").log" ||
  fail "the merge's log: $(cat "$FAKE_SLURM_DIR/$(cat "$FAKE_SLURM_DIR/next").log")"
test ! -e "$out/parts/shard-3-of-4.json" || fail "the killed task wrote its part"
ls -a "$out/parts" | grep -q '\.tmp' && fail "a temporary part left: $(ls -a "$out/parts")"
sbatch --array=2 "$src/examples/slurm/audit.sbatch" "$samples" "$out" --no-figures > /dev/null
grep -q "shard 3 of 4 (index 2; 4 shards, indices from 0, the plan of Slurm array job" \
  "$FAKE_SLURM_DIR/$(cat "$FAKE_SLURM_DIR/next")_2.log" ||
  fail "the re-run: $(cat "$FAKE_SLURM_DIR/$(cat "$FAKE_SLURM_DIR/next")_2.log")" 
"$wearscar" audit --merge "$out" --no-figures --quiet || fail "the merge after the re-run exited $?"
rows "$out" | cmp -s - "$scratch/single.rows" || fail "rows after the re-run differ"
echo "a task killed: merge exit 3 naming shard 3; re-run as --array=2: the single audit's rows"

# Two tasks re-run as a list (--array=1,3) follow the plan too.
out=$scratch/audit-0-3
rm "$out/parts/shard-2-of-4.json" "$out/parts/shard-4-of-4.json"
sbatch --array=1,3 "$src/examples/slurm/audit.sbatch" "$samples" "$out" --no-figures > /dev/null
"$wearscar" audit --merge "$out" --no-figures --quiet || fail "the merge after --array=1,3 exited $?"
rows "$out" | cmp -s - "$scratch/single.rows" || fail "rows after --array=1,3 differ"
echo "--array=1,3 re-run: shards 2 and 4 of the plan, the single audit's rows"
