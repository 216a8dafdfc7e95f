#!/bin/sh
# check_stages.sh [--background CMD] CMD...: runs each stage command in turn (all of them,
# even after one fails), then prints each stage's wall time, so the next slowdown shows;
# exits 1 when any stage failed. With --background, CMD starts first at the lowest CPU
# priority (nice 19) and runs beside the stages, using only the CPU they leave idle (the
# tail of a test queue, a link); the last stage starts only when it has finished. make
# check draws the generated parts of partgen-check this way. Its failure is not a
# stage's: the last stage does the work again and reports it.
rc=0
times=""
bg_pid=""
bg_cmd=""
if [ "${1:-}" = --background ]; then
    bg_cmd=${2:?usage: check_stages.sh [--background CMD] CMD...}
    shift 2
    bg_start=$(date +%s)
    nice -n 19 sh -c "$bg_cmd" &
    bg_pid=$!
fi
n=$#
i=0
for cmd in "$@"; do
    i=$((i + 1))
    if [ "$i" -eq "$n" ] && [ -n "$bg_pid" ]; then
        wait "$bg_pid"
        times="$times$(printf '  %-40s %5ss (in the background, from the start)' "$bg_cmd" $(( $(date +%s) - bg_start )))
"
        bg_pid=""
    fi
    start=$(date +%s)
    sh -c "$cmd" || rc=1
    times="$times$(printf '  %-40s %5ss' "$cmd" $(( $(date +%s) - start )))
"
done
echo "make check stages (wall time):"
printf '%s' "$times"
exit $rc
