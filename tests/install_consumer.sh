#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then configures, builds and
# runs tests/consumer against it: find_package(wearscar) must just work, and
# a program using only the public API writes the same files as
# `wearscar fuse` (byte for byte).
#   install_consumer.sh <build dir> <source dir> <scratch dir>
set -euo pipefail
build=$1 source=$2 scratch=$3
# One date for both runs' provenance (result.json), so they compare.
export SOURCE_DATE_EPOCH=1700000000
rm -rf "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" > /dev/null
test -x "$scratch/prefix/bin/wearscar"
test -f "$scratch/prefix/include/wearscar/fusion/fit_mu.h"
test -f "$scratch/prefix/include/wearscar/fusion/products.h"
test -f "$scratch/prefix/include/wearscar/report/audit.h"
# The support library's headers travel with it (the settings of
# wearscar/fusion/settings.h are its).
test -f "$scratch/prefix/include/wearscar/support/settings.h"
cmake -S "$source/tests/consumer" -B "$scratch/consumer" \
  -DCMAKE_PREFIX_PATH="$scratch/prefix" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$scratch/consumer" > /dev/null
"$scratch/consumer/consumer"
wearscar="$scratch/prefix/bin/wearscar"
"$wearscar" simulate --case S-RL-R --cycles 40 --formats csv,gsf \
  -o "$scratch/sim" > /dev/null 2>&1
force="$scratch/sim/S-RL-R.force.csv" scan="$scratch/sim/S-RL-R.scan.gsf"
"$wearscar" fuse --force "$force" --scan "$scan" --no-figures \
  -o "$scratch/by-command" > /dev/null
mkdir -p "$scratch/by-library"
"$scratch/consumer/consumer" "$force" "$scan" S-RL-R "$scratch/by-library"
# The command also writes the test's page (report.html), which the
# library's WriteTestResults leaves to report::WriteTestPage.
diff -r --exclude=.wearscar.lock --exclude=.wearscar-manifest \
  --exclude=report.html "$scratch/by-command" "$scratch/by-library"
grep -q "S-RL-R" "$scratch/by-command/report.html"
# With the scan used: its profiles are among them.
test -f "$scratch/by-library/profiles.csv"
echo "the library wrote what the command wrote: $(ls "$scratch/by-library" | tr '\n' ' ')"
# The audit of the same folder, by the command and by wearscar::report.
"$wearscar" audit "$scratch/sim" --no-figures -q -o "$scratch/audit-by-command"
"$scratch/consumer/consumer" audit "$scratch/sim" "$scratch/audit-by-library"
diff -r --exclude=.wearscar.lock --exclude=.wearscar-manifest \
  "$scratch/audit-by-command" "$scratch/audit-by-library"
test -f "$scratch/audit-by-library/report.html"
test -f "$scratch/audit-by-library/S-RL-R/result.json"
echo "the library audited as the command did: $(ls "$scratch/audit-by-library" | tr '\n' ' ')"
