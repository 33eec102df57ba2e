#!/usr/bin/env bash
# Builds the Debian packages with CPack (wearscar, libwearscar-dev,
# python3-wearscar, and the -dbgsym packages of the first and the last),
# checks what each holds and depends on, runs lintian on them (no error, no
# warning), unpacks them into a scratch root (dpkg -x) and runs the command
# and the Python module from there, their symbols read back from the
# -dbgsym packages.
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
      grep -q "Depends:.*python3 (>= 3\.[0-9]*), python3 (<< 3\.[0-9]*), python3-numpy" <<< "$info" || {
        echo "python3-wearscar: no versioned python3 dependency"; echo "$info"; exit 1; }
      grep -q "usr/lib/python3/dist-packages/wearscar/__init__.py" <<< "$files" || {
        echo "python3-wearscar: the module is not in usr/lib/python3/dist-packages"; echo "$files"; exit 1; }
      ;;
  esac
  grep -q "usr/share/doc/$package/copyright" <<< "$files" || { echo "$package: no copyright"; exit 1; }
  grep -q "usr/share/doc/$package/changelog.gz" <<< "$files" || { echo "$package: no changelog.gz"; exit 1; }
  if command -v lintian > /dev/null; then
    # (as root lintian says it should not run as root: not a finding)
    said=$(lintian --tag-display-limit 0 "$deb" 2>&1 | grep -v "running with root privileges" || true)
    [ -z "$said" ] || { echo "lintian on $package:"; echo "$said"; exit 1; }
    echo "lintian on $package: clean"
  else
    echo "lintian is not installed (scripts/install-deps test installs it): not run"
  fi
  echo "$(basename "$deb"): $(du -k "$deb" | cut -f1) KiB"
done
test -f "$root/usr/include/wearscar/fusion/products.h"
# Each command's man page, compressed, names its own command.
for page in wearscar wearscar-audit wearscar-fuse wearscar-watch; do
  man=$(zcat "$root/usr/share/man/man1/$page.1.gz")
  grep -A1 '^\.SH NAME' <<< "$man" | grep -q "^$page \\\\- " || {
    echo "$page.1.gz does not name $page"; zcat "$root/usr/share/man/man1/$page.1.gz" | head; exit 1; }
done
sections=$(readelf -S "$root/usr/bin/wearscar")
if grep -q '\.symtab' <<< "$sections"; then
  echo "usr/bin/wearscar is not stripped"; exit 1
fi
# What was stripped is kept apart: each binary's -dbgsym package holds
# /usr/lib/debug/.build-id/<its build id>.debug, which the binary names
# (.gnu_debuglink) and whose symbols name the functions. A build without
# debug information (Release) keeps the symbol table alone, which lintian
# calls debug-file-with-no-debug-symbols: accepted for such a build only.
symbols_only=
built=$(readelf -S "$build/apps/wearscar")
grep -q '\.debug_info' <<< "$built" ||
  symbols_only=--suppress-tags=debug-file-with-no-debug-symbols
for package in wearscar python3-wearscar; do
  ddeb="$scratch/${package}-dbgsym_${version}_amd64.ddeb"
  test -f "$ddeb" || { echo "no $ddeb"; ls "$scratch"; exit 1; }
  info=$(dpkg-deb --info "$ddeb")
  grep -q "^ Depends: $package (= $version)" <<< "$info" || {
    echo "$package-dbgsym does not depend on $package $version"; exit 1; }
  if command -v lintian > /dev/null; then
    said=$(lintian --tag-display-limit 0 $symbols_only "$ddeb" 2>&1 | grep -v "running with root privileges" || true)
    [ -z "$said" ] || { echo "lintian on $package-dbgsym:"; echo "$said"; exit 1; }
    echo "lintian on $package-dbgsym: clean${symbols_only:+ (symbol table only: a build without debug information)}"
  fi
  dpkg -x "$ddeb" "$root"
done
binary="$root/usr/bin/wearscar"
id=$(readelf -n "$binary" | awk '/Build ID:/ {print $3}')
debug="$root/usr/lib/debug/.build-id/${id:0:2}/${id:2}.debug"
test -f "$debug" || { echo "no $debug for usr/bin/wearscar's build id $id"; exit 1; }
link=$(readelf --string-dump=.gnu_debuglink "$binary")
grep -q "${id:2}.debug" <<< "$link" || {
  echo "usr/bin/wearscar does not name its debug file"; exit 1; }
symbols=$(nm -C "$debug")
grep -q " T wearscar::fusion::AnalyzeTest(" <<< "$symbols" || {
  echo "$debug does not name wearscar::fusion::AnalyzeTest"; exit 1; }
echo "usr/bin/wearscar's symbols are in wearscar-dbgsym (build id $id)"
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
