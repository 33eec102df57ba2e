#!/usr/bin/env bash
# scripts/check-function-size holds functions to 80 lines (the limit
# .clang-tidy states) and classes to 200, in C++, in a test's body and in
# Python: each planted one a line over is named and fails the check, one
# at the limit passes.
# usage: check_function_size_test.sh SOURCE_DIR
set -u
src=$1
command -v ctags >/dev/null 2>&1 && ctags --version | grep -q "Universal Ctags" ||
  { echo "SKIP: Universal Ctags is not installed"; exit 77; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
plant() {  # FILE NAME LINES: a C++ function NAME of LINES lines in FILE
  { echo "int $2(int x) {"
    for ((i = 0; i < $3 - 2; ++i)); do echo "  x += $i;"; done
    echo "}"; } >> "$1"
}
plant_test() {  # FILE NAME LINES: a GoogleTest body of LINES lines
  { echo "TEST(Planted, $2) {"
    for ((i = 0; i < $3 - 2; ++i)); do echo "  EXPECT_EQ($i, $i);"; done
    echo "}"; } >> "$1"
}
plant_py() {  # FILE NAME LINES: a Python function of LINES lines
  { echo "def $2(x):"
    for ((i = 0; i < $3 - 1; ++i)); do echo "    x += $i"; done; } >> "$1"
}
plant_class() {  # FILE NAME LINES: a C++ class of LINES lines
  { echo "class $2 {"; echo " public:"
    for ((i = 0; i < $3 - 3; ++i)); do echo "  int m$i = $i;"; done
    echo "};"; } >> "$1"
}
expect() {  # DIR STATUS WANTED...: the check's status on DIR and what it names
  local d=$1 want=$2; shift 2
  out=$("$src/scripts/check-function-size" "$dir/$d" 2>&1); rc=$?
  [ $rc -eq "$want" ] || { echo "FAIL: $d: exit $rc, expected $want: $out"; exit 1; }
  for w in "$@"; do
    grep -qF "$w" <<<"$out" || { echo "FAIL: $d: '$w' not said: $out"; exit 1; }
  done
  grep -q "Fits" <<<"$out" && { echo "FAIL: $d: one within the limit named: $out"; exit 1; }
  echo "ok $d: $(tail -1 <<<"$out")"
}
mkdir "$dir/ok" "$dir/cc" "$dir/test" "$dir/py" "$dir/class"
plant "$dir/ok/a.cc" Fits 80
plant_test "$dir/ok/a_test.cc" Fits 80
plant_py "$dir/ok/a.py" Fits 80
plant_class "$dir/ok/b.h" Fits 200
expect ok 0 "no function over 80 lines, no class over 200"
plant "$dir/cc/a.cc" Fits 80
plant "$dir/cc/b.cc" TooLong 81
expect cc 1 "b.cc:1: TooLong is 81 lines (limit 80)"
plant_test "$dir/test/a_test.cc" Fits 80
plant_test "$dir/test/b_test.cc" TooLong 81
expect test 1 "b_test.cc:1: TEST is 81 lines (limit 80)"
plant_py "$dir/py/a.py" Fits 80
plant_py "$dir/py/b.py" too_long 81
expect py 1 "b.py:1: too_long is 81 lines (limit 80)"
plant_class "$dir/class/a.h" Fits 200
plant_class "$dir/class/b.h" TooLong 201
expect class 1 "b.h:1: class TooLong is 201 lines (limit 200)"
