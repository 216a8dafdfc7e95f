#!/bin/sh
# run_tests.sh: runs symrec's cmocka test binaries and sums their results.
#
#   sh tests/run_tests.sh BUILD_DIR [NAMES]
#
# Runs every BUILD_DIR/tests/test_* binary from the repository root (or only those
# NAMES lists, comma-separated, e.g. "test_cli,test_mend"; "cli" alone means test_cli),
# each with its output in a log of its own, up to SYMREC_TEST_JOBS jobs at a time
# (default: the online CPUs; the longest start first). Prints one line per job in name
# order (passed/failed counts, or how it crashed, followed by its log when anything
# failed) and ends with exactly one line "N passed, N failed". Exits non-zero if any
# test failed or any binary exited non-zero (a crash, a sanitizer report, a leak) - even
# if cmocka's own counts look clean. The binaries share nothing: each test makes its own
# mkdtemp directory.
#
# test_cli runs as SYMREC_CLI_SHARDS shards, default 4 (tags shard1..shardN:
# SYMREC_TEST_SHARD=K/N, see tests/support/test_select.h), which matters under Valgrind
# (make valgrind runs 6: its long cases then spread over both CPUs). test_accuracy, by far the
# longest, runs as four shards side by side (tags scan1, scan2: the noisy scans' cases;
# posed: the posed parts' robust cases; rest: all others).
# With SYMREC_ACCURACY_BUILD=DIR (make test: the release build) the shards run DIR's
# optimised test_accuracy, and BUILD_DIR's own (sanitized) one runs the smoke shard:
# the paper method on seven of the nine parts (not the keyed shaft and the gear, the
# slowest under ASan) and the robust method on the posed shaft, bracket and rail (one
# per kind of symmetry).
#
# Without NAMES, two more jobs run in the same queue: the browser check of the HTML
# report (tests/browser/run_check.sh; node and Debian's chromium-headless-shell, which
# `make deps` installs for test, quick and check: there it fails when they are missing;
# elsewhere it is skipped with a message) and the Khronos glTF validator on the GLB that
# reconstruct writes (tests/gltf/run_check.sh; skipped without node and npm).
#
# Environment: SYMREC_BIN (the CLI under test; default BUILD_DIR/symrec) and
# SYMREC_WRAP (e.g. "valgrind -q --error-exitcode=99 ...") are passed on to test_cli,
# which runs the CLI under SYMREC_WRAP; SYMREC_TEST_WRAP runs every other binary under
# it.
set -u

if [ $# -lt 1 ] || [ $# -gt 2 ]; then
    echo "usage: sh tests/run_tests.sh BUILD_DIR [NAMES]" >&2
    exit 2
fi
only=${2:-}
[ "$only" = cli ] && only=test_cli
case $only in *[!A-Za-z0-9_,]*)
    echo "run_tests.sh: NAMES must be test binary names separated by commas, not '$only'" >&2
    exit 2 ;;
esac
# Paths given relative to the caller's directory stay valid after the cd below.
build=$(cd "$1" 2>/dev/null && pwd) || { echo "run_tests.sh: no build directory '$1'" >&2; exit 2; }
acc_build=$build
if [ -n "${SYMREC_ACCURACY_BUILD:-}" ]; then
    acc_build=$(cd "$SYMREC_ACCURACY_BUILD" 2>/dev/null && pwd) ||
        { echo "run_tests.sh: no build directory '$SYMREC_ACCURACY_BUILD' (SYMREC_ACCURACY_BUILD)" >&2; exit 2; }
    [ -x "$acc_build/tests/test_accuracy" ] ||
        { echo "run_tests.sh: no $acc_build/tests/test_accuracy (SYMREC_ACCURACY_BUILD; build it first)" >&2; exit 2; }
