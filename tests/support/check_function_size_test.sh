#!/usr/bin/env bash
# scripts/check-function-size fails on a function of 81 lines and passes
# one of 80 (the limit .clang-tidy states), naming the long one.
# usage: check_function_size_test.sh SOURCE_DIR
set -u
src=$1
command -v ctags >/dev/null 2>&1 && ctags --version | grep -q "Universal Ctags" ||
  { echo "SKIP: Universal Ctags is not installed"; exit 77; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
plant() {  # FILE NAME LINES: a function NAME of LINES lines in FILE
  { echo "int $2(int x) {"
    for ((i = 0; i < $3 - 2; ++i)); do echo "  x += $i;"; done
    echo "}"; } >> "$1"
}
mkdir "$dir/ok" "$dir/long"
plant "$dir/ok/a.cc" Fits 80
plant "$dir/long/a.cc" Fits 80
plant "$dir/long/b.cc" TooLong 81
out=$("$src/scripts/check-function-size" "$dir/ok" 2>&1); rc=$?
[ $rc -eq 0 ] || { echo "FAIL: 80 lines refused (exit $rc): $out"; exit 1; }
out=$("$src/scripts/check-function-size" "$dir/long" 2>&1); rc=$?
[ $rc -eq 1 ] || { echo "FAIL: 81 lines passed (exit $rc): $out"; exit 1; }
grep -q "b.cc:1: TooLong is 81 lines (limit 80)" <<<"$out" ||
  { echo "FAIL: the long function not named: $out"; exit 1; }
grep -q "Fits" <<<"$out" && { echo "FAIL: the 80-line function named: $out"; exit 1; }
echo "ok: $out"
