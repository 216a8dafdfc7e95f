#!/bin/sh
# partgen_bench.sh SYMREC [SEED]: accuracy on random parts for `make bench`. Draws 48
# parts of every family with ../shared/partgen from SEED (default: from the date, so it
# varies; printed), reconstructs each from its posed and its noisy scan with the
# default (image) method and with the paper's, scores the files written with
# ../shared/eval/runparts --strict, and prints pass rates per family, posed and noisy,
# `hard` parts (damage without an intact counterpart) apart.
set -u
symrec=${1:?usage: partgen_bench.sh SYMREC [SEED]}
seed=${2:-${SYMREC_BENCH_SEED:-$(date +%Y%m%d)}}
count=${SYMREC_BENCH_PARTS:-48}
shared=$(cd "$(dirname "$0")/../../.." && pwd)/shared
if [ ! -x "$shared/partgen/partgen" ] || ! command -v openscad >/dev/null 2>&1; then
    echo "section 4 (random parts): skipped, no ../shared/partgen or OpenSCAD"
    exit 0
fi
dir=build/bench-partgen-$seed
echo "section 4: random parts, partgen --seed $seed --count $count (runparts --strict)"
[ -f "$dir/README.md" ] || "$shared/partgen/partgen" --seed "$seed" --count "$count" \
    --out "$dir" --jobs 2 >"$dir.log" 2>&1 || { echo "  partgen failed (see $dir.log)"; exit 1; }
for method in image paper; do
    for input in damaged_posed.stl damaged_scan.stl; do
        "$shared/eval/runparts" "$symrec" "$dir" --strict --input "$input" --timeout 300 \
            --extra "--method $method" --json "$dir.$method.$input.json" >"$dir.$method.$input.txt" 2>&1
    done
done
/usr/bin/python3 - "$dir" <<'PY'
import json, os, sys
d = sys.argv[1]
hard = {p: json.load(open(os.path.join(d, p, 'meta.json'))).get('hard', False)
        for p in os.listdir(d) if os.path.isfile(os.path.join(d, p, 'meta.json'))}
fam = lambda p: p.split('_')[1]
print(f"  {'family':8s} {'parts':>5s}   {'image posed':>11s} {'image noisy':>11s}   {'paper posed':>11s} {'paper noisy':>11s}")
rows = {}
for m in ('image', 'paper'):
    for i in ('damaged_posed.stl', 'damaged_scan.stl'):
        f = f"{d}.{m}.{i}.json"
        rows[m, i] = {r['part']: r['ok'] for r in json.load(open(f))} if os.path.exists(f) else {}
for group in ('axial', 'cyclic', 'mirror', 'glide', 'all', 'hard'):
    parts = [p for p in hard if (hard[p] if group == 'hard' else not hard[p] and group in ('all', fam(p)))]
    cells = []
    for m in ('image', 'paper'):
        for i in ('damaged_posed.stl', 'damaged_scan.stl'):
            ok = sum(rows[m, i].get(p, False) for p in parts)
            cells.append(f"{ok:3d}/{len(parts):<3d} {100 * ok / max(len(parts), 1):3.0f}%")
    print(f"  {group:8s} {len(parts):5d}   {cells[0]:>11s} {cells[1]:>11s}   {cells[2]:>11s} {cells[3]:>11s}")
PY
echo "  (per-part rows: $dir.<method>.<input>.txt)"
