#!/bin/sh
# build.test_names: no Catch2 test name holds '[' or ']'. catch_discover_tests hands the names to
# CTest as a CMake list, in which square brackets group elements: one unmatched bracket merges
# every name up to the next bracket into one bogus test, and the tests merged into it never run.
# Usage: check_test_names.sh SOURCE_DIR
src=$1
bad=$(grep -rnE '(TEST_CASE|SCENARIO)[A-Z_]*\( *"[^"]*[][]' "$src/tests" "$src/examples" \
        --include='*.cpp' --include='*.hpp')
if [ -n "$bad" ]; then
  echo "test names with a square bracket (rename them):"
  echo "$bad"
  exit 1
fi
echo "build.test_names: no test name holds a square bracket"