fi
SYMREC_BIN=${SYMREC_BIN:-$build/symrec}
case $SYMREC_BIN in
    /*) ;;
    *) [ -e "$SYMREC_BIN" ] && SYMREC_BIN=$(pwd)/$SYMREC_BIN ;;
esac
export SYMREC_BIN

# Tests assume the repository root as the working directory.
cd "$(dirname "$0")/.." || exit 2
# cmocka prints its per-test lines to stdout in this mode.
CMOCKA_MESSAGE_OUTPUT=stdout
export CMOCKA_MESSAGE_OUTPUT
# ASan keeps 2 frames of each allocation's stack, not 30: CGAL's exact arithmetic
# allocates millions of small numbers, and recording their stacks took over half of a
# sanitized reconstruction (a posed bracket: 10 s instead of more than 4 min). Set
# ASAN_OPTIONS=malloc_context_size=30 to rerun a failure with the full stacks.
ASAN_OPTIONS=${ASAN_OPTIONS:-malloc_context_size=2}
export ASAN_OPTIONS

if [ -n "$only" ]; then
    bins=$(echo "$only" | tr ',' '\n' | sed "s|^|$build/tests/|")
else
    bins=$(ls "$build"/tests/test_* 2>/dev/null | grep -v '\.[od]$')
fi
# make quick: no accuracy matrix (whole restorations of every shared part)
[ -n "${SYMREC_QUICK:-}" ] && bins=$(echo "$bins" | grep -v '/test_accuracy$')

# The browser check of the HTML report (tests/browser/run_check.sh) runs as one job of
# the queue, beside the test binaries, when every binary runs (no NAMES). It needs node
# and Debian's chromium-headless-shell, which `make deps` installs for test, quick and
# check; SYMREC_REQUIRE_BROWSER=1 (the Makefile's test, quick) makes their absence a
# failure; otherwise it is skipped with a line.
browser=
if [ -z "$only" ]; then
    browser=${SYMREC_BROWSER:-}
    [ -z "$browser" ] && [ -x /usr/bin/chromium-headless-shell ] && browser=/usr/bin/chromium-headless-shell
    [ -z "$browser" ] && [ -x /usr/bin/chromium ] && browser=/usr/bin/chromium
    command -v node >/dev/null 2>&1 || browser=
fi
SYMREC_BROWSER=$browser
export SYMREC_BROWSER
# where the glTF validator's check (tests/gltf/run_check.sh) installs gltf-validator once
SYMREC_NPM_DIR=${SYMREC_NPM_DIR:-$build/npm}
export SYMREC_NPM_DIR

logs=$(mktemp -d /tmp/symrec-run-tests-XXXXXX) || exit 2
trap 'rm -rf "$logs"' EXIT
trap 'exit 130' INT TERM

# Run them: the longest first, then the others, SYMREC_TEST_JOBS at a time. A job is
# "binary tag": test_accuracy runs as its shards (see the top), every other binary is
# one job (tag all). Each job leaves NAME.TAG.out, .err, .rc (exit status) and .secs in
# $logs.
jobs=${SYMREC_TEST_JOBS:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)}
cli_shards=${SYMREC_CLI_SHARDS:-4}
case $cli_shards in ''|*[!0-9]*|0) echo "run_tests.sh: SYMREC_CLI_SHARDS must be a count, not '$cli_shards'" >&2; exit 2 ;; esac
export cli_shards
case $jobs in ''|*[!0-9]*|0) jobs=1 ;; esac
# the jobs fill the CPUs: a job's own OpenMP threads (the vote, the alignment's queries)
# would only queue behind the other job's, spinning while they wait (test_align under
# the sanitizers took 81 s of the stage with two threads, 38 s alone on one). The tests
# that compare one thread with two ask for their threads by count.
if [ "$jobs" -gt 1 ] && [ -z "${OMP_NUM_THREADS:-}" ]; then
    OMP_NUM_THREADS=1
    export OMP_NUM_THREADS
fi
# the tags of a binary's jobs
tags_of() {
    case $1 in
        */test_accuracy) if [ "$acc_build" = "$build" ]; then echo "scan1 scan2 posed rest"
                         else echo "scan1 scan2 posed rest smoke"; fi ;;
        */test_cli) k=1; while [ "$k" -le "$cli_shards" ]; do printf 'shard%d ' "$k"; k=$((k + 1)); done ;;
        *) echo all ;;
    esac
}
job_list() {
    for bin in $bins; do case $bin in */test_accuracy)
        for tag in $(tags_of "$bin"); do
            if [ "$tag" = smoke ]; then echo "$bin $tag"; else echo "$acc_build/tests/test_accuracy $tag"; fi
        done ;;
    esac; done
    # the browser check (a demo, a reconstruction and an inspection: about a minute)
    [ -n "$SYMREC_BROWSER" ] && echo "browser_check browser"
    [ -z "$only" ] && echo "gltf_validator gltf"
    # then the binaries that take about a minute under ASan, before test_cli's shards
    # (a long one started last leaves the other CPU idle at the end)
    for bin in $bins; do case $bin in */test_union_local|*/test_image|*/test_align)
        echo "$bin all" ;;
    esac; done
    for bin in $bins; do case $bin in */test_cli)
        for tag in $(tags_of "$bin"); do echo "$bin $tag"; done ;;
    esac; done
    for bin in $bins; do case $bin in
        */test_accuracy|*/test_cli|*/test_union_local|*/test_image|*/test_align) ;;
        *) echo "$bin all" ;;
    esac; done
}
job_list | xargs -P "$jobs" -L 1 sh -c '
    logs=$1; bin=$2; tag=$3; name=$(basename "$bin")
    if [ "$tag" = browser ]; then
        start=$(date +%s)
        sh tests/browser/run_check.sh "$logs/browser.out"
        echo $? >"$logs/browser.rc"
        echo $(( $(date +%s) - start )) >"$logs/browser.secs"
        exit 0
    fi
    if [ "$tag" = gltf ]; then
        start=$(date +%s)
        sh tests/gltf/run_check.sh "$logs/gltf.out"
        echo $(( $(date +%s) - start )) >"$logs/gltf.secs"
        exit 0
    fi
    [ -f "$bin" ] && [ -x "$bin" ] || exit 0
    # the slowest noisy scans, apart from the others
    slow="bushing_gouged_scan_*,spur_gear_broken_tooth_scan_*,u_clamp_broken_arm_scan_*"
    # under ASan: the paper method on every part but the two slowest there (24 s for
    # the keyed shaft, 16 s for the gear; both run optimised in the rest shard), the
    # robust one on one part of each kind of symmetry (about 35 s)
    smoke="*_reconstructs_within_measured_bounds,shaft_chipped_shoulder_posed_robust_*"
    smoke="$smoke,bracket_broken_ear_posed_robust_*,rail_glide_chipped_posed_robust_*"
    case $tag in
        scan1) SYMREC_TEST_FILTER=$slow ;;
        scan2) SYMREC_TEST_FILTER="*_scan_*"; SYMREC_TEST_SKIP=$slow ;;
        posed) SYMREC_TEST_FILTER="*_posed_robust_*" ;;
        rest)  SYMREC_TEST_SKIP="*_robust_restored_within_bounds" ;;
        smoke) SYMREC_TEST_FILTER="$smoke"; SYMREC_TEST_SKIP="keyed_shaft_dent_*,spur_gear_broken_tooth_*" ;;
        shard*) SYMREC_TEST_SHARD="${tag#shard}/$cli_shards"; export SYMREC_TEST_SHARD ;;
    esac
    export SYMREC_TEST_FILTER SYMREC_TEST_SKIP
    wrap=
    [ "$name" = test_cli ] || wrap=${SYMREC_TEST_WRAP:-}
    start=$(date +%s)
    $wrap "$bin" >"$logs/$name.$tag.out" 2>"$logs/$name.$tag.err"
    echo $? >"$logs/$name.$tag.rc"
    echo $(( $(date +%s) - start )) >"$logs/$name.$tag.secs"
