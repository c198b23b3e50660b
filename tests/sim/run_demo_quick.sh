#!/bin/sh
# demo.quick: runs the shortened main job (lieservo_demo --quick --trials 1) into OUT_DIR and
# checks what a user opens: one trial per case, exit status 0 (every task met its criteria; 1, a missed criterion,
# fails the test like a set-up error, 2, or a sanitizer's abort), and OUT_DIR/index.html
# embedding every figure written (SVG, PNG; none empty) and linking every CSV log.
# Usage: run_demo_quick.sh LIESERVO_DEMO OUT_DIR
set -u
demo=$1
out=$2
log="$out.stdout.txt"  # beside the folder: the demo writes only into a folder of its own
rm -rf "$out"
"$demo" --quick --trials 1 --out "$out" >"$log" 2>&1
rc=$?
cat "$log"
if [ "$rc" -ne 0 ]; then echo "demo.quick: lieservo_demo exited with $rc"; exit 1; fi
# --trials given beside --quick is kept (--quick alone means 2).
grep -q "x 1 trials" "$log" || { echo "demo.quick: --trials 1 was not kept beside --quick"; exit 1; }
page="$out/index.html"
[ -s "$page" ] || { echo "demo.quick: no $page"; exit 1; }
figures=0
for f in $(cd "$out" && find . -name '*.svg' -o -name '*.png' -o -name '*.csv' | sed 's|^\./||'); do
  [ -s "$out/$f" ] || { echo "demo.quick: $f is empty"; exit 1; }
  grep -qF "\"$f\"" "$page" || { echo "demo.quick: index.html does not show $f"; exit 1; }
  case "$f" in *.csv) ;; *) figures=$((figures + 1)) ;; esac
done
[ "$figures" -ge 10 ] || { echo "demo.quick: only $figures figures"; exit 1; }
echo "demo.quick: exit status $rc, index.html shows $figures figures and every log"
