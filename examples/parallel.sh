#!/usr/bin/env bash
# Audits a folder (or a manifest) as N shards at once with GNU parallel,
# then merges them into one summary and report. The shards run on this
# machine, or on several over ssh when they share the input and the output
# folder (PARALLEL_HOSTS, GNU parallel's --sshlogin list; ":" is this
# machine). Without GNU parallel, xargs -P runs them here.
#
#   examples/parallel.sh INPUT OUT [N [AUDIT OPTIONS...]]
#   examples/parallel.sh lab/ audit 4 -j 1 --no-figures
#   PARALLEL_HOSTS=":,node1,node2" examples/parallel.sh /nfs/lab /nfs/audit 12
#
# $WEARSCAR names the command (default: wearscar on the PATH). Exit status:
# the worst of the shards' and the merge's (3: some specimen failed).
set -uo pipefail
if [ $# -lt 2 ]; then
  sed -n '2,14p' "$0" >&2
  exit 2
fi
input=$1 out=$2 n=${3:-4}
shift $(( $# < 3 ? $# : 3 ))
wearscar=${WEARSCAR:-wearscar}
status=0
if command -v parallel >/dev/null 2>&1; then
  hosts=()
  if [ -n "${PARALLEL_HOSTS:-}" ]; then hosts=(--sshlogin "$PARALLEL_HOSTS"); fi
  seq 1 "$n" | parallel --will-cite --halt never "${hosts[@]}" \
    "$wearscar" audit "$input" -o "$out" --shard "{}/$n" --quiet "$@" ||
    status=$?
else
  seq 1 "$n" | xargs -P "$n" -I{} \
    "$wearscar" audit "$input" -o "$out" --shard "{}/$n" --quiet "$@" ||
    status=$?
fi
# Each shard merged what was there when it ended; once all have, the
# merge is whole (it also names a shard that failed to write its part).
"$wearscar" audit --merge "$out" || status=$?
exit "$status"
