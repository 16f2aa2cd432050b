#!/usr/bin/env bash
# ctest runs each doctest case by its name (doctest_discover_tests). CMake cuts a name at ';' (its
# list separator): the pieces match no case, and a filter that matches nothing passes, so such a
# case would never run in ctest. Every case must therefore be named without ';'.
set -u
names=$("$1" --list-test-cases --no-version) || { echo "FAIL: $1 --list-test-cases"; exit 1; }
bad=$(grep -F ';' <<<"$names")
if [ -n "$bad" ]; then
  echo "FAIL: test case names with ';' (ctest would never run them):"
  echo "$bad"
  exit 1
fi
echo "$(grep -vcE '^(\[doctest\]|=+$)' <<<"$names") test case names, none with ';'"
