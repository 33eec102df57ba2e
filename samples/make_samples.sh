#!/usr/bin/env bash
# Regenerates samples/data with the virtual tribometer and scanner. The
# files are small versions of two of the paper's cases (40 cycles at 500 Hz,
# 256 x 192 scans at 29.6 um): B-RT-R (explained by wear-scar interaction)
# and S-RL-R (not: a large elastic part). A test checks that this command
# reproduces them byte for byte.
#   samples/make_samples.sh [path/to/wearscar]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/../build/apps/wearscar}
"$bin" simulate --case B-RT-R --case S-RL-R --cycles 40 --rate 500 \
  --scan-cols 256 --scan-rows 192 --scan-pitch 0.0296 -o "${2:-$here/data}" > /dev/null
