#!/usr/bin/env bash
# ctest meta.test_names: no Catch2 test name holds a character that breaks its ctest registration.
# catch_discover_tests writes each name into a CMake list, so a ';' splits one test into two
# filters that match nothing (CI then fails on "No tests ran"); this names the test at once.
# Usage: check_test_names.sh TEST_SOURCE_DIR
set -uo pipefail
DIR=$1
bad=$(grep -nE 'TEST_CASE\("[^"]*;' "$DIR"/*.cpp)
[[ -z $bad ]] || { echo "FAIL: ';' in a test name (ctest would split it):"; echo "$bad"; exit 1; }
n=$(grep -c 'TEST_CASE("' "$DIR"/*.cpp | awk -F: '{ s += $2 } END { print s }')
((n > 50)) || { echo "FAIL: only $n TEST_CASE names found in $DIR (pattern out of date?)"; exit 1; }
echo "checked $n test names"
