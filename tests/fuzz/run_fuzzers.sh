#!/usr/bin/env bash
# Runs every libFuzzer target for a given time (one per core at once) and fails if any finds a crash, a sanitizer
# error, a property violation (abort), a timeout or an out-of-memory.
#
#   tests/fuzz/run_fuzzers.sh <build_dir> [seconds_each=60]     (FUZZ_JOBS=N: N at once)
#
# The build directory must be configured with clang and fuzzers enabled, e.g.
#   CXX=clang++ cmake -S . -B build-fuzz -DLIESERVO_BUILD_FUZZERS=ON \
#       -DLIESERVO_BUILD_EXAMPLES=OFF -DLIESERVO_BUILD_BENCHMARKS=OFF
#   cmake --build build-fuzz --target fuzz_log fuzz_fusion fuzz_filter fuzz_control fuzz_realtime fuzz_cli
# Corpora (kept between runs) and crash artifacts go to <build_dir>/tests/fuzz/.
set -u
if [ $# -lt 1 ]; then
  echo "usage: $0 <build_dir> [seconds_each]" >&2
  exit 2
fi
build=$1
secs=${2:-60}
dir="$build/tests/fuzz"
jobs=${FUZZ_JOBS:-$(nproc)}   # targets fuzzed at once, one core each
targets=(fuzz_log fuzz_fusion fuzz_filter fuzz_control fuzz_realtime fuzz_cli)
for t in "${targets[@]}"; do
  if [ ! -x "$dir/$t" ]; then
    echo "missing $dir/$t (build the fuzz targets first)" >&2
    exit 2
  fi
done

# Fuzzes one target; its exit status says whether it found anything.
fuzz() {
  local t=$1 corpus="$dir/corpus_$1" artifacts="$dir/artifacts_$1/"
  mkdir -p "$corpus" "$artifacts"
  "$dir/$t" -max_total_time="$secs" -max_len=4096 -len_control=0 -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$artifacts" "$corpus" >"$dir/$t.log" 2>&1
}

echo "fuzzing ${targets[*]}: ${secs}s each, $jobs at a time (logs: $dir/<target>.log)"
status=0
for ((i = 0; i < ${#targets[@]}; i += jobs)); do
  batch=("${targets[@]:i:jobs}")
  pids=()
  for t in "${batch[@]}"; do fuzz "$t" & pids+=($!); done
  for k in "${!batch[@]}"; do
    t=${batch[$k]}
    if wait "${pids[$k]}"; then
      echo "== $t: ok"
      grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$dir/$t.log" | tail -2
    else
      echo "== $t: FAILED: see $dir/$t.log and $dir/artifacts_$t/" >&2
      tail -40 "$dir/$t.log" >&2
      status=1
    fi
  done
done
exit $status
