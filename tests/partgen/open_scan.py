#!/usr/bin/python3
"""open_scan.py: turn a part's closed noisy scan into one as a scanner delivers it, with truth.

usage: open_scan.py PART_DIR [PART_DIR ...] --out SETDIR [--seed N] [--name open_scan]
                    [--from damaged_scan.stl] [--holes 10,30] [--strays 24,48] [--uneven]
                    [--no-base]

PART_DIR is a part folder in the layout of ../shared/parts (a shared part or one made by
../shared/partgen): truth.json (pose, sections), missing.stl and the posed scan. For each
part, SETDIR/<part>/ gets symbolic links to the part's own files (so ../shared/eval/runparts
SETDIR --input NAME.stl scores it against the part's truth; nothing in PART_DIR is changed),
and two files of its own:

  NAME.stl   the scan (binary STL, posed frame like the input): the face the part stood on is
             gone (the triangles at the canonical minimum z whose normal points down within
             8 degrees, or a 1 mm slab at the bottom when there is no such face); 10-30
             occlusion holes of 1-4 mm diameter cut into the surface at least 4 mm away from
             the damage (missing.stl) and from one another; a few dozen stray triangles and
             small islands 1.5-12 mm off the surface (a quarter of them under the base, as a
             turntable leaves them); with --uneven, a third of the surface coarsened (its
             vertices snapped to a 2.5 mm grid and the collapsed triangles dropped), so the
             triangle size varies about 10:1. --no-base keeps the base, --holes 0,0 and
             --strays 0,0 leave out the holes or the strays (to see which one matters).
  NAME.json  the truth: the base opening (triangles, area, the canonical z it lay at), every
             hole (centre in posed and canonical frames, diameter drawn, triangles and area
             removed), every stray island (centre, triangles, area, distance to the surface),
             and the boundary loops of the written scan (edges, length mm, which hole or the
             base they belong to).

Deterministic: the same seed, part and input give the same files byte for byte (the draw of
a part depends on the seed and the part's name, not on the other parts listed).
Needs numpy and scipy (Debian python3-numpy, python3-scipy); runs under /usr/bin/python3.
"""
import argparse
import json
import os
import struct
import sys
import zlib

import numpy as np
from scipy.spatial import cKDTree

REC = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])


def read_stl(path):
    """(V, F) of a binary STL, welded by exact coordinates (the shared scans share vertices)."""
    with open(path, "rb") as f:
        data = f.read()
    n = struct.unpack("<I", data[80:84])[0]
    if 84 + 50 * n != len(data):
        sys.exit(f"open_scan: error: '{path}' is not a binary STL")
    tris = np.frombuffer(data, dtype=REC, count=n, offset=84)["v"].astype(np.float64)
    V, inv = np.unique(tris.reshape(-1, 3), axis=0, return_inverse=True)
    return V, inv.reshape(-1, 3).astype(np.int64)


def write_stl(path, tri):
    """tri: (n, 3, 3) posed triangles."""
    t32 = tri.astype(np.float32)
    n = np.cross(t32[:, 1] - t32[:, 0], t32[:, 2] - t32[:, 0]).astype(np.float64)
    ln = np.linalg.norm(n, axis=1)
    ln[ln == 0] = 1.0
    arr = np.zeros(len(t32), dtype=REC)
    arr["n"] = (n / ln[:, None]).astype(np.float32)
    arr["v"] = t32
    with open(path, "wb") as f:
        f.write(b"symrec open scan (tests/partgen/open_scan.py)".ljust(80, b" "))
        f.write(struct.pack("<I", len(t32)))
        f.write(arr.tobytes())


def clean(F, removed, nv):
    """Removes (in place) every kept triangle with two or three edges on the opening, until
    none is left: no spikes into a hole, no lone triangle inside one, one loop per hole."""
    e = np.stack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]], axis=1)  # (n, 3, 2)
    key = e[..., 0] * (nv + 1) + e[..., 1]
    rkey = e[..., 1] * (nv + 1) + e[..., 0]
    while True:
        kept = ~removed
        live = np.isin(rkey, key[kept].ravel())
        open_edges = (~live).sum(axis=1)
        drop = kept & (open_edges >= 2)
        if not drop.any():
            return
        removed |= drop


