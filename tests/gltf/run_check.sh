#!/bin/sh
# run_check.sh OUT: the GLB that reconstruct writes, through the Khronos glTF validator
# (npm package gltf-validator, installed once into SYMREC_NPM_DIR, default BUILD/npm, from
# the npm registry); one job of tests/run_tests.sh, which runs it beside the test binaries.
# The demo instance's result.glb must have no error, and a truncated copy must be caught
# (so the check can fail). Writes "PASSED FAILED" to OUT.counts (or "skip" without node
# and npm) and the failures' lines to OUT. Needs SYMREC_BIN and SYMREC_NPM_DIR.
set -u
out=${1:?usage: run_check.sh OUT}
npm_dir=${SYMREC_NPM_DIR:?}
: >"$out"
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo skip >"$out.counts"
    exit 0
fi
rc=0
if [ ! -f "$npm_dir/node_modules/gltf-validator/package.json" ]; then
    mkdir -p "$npm_dir" &&
    npm install --prefix "$npm_dir" --no-audit --no-fund --silent \
        gltf-validator@2.0.0-dev.3.10 >"$out.npm" 2>&1 || rc=$?
fi
gdir=$(mktemp -d /tmp/symrec-gltf-test-XXXXXX) || exit 2
trap 'rm -rf "$gdir"' EXIT
gpass=0
gfail=0
if [ "$rc" -ne 0 ]; then
    gfail=1
    echo "    | npm install gltf-validator failed (exit $rc):" >"$out"
    sed 's/^/    | /' "$out.npm" >>"$out"
else
    if "$SYMREC_BIN" --db "$gdir/c.db" demo --catalog-only >/dev/null 2>&1 &&
       "$SYMREC_BIN" --db "$gdir/c.db" reconstruct 1 --params coarse --no-record \
           --out "$gdir/run" >/dev/null 2>"$gdir/err" &&
       node tests/gltf/validate_glb.js "$gdir/run/result.glb" "$npm_dir/node_modules" \
           >"$gdir/report" 2>&1; then
        gpass=$((gpass + 1))
    else
        gfail=$((gfail + 1))
        { echo "    | result.glb:"; sed 's/^/    | /' "$gdir/err" "$gdir/report" 2>/dev/null; } >>"$out"
    fi
    # a GLB cut short must be reported (exit 1: errors found)
    vrc=0
    [ -f "$gdir/run/result.glb" ] && head -c 3000 "$gdir/run/result.glb" >"$gdir/cut.glb"
    node tests/gltf/validate_glb.js "$gdir/cut.glb" "$npm_dir/node_modules" \
        >"$gdir/cut.report" 2>&1 || vrc=$?
    if [ "$vrc" -eq 1 ] && grep -q '"errors":[1-9]' "$gdir/cut.report"; then
        gpass=$((gpass + 1))
    else
        gfail=$((gfail + 1))
        { echo "    | a truncated GLB was not reported (exit $vrc):"; sed 's/^/    | /' "$gdir/cut.report"; } >>"$out"
    fi
fi
echo "$gpass $gfail" >"$out.counts"
