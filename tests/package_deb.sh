#!/usr/bin/env bash
# Builds the Debian packages with CPack (wearscar, libwearscar-dev,
# python3-wearscar), checks what each holds and depends on, unpacks them
# into a scratch root (dpkg -x) and runs the command and the Python module
# from there.
#   package_deb.sh <build dir> <scratch dir> <version>
set -euo pipefail
build=$1 scratch=$2 version=$3
rm -rf "$scratch"
mkdir -p "$scratch"
(cd "$build" && cpack -G DEB -B "$scratch" > "$scratch/cpack.log" 2>&1) || {
  cat "$scratch/cpack.log"; exit 1; }
root="$scratch/root"
for package in wearscar libwearscar-dev python3-wearscar; do
  deb="$scratch/${package}_${version}_amd64.deb"
  test -f "$deb" || { echo "no $deb"; ls "$scratch"; exit 1; }
  # (read whole first: grep -q closing the pipe early would fail it)
  info=$(dpkg-deb --info "$deb")
  grep -q "^ Maintainer: .*<.*@.*>" <<< "$info" || {
    echo "$package: no maintainer with an address"; echo "$info"; exit 1; }
  grep -q "@localhost" <<< "$info" && { echo "$package: maintainer at localhost"; exit 1; }
  dpkg -x "$deb" "$root"
  files=$(dpkg-deb -c "$deb")
  case $package in
    wearscar)
      grep -q "Depends:.*libopencv-core" <<< "$info" || {
        echo "wearscar does not depend on OpenCV"; echo "$info"; exit 1; }
      grep -q "usr/share/doc/wearscar/copyright" <<< "$files"
      if grep -q "usr/include" <<< "$files"; then echo "headers in wearscar"; exit 1; fi
      ;;
    libwearscar-dev)
      grep -q "Depends:.*libpcl-dev" <<< "$info"
      if grep -q "usr/bin/wearscar" <<< "$files"; then echo "the command in -dev"; exit 1; fi
      ;;
    python3-wearscar)
      grep -q "Depends:.*python3-numpy" <<< "$info"
      ;;
  esac
  echo "$(basename "$deb"): $(du -k "$deb" | cut -f1) KiB"
done
test -f "$root/usr/include/wearscar/fusion/products.h"
test -f "$root/usr/lib/x86_64-linux-gnu/cmake/wearscar/wearscarConfig.cmake" ||
  test -f "$root/usr/lib/cmake/wearscar/wearscarConfig.cmake"
printed=$("$root/usr/bin/wearscar" version)
grep -q "^wearscar ${version} (commit " <<< "$printed"
init=$(cd "$root" && find usr/lib -path '*/wearscar/__init__.py' | head -1)
test -n "$init" || { echo "no Python module in python3-wearscar"; exit 1; }
site=/$(dirname "$(dirname "$init")")
# Where /usr/bin/python3 looks for the packages of /usr.
/usr/bin/python3 -c "import sys; assert '$site' in sys.path, ('$site', sys.path)"
cd / && PYTHONPATH="$root$site" /usr/bin/python3 -c "
import wearscar
assert wearscar.__version__ == '${version}', wearscar.__version__
assert wearscar.__file__.startswith('$root'), wearscar.__file__
print('import wearscar from', wearscar.__file__)"
echo "wearscar and import wearscar run from dpkg -x"
