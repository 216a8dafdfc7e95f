#!/bin/sh
# check_generated.sh SYMREC [SEED] [INDICES] [COUNT]: accuracy on parts nobody tuned to. Draws a
# fixed sample of random parts with ../shared/partgen (two per family, none of them
# `hard`), reconstructs each from its posed and its noisy scan with SYMREC, and scores
# the files written with ../shared/eval/runparts --strict (patch file volume within 5 %,
# fill outside the intact part <= 3 %, missed <= 5 %, restored mean <= 0.05 mm and
# max <= 1 mm). One line per input in the test runner's format; exit 1 if any part is
# out of bounds. The parts are made once into build/partgen-SEED (a seed gives the same
# parts byte for byte). Skipped, with a line saying so, without ../shared or OpenSCAD.
# With SEED, INDICES and COUNT it checks chosen parts of another draw: the Makefile runs
# the parts of fresh seeds that once failed (a class fixed stays fixed).
set -u
symrec=${1:?usage: check_generated.sh SYMREC [SEED] [INDICES] [COUNT]}
seed=${2:-777}
# of 16 drawn (the draw depends on the count): two per family, none of them hard
only=${3:-3,4,5,6,7,8,13,14}
shared=$(cd "$(dirname "$0")/../../.." && pwd)/shared
gen=$shared/partgen/partgen
runparts=$shared/eval/runparts
if [ ! -x "$gen" ] || [ ! -x "$runparts" ] || ! command -v openscad >/dev/null 2>&1 ||
   ! /usr/bin/python3 -c 'import numpy, scipy' 2>/dev/null; then
    echo "partgen_check  skipped: no ../shared/partgen, OpenSCAD or python3-numpy/scipy"
    exit 0
fi
count=${4:-16}
dir=build/partgen-$seed-$count
mkdir -p "$dir"
if [ "$(ls "$dir"/*/truth.json 2>/dev/null | wc -l)" -lt "$(echo "$only" | tr ',' '\n' | wc -l)" ]; then
    "$gen" --seed "$seed" --count "$count" --only "$only" --out "$dir" --jobs 2 >"$dir.log" 2>&1 ||
        { echo "partgen_check  FAILED: partgen --seed $seed did not draw the sample (see $dir.log)"; exit 1; }
fi
names=$(for i in $(echo "$only" | tr ',' ' '); do ls "$dir" | grep "^s${seed}p$(printf %02d "$i")_"; done | paste -sd, -)
# posed and noisy side by side: a reconstruct is mostly one thread, the machine has two
# (runparts gives each run a folder of its own)
for input in damaged_posed.stl damaged_scan.stl; do
    (
        start=$(date +%s)
        "$runparts" "$symrec" "$dir" --strict --only "$names" --input "$input" --timeout 300 \
            >"$dir.$input.txt" 2>&1
        echo "$? $(( $(date +%s) - start ))" >"$dir.$input.rc"
    ) &
done
wait
rc=0
for input in damaged_posed.stl damaged_scan.stl; do
    out=$dir.$input.txt
    read -r r secs <"$dir.$input.rc" || { r=1; secs=0; }
    pass=$(grep -c ' ok ' "$out")
    total=$(grep -c '^s[0-9]*p' "$out")
    if [ "$r" -eq 0 ]; then
        printf '%-14s %3d passed, %d failed  ok  (%ss)\n' "partgen[$seed ${input%%.stl}]" "$pass" 0 "$secs"
    else
        printf '%-14s %3d passed, %d failed  FAILED  (%ss)\n' "partgen[$seed ${input%%.stl}]" "$pass" $((total - pass)) "$secs"
        grep -v ' ok ' "$out" | sed 's/^/    | /'
        rc=1
    fi
done
exit $rc
