#!/bin/sh
# symmetry_bench.sh SYMREC [DIR...]: `symrec symmetry` (the fit behind
# `reconstruct --symmetry auto`) on the nine shared parts, posed and noisy, and on the
# generated parts of each DIR (partgen layout: DIR/<part>/meta.json with the truth;
# default: the set partgen_bench.sh drew for today's seed, build/bench-partgen-SEED,
# when it is there). Prints per part the truth, the proposal, the consistency of every
# kind, the confidence and the time, then right / total per family, posed and noisy.
# Right: the kind; an axial part's order when the truth gives one, else continuous
# (the shared flange may be 6-fold: its six bolt holes make it so); a glide's shift an
# odd multiple of the truth's within 2 %. "ambiguous" counts as wrong.
set -u
symrec=${1:?usage: symmetry_bench.sh SYMREC [DIR...]}
shift
shared=$(cd "$(dirname "$0")/../../.." && pwd)/shared
if [ $# -eq 0 ]; then
    seed=${SYMREC_BENCH_SEED:-$(date +%Y%m%d)}
    set -- "build/bench-partgen-$seed"
fi
echo "section 5: symmetry auto (symrec symmetry --json), shared parts and generated sets"
/usr/bin/python3 - "$symrec" "$shared/parts" "$@" <<'PY'
import json, os, subprocess, sys, time
symrec, shared, dirs = sys.argv[1], sys.argv[2], sys.argv[3:]
cases = []  # (family, part dir, mesh file, name)
if os.path.isdir(shared):
    for p in sorted(os.listdir(shared)):
        if os.path.isfile(os.path.join(shared, p, 'meta.json')):
            cases.append(('shared', os.path.join(shared, p), p))
for d in dirs:
    if not os.path.isdir(d):
        print(f"  {d}: no such set, skipped")
        continue
    for p in sorted(os.listdir(d)):
        if os.path.isfile(os.path.join(d, p, 'meta.json')):
            m = json.load(open(os.path.join(d, p, 'meta.json')))
            cases.append((m.get('generator', {}).get('family', m['symmetry']), os.path.join(d, p), p))

def truth_of(pd):
    m = json.load(open(os.path.join(pd, 'meta.json')))
    return m['symmetry'], m.get('order') or 0, m.get('glide_shift_mm') or 0

def right(t, f, name):
    kind, order, shift = t
    p = f['proposal']
    if f['ambiguous'] or p['kind'] != kind:
        return False
    if kind == 'axial':
        if order:
            return p['order'] == order
        return p['order'] == 0 or (name == 'flange_broken_rim' and p['order'] == 6)
    if kind == 'glide':
        k = p['shift_mm'] / shift
        return abs(k - round(k)) < 0.02 and round(k) % 2 == 1
    return True

def sym_str(kind, order, shift):
    return kind + (f" {order}-fold" if order else "") + (f" {shift:.2f} mm" if shift else "")

tally = {}
times = []
print(f"  {'part':34s} {'input':6s} {'truth':18s} {'proposal':26s} {'ax':>5s} {'n-fold':>9s} {'mir':>5s} {'glide':>5s} {'conf':>4s} {'s':>5s}")
for fam, pd, name in cases:
    t = truth_of(pd)
    for inp, tag in (('damaged_posed.stl', 'posed'), ('damaged_scan.stl', 'noisy')):
        mesh = os.path.join(pd, inp)
        if not os.path.isfile(mesh):
            continue
        t0 = time.time()
        r = subprocess.run([symrec, '--quiet', 'symmetry', '--mesh', mesh, '--json'],
                           capture_output=True, text=True)
        dt = time.time() - t0
        key = (fam, tag)
        tally.setdefault(key, [0, 0])[1] += 1
        if r.returncode != 0:
            print(f"  {name[:34]:34s} {tag:6s} error: {r.stderr.strip()[:80]}")
            continue
        f = json.loads(r.stdout)['symmetry_fit']
        ok = right(t, f, name)
        tally[key][0] += ok
        times.append(f['seconds'])
        p = f['proposal']
        prop = ('ambiguous ' if f['ambiguous'] else '') + sym_str(p['kind'], p.get('order', 0), p.get('shift_mm', 0))
        c = f['consistency']
        nf = f"{c['axial_nfold']:.3f}({f['order_found']})" if c['axial_nfold'] is not None else '-'
        print(f"  {name[:34]:34s} {tag:6s} {sym_str(*t):18s} {prop[:26]:26s} {c['axial']:5.3f} {nf:>9s} "
              f"{c['mirror']:5.3f} {c['glide']:5.3f} {f['confidence']:4.2f} {f['seconds']:5.2f}"
              f"{'' if ok else '  WRONG'}", flush=True)
print("  right / total:")
for tag in ('posed', 'noisy'):
    row = [f"{fam} {tally[fam, tag][0]}/{tally[fam, tag][1]}" for fam in
           ('shared', 'axial', 'cyclic', 'mirror', 'glide') if (fam, tag) in tally]
    gen = [tally[k] for k in tally if k[1] == tag and k[0] != 'shared']
    g = f", generated {sum(a for a, _ in gen)}/{sum(b for _, b in gen)}" if gen else ""
    print(f"    {tag}: " + ", ".join(row) + g)
if times:
    times.sort()
    print(f"  fit time: median {times[len(times) // 2]:.2f} s, max {times[-1]:.2f} s")
PY
