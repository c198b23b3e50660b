#!/usr/bin/env bash
# Runs every libFuzzer target for a given time and fails if any finds a crash, a sanitizer
# error, a property violation (abort), a timeout or an out-of-memory.
#
#   tests/fuzz/run_fuzzers.sh <build_dir> [seconds_each=60]
#
# The build directory must be configured with clang and fuzzers enabled, e.g.
#   CXX=clang++ cmake -S . -B build-fuzz -DLIESERVO_BUILD_FUZZERS=ON \
#       -DLIESERVO_BUILD_EXAMPLES=OFF -DLIESERVO_BUILD_BENCHMARKS=OFF
#   cmake --build build-fuzz --target fuzz_log fuzz_fusion fuzz_filter fuzz_control
# Corpora (kept between runs) and crash artifacts go to <build_dir>/tests/fuzz/.
set -u
if [ $# -lt 1 ]; then
  echo "usage: $0 <build_dir> [seconds_each]" >&2
  exit 2
fi
build=$1
secs=${2:-60}
dir="$build/tests/fuzz"
status=0
for t in fuzz_log fuzz_fusion fuzz_filter fuzz_control; do
  exe="$dir/$t"
  if [ ! -x "$exe" ]; then
    echo "missing $exe (build the fuzz targets first)" >&2
    exit 2
  fi
  corpus="$dir/corpus_$t"
  artifacts="$dir/artifacts_$t/"
  mkdir -p "$corpus" "$artifacts"
  log="$dir/$t.log"
  echo "== $t: ${secs}s (log: $log)"
  if "$exe" -max_total_time="$secs" -max_len=4096 -len_control=0 -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$artifacts" "$corpus" >"$log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$log" | tail -2
    echo "   ok"
  else
    echo "   FAILED: see $log and $artifacts" >&2
    tail -40 "$log" >&2
    status=1
  fi
done
exit $status
