#!/bin/sh
# check_stages.sh CMD...: runs each stage command in turn (all of them, even after one
# fails), then prints each stage's wall time, so the next slowdown shows; exits 1 when
# any stage failed.
rc=0
times=""
for cmd in "$@"; do
    start=$(date +%s)
    sh -c "$cmd" || rc=1
    times="$times$(printf '  %-40s %5ss' "$cmd" $(( $(date +%s) - start )))
"
done
echo "make check stages (wall time):"
printf '%s' "$times"
exit $rc
