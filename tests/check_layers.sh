#!/bin/sh
# check_layers.sh: the layers of STYLE.md rule 2, checked on the sources (run by
# `make quick` and `make test` through `make layers`, from the repository root):
#
#   1. the core - the geometry stages (src/base mesh io align slice images robust
#      paper, src/reconstruct*.c/.h) and the stages on top of them that describe,
#      advise, plan and report a run (src/advice plan run report) - includes no
#      catalogue header ("catalog/...") and no sqlite3.h: the catalogue stores the
#      core's records, the core never reaches into it. The one place that joins rule
#      engine and catalogue for recording is src/catalog/catalog_record.c, inside the
#      catalogue, so no core file is excepted (RECORD_FILE would name one outside
#      src/catalog);
#   2. nothing outside src/bridge/ is C++ or includes a C++ header (a standard header
#      without .h, or CGAL, OpenMesh, tinygltf, nlohmann, Clipper, *.hpp, *.hh);
#   3. nothing outside cli/ prints to stdout/stderr or exits: no printf, puts,
#      putchar, perror, fprintf/fputs/fputc to stdout or stderr, exit, _Exit,
#      std::cout/std::cerr <<.
#
# Prints one line per violation naming the file and line, and exits 1 when there is
# any; prints nothing and exits 0 otherwise.
set -u
cd "$(dirname "$0")/.." || exit 2

CORE="src/base src/mesh src/io src/align src/slice src/images src/robust src/paper
      src/advice src/plan src/run src/report src/reconstruct.c src/reconstruct_union.c
      src/reconstruct.h src/reconstruct_int.h"
RECORD_FILE=""
bad=0

report() { # FILE:LINE:TEXT lines on stdin, the rule as $1
    while IFS= read -r hit; do
        rest=${hit#*:}
        printf 'check_layers: %s:%s: %s\n' "${hit%%:*}" "${rest%%:*}" "$1" >&2
        bad=1
    done
}

# 1. the core below the catalogue
hits=$(grep -nE '#[[:space:]]*include[[:space:]]*[<"](catalog/[^">]*|sqlite3\.h)[">]' \
       $(find $CORE -name '*.[ch]' -o -name '*.cpp' | sort) /dev/null)
[ -n "$RECORD_FILE" ] && hits=$(echo "$hits" | grep -v "^$RECORD_FILE:")
[ -n "$hits" ] && report "the core includes the catalogue (catalog/ or sqlite3.h)" <<EOT
$hits
EOT

# 2. C++ only in src/bridge/
for f in $(find src cli -name '*.cpp' -o -name '*.cc' -o -name '*.cxx' -o -name '*.hpp' \
           -o -name '*.hh' | grep -v '^src/bridge/' | sort); do
    echo "check_layers: $f: C++ outside src/bridge/" >&2
    bad=1
done
hits=$(grep -nE '#[[:space:]]*include[[:space:]]*(<[^>.]*>|[<"](CGAL|OpenMesh|nlohmann|polyclipping)/|[<"]tiny_gltf\.h[">]|[<"][^">]*\.(hpp|hh)[">])' \
       $(find src cli -name '*.[ch]' | grep -v '^src/bridge/' | sort) /dev/null)
[ -n "$hits" ] && report "includes a C++ header outside src/bridge/" <<EOT
$hits
EOT

# 3. only cli/ prints or exits
hits=$(grep -nE '(^|[^A-Za-z0-9_])(printf|puts|putchar|perror|exit|_Exit|quick_exit)[[:space:]]*\(|(^|[^A-Za-z0-9_])(fprintf|fputs|fputc|fwrite|vfprintf|putc)[[:space:]]*\([^;]*(stdout|stderr)|std::(cout|cerr|clog)[[:space:]]*<<' \
       $(find src -name '*.[ch]' -o -name '*.cpp' | sort) /dev/null)
[ -n "$hits" ] && report "prints or exits outside cli/" <<EOT
$hits
EOT

exit $bad
