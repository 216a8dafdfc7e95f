#!/bin/sh
# check_generated.sh SYMREC [SEED:INDICES:COUNT ...]: accuracy on parts nobody tuned to.
# Draws samples of random parts with ../shared/partgen, reconstructs each from its posed
# and its noisy scan with SYMREC, and scores the files written with ../shared/eval/runparts
# --strict (patch file volume within 5 %, fill outside the intact part <= 3 %, missed
# <= 5 %, restored mean <= 0.05 mm and max <= 1 mm). Without a sample it checks seed 777's
# parts 3,4,5,6,7,8,13,14 of 16 (two per family, none of them `hard`; make check takes one
# per family, 3,4,5,6); the Makefile adds
# the parts of fresh seeds that once failed (a class fixed stays fixed). The old form
# `check_generated.sh SYMREC SEED [INDICES] [COUNT]` still checks one sample.
# A sample SEED:INDICES:COUNT:open is checked on open scans instead: each part's noisy
# scan opened as a scanner delivers it by tests/partgen/open_scan.py (seed 4242, into
# build/partgen-SEED-COUNT-open) and reconstructed from open_scan.stl.
# `check_generated.sh --draw-only SEED:INDICES:COUNT ...` only draws the samples (make
# check runs it in the background at idle priority from its start, so the drawing uses
# the CPU the other stages leave idle and partgen-check finds its parts made).
#
# Every part is made once into build/partgen-SEED-COUNT (a seed gives the same parts byte
# for byte). The reconstructions of all samples then run as one queue, two at a time
# (a reconstruct is mostly one thread and the machine has two; runparts gives each run a
# folder of its own), the noisy scans first since they take longest, so neither CPU idles
# while the other finishes a seed. One line per sample and input in the test runner's
# format, then the failures' lines; exit 1 if any part is out of bounds. Skipped, with a
# line saying so, without ../shared, OpenSCAD or python3-numpy/scipy.
set -u
symrec=${1:?usage: check_generated.sh SYMREC|--draw-only [SEED:INDICES:COUNT ...]}
shift
draw_only=false
[ "$symrec" = --draw-only ] && draw_only=true
case $# in
    0) set -- "777:3,4,5,6,7,8,13,14:16" ;;
    *) case $1 in *:*) ;; *) set -- "$1:${2:-3,4,5,6,7,8,13,14}:${3:-16}" ;; esac ;;
esac
shared=$(cd "$(dirname "$0")/../../.." && pwd)/shared
gen=$shared/partgen/partgen
runparts=$shared/eval/runparts
if [ ! -x "$gen" ] || [ ! -x "$runparts" ] || ! command -v openscad >/dev/null 2>&1 ||
   ! /usr/bin/python3 -c 'import numpy, scipy' 2>/dev/null; then
    echo "partgen_check  skipped: no ../shared/partgen, OpenSCAD or python3-numpy/scipy"
    exit 0
fi
case $symrec in /* | --draw-only) ;; *) symrec=$(pwd)/$symrec ;; esac
logs=$(mktemp -d /tmp/symrec-partgen-check-XXXXXX) || exit 2
trap 'rm -rf "$logs"' EXIT
trap 'exit 130' INT TERM

# Draw every sample first (partgen runs two OpenSCADs at a time itself); a sample's
# folder name and part names go to $logs/samples as "SEED DIR NAME,NAME,...".
for spec in "$@"; do
    seed=${spec%%:*}
    rest=${spec#*:}
    only=${rest%%:*}
    count=${rest#*:}
    inputs="damaged_scan.stl damaged_posed.stl"
    case $count in *:open) count=${count%:open}; inputs=open_scan.stl ;; esac
    case "$seed$count" in ''|*[!0-9]*)
        echo "partgen_check  FAILED: '$spec' is not SEED:INDICES:COUNT"; exit 1 ;;
    esac
    dir=build/partgen-$seed-$count
    mkdir -p "$dir"
    if [ "$(ls "$dir"/*/truth.json 2>/dev/null | wc -l)" -lt "$(echo "$only" | tr ',' '\n' | wc -l)" ]; then
        "$gen" --seed "$seed" --count "$count" --only "$only" --out "$dir" --jobs 2 >"$dir.log" 2>&1 ||
            { echo "partgen_check  FAILED: partgen --seed $seed did not draw the sample (see $dir.log)"; exit 1; }
    fi
    names=$(for i in $(echo "$only" | tr ',' ' '); do ls "$dir" | grep "^s${seed}p$(printf %02d "$i")_"; done | paste -sd, -)
    if [ "$inputs" = open_scan.stl ]; then
        # the scans as a scanner delivers them (tests/partgen/open_scan.py, its seed fixed)
        open=$dir-open
        for name in $(echo "$names" | tr ',' ' '); do
            [ -f "$open/$name/open_scan.stl" ] && continue
            /usr/bin/python3 "$(dirname "$0")/open_scan.py" "$dir/$name" --out "$open" --seed 4242 \
                >>"$open.log" 2>&1 ||
                { echo "partgen_check  FAILED: open_scan.py did not open $name (see $open.log)"; exit 1; }
        done
        dir=$open
    fi
    echo "$seed $dir $names $inputs" >>"$logs/samples"
done
$draw_only && exit 0

# The queue: one job per part and input, the noisy scans first, two at a time on one
# OpenMP thread each (two reconstructions fill the CPUs; more threads would queue).
[ -n "${OMP_NUM_THREADS:-}" ] || { OMP_NUM_THREADS=1; export OMP_NUM_THREADS; }
for input in damaged_scan.stl open_scan.stl damaged_posed.stl; do
    while read -r seed dir names inputs; do
        case " $inputs " in *" $input "*) ;; *) continue ;; esac
        for name in $(echo "$names" | tr ',' ' '); do echo "$dir $name $input"; done
    done <"$logs/samples"
done | xargs -P 2 -L 1 sh -c '
    logs=$1; symrec=$2; runparts=$3; dir=$4; name=$5; input=$6
    start=$(date +%s)
    "$runparts" "$symrec" "$dir" --strict --only "$name" --input "$input" --timeout 300 \
        >"$logs/$name.$input.txt" 2>&1
    echo "$? $(( $(date +%s) - start ))" >"$logs/$name.$input.rc"
' sh "$logs" "$symrec" "$runparts"

rc=0
while read -r seed dir names inputs; do
    for input in $inputs; do
        pass=0 fail=0 secs=0 bad=
        for name in $(echo "$names" | tr ',' ' '); do
            out=$logs/$name.$input.txt
            read -r r s <"$logs/$name.$input.rc" 2>/dev/null || { r=1; s=0; }
            secs=$((secs + s))
            if [ "$r" -eq 0 ] && grep -q ' ok ' "$out"; then
                pass=$((pass + 1))
            else
                fail=$((fail + 1))
                bad="$bad $out"
            fi
        done
        if [ "$fail" -eq 0 ]; then
            printf '%-14s %3d passed, %d failed  ok  (%ss)\n' "partgen[$seed ${input%%.stl}]" "$pass" 0 "$secs"
        else
            printf '%-14s %3d passed, %d failed  FAILED  (%ss)\n' "partgen[$seed ${input%%.stl}]" "$pass" "$fail" "$secs"
            for out in $bad; do grep -v ' ok ' "$out" | sed 's/^/    | /'; done
            rc=1
        fi
    done
done <"$logs/samples"
exit $rc