' sh "$logs"

total_pass=0
total_fail=0
bad_binaries=0
found=0
for bin in $bins; do
    if ! [ -f "$bin" ] || ! [ -x "$bin" ]; then
        # a binary asked for by name and missing fails the run
        if [ -n "$only" ]; then
            echo "run_tests.sh: no test binary '$bin' (build it first)"
            total_fail=$((total_fail + 1))
            bad_binaries=$((bad_binaries + 1))
        fi
        continue
    fi
    found=$((found + 1))
    name=$(basename "$bin")
    for tag in $(tags_of "$bin"); do
        out=$logs/$name.$tag.out
        err=$logs/$name.$tag.err
        rc=$(cat "$logs/$name.$tag.rc" 2>/dev/null || echo 127)
        secs=$(cat "$logs/$name.$tag.secs" 2>/dev/null || echo 0)
        [ "$tag" = all ] || name=$(basename "$bin")[$tag]
        # cmocka writes one result line per test to stdout ("[       OK ] name",
        # "[  FAILED  ] name", "[  SKIPPED ] name") and its summary to stderr, so counting
        # the stdout lines counts each test once. Names are C identifiers.
        pass=$(grep -c '^\[       OK \] [A-Za-z_]' "$out")
        fail=$(grep -c '^\[  FAILED  \] [A-Za-z_]' "$out")
        skipped=$(grep -c '^\[  SKIPPED \] [A-Za-z_]' "$out")
        ran=$(grep -c '^\[ RUN      \] ' "$out")
        # A binary that died mid-test never printed "[==========] N test(s) run.": the
        # tests it started without a result failed, and at least one did.
        if ! grep -q '^\[==========\] [0-9]* test(s) run\.' "$out"; then
            unfinished=$((ran - pass - fail - skipped))
            [ "$unfinished" -lt 1 ] && unfinished=1
            fail=$((fail + unfinished))
        fi
        status="ok"
        if [ "$rc" -ne 0 ] || [ "$fail" -ne 0 ]; then
            bad_binaries=$((bad_binaries + 1))
            if [ "$rc" -gt 128 ]; then
                status="crashed (signal $((rc - 128)))"
            else
                status="FAILED (exit $rc)"
            fi
            # Exit non-zero with every test passing: a sanitizer or leak report at exit.
            [ "$fail" -eq 0 ] && fail=1
        fi
        printf '%-14s %3d passed, %d failed  %s  (%ss)\n' "$name" "$pass" "$fail" "$status" "$secs"
        if [ "$status" != ok ]; then
            # Its log, without the lines of the tests that passed.
            grep -v '^\[ RUN      \] \|^\[       OK \] ' "$out" "$err" | sed 's/^[^:]*:/    | /'
        fi
        total_pass=$((total_pass + pass))
        total_fail=$((total_fail + fail))
        name=$(basename "$bin")
    done
