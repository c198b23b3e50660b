#!/bin/sh
# programs.bad_invocations: every command-line program the build has keeps the exit contract
# (lieservo_cli/program.hpp): bad usage or set-up exits 2 with a message naming the option or
# file, --help exits 0, and a file or folder that a program did not write is refused and left
# byte for byte as it was. At least 8 bad invocations per program.
#
# Usage: bad_invocations.sh WORK_DIR DATA_DIR MODELS_DIR NAME=PATH...
#   NAME: lieservo_demo, lieservo_replay, lieservo_push_start_map, lieservo_filter_diagnosis,
#   lieservo_fusion_error_table, lieservo_collect, lieservo_speed_error_report,
#   franka_servo_example_on_double, or a Google Benchmark program (lieservo_bench,
#   lieservo_frame_bench, lieservo_replay_bench, lieservo_bench_peers); the build passes those
#   it has. The set-up cases that need the TacTip data set (an unreadable image, a corrupted
#   model or params file) are skipped, with a message, when it is absent.
set -u
work=$1
data=$2
models=$3
shift 3
rm -rf "$work"
mkdir -p "$work"
fails=0
count=0

# expect STATUS PATTERN -- COMMAND...: COMMAND exits STATUS, its output contains PATTERN
# (tests/support/expect_exit.sh).
checker="$(dirname "$0")/../support/expect_exit.sh"
expect() {
  want=$1
  pattern=$2
  shift 3
  count=$((count + 1))
  sh "$checker" "$want" "$pattern" "$@" || fails=$((fails + 1))
}
# A user's file and a user's folder, and a check that a refusal left them as they were.
printf 'a user'"'"'s notes\n' >"$work/notes.txt"
cp "$work/notes.txt" "$work/notes.orig"
mkdir -p "$work/user_folder"
printf 'keep me\n' >"$work/user_folder/thesis.tex"
untouched() {
  cmp -s "$work/notes.txt" "$work/notes.orig" || { echo "FAIL: $1 changed $work/notes.txt"; fails=$((fails + 1)); }
  [ "$(ls -A "$work/user_folder")" = "thesis.tex" ] && [ "$(cat "$work/user_folder/thesis.tex")" = "keep me" ] ||
    { echo "FAIL: $1 changed $work/user_folder"; fails=$((fails + 1)); }
}
have_data() { [ -f "$data/val/targets.csv" ] && [ -f "$data/train/targets.csv" ] && [ -f "$models/train_val/gdn.onnx" ]; }

demo() {
  p=$1
  expect 2 "--trials" -- "$p" --trials 1000000000 --no-files
  expect 2 "--seed" -- "$p" --seed abc --no-files
  expect 2 "--seed" -- "$p" --seed -1 --no-files
  expect 2 "--seed" -- "$p" --seed 1e3 --no-files
  expect 2 "--trials" -- "$p" --trials 2x --no-files
  expect 2 "--rate" -- "$p" --rate 20abc --no-files
  expect 2 "--rate" -- "$p" --rate nan --no-files
  expect 2 "--observations" -- "$p" --observations everything --no-files
  expect 2 "--bogus" -- "$p" --bogus
  expect 2 "--out" -- "$p" --out ''
  expect 2 "$work/user_folder" -- "$p" --out "$work/user_folder" --quick --trials 1
  expect 2 "$work/notes.txt" -- "$p" --out "$work/notes.txt" --quick --trials 1
  untouched lieservo_demo
  expect 0 "Exit status" -- "$p" --help
  have_data || return 0
  # Every image of the data set replaced by an empty file: the first observation fails.
  for split in train val; do
    mkdir -p "$work/broken/$split/processed_images"
    cp "$data/$split/targets.csv" "$data/$split/processed_image_params.json" "$work/broken/$split/"
    (cd "$data/$split/processed_images" && for f in *.png; do : >"$work/broken/$split/processed_images/$f"; done)
  done
  expect 2 "$work/broken/" -- "$p" --data "$work/broken" --observations real --quick --trials 1 --no-files
  # The deployed GDN with its first 4 KB zeroed, under its own card: refused by its SHA-256.
  mkdir -p "$work/model"
  cp "$models/train_val/model_card.json" "$models/train_val/held_out.csv" "$models/train_val/gdn.onnx" "$work/model/"
  dd if=/dev/zero of="$work/model/gdn.onnx" bs=4096 count=1 conv=notrunc 2>/dev/null
  expect 2 "SHA-256" -- "$p" --model-card "$work/model/model_card.json" --quick --trials 1 --no-files
  # A corrupted params file in val.
  for split in train val; do
    mkdir -p "$work/params/$split"
    cp "$data/$split/targets.csv" "$data/$split/processed_image_params.json" "$work/params/$split/"
    ln -s "$data/$split/processed_images" "$work/params/$split/processed_images"
  done
  printf '{"gray": true, "bbox": [105, 20, 5' >"$work/params/val/processed_image_params.json"
  expect 2 "$work/params/val/processed_image_params.json" -- "$p" --data "$work/params" --observations real --quick --trials 1 --no-files
}

