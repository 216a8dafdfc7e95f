#!/bin/sh
# nominal_bench.sh SYMREC [PARTS_DIR] [INPUT]: the nominal's second opinion against
# truth for `make bench` (issue 19, item 3). For every part of PARTS_DIR (default, or
# empty: ../shared/parts) a catalogue with the part's intact.stl and the instance INPUT
# (default damaged_posed.stl; damaged_scan.stl for the noisy scans, which `make bench`
# runs too) is made in a
# temporary folder, `reconstruct --json` runs, and the nominal's missing volume is set
# beside truth.json's missing_volume: the error in %, PASS within 2 %. Also the
# symmetry's volume, the registration's coverage, the flag and the seconds the
# nominal took. Prints one line per part and the pass count.
set -u
symrec=${1:?usage: nominal_bench.sh SYMREC [PARTS_DIR] [INPUT]}
symrec=$(cd "$(dirname "$symrec")" && pwd)/$(basename "$symrec")
parts=${2:-$(cd "$(dirname "$0")/../../.." && pwd)/shared/parts}
input=${3:-damaged_posed.stl}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "nominal vs truth: $parts ($input)"
for d in "$parts"/*/; do
    p=$(basename "$d")
    [ -f "$d/truth.json" ] && [ -f "$d/intact.stl" ] && [ -f "$d/$input" ] || continue
    sym=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["symmetry"])' "$d/truth.json")
    kind=$sym; extra=""
    case $sym in
    axial|cyclic) kind=axial; extra="--order auto" ;;
    esac
    db=$tmp/$p.db
    "$symrec" --db "$db" catalog init >/dev/null 2>&1
    "$symrec" --db "$db" part add --number P --name "$p" --material C45 \
        --mesh "$d/intact.stl" >/dev/null 2>&1
    "$symrec" --db "$db" instance add --part P --mesh "$d/$input" >/dev/null 2>&1
    "$symrec" --quiet --db "$db" reconstruct 1 --symmetry "$kind" $extra --no-record --json \
        >"$tmp/$p.json" 2>"$tmp/$p.err"
    /usr/bin/python3 - "$p" "$tmp/$p.json" "$d/truth.json" "$tmp/$p.err" <<'PY'
import json, sys
name, out, truth, errf = sys.argv[1:]
t = json.load(open(truth))["missing_volume"]
try:
    r = json.load(open(out))
except Exception:
    print("%-28s FAIL  reconstruct: %s" % (name, open(errf).read().strip()[:100]))
    sys.exit(0)
n = r.get("nominal")
if not n:
    print("%-28s FAIL  no nominal" % name)
    sys.exit(0)
e = 100.0 * (n["nominal_mm3"] - t) / t
print("%-28s %s  truth %9.1f  nominal %9.1f (%+6.2f %%)  symmetry %9.1f  coverage %5.1f %%  "
      "pieces %d  only-symmetry %d  %s%.2f s" % (
      name, "PASS" if abs(e) <= 2 else "FAIL", t, n["nominal_mm3"], e, n["symmetry_mm3"],
      100 * n["coverage"], len(n["pieces"]),
      sum(1 for s in n["sections"] if s["pieces"] == 0),
      "POOR " if n["poor"] else "", n["seconds"]))
PY
done | tee "$tmp/all.txt"
echo "passed $(grep -c ' PASS ' "$tmp/all.txt") of $(wc -l <"$tmp/all.txt") within 2 %"
