#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then configures, builds and
# runs tests/consumer against it: find_package(wearscar) must just work.
#   install_consumer.sh <build dir> <source dir> <scratch dir>
set -euo pipefail
build=$1 source=$2 scratch=$3
rm -rf "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" > /dev/null
test -x "$scratch/prefix/bin/wearscar"
test -f "$scratch/prefix/include/wearscar/fusion/fit_mu.h"
cmake -S "$source/tests/consumer" -B "$scratch/consumer" \
  -DCMAKE_PREFIX_PATH="$scratch/prefix" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$scratch/consumer" > /dev/null
"$scratch/consumer/consumer"
