#!/usr/bin/env bash
# Builds the Debian package with CPack, unpacks it into a scratch root
# (dpkg -x) and runs the command and the Python module from there.
#   package_deb.sh <build dir> <scratch dir> <version>
set -euo pipefail
build=$1 scratch=$2 version=$3
rm -rf "$scratch"
mkdir -p "$scratch"
(cd "$build" && cpack -G DEB -B "$scratch" > "$scratch/cpack.log" 2>&1) || {
  cat "$scratch/cpack.log"; exit 1; }
deb="$scratch/wearscar_${version}_amd64.deb"
test -f "$deb" || { echo "no $deb"; ls "$scratch"; exit 1; }
# (read whole first: grep -q closing the pipe early would fail it)
info=$(dpkg-deb --info "$deb")
grep -q "Depends:.*libopencv-core" <<< "$info" || {
  echo "the package does not depend on OpenCV"; echo "$info"; exit 1; }
root="$scratch/root"
dpkg -x "$deb" "$root"
test -f "$root/usr/include/wearscar/fusion/products.h"
test -f "$root/usr/lib/x86_64-linux-gnu/cmake/wearscar/wearscarConfig.cmake" ||
  test -f "$root/usr/lib/cmake/wearscar/wearscarConfig.cmake"
printed=$("$root/usr/bin/wearscar" version)
grep -q "^wearscar ${version} (commit " <<< "$printed"
PYTHONPATH="$root/usr/lib/python3/dist-packages" /usr/bin/python3 -c "
import wearscar
assert wearscar.__version__ == '${version}', wearscar.__version__
assert wearscar.__file__.startswith('$root'), wearscar.__file__
print('import wearscar from', wearscar.__file__)"
echo "$(basename "$deb"): $(du -k "$deb" | cut -f1) KiB; wearscar and import wearscar run from dpkg -x"