replay() {
  p=$1
  expect 2 "--sigmas" -- "$p" --sigmas nan
  expect 2 "--sigmas" -- "$p" --sigmas inf
  expect 2 "--sigmas" -- "$p" --sigmas 1e300
  expect 2 "--quick" -- "$p" --quick -5
  expect 2 "--seed" -- "$p" --seed abc
  expect 2 "$work/none/val/targets.csv" -- "$p" --data "$work/none" --quick 5
  expect 2 "--bogus" -- "$p" --bogus
  expect 2 "--cache" -- "$p" --cache ''
  expect 2 "$work/notes.txt" -- "$p" --results-md "$work/notes.txt" --quick 5
  expect 2 "$work/user_folder" -- "$p" --plots "$work/user_folder" --quick 5
  untouched lieservo_replay
  expect 0 "Exit status" -- "$p" --help
  have_data || return 0
  expect 2 "not a lieservo_replay cache" -- "$p" --data "$data" --models "$models/train_val" --quick 5 --no-cnn --cache "$work/notes.txt"
  untouched "lieservo_replay --cache"
}

start_map() {
  p=$1
  expect 2 "--max-offset" -- "$p" --max-offset -1
  expect 2 "--max-yaw" -- "$p" --max-yaw nan
  expect 2 "--offset-step" -- "$p" --offset-step 0
  expect 2 "whole numbers" -- "$p" --max-offset 3 --offset-step 2
  expect 2 "--seed" -- "$p" --seed abc
  expect 2 "$work/none.json" -- "$p" --model-card "$work/none.json"
  expect 2 "$work/none/map.csv" -- "$p" --out "$work/none/map.csv" --observations gaussian
  expect 2 "$work/notes.txt" -- "$p" --out "$work/notes.txt" --observations gaussian
  expect 2 "--out" -- "$p" --out ''
  expect 2 "--bogus" -- "$p" --bogus
  untouched lieservo_push_start_map
  expect 0 "Exit status" -- "$p" --help
  have_data || return 0
  mkdir -p "$work/broken_map/val/processed_images"
  cp "$data/val/targets.csv" "$data/val/processed_image_params.json" "$work/broken_map/val/"
  (cd "$data/val/processed_images" && for f in *.png; do : >"$work/broken_map/val/processed_images/$f"; done)
  expect 2 "$work/broken_map/" -- "$p" --data "$work/broken_map" --observations real --max-offset 0 --max-yaw 0
}

filter_diagnosis() {
  p=$1
  printf '1 2 3\n' >"$work/short_rows.txt"
  expect 2 "FILE" -- "$p"
  expect 2 "$work/none.txt" -- "$p" "$work/none.txt"
  expect 2 "$work/short_rows.txt" -- "$p" "$work/short_rows.txt"
  expect 2 "--sigmas" -- "$p" "$work/short_rows.txt" --sigmas nan
  expect 2 "--sigmas" -- "$p" "$work/short_rows.txt" --sigmas 0
  expect 2 "--synthetic" -- "$p" "$work/short_rows.txt" --synthetic -1
  expect 2 "--synthetic" -- "$p" "$work/short_rows.txt" --synthetic abc
  expect 2 "--bogus" -- "$p" "$work/short_rows.txt" --bogus
  expect 0 "Exit status" -- "$p" --help
}

fusion_error_table() {
  p=$1
  expect 2 "--bogus" -- "$p" --bogus
  expect 2 "nan" -- "$p" nan
  expect 2 "--x" -- "$p" --x 1e3
  expect 2 "-q" -- "$p" -q
  expect 2 "--quick" -- "$p" --quick
  expect 2 "1" -- "$p" 1
  expect 2 "--csv" -- "$p" --csv "$work/table.csv"
  expect 2 "--seed" -- "$p" --seed 3
  expect 0 "no options" -- "$p" --help
}

