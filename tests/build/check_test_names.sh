#!/bin/sh
# build.test_names: no Catch2 test name holds '[' or ']'. catch_discover_tests hands the names to
# CTest as a CMake list, in which square brackets group elements: one unmatched bracket merges
# every name up to the next bracket into one bogus test, and the tests merged into it never run.
# A name may start on the line after `TEST_CASE(` and be split into adjacent string literals.
# Usage: check_test_names.sh SOURCE_DIR
src=$1
bad=$(find "$src/tests" "$src/examples" -name '*.cpp' -o -name '*.hpp' | sort | xargs perl -0777 -ne '
  while (/(?:TEST_CASE|SCENARIO)[A-Z_]*\(\s*((?:"[^"\n]*"\s*)+)/g) {
    my $lits = $1;
    my $name = join("", $lits =~ /"([^"\n]*)"/g);
    print "$ARGV: $name\n" if $name =~ /[][]/;
  }')
if [ -n "$bad" ]; then
  echo "test names with a square bracket (rename them):"
  echo "$bad"
  exit 1
fi
echo "build.test_names: no test name holds a square bracket"
