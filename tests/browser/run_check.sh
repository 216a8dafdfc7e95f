#!/bin/sh
# run_check.sh OUT: the browser check of the HTML report, one job of tests/run_tests.sh
# (which runs it beside the test binaries and prints its result).
#
# The demo run's report rendered in a real headless browser (check_report.js): no script
# error, no network request, its WebGL view checked on a screenshot (the part's and the
# patches' colours), printed to A4 PDF in at most SYMREC_REPORT_MAX_PAGES pages (default
# 5: 4 before the inspection's page; the demo's report printed to 8 before it had print
# rules). The run is inspected first with the damaged scan itself as the part "after
# repair" (the gouge left: rework), so the page has its inspection section, checked too:
# the gouge's blue and the rest's green in its view, the colour scale, one table row per
# section. Needs SYMREC_BIN, node and SYMREC_BROWSER (a Chromium). Writes its lines to
# OUT; exits non-zero when anything fails.
set -u
out=${1:?usage: run_check.sh OUT}
bdir=$(mktemp -d /tmp/symrec-browser-test-XXXXXX) || exit 2
trap 'rm -rf "$bdir"' EXIT
rc=0
{ "$SYMREC_BIN" --db "$bdir/c.db" demo >/dev/null 2>&1 &&
  "$SYMREC_BIN" --db "$bdir/c.db" reconstruct 1 --params coarse --no-union >/dev/null 2>&1 &&
  "$SYMREC_BIN" --db "$bdir/c.db" export instance 1 --out "$bdir/d.stl" >/dev/null 2>&1 &&
  "$SYMREC_BIN" --db "$bdir/c.db" inspect 1 --mesh "$bdir/d.stl" >/dev/null 2>&1 &&
  "$SYMREC_BIN" --db "$bdir/c.db" report 1 --out "$bdir/r.html" >/dev/null 2>&1 &&
  rows=$("$SYMREC_BIN" --db "$bdir/c.db" run show 1 --json |
         node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.parse(s).sections.length))'); } >"$out" 2>&1 || rc=$?
[ "$rc" -eq 0 ] || exit "$rc"
node tests/browser/check_report.js "$bdir/r.html" "$rows" "$SYMREC_BROWSER" \
    "${SYMREC_REPORT_MAX_PAGES:-5}" "$rows" >"$out" 2>&1