def tri_geometry(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    n = np.cross(b - a, c - a)
    area2 = np.linalg.norm(n, axis=1)
    unit = n / np.where(area2 > 0, area2, 1.0)[:, None]
    return (a + b + c) / 3.0, unit, area2 / 2.0


def sample_surface(V, F, rng, spacing=0.5):
    """Points on the triangles about `spacing` apart (area-weighted), plus the vertices."""
    _, _, area = tri_geometry(V, F)
    count = int(max(1000, area.sum() / (spacing * spacing)))
    pick = rng.choice(len(F), size=count, p=area / area.sum())
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    a, b, c = V[F[pick, 0]], V[F[pick, 1]], V[F[pick, 2]]
    pts = a + u[:, None] * (b - a) + v[:, None] * (c - a)
    return np.vstack([pts, V])


def boundary_loops(F, V):
    """Boundary loops of a triangle list: [(vertex list, edge count, length)]. A boundary
    edge is a directed edge whose reverse is absent (for a consistently oriented surface
    that is an edge used once); loops are walked along the directed edges."""
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    key = e[:, 0] * (len(V) + 1) + e[:, 1]
    rkey = e[:, 1] * (len(V) + 1) + e[:, 0]
    bnd = e[~np.isin(key, rkey)]
    nxt = {}
    for a, b in bnd:
        nxt.setdefault(int(a), []).append(int(b))
    loops, seen = [], set()
    for a0, b0 in bnd:
        a0, b0 = int(a0), int(b0)
        if (a0, b0) in seen:
            continue
        loop, a, b = [a0], a0, b0
        while (a, b) not in seen:
            seen.add((a, b))
            loop.append(b)
            cand = [x for x in nxt.get(b, []) if (b, x) not in seen]
            if not cand:
                break
            a, b = b, cand[0]
        pts = V[np.array(loop)]
        length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
        loops.append((loop[:-1], len(loop) - 1, length))
    return loops


def uneven(V, F, canon, rng, cell=2.5):
    """Coarsens a third of the surface (a slab across the canonical x range, so both sides
    of a mirror plane are not hit alike): vertices inside snap to one representative per
    cell of a `cell` mm grid, collapsed triangles are dropped. Returns the new F."""
    x = canon[:, 0]
    lo = np.quantile(x, rng.uniform(0.05, 0.6))
    hi = lo + (x.max() - x.min()) / 3.0
    inside = (x >= lo) & (x <= hi)
    cellid = np.floor(canon / cell).astype(np.int64)
    rep = np.arange(len(V))
    keys = {}
    for i in np.nonzero(inside)[0]:
        k = tuple(cellid[i])
        rep[i] = keys.setdefault(k, i)
    G = rep[F]
    keep = (G[:, 0] != G[:, 1]) & (G[:, 1] != G[:, 2]) & (G[:, 2] != G[:, 0])
    G = G[keep]
    # two triangles collapsed onto the same three vertices: keep one
    _, first = np.unique(np.sort(G, axis=1), axis=0, return_index=True)
    return G[np.sort(first)], float(lo), float(hi)


def make_scan(part_dir, out_dir, seed, name, src, holes_rng, strays_rng, use_uneven, no_base):
    pname = os.path.basename(os.path.normpath(part_dir))
    truth = json.load(open(os.path.join(part_dir, "truth.json")))
    R = np.array(truth["pose"]["rotation_matrix_3x3"], dtype=np.float64)
    t = np.array(truth["pose"]["translation"], dtype=np.float64)
    rng = np.random.default_rng([seed, zlib.crc32(pname.encode())])
    V, F = read_stl(os.path.join(part_dir, src))
    C = (V - t) @ R  # canonical: R^T (p - t), row vectors
    record = {"part": pname, "source": src, "seed": seed, "frame": "posed (as the source); "
              "canonical = R^T (p - t) with truth.json's pose"}
    if use_uneven:
        F, lo, hi = uneven(V, F, C, rng)
        record["uneven"] = {"coarsened_canonical_x": [lo, hi], "cell_mm": 2.5}
    cen, nrm, area = tri_geometry(C, F)
    total_area = float(area.sum())
    removed = np.zeros(len(F), dtype=bool)

    # the face the part stood on
    zmin = float(C[:, 2].min())
    zt = C[F, 2].max(axis=1)
    base = (nrm[:, 2] < -np.cos(np.radians(30))) & (zt < zmin + 0.3)
    how = "down-facing triangles at the minimum z"
    if no_base:
        base[:] = False
        how = "kept (--no-base)"
    elif area[base].sum() < 1.0:
        base = zt < zmin + 1.0
        how = "a 1 mm slab at the minimum z"
    removed |= base
    clean(F, removed, len(V))
    base = removed.copy()
    record["base"] = {"how": how, "canonical_z": zmin, "triangles": int(base.sum()),
                      "area_mm2": float(area[base].sum())}

    # distance to the damage: the surface of missing.stl in the canonical frame
    MV, MF = read_stl(os.path.join(part_dir, "missing.stl"))
    damage = cKDTree(sample_surface(MV, MF, rng))
    base_tree = cKDTree(cen[base]) if base.any() else None
    d_damage, _ = damage.query(cen)
    d_base = base_tree.query(cen)[0] if base_tree is not None else np.full(len(F), np.inf)
    tri_tree = cKDTree(cen)

    lo_h, hi_h = holes_rng
    want = int(rng.integers(lo_h, hi_h + 1))
    holes, centres = [], []
    tries = 0
    while len(holes) < want and tries < 5000:
        tries += 1
        diameter = float(rng.uniform(1.0, 4.0))
        r = diameter / 2
        i = int(rng.choice(len(F), p=area / total_area))
        if removed[i] or d_damage[i] < r + 4.0 or d_base[i] < r + 3.0:
            continue
        if any(np.linalg.norm(cen[i] - c) < r + rc + 3.0 for c, rc in centres):
            continue
        near = np.array(tri_tree.query_ball_point(cen[i], r), dtype=np.int64)
        near = near[(nrm[near] @ nrm[i]) > 0.5] if len(near) else near
        cut = np.union1d(near, [i])
        cut = cut[~removed[cut]]
        removed[cut] = True
        centres.append((cen[i], r))
        holes.append({"id": len(holes), "diameter_mm": diameter,
                      "centre_posed": (R @ cen[i] + t).tolist(), "centre_canonical": cen[i].tolist(),
                      "normal_canonical": nrm[i].tolist(), "triangles": int(len(cut)),
                      "area_mm2": float(area[cut].sum()),
                      "distance_to_damage_mm": float(d_damage[i])})

    clean(F, removed, len(V))
    keep = ~removed
    KF = F[keep]
    # which opening each remaining boundary loop belongs to
    loops = []
    hole_c = np.array([h["centre_canonical"] for h in holes]) if holes else np.zeros((0, 3))
    for verts, edges, length in boundary_loops(KF, C):
        p = C[np.array(verts)]
        mid = p.mean(axis=0)
        owner = "other"
        if len(hole_c):
            d = np.linalg.norm(hole_c - mid, axis=1)
            j = int(np.argmin(d))
            if d[j] < holes[j]["diameter_mm"] / 2 + 3.0:
                owner = f"hole {j}"
        if owner == "other" and base.any() and p[:, 2].min() < zmin + 1.5:
            owner = "base"
        loops.append({"edges": edges, "length_mm": length, "of": owner})
    loops.sort(key=lambda x: -x["length_mm"])

    # strays, canonical frame, then posed
    surf = cKDTree(C)
    lo_s, hi_s = strays_rng
    nstray = int(rng.integers(lo_s, hi_s + 1))
    bmin, bmax = C.min(axis=0), C.max(axis=0)
    stray_tris, strays = [], []
    tries = 0
    while len(strays) < nstray and tries < 20000:
        tries += 1
        under = rng.random() < 0.25
        if under:
            c = np.array([rng.uniform(bmin[0], bmax[0]), rng.uniform(bmin[1], bmax[1]),
                          zmin - rng.uniform(1.5, 6.0)])
        else:
            i = int(rng.choice(len(F), p=area / total_area))
            c = cen[i] + nrm[i] * rng.uniform(1.5, 12.0)
        k = int(rng.integers(1, 7))
        size = rng.uniform(0.3, 2.0)
        pts = [c + rng.normal(size=3) * size * 0.5 for _ in range(k + 2)]
        tris = [np.array([pts[0], pts[j + 1], pts[j + 2]]) for j in range(k)]  # a fan
        allp = np.array(pts)
        d = surf.query(allp)[0].min()
        if d < 1.0:
            continue
        ar = sum(0.5 * np.linalg.norm(np.cross(q[1] - q[0], q[2] - q[0])) for q in tris)
        if ar < 1e-3:
            continue
        stray_tris += tris
        strays.append({"centre_posed": (R @ c + t).tolist(), "triangles": k, "area_mm2": float(ar),
                       "distance_to_surface_mm": float(d), "under_base": bool(under)})

    tri = C[KF]
    if stray_tris:
        tri = np.concatenate([tri, np.array(stray_tris)])
    tri_posed = tri @ R.T + t
    os.makedirs(out_dir, exist_ok=True)
    write_stl(os.path.join(out_dir, name + ".stl"), tri_posed)
    record.update({
        "triangles": {"source": int(len(F) + 0), "scan": int(len(tri_posed)),
                      "part": int(len(KF)), "strays": int(len(stray_tris))},
        "area_mm2": {"source": total_area, "removed": float(area[removed].sum()),
                     "open_share": float(area[removed].sum() / total_area)},
        "holes": holes, "strays": strays,
        "stray_summary": {"islands": len(strays), "triangles": len(stray_tris),
                          "area_mm2": float(sum(s["area_mm2"] for s in strays))},
        "boundary_loops": loops,
    })
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(record, f, indent=1)
    for entry in sorted(os.listdir(part_dir)):
        dst = os.path.join(out_dir, entry)
        if entry.startswith(name + ".") or os.path.lexists(dst):
            continue
        os.symlink(os.path.abspath(os.path.join(part_dir, entry)), dst)
    print(f"{pname:32s} {len(tri_posed):7d} triangles, base {int(base.sum())} removed, "
          f"{len(holes)} holes, {len(strays)} stray islands ({len(stray_tris)} triangles), "
          f"{len(loops)} boundary loops, open {100 * area[removed].sum() / total_area:.2f} %")


def pair(text):
    a, b = (int(x) for x in text.split(","))
    return a, b


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("parts", nargs="+")
    ap.add_argument("--out", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--name", default="open_scan")
    ap.add_argument("--from", dest="src", default="damaged_scan.stl")
    ap.add_argument("--holes", type=pair, default=(10, 30))
    ap.add_argument("--strays", type=pair, default=(24, 48))
    ap.add_argument("--uneven", action="store_true")
    ap.add_argument("--no-base", action="store_true", help="keep the face the part stood on")
    a = ap.parse_args()
    for p in a.parts:
        if not os.path.isfile(os.path.join(p, "truth.json")):
            sys.exit(f"open_scan: error: '{p}' is not a part folder (no truth.json)")
        pname = os.path.basename(os.path.normpath(p))
        make_scan(p, os.path.join(a.out, pname), a.seed, a.name, a.src, a.holes, a.strays,
                  a.uneven, a.no_base)


if __name__ == "__main__":
    main()