collect() {
  p=$1
  expect 2 "--out" -- "$p"
  expect 2 "--out" -- "$p" --out ''
  expect 2 "$work/notes.txt" -- "$p" --out "$work/notes.txt" --samples 2 --quiet
  expect 2 "$work/user_folder" -- "$p" --out "$work/user_folder" --samples 2 --quiet
  untouched lieservo_collect
  expect 2 "/proc/lieservo" -- "$p" --out /proc/lieservo/set --samples 2 --quiet
  expect 2 "--z-min" -- "$p" --out "$work/c1" --z-min 7 --samples 2 --quiet
  expect 2 "--phi-max" -- "$p" --out "$work/c2" --phi-max 95 --samples 2 --quiet
  expect 2 "--samples" -- "$p" --out "$work/c3" --samples 0
  expect 2 "--seed" -- "$p" --out "$work/c4" --seed abc
  expect 2 "--image-size" -- "$p" --out "$work/c5" --image-size 0 0
  expect 2 "--source" -- "$p" --out "$work/c6" --source camera
  expect 2 "--bogus" -- "$p" --out "$work/c7" --bogus
  expect 0 "Exit status" -- "$p" --help
}

speed_error_report() {
  p=$1
  expect 2 "--reps" -- "$p" --reps abc
  expect 2 "--reps" -- "$p" --reps 0
  expect 2 "--reps" -- "$p" --reps 2x
  expect 2 "--bogus" -- "$p" --bogus
  expect 2 "--dump" -- "$p" --dump "$work/x.csv" --quick
  expect 2 "--csv" -- "$p" --quick --csv ''
  expect 2 "/nonexistent/dir/r.csv" -- "$p" --quick --csv /nonexistent/dir/r.csv
  expect 2 "$work/notes.txt" -- "$p" --quick --csv "$work/notes.txt"
  expect 2 "$work/notes.txt" -- "$p" --dump "$work/notes.txt"
  untouched lieservo_speed_error_report
  expect 0 "Exit status" -- "$p" --help
}

franka_double() {
  p=$1
  r="--robot 172.16.0.2 --model-card $models/train_val/model_card.json"
  expect 2 "--robot" -- "$p" --model-card "$models/train_val/model_card.json"
  expect 2 "--task" -- "$p" $r --task dance
  expect 2 "--camera" -- "$p" $r --camera 99
  expect 2 "--duration" -- "$p" $r --duration 0
  expect 2 "--max-speed" -- "$p" $r --max-speed nan
  expect 2 "--mount" -- "$p" $r --mount 1,2
  expect 2 "--heading" -- "$p" $r --heading inf
  expect 2 "--bogus" -- "$p" $r --bogus
  expect 0 "--robot" -- "$p" --help
}

google_benchmark() {
  p=$1
  expect 2 "--benchmark_min_time" -- "$p" --benchmark_min_time=nan
  expect 2 "--benchmark_min_time" -- "$p" --benchmark_min_time=-1
  expect 2 "--benchmark_repetitions" -- "$p" --benchmark_repetitions=inf
  expect 2 "--bogus" -- "$p" --bogus
  expect 2 "--benchmark_format" -- "$p" --benchmark_format=xml
  expect 2 "--benchmark_out_format" -- "$p" --benchmark_out_format=bogus
  expect 2 "--benchmark_out" -- "$p" --benchmark_out=
  expect 2 "$work/notes.txt" -- "$p" --benchmark_out="$work/notes.txt" --benchmark_min_time=0.001
  expect 2 "--benchmark_filter" -- "$p" --benchmark_filter=no_such_benchmark --benchmark_min_time=0.001
  untouched "$(basename "$p")"
  expect 0 "benchmark_filter" -- "$p" --help
}

for arg in "$@"; do
  name=${arg%%=*}
  path=${arg#*=}
  before=$count
  case $name in
    lieservo_demo) demo "$path" ;;
    lieservo_replay) replay "$path" ;;
    lieservo_push_start_map) start_map "$path" ;;
    lieservo_filter_diagnosis) filter_diagnosis "$path" ;;
    lieservo_fusion_error_table) fusion_error_table "$path" ;;
    lieservo_collect) collect "$path" ;;
    lieservo_speed_error_report) speed_error_report "$path" ;;
    franka_servo_example_on_double) franka_double "$path" ;;
    lieservo_bench | lieservo_frame_bench | lieservo_replay_bench | lieservo_bench_peers) google_benchmark "$path" ;;
    *) echo "FAIL: no cases for $name"; fails=$((fails + 1)) ;;
  esac
  echo "== $name: $((count - before)) invocations"
done
have_data || echo "note: the TacTip data set or the deployed GDN is absent ($data, $models): the unreadable-image, corrupted-model and corrupted-params cases are skipped"
[ "$fails" -eq 0 ] || { echo "programs.bad_invocations: $fails case(s) failed"; exit 1; }
echo "programs.bad_invocations: $count invocations, every one answered as expected"
