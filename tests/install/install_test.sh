#!/usr/bin/env bash
# cmake --install --prefix /usr/local as a user runs it, into a scratch
# DESTDIR: the Python module lands where the interpreter looks for packages
# under that prefix and imports from there; the command's package holds its
# man pages (when help2man was there to make them) and Debian's copyright.
#   install_test.sh BUILD_DIR PYTHON WITH_MAN(0|1)
set -euo pipefail
build=$1 python=$2 with_man=$3
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
DESTDIR=$dest cmake --install "$build" --prefix /usr/local >/dev/null
init=$(cd "$dest" && find usr/local -path '*/wearscar/__init__.py' | head -1)
[ -n "$init" ] || { echo "no wearscar/__init__.py installed under $dest"; exit 1; }
dir=/$(dirname "$(dirname "$init")")
"$python" - "$dir" <<'PY'
import sys
d = sys.argv[1]
assert d in sys.path, f"{d} is not on {sys.executable}'s path: {sys.path}"
print("on the path:", d)
PY
cd / && PYTHONPATH=$dest$dir "$python" -c "import wearscar, sys; assert wearscar.__file__.startswith('$dest'), wearscar.__file__; print('imports from', wearscar.__file__)"
[ -f "$dest/usr/local/share/doc/wearscar/copyright" ] || { echo "no copyright"; exit 1; }
if [ "$with_man" = 1 ]; then
  for page in wearscar wearscar-fuse wearscar-audit wearscar-scan; do
    f=$dest/usr/local/share/man/man1/$page.1.gz
    [ -f "$f" ] || { echo "no $f"; exit 1; }
    zcat "$f" | grep -q '^\.SH OPTIONS' || { echo "$f has no OPTIONS section"; exit 1; }
  done
  zcat "$dest/usr/local/share/man/man1/wearscar-audit.1.gz" | grep -q 'Process shard i of n' ||
    { echo "wearscar-audit.1.gz does not document --shard"; exit 1; }
fi
echo ok
