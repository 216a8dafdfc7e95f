#!/bin/sh
# big_scan_bench.sh SYMREC: the default method on a noisy scan of about a million
# triangles (issue 15's target: under 10 s wall, peak memory under 3x the mesh).
# The scan is the shared chipped shaft densified the way ../shared/parts/tools does
# (conforming midpoint splits until every edge is <= SYMREC_BIG_EDGE_MM, default 0.37,
# about 1.0M triangles; then posed, with N(0, 0.02 mm) noise on every vertex), made once
# into build/bench-big/. Prints the triangle count, the wall time and peak RSS of
# `symrec reconstruct --mesh` (and of `symrec check` on the same file, the cost of
# reading it), the phases, the peak RSS against the mesh's size in memory (24 bytes a
# vertex, 12 a triangle), and the patch volume against truth.json; then the same for the
# scan opened as a scanner delivers it (base off, holes, strays). Skipped, with a line
# saying so, without ../shared or python3-numpy.
set -u
symrec=${1:?usage: big_scan_bench.sh SYMREC}
shared=$(cd "$(dirname "$0")/../../.." && pwd)/shared
part=$shared/parts/shaft_chipped_shoulder
tool=$shared/parts/tools/parttool.py
echo "big noisy scan: about 1M triangles, default method"
if [ ! -f "$part/meta.json" ] || [ ! -f "$tool" ] ||
   ! /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
    echo "  skipped: no ../shared/parts or python3-numpy"
    exit 0
