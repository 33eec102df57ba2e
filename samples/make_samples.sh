#!/usr/bin/env bash
# Regenerates samples/data with the virtual tribometer and scanner: the
# paper's 12 cases, small (20 cycles at 500 Hz, 256 x 192 scans at 29.6 um),
# as force CSV, GSF scan and ground-truth JSON. B-RT-R etc. are explained by
# wear-scar interaction, S-RL-R is not (a large elastic part). A test checks
# that this command reproduces them byte for byte. Full-size data (600
# cycles at 2 kHz, 1024 x 768 at 7.413 um, also Rtec-like CSV and Keyence VR
# CSV) come from `wearscar simulate --all` on demand.
#   samples/make_samples.sh [path/to/wearscar] [output dir]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/../build/apps/wearscar}
"$bin" simulate --all --cycles 20 --rate 500 --scan-cols 256 --scan-rows 192 \
  --scan-pitch 0.0296 --formats csv,gsf -o "${2:-$here/data}" > /dev/null 2>&1
