#!/bin/sh
# expect_exit.sh STATUS PATTERN COMMAND [ARGS...]: passes when COMMAND exits with STATUS and its
# output (stdout and stderr) contains PATTERN (a fixed string): how the programs' bad-input
# tests check "a clear error, and the right exit status" (lieservo_cli/cli.hpp).
want=$1
pattern=$2
shift 2
out=$("$@" 2>&1)
rc=$?
if [ "$rc" -ne "$want" ]; then
  printf 'FAILED: %s exited %s, expected %s\n%s\n' "$*" "$rc" "$want" "$out"
  exit 1
fi
if ! printf '%s' "$out" | grep -qF -- "$pattern"; then
  printf "FAILED: %s: no '%s' in its output\n%s\n" "$*" "$pattern" "$out"
  exit 1
fi
printf 'ok: %s -> %s (%s)\n' "$*" "$rc" "$pattern"
