#!/bin/sh
# programs.bad_input: the command-line programs refuse bad usage and set-up with exit status 2
# and a message naming the option or file (lieservo_cli/cli.hpp).
# Usage: run_programs_bad_input.sh LIESERVO_DEMO LIESERVO_REPLAY DATA_DIR MODELS_DIR WORK_DIR [START_MAP]
# (START_MAP: lieservo_push_start_map, where the build has it.)
# The set-up cases that need the TacTip data set (an unreadable image, a corrupted model) are
# skipped, with a message, when it is absent; the rest always run.
set -u
demo=$1
replay=$2
data=$3
models=$4
work=$5
map=${6:-}
rm -rf "$work"
mkdir -p "$work"
fails=0

# expect STATUS PATTERN -- COMMAND...: COMMAND exits STATUS, its output contains PATTERN
# (tests/support/expect_exit.sh).
checker="$(dirname "$0")/../support/expect_exit.sh"
expect() {
  want=$1
  pattern=$2
  shift 3
  sh "$checker" "$want" "$pattern" "$@" || fails=$((fails + 1))
}

expect 2 "--trials" -- "$demo" --trials 1000000000 --no-files
expect 2 "--seed" -- "$demo" --seed abc --no-files
expect 2 "--seed" -- "$demo" --seed -1 --no-files
expect 2 "--seed" -- "$demo" --seed 1e3 --no-files
expect 2 "--trials" -- "$demo" --trials 2x --no-files
expect 2 "--rate" -- "$demo" --rate 20abc --no-files
expect 2 "--rate" -- "$demo" --rate nan --no-files
expect 2 "--observations" -- "$demo" --observations everything --no-files
expect 2 "--bogus" -- "$demo" --bogus
expect 0 "Exit status" -- "$demo" --help
expect 2 "--sigmas" -- "$replay" --sigmas nan
expect 2 "--sigmas" -- "$replay" --sigmas inf
expect 2 "--sigmas" -- "$replay" --sigmas 1e300
expect 2 "--quick" -- "$replay" --quick -5
expect 2 "--seed" -- "$replay" --seed abc
expect 2 "$work/none/val/targets.csv" -- "$replay" --data "$work/none" --quick 5
if [ -n "$map" ]; then
  expect 2 "--max-offset" -- "$map" --max-offset -1
  expect 2 "--max-yaw" -- "$map" --max-yaw nan
  expect 2 "--offset-step" -- "$map" --offset-step 0
  expect 2 "whole numbers" -- "$map" --max-offset 3 --offset-step 2
  expect 2 "--seed" -- "$map" --seed abc
  expect 2 "$work/none.json" -- "$map" --model-card "$work/none.json"
  expect 2 "$work/none/map.csv" -- "$map" --out "$work/none/map.csv" --observations gaussian
  expect 2 "--bogus" -- "$map" --bogus
  expect 0 "Exit status" -- "$map" --help
fi

if [ -f "$data/val/targets.csv" ] && [ -f "$data/train/targets.csv" ] && [ -f "$models/train_val/gdn.onnx" ]; then
  # Every image of the data set replaced by an empty file: the first observation fails.
  for split in train val; do
    mkdir -p "$work/broken/$split/processed_images"
    cp "$data/$split/targets.csv" "$data/$split/processed_image_params.json" "$work/broken/$split/"
    (cd "$data/$split/processed_images" && for f in *.png; do : >"$work/broken/$split/processed_images/$f"; done)
  done
  expect 2 "$work/broken/" -- "$demo" --data "$work/broken" --observations real --quick --trials 1 --no-files
  [ -z "$map" ] || expect 2 "$work/broken/" -- "$map" --data "$work/broken" --observations real --max-offset 0 --max-yaw 0
  # The deployed GDN with its first 4 KB zeroed, under its own card: refused by its SHA-256.
  mkdir -p "$work/model"
  cp "$models/train_val/model_card.json" "$models/train_val/held_out.csv" "$models/train_val/gdn.onnx" "$work/model/"
  dd if=/dev/zero of="$work/model/gdn.onnx" bs=4096 count=1 conv=notrunc 2>/dev/null
  expect 2 "SHA-256" -- "$demo" --model-card "$work/model/model_card.json" --quick --trials 1 --no-files
  # --cache naming a file that is not a cache: refused, the file left byte for byte as it was.
  printf 'a user'"'"'s notes\n' >"$work/notes.txt"
  cp "$work/notes.txt" "$work/notes.orig"
  expect 2 "not a lieservo_replay cache" -- "$replay" --data "$data" --models "$models/train_val" --quick 5 --no-cnn --cache "$work/notes.txt"
  cmp -s "$work/notes.txt" "$work/notes.orig" || { echo "FAIL: --cache changed $work/notes.txt"; fails=$((fails + 1)); }
  # A corrupted params file in val.
  mkdir -p "$work/params"
  for split in train val; do
    mkdir -p "$work/params/$split"
    cp "$data/$split/targets.csv" "$data/$split/processed_image_params.json" "$work/params/$split/"
    ln -s "$data/$split/processed_images" "$work/params/$split/processed_images"
  done
  printf '{"gray": true, "bbox": [105, 20, 5' >"$work/params/val/processed_image_params.json"
  expect 2 "$work/params/val/processed_image_params.json" -- "$demo" --data "$work/params" --observations real --quick --trials 1 --no-files
else
  echo "note: the TacTip data set or the deployed GDN is absent ($data, $models): the unreadable-image,"
  echo "      corrupted-model and corrupted-params cases are skipped"
fi
[ "$fails" -eq 0 ] || { echo "programs.bad_input: $fails case(s) failed"; exit 1; }
echo "programs.bad_input: every case refused as expected"
