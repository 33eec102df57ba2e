#!/usr/bin/env bash
# The live page of `wearscar watch --port 0` in headless Chromium while a
# replayer writes S-RL-R at 10x real time: one load of the page sees the
# cycles grow over several of its updates (no reload), and shows the
# verdict's alert.
#   watch_page_test.sh <wearscar> <source dir> <scratch dir>
set -euo pipefail
wearscar=$1 src=$2 scratch=$3
if ! command -v chromium > /dev/null 2>&1; then
  echo "skipped: Debian's chromium is not installed (scripts/install-deps test)"
  exit 77
fi
rm -rf "$scratch"
mkdir -p "$scratch"
cd "$scratch"
fail() { echo "FAILED: $*"; exit 1; }
"$wearscar" simulate --case S-RL-R --cycles 120 --formats csv -o sim > /dev/null
python3 "$src/tests/apps/replay.py" sim/S-RL-R.force.csv live.csv replay.log \
  --speed 10 &
writer=$!
"$wearscar" watch live.csv -o out --idle 2 --no-figures --port 0 \
  > watch.txt 2> watch.err &
watcher=$!
trap 'kill $writer $watcher 2> /dev/null || true' EXIT
url=
for _ in $(seq 50); do
  url=$(grep -ao 'http://127.0.0.1:[0-9]*/' watch.err || true)
  [ -n "$url" ] && break
  sleep 0.1
done
[ -n "$url" ] || fail "no address said: $(cat watch.err)"
sleep 4  # past cycle 20, the verdict's first
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$scratch/profile" --virtual-time-budget=4000 \
  --dump-dom "$url" > dom.html 2> /dev/null
seen=$(grep -o 'data-cycles-seen="[^"]*"' dom.html | cut -d'"' -f2)
[ -n "$seen" ] || fail "the page never updated: $(grep -o 'id="status">[^<]*' dom.html)"
python3 - "$seen" <<'PY' || fail "the page did not follow the cycles: $seen"
import sys
seen = [int(v) for v in sys.argv[1].split(",")]
assert len(seen) >= 4, f"{len(seen)} updates"
assert all(b >= a for a, b in zip(seen, seen[1:])), "cycles went back"
assert seen[-1] > seen[0], "no new cycle while the page was open"
print(f"one load of the page: {len(seen)} updates, cycles {seen[0]} to {seen[-1]}")
PY
grep -q 'class="alert-verdict">cycle 20 · verdict: over cycles 1-20' dom.html ||
  fail "no verdict alert on the page"
grep -q '<div id="verdict">verdict over cycles' dom.html ||
  fail "no verdict line on the page"
wait $writer
wait $watcher
trap - EXIT
echo "the live page: updated without reload, the verdict's alert shown"
