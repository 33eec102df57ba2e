#!/bin/bash
# Submits a wearscar audit to Slurm: a job array of shards
# (audit.sbatch), then one merge that runs when every task has ended,
# whatever their outcome. The merge job fails (exit 3) while a shard is
# missing; re-run that task (sbatch --array=I audit.sbatch INPUT OUT) and
# merge again (wearscar audit --merge OUT).
#
#   examples/slurm/submit.sh INPUT OUT [ARRAY [SBATCH OPTIONS...]]
#   examples/slurm/submit.sh /data/lab /scratch/audit 0-15 --partition=short
#
# $WEARSCAR names the command (default: wearscar on the PATH).
set -euo pipefail
if [ $# -lt 2 ]; then
  sed -n '2,11p' "$0" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
input=$1 out=$2 array=${3:-0-15}
shift $(( $# < 3 ? $# : 3 ))
job=$(sbatch --parsable --array="$array" "$@" "$here/audit.sbatch" "$input" "$out")
job=${job%%;*}  # --parsable prints "id" or "id;cluster"
merge=$(sbatch --parsable --dependency="afterany:$job" "$@" \
  --job-name=wearscar-merge --output="wearscar-merge-%j.log" \
  --wrap "${WEARSCAR:-wearscar} audit --merge '$out'")
echo "audit: array job $job ($array), merge job ${merge%%;*}"