fi
edge=${SYMREC_BIG_EDGE_MM:-0.37}
dir=build/bench-big/shaft_$edge
if [ ! -f "$dir/damaged_scan.stl" ]; then
    rm -rf "$dir" && mkdir -p "$dir" || exit 1
    cp "$part"/intact.stl "$part"/damaged.stl "$part"/missing.stl "$part"/meta.json "$dir"/ &&
        chmod u+w "$dir"/* || exit 1
    /usr/bin/python3 - "$dir/meta.json" "$edge" <<'PY' || exit 1
import json, sys
m = json.load(open(sys.argv[1]))
m['scan_max_edge_mm'] = float(sys.argv[2])
json.dump(m, open(sys.argv[1], 'w'), indent=2)
PY
    /usr/bin/python3 "$tool" "$dir" >"$dir.log" 2>&1 || { echo "  FAILED: parttool (see $dir.log)"; exit 1; }
fi
out=$(mktemp -d /tmp/symrec-big-XXXXXX) || exit 1
trap 'rm -rf "$out"' EXIT
/usr/bin/time -o "$out/check.time" -f "%e %M" "$symrec" check "$dir/damaged_scan.stl" \
    >/dev/null 2>&1
/usr/bin/time -o "$out/recon.time" -f "%e %M" "$symrec" --db "$out/cat.db" reconstruct \
    --mesh "$dir/damaged_scan.stl" --symmetry axial --out "$out/res" --no-record --json \
    >"$out/recon.json" 2>"$out/recon.err" || { echo "  FAILED: reconstruct"; sed 's/^/    | /' "$out/recon.err"; exit 1; }
/usr/bin/python3 - "$dir" "$out" <<'PY'
import json, os, struct, sys
d, out = sys.argv[1], sys.argv[2]
truth = json.load(open(os.path.join(d, 'truth.json')))
r = json.load(open(os.path.join(out, 'recon.json')))
tri = truth['triangles']['damaged_scan.stl']
verts = tri // 2 + 1                       # a closed genus-0 surface
mesh_mb = (24 * verts + 12 * tri) / 1e6
cw, ck = (float(x) for x in open(os.path.join(out, 'check.time')).read().split())
rw, rk = (float(x) for x in open(os.path.join(out, 'recon.time')).read().split())
t = r['timings']
phases = ', '.join(f"{k[:-2]} {v:.2f}" for k, v in t.items() if k.endswith('_s') and k != 'total_s' and v >= 0.005)
want = truth['missing_volume']
got = r['patch_volume_mm3']
print(f"  scan: {tri:,} triangles, {mesh_mb:.1f} MB in memory (noise sigma {truth['scan']['noise_sigma_mm']} mm)")
print(f"  read + check (symrec check): {cw:.2f} s wall, peak {ck / 1024:.0f} MB")
print(f"  reconstruct: {rw:.2f} s wall (target < 10 s: {'met' if rw < 10 else 'MISSED by %.1f s' % (rw - 10)}), "
      f"{rw / max(cw, 1e-3):.1f}x the read")
print(f"    phases (s): {phases}")
print(f"  peak memory: {rk / 1024:.0f} MB = {rk * 1024 / 1e6 / mesh_mb:.1f}x the mesh "
      f"(target < 3x: {'met' if rk * 1024 / 1e6 < 3 * mesh_mb else 'MISSED'})")
print(f"  patch volume: {got:.1f} mm3 against {want:.1f} mm3 true ({100 * (got - want) / want:+.2f} %)")
PY

# The same scan as a scanner delivers it (issue 16): its base left off, occlusion holes
# and strays (tests/partgen/open_scan.py, made once beside it); the target is the
# closed scan's scaled by its size (10 s and 3x the mesh per million triangles).
echo "big open scan: the scan above, open, holed, with strays (tests/partgen/open_scan.py)"
open_dir=build/bench-big/open_$edge
if [ ! -f "$open_dir/$(basename "$dir")/open_scan.stl" ]; then
    rm -rf "$open_dir" &&
        /usr/bin/python3 "$(dirname "$0")/../partgen/open_scan.py" "$dir" --out "$open_dir" \
            >"$open_dir.log" 2>&1 || { echo "  FAILED: open_scan.py (see $open_dir.log)"; exit 1; }
fi
open_scan=$open_dir/$(basename "$dir")/open_scan.stl
/usr/bin/time -o "$out/open.time" -f "%e %M" "$symrec" --db "$out/cat.db" reconstruct \
    --mesh "$open_scan" --symmetry axial --out "$out/open" --no-record --json \
    >"$out/open.json" 2>"$out/open.err" || { echo "  FAILED: reconstruct"; sed 's/^/    | /' "$out/open.err"; exit 1; }
/usr/bin/python3 - "$dir" "$out" <<'PY'
import json, os, sys
d, out = sys.argv[1], sys.argv[2]
truth = json.load(open(os.path.join(d, 'truth.json')))
r = json.load(open(os.path.join(out, 'open.json')))
g = r['scan_gaps']
tri = g['triangles']
mesh_mb = (24 * (tri // 2 + 1) + 12 * tri) / 1e6
w, k = (float(x) for x in open(os.path.join(out, 'open.time')).read().split())
t = r['timings']
target = 10 * tri / 1e6
want, got = truth['missing_volume'], r['patch_volume_mm3']
print(f"  scan: {tri:,} triangles, {g['boundary_edges']} boundary edges in {len(g['gaps'])} gaps, "
      f"{g['strays']} strays ({g['stray_triangles']} triangles) dropped, "
      f"{g['sealed_triangles']} triangles sealed")
print(f"  reconstruct: {w:.2f} s wall (scaled target < {target:.1f} s: "
      f"{'met' if w < target else 'MISSED by %.1f s' % (w - target)}); "
      f"reading {t['read_s']:.2f} s, closing the scan {t['scan_s']:.2f} s, the method "
      f"{t['total_s']:.2f} s, writing and the rest {w - t['read_s'] - t['scan_s'] - t['total_s']:.2f} s")
print(f"  peak memory: {k / 1024:.0f} MB = {k * 1024 / 1e6 / mesh_mb:.1f}x the mesh")
print(f"  sections: {len(r['sections'])}; patch volume {got:.1f} mm3 against {want:.1f} mm3 true "
      f"({100 * (got - want) / want:+.2f} %)")
PY