done

# The browser check's result (its job ran in the queue above).
if [ -z "$only" ]; then
    out=$logs/browser.out
    if [ -z "$browser" ]; then
        if [ -n "${SYMREC_REQUIRE_BROWSER:-}" ]; then
            echo "browser_check    0 passed, 1 failed  FAILED: no node or no headless browser (make deps installs nodejs and chromium-headless-shell)"
            total_fail=$((total_fail + 1))
        else
            echo "browser_check  skipped: no node or no headless browser (apt-get install nodejs chromium-headless-shell)"
        fi
    else
        rc=$(cat "$logs/browser.rc" 2>/dev/null || echo 127)
        secs=$(cat "$logs/browser.secs" 2>/dev/null || echo 0)
        if [ "$rc" -eq 0 ]; then
            printf '%-14s %3d passed, %d failed  ok  (%ss)\n' browser_check 1 0 "$secs"
            sed 's/^check_report: ok: [^:]*:[^:]*: /    | /' "$out"
            total_pass=$((total_pass + 1))
        else
            printf '%-14s %3d passed, %d failed  FAILED (exit %d)  (%ss)\n' browser_check 0 1 "$rc" "$secs"
            sed 's/^/    | /' "$out" 2>/dev/null
            total_fail=$((total_fail + 1))
        fi
    fi
fi

# The glTF validator's result (tests/gltf/run_check.sh, a job of the queue above).
if [ -z "$only" ]; then
    read -r gpass gfail <"$logs/gltf.out.counts" 2>/dev/null || { gpass=0; gfail=1; }
    secs=$(cat "$logs/gltf.secs" 2>/dev/null || echo 0)
    if [ "$gpass" = skip ]; then
        echo "gltf_validator skipped: no node or npm (apt-get install nodejs npm)"
    else
        if [ "$gfail" -eq 0 ]; then
            printf '%-14s %3d passed, %d failed  ok  (%ss)\n' gltf_validator "$gpass" 0 "$secs"
        else
            printf '%-14s %3d passed, %d failed  FAILED  (%ss)\n' gltf_validator "$gpass" "$gfail" "$secs"
            cat "$logs/gltf.out"
        fi
        total_pass=$((total_pass + gpass))
        total_fail=$((total_fail + gfail))
    fi
fi

if [ "$found" -eq 0 ]; then
    echo "run_tests.sh: no test binaries in '$build/tests' (build them first)" >&2
    echo "0 passed, 1 failed"
    exit 1
fi

echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ] && [ "$bad_binaries" -eq 0 ]
