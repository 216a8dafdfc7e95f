# symrec build. Plain make: `make [config=debug|release|sanitize]`, objects out of tree
# under build/$(config)/. Targets: all (libsymrec.a + symrec), deps (install the Debian
# packages this project needs, only when missing), demo (the README's main job),
# test (unit + CLI tests under ASan/UBSan), valgrind (CLI and CGAL-bridge tests under Valgrind),
# check (deps + test + valgrind: what CI runs), bench (make bench: speed and accuracy
# ratios measured in one run), fuzz (libFuzzer targets of the mesh import, one per
# format, each run FUZZ_SECONDS), clean; habits: format (clang-format on the files named
# or changed), compdb (compile_commands.json), lint (cppcheck on src/ and cli/).

config ?= debug
# the build steps of demo, test, valgrind and bench compile on every CPU
NPROC  := $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
BUILD  := build/$(config)

# Debian packages, installed by `make deps` when missing (as root, fresh Debian 12).
DEB_PACKAGES := pkg-config libsqlite3-dev sqlite3 libopenmesh-dev libtinygltf-dev \
                nlohmann-json3-dev libcmocka-dev libpolyclipping-dev libcgal-dev \
                libgmp-dev libmpfr-dev valgrind libjs-three
# for the accuracy checks on generated parts (../shared/partgen draws them with OpenSCAD;
# ../shared/eval/meshcompare scores them with numpy and scipy)
DEB_CHECK_PACKAGES := openscad python3-numpy python3-scipy
# for the HTML report's check in a real browser (tests/browser/check_report.js, run by
# tests/run_tests.sh from test and quick): node drives a headless Chromium
DEB_BROWSER_PACKAGES := nodejs chromium-headless-shell
# for `make lint` and `make format`
DEB_LINT_PACKAGES := cppcheck clang-format
# for `make fuzz` (clang with libFuzzer and the sanitizer runtimes)
DEB_FUZZ_PACKAGES := clang-14 libclang-rt-14-dev

CC  ?= cc
CXX ?= g++
PKG_LIBS := sqlite3 openmesh tinygltf polyclipping

CFLAGS_COMMON   := -std=c11 -fopenmp -D_DEFAULT_SOURCE -Wall -Wextra -Wshadow -Wstrict-prototypes \
                   -Wno-unused-parameter -Isrc -Icli -Itests -I$(BUILD)/gen -MMD -MP
CXXFLAGS_COMMON := -std=c++17 -fopenmp -Wall -Wextra -Wno-unused-parameter -Isrc -MMD -MP \
                   -DOM_STATIC_BUILD=0 -Wno-deprecated-copy -Wno-class-memaccess
# werror=1 turns every warning into an error (the tree builds warning-free; CI and a
# pre-push check may ask for it): `make werror=1 config=debug all tests-built`
ifeq ($(werror),1)
  CFLAGS_COMMON += -Werror
  CXXFLAGS_COMMON += -Werror
endif
LDLIBS := -fopenmp -lOpenMeshCore -lOpenMeshTools -ltinygltf -lpolyclipping -lsqlite3 -lgmp -lmpfr -lm -lstdc++

ifeq ($(config),release)
  OPT := -O2 -DNDEBUG
else ifeq ($(config),sanitize)
  OPT := -O1 -g1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
  LDFLAGS += -fsanitize=address,undefined
else ifeq ($(config),debug)
  OPT := -O1 -g
else
  $(error config must be debug, release or sanitize)
endif
# The CGAL translation units are the slow ones to compile (the 16 take about 5 min of
# CPU at -O2, their shared headers precompiled: CGAL_PCH below). They are compiled
# once, into build/cgal/, and linked into every config: -O2, no assertions and no
# sanitizer instrumentation. Instrumented, they made the sanitize build take about
# 19 min on 2 cores and ran test_cli 290 s and test_mend 56 s under ASan
# (uninstrumented: 161 s and 15 s). The C code calling them is instrumented in
# config=sanitize, and `make valgrind` runs the tests that drive the CGAL bridge under
# Memcheck, which needs no instrumentation.
CGAL_OPT := -O2 -g0 -DNDEBUG -DCGAL_NDEBUG -Wno-maybe-uninitialized

ifneq ($(V),1)
  Q := @
endif

LIB_C_SRC   := $(wildcard src/*.c $(filter-out src/bridge/%,$(wildcard src/*/*.c)))
# the longest to compile (about 40 s) first
CGAL_SRC    := src/bridge/union_local_cgal.cpp \
               $(filter-out src/bridge/union_local_cgal.cpp,$(wildcard src/bridge/*_cgal.cpp))
LIB_CXX_SRC := $(filter-out $(CGAL_SRC),$(wildcard src/bridge/*.cpp))
CLI_SRC     := $(wildcard cli/*.c)
SQL_SRC     := $(sort $(wildcard sql/*.sql))
TEST_SRC    := $(wildcard tests/test_*.c)
BENCH_SRC   := $(wildcard tests/bench/*.c)
FIX_SRC     := $(wildcard fixtures/*.c)

GEN_SQL := $(BUILD)/gen/sql_embedded.c
REPORT_ASSETS := src/report/report.css src/report/report.js src/report/report_view.js
GEN_REPORT := $(BUILD)/gen/report_assets.c
# three.js (Debian libjs-three, in DEB_PACKAGES): the report's 3D view, compiled in
THREE_JS ?= /usr/share/javascript/three/three.min.js
GEN_THREE := $(BUILD)/gen/report_three.c
CGAL_OBJ := $(CGAL_SRC:%.cpp=build/cgal/%.o)
# the CGAL objects first: `make -j` starts them first, the quick C files fill in beside
LIB_OBJ := $(CGAL_OBJ) $(LIB_C_SRC:%.c=$(BUILD)/%.o) $(LIB_CXX_SRC:%.cpp=$(BUILD)/%.o) $(GEN_SQL:.c=.o) $(GEN_REPORT:.c=.o) $(GEN_THREE:.c=.o)
CLI_OBJ := $(CLI_SRC:%.c=$(BUILD)/%.o)
LIB     := $(BUILD)/libsymrec.a
BIN     := $(BUILD)/symrec
TESTS   := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
BENCH   := $(BUILD)/bench/symrec_bench

.PHONY: all deps demo test valgrind check bench clean fixtures tests-built bench-built install \
        partgen-check partgen-draw quick layers format compdb lint fuzz fuzz-built
# keep test objects: they are intermediates of the test binaries, not throwaways
.SECONDARY:
all: $(LIB) $(BIN)

deps:
	$(Q)missing=""; for p in $(DEB_PACKAGES) $(if $(filter check partgen-check partgen-draw bench quick,$(MAKECMDGOALS)),$(DEB_CHECK_PACKAGES)) \
	  $(if $(filter check test quick,$(MAKECMDGOALS)),$(DEB_BROWSER_PACKAGES)) \
	  $(if $(filter lint format,$(MAKECMDGOALS)),$(DEB_LINT_PACKAGES)) \
	  $(if $(filter fuzz,$(MAKECMDGOALS)),$(DEB_FUZZ_PACKAGES)); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "symrec: installing Debian packages:$$missing" >&2; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >&2; \
	fi

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC    $<")
	$(Q)$(CC) $(CFLAGS_COMMON) $(OPT) $(CFLAGS) -c $< -o $@

# The CGAL headers the CGAL files share (src/bridge/cgal_pch.hpp), precompiled once with
# the same flags; each CGAL file is compiled with it first (-include: gcc takes the .gch
# it finds in build/cgal/bridge/ for the header, and says so with -Winvalid-pch when
# it cannot).
CGAL_PCH := build/cgal/bridge/cgal_pch.hpp.gch
$(CGAL_PCH): src/bridge/cgal_pch.hpp
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CXX   $< (CGAL headers, precompiled)")
	$(Q)$(CXX) $(CXXFLAGS_COMMON) $(CGAL_OPT) -x c++-header -c $< -o $@

build/cgal/src/bridge/%_cgal.o: src/bridge/%_cgal.cpp $(CGAL_PCH)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CXX   $< (CGAL, slow)")
	$(Q)$(CXX) -Ibuild/cgal $(CXXFLAGS_COMMON) $(CGAL_OPT) -include bridge/cgal_pch.hpp \
	  -Winvalid-pch -c $< -o $@

$(BUILD)/%.o: %.cpp
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CXX   $<")
	$(Q)$(CXX) $(CXXFLAGS_COMMON) $(OPT) $(CXXFLAGS) -c $< -o $@

# SQL files are compiled into the binary: each becomes one C string, fetched by name.
$(GEN_SQL): $(SQL_SRC) Makefile
	@mkdir -p $(dir $@)
	$(Q){ echo '/* generated from the files of sql/ by the Makefile; do not edit */'; \
	  echo '#include "catalog/sql_embedded.h"'; \
	  echo 'const sr_sql_file sr_sql_files[] = {'; \
	  for f in $(SQL_SRC); do \
	    printf '  { "%s",\n' "$$(basename $$f)"; \
	    sed -e 's/\\/\\\\/g' -e 's/"/\\"/g' -e 's/^/    "/' -e 's/$$/\\n"/' $$f; \
	    echo '  },'; \
	  done; \
	  echo '  { 0, 0 }'; echo '};'; } > $@

$(GEN_SQL:.c=.o): $(GEN_SQL)
	$(Q)$(CC) $(CFLAGS_COMMON) $(OPT) $(CFLAGS) -c $< -o $@

# The report's stylesheet and scripts are compiled in the same way (report_assets.h):
# each file without its opening comment (up to the first line " */"), the stylesheet's
# lines joined into one, the scripts' kept as lines.
$(GEN_REPORT): $(REPORT_ASSETS) Makefile
	@mkdir -p $(dir $@)
	$(Q){ echo '/* generated from src/report/report.css and report.js by the Makefile; do not edit */'; \
	  echo '#include "report/report_assets.h"'; \
	  echo 'const char sr_report_css[] ='; \
	  sed -e '1,/^ \*\/$$/d' -e 's/\\/\\\\/g' -e 's/"/\\"/g' -e 's/^/    "/' -e 's/$$/"/' src/report/report.css; \
	  echo '    "";'; \
	  echo 'const char sr_report_js[] ='; \
	  sed -e '1,/^ \*\/$$/d' -e 's/\\/\\\\/g' -e 's/"/\\"/g' -e 's/^/    "/' -e 's/$$/\\n"/' src/report/report.js; \
	  echo '    "";'; \
	  echo 'const char sr_report_view_js[] ='; \
	  sed -e '1,/^ \*\/$$/d' -e 's/\\/\\\\/g' -e 's/"/\\"/g' -e 's/^/    "/' -e 's/$$/\\n"/' src/report/report_view.js; \
	  echo '    "";'; } > $@

$(GEN_REPORT:.c=.o): $(GEN_REPORT)
	$(Q)$(CC) $(CFLAGS_COMMON) $(OPT) $(CFLAGS) -c $< -o $@

# three.js as bytes (report_assets.h: sr_report_three_js), so the report's 3D view works
# offline from the one file. Refused when missing (make deps installs libjs-three) or
# when its text could end the page's <script> element.
$(GEN_THREE): Makefile $(wildcard $(THREE_JS))
	@mkdir -p $(dir $@)
	$(Q)[ -f "$(THREE_JS)" ] || { echo "symrec: no $(THREE_JS): run 'make deps' (Debian libjs-three)" >&2; exit 1; }
	$(Q)! grep -qi '</script' "$(THREE_JS)" || { echo "symrec: $(THREE_JS) contains '</script'" >&2; exit 1; }
	$(Q){ echo '/* generated from $(THREE_JS) (Debian libjs-three) by the Makefile; do not edit */'; \
	  echo '#include "report/report_assets.h"'; \
	  echo 'const char sr_report_three_js[] = {'; \
	  od -An -v -tx1 "$(THREE_JS)" | sed -e 's/ \([0-9a-f][0-9a-f]\)/0x\1,/g'; \
	  echo '0x00};'; } > $@.tmp && mv $@.tmp $@

$(GEN_THREE:.c=.o): $(GEN_THREE)
	$(Q)$(CC) $(CFLAGS_COMMON) $(OPT) $(CFLAGS) -c $< -o $@

# made afresh: `ar rcs` into the old archive would keep the objects of deleted sources
$(LIB): $(LIB_OBJ)
	@$(if $(Q),echo "  AR    $@")
	$(Q)rm -f $@ && ar rcs $@ $^

$(BIN): $(CLI_OBJ) $(LIB)
	@$(if $(Q),echo "  LINK  $@")
	$(Q)$(CC) $(LDFLAGS) $(CLI_OBJ) $(LIB) $(LDLIBS) -o $@

TEST_SUPPORT_OBJ := $(patsubst %.c,$(BUILD)/%.o,$(wildcard tests/support/*.c))
$(BUILD)/tests/%: $(BUILD)/tests/%.o $(TEST_SUPPORT_OBJ) $(LIB)
	@$(if $(Q),echo "  LINK  $@")
	$(Q)$(CC) $(LDFLAGS) $< $(TEST_SUPPORT_OBJ) $(LIB) $(LDLIBS) -lcmocka -o $@

# (-lcmocka: tests/support holds the CLI tests' kit, which reports through cmocka)
$(BENCH): $(BENCH_SRC:%.c=$(BUILD)/%.o) $(TEST_SUPPORT_OBJ) $(LIB)
	@mkdir -p $(dir $@)
	$(Q)$(CC) $(LDFLAGS) $^ $(LDLIBS) -lcmocka -o $@

# The project's own fixtures: small meshes with known volumes, made by its own code.
fixtures: $(BIN)
	$(Q)$(BIN) fixtures --out fixtures

demo: deps
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=release all
	$(Q)rm -rf build/demo.db build/demo.db-wal build/demo.db-shm build/demo
	$(Q)build/release/symrec --db build/demo.db demo --out build/demo

# Every test binary under ASan/UBSan; test_accuracy's shards (18 reconstructions of
# noisy and posed parts, each checked by CGAL booleans) in the release build beside
# them, the sanitized test_accuracy on a smoke subset (tests/run_tests.sh says which).
test: deps layers
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=sanitize all tests-built
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=release build/release/tests/test_accuracy
	$(Q)SYMREC_BIN=build/sanitize/symrec SYMREC_ACCURACY_BUILD=build/release SYMREC_REQUIRE_BROWSER=1 \
	  sh tests/run_tests.sh build/sanitize

tests-built: $(TESTS)

# The layers of STYLE.md rule 2 on the sources: the core includes no catalogue header
# and no sqlite3.h, C++ only in src/bridge/, only cli/ prints or exits
# (tests/check_layers.sh names each file that breaks one). Run by quick and test.
layers:
	$(Q)sh tests/check_layers.sh

# The CLI tests with every CLI run under Memcheck, and the unit tests of the CGAL
# bridge (booleans, stacked patch meshes, the needles' collapse) under it whole: the
# CGAL units carry no sanitizer instrumentation, so this is where their memory use is
# checked; so are the mesh files' readers and writers (test_mesh_io), whose OpenMesh
# and tinygltf libraries are not instrumented either. It checks
# the release build, the one users run (test has compiled its library already; a debug
# build of its own took a minute of the stage, its runs no faster to check).
# The CLI cases that run whole reconstructions of damaged parts or the demo are left to
# the sanitized stage (under Memcheck each is 50x slower: 16 min for all of them, 4.5 min
# for the instance run alone; a failed run's, that fails only when it writes, 7 min);
# under Valgrind the intact scan's reconstruction (vote, no section) and the refused
# ones remain, with the CGAL bridge's unit tests whole. The registration's own cases
# (compare_registers_*: 120 s under Memcheck) run under ASan, as do those that only
# need a reconstruction to read from (export_run_*, json_names_agree_*), and the
# symmetry fits of test_symmetry_fit and test_cli_symmetry (three or four alignments each).
# So do the catalogue's listings and the usage errors, the rules, parameters and
# history (a dozen or more CLI runs each, 10-60 s apiece under Memcheck, 440 s in all;
# C and SQLite only, their leaks caught by LeakSanitizer there), and the refusal of a
# mesh read whole and found not closed (its reading is the refusals' of garbage and
# truncated files, which stay under Memcheck).
# The CGAL union's heap-independence (twelve unions, each after stirring the heap: 3.5
# min under Memcheck, whose allocator lays the heap out its own way anyway) runs under ASan.
VALGRIND_SKIP := part_add_refuses_a_mesh_that_is_not_a_closed_solid,a_union_does_not_follow_the_heap,\
rules_set_errors_change_nothing,rules_add_enable_and_disable,rules_list_show_and_set,\
params_list_show_and_set,history_refuses_bad_filters,history_filters_return_exactly_the_runs_made,\
run_commands_refuse_wrong_ids_and_filters,\
part_list_filters_by_name_number_and_material,strings_are_escaped_in_json,\
instance_add_list_and_show,part_show_by_number_and_by_id,part_add_refuses_an_unknown_extension,\
bad_numbers_are_usage_errors_naming_the_option,unknown_options_are_usage_errors,\
missing_command_is_a_usage_error,missing_option_values_are_usage_errors,\
demo_runs_the_whole_job,demo_builds_the_catalogue_*,reconstruct_order_auto_*,\
reconstruct_params_and_*,reconstruct_prints_run_recorded_*,compare_takes_stored_meshes,\
plan_writes_*,report_writes_*,run_list_filters_*,a_symmetry_that_does_not_fit_*,\
reconstruct_of_an_instance_records_*,a_failed_reconstruct_records_nothing,\
reconstruct_of_a_mesh_file_*,reconstruct_applies_the_sets_*,reconstruct_shows_progress_*,\
compare_registers_*,export_run_*,json_names_agree_*,demo_json_runs_the_job_*,identify_*,instance_add_part_auto_*,\
grooved_cylinder_is_*,\
toothed_wheel_is_*,angle_bracket_is_mirror,bumped_bar_is_a_glide_*,the_fit_is_deterministic,\
symfit_part_*,symmetry_of_a_mesh_file_is_proposed,reconstruct_symmetry_auto_*,\
inspect_records_the_verdict_*,a_scan_in_another_frame_is_registered_*
VALGRIND := valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite
VALGRIND_TESTS := test_cli test_boolean test_stack_mesh test_fold_slivers test_mesh_io
comma := ,
empty :=
space := $(empty) $(empty)
valgrind: deps
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=release all \
	  $(VALGRIND_TESTS:%=build/release/tests/%)
	$(Q)SYMREC_BIN=build/release/symrec SYMREC_WRAP="$(VALGRIND)" SYMREC_TEST_WRAP="$(VALGRIND)" \
	  SYMREC_TEST_SKIP="$(VALGRIND_SKIP)" SYMREC_CLI_SHARDS=6 \
	  sh tests/run_tests.sh build/release $(subst $(space),$(comma),$(VALGRIND_TESTS))

# Accuracy on generated parts: a fixed sample of ../shared/partgen (one per family)
# reconstructed posed and noisy by the release binary, scored by ../shared/eval/runparts
# --strict on the files written; then the parts of fresh seeds that showed a class
# failing (a U clamp's false plane, two chips of a nut a turn apart, two gears whose
# united images crossed themselves by a micrometre and were filled or dropped, a
# sleeve's bore chip and a pulley's rim read as designed pockets, a noisy strip's glide
# shift at the scan's lower bound, a noisy strip whose folded slivers the mender filled
# flat across a chip, a noisy rack's pattern end whose facets noise tilted off the frame
# built as a phantom tooth), and open scans of a gear whose base's scraps, peeled, left
# its rim off the plane, fanned across the bore, and of a fork whose base rim ran out
# and back along its walls' needles, fanned across the gap between its prongs, of a
# bracket whose peeled base rim left the base fanned across its bores to mend one edge,
# and of a plate whose mended scan kept a fin where a fill took the diagonal across the
# sharp edge between a bore's wall and its base.
PARTGEN_SAMPLES := 777:3,4,5,6:16 1202:2:24 271828:9:24 55441:13:24 \
  987654:0,13:24 2718:7,20:24 8128:7:24 41207:7:8 16180:5:16:open 46368:10:16:open \
  1346269:6:8:open 75025:6:7:open
partgen-check: deps
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=release all
	$(Q)sh tests/partgen/check_generated.sh build/release/symrec $(PARTGEN_SAMPLES)

# Only draws partgen-check's parts (into build/partgen-SEED-COUNT; once).
partgen-draw: deps
	$(Q)sh tests/partgen/check_generated.sh --draw-only $(PARTGEN_SAMPLES)

# The inner loop: the debug build's unit tests and the CLI tests, no accuracy matrix,
# no sanitizer, no Valgrind.
quick: deps layers
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=debug all tests-built
	$(Q)SYMREC_BIN=build/debug/symrec SYMREC_QUICK=1 SYMREC_REQUIRE_BROWSER=1 sh tests/run_tests.sh build/debug

# What CI runs: every stage, its wall time printed at the end; partgen-check's parts are
# drawn in the background at idle priority from the start (OpenSCAD on the CPU the
# other stages leave idle).
check: deps
	$(Q)sh tests/check_stages.sh --background "$(MAKE) --no-print-directory partgen-draw" \
	  "$(MAKE) --no-print-directory test" \
	  "$(MAKE) --no-print-directory valgrind" "$(MAKE) --no-print-directory partgen-check"

# Installs the release build: $(DESTDIR)$(PREFIX)/bin/symrec, lib/libsymrec.a and the
# C headers under include/symrec/ (the library's folders kept; C++ headers stay out).
PREFIX ?= /usr/local
install:
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=release all
	$(Q)install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/include/symrec
	$(Q)install -m 0755 build/release/symrec $(DESTDIR)$(PREFIX)/bin/symrec
	$(Q)install -m 0644 build/release/libsymrec.a $(DESTDIR)$(PREFIX)/lib/libsymrec.a
	$(Q)cd src && for h in $$(find . -name '*.h' | sort); do \
	  install -D -m 0644 "$$h" "$(DESTDIR)$(PREFIX)/include/symrec/$$h"; done
	$(Q)echo "  installed symrec into $(DESTDIR)$(PREFIX)"

# IDENTIFY_GEN_DIRS: colon-separated ../shared/partgen output folders whose intact parts
# are section 6's distractors (unset: 100 parts made once into build/bench-identify/gen).
bench: deps
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) config=release all bench-built
	$(Q)SYMREC_IDENTIFY_GEN="$(IDENTIFY_GEN_DIRS)" build/release/bench/symrec_bench
	$(Q)sh tests/bench/nominal_bench.sh build/release/symrec
	$(Q)sh tests/bench/nominal_bench.sh build/release/symrec "" damaged_scan.stl
	$(Q)sh tests/bench/partgen_bench.sh build/release/symrec
	$(Q)sh tests/bench/symmetry_bench.sh build/release/symrec
	$(Q)sh tests/bench/big_scan_bench.sh build/release/symrec

bench-built: $(BENCH)

# Fuzzing the import (tests/fuzz/): one libFuzzer target per format over
# sr_mesh_read_memory, the check-and-read path sr_mesh_read uses. Only the mesh I/O is
# compiled into them, by Debian's clang-14 with coverage, ASan and UBSan, into
# build/fuzz/ (OpenMesh and tinygltf are linked as installed, uninstrumented). The seed
# corpus (a box and a cylinder in every format and variant) is written by the project's
# own writers (tests/fuzz/make_corpus.c) into build/fuzz/corpus/FORMAT, with what the
# targets once found (tests/fuzz/found/, replayed by test_fuzz_replay too); each run
# grows it; crashes and hangs land in build/fuzz/crash-* and timeout-*. `make fuzz FUZZ_SECONDS=300` runs longer.
FUZZ_SECONDS ?= 60
FUZZ_FORMATS := stl obj ply off gltf glb
FUZZ_CC  := clang-14
FUZZ_CXX := clang++-14
FUZZ_SAN := -g -O1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
FUZZ_C_SRC   := $(wildcard src/io/*.c) src/mesh/mesh.c src/mesh/pair_sort.c src/mesh/units.c \
                src/mesh/mesh_float.c src/mesh/tri_flaps.c \
                src/mesh/mesh_facts.c \
                src/base/status.c
FUZZ_CXX_SRC := $(addprefix src/bridge/,io_bytes.cpp openmesh_io.cpp read_gltf.cpp \
                gltf_meshes.cpp mesh_io_api.cpp write_text.cpp write_glb.cpp)
FUZZ_OBJ := $(FUZZ_C_SRC:%.c=build/fuzz/obj/%.o) $(FUZZ_CXX_SRC:%.cpp=build/fuzz/obj/%.o)
FUZZ_BIN := $(FUZZ_FORMATS:%=build/fuzz/fuzz_%)

build/fuzz/obj/%.o: %.c
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  FUZZCC  $<")
	$(Q)$(FUZZ_CC) $(filter-out -fopenmp,$(CFLAGS_COMMON)) $(FUZZ_SAN) -fsanitize=fuzzer-no-link -c $< -o $@

build/fuzz/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  FUZZCXX $<")
	$(Q)$(FUZZ_CXX) $(CXXFLAGS_COMMON) -Wno-unknown-warning-option $(FUZZ_SAN) -fsanitize=fuzzer-no-link -c $< -o $@

build/fuzz/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_read.h $(FUZZ_OBJ)
	@$(if $(Q),echo "  FUZZLD  $@")
	$(Q)$(FUZZ_CXX) -x c -std=c11 -Isrc -Itests $(FUZZ_SAN) -fsanitize=fuzzer -c $< -o $@.o
	$(Q)$(FUZZ_CXX) $(FUZZ_SAN) -fsanitize=fuzzer $@.o $(FUZZ_OBJ) -lOpenMeshCore -ltinygltf -lm -o $@

$(BUILD)/fuzz/make_corpus: $(BUILD)/tests/fuzz/make_corpus.o $(BUILD)/tests/support/fuzz_seeds.o $(LIB)
	@mkdir -p $(dir $@)
	$(Q)$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

fuzz-built: $(FUZZ_BIN) $(BUILD)/fuzz/make_corpus

# Each target for FUZZ_SECONDS on its corpus; prints its executions and exits non-zero
# at the first crash (the input is kept as build/fuzz/crash-*).
fuzz: deps
	$(Q)$(MAKE) --no-print-directory -j$(NPROC) fuzz-built
	$(Q)rm -rf build/fuzz/corpus && mkdir -p build/fuzz/corpus && \
	  $(BUILD)/fuzz/make_corpus build/fuzz/corpus && \
	  for f in tests/fuzz/found/*; do cp "$$f" "build/fuzz/corpus/$${f##*.}/"; done
	$(Q)for f in $(FUZZ_FORMATS); do \
	  log=build/fuzz/fuzz_$$f.log; \
	  if ! build/fuzz/fuzz_$$f -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2560 \
	       -max_len=65536 -artifact_prefix=build/fuzz/ -print_final_stats=1 \
	       build/fuzz/corpus/$$f > $$log 2>&1; then \
	    echo "fuzz_$$f: FAILED, see $$log" >&2; tail -40 $$log >&2; exit 1; fi; \
	  execs=$$(sed -n 's/^stat::number_of_executed_units: *//p' $$log); \
	  echo "fuzz_$$f: $$execs executions in $(FUZZ_SECONDS) s, no crash ($$(ls build/fuzz/corpus/$$f | wc -l) corpus files)"; \
	done

# clang-format (.clang-format) on the files named, `make format FILES="src/a.c src/a.h"`
# (whole files); without FILES, on the lines changed since HEAD (git clang-format) and
# on new files whole. Never the whole tree, nor the untouched lines of a changed file: a
# reformat of old code would bury the history (much of the tree predates the config).
FORMAT_EXT := '*.c' '*.h' '*.cpp' '*.hpp'
format: deps
	$(Q)if [ -n "$(FILES)" ]; then \
	  echo "  FORMAT $(FILES)"; clang-format -i $(FILES); \
	else \
	  git clang-format --force --quiet --extensions c,h,cpp,hpp HEAD >/dev/null || true; \
	  new=$$(git ls-files --others --exclude-standard -- $(FORMAT_EXT)); \
	  if [ -n "$$new" ]; then echo "  FORMAT $$new" | tr '\n' ' '; echo; clang-format -i $$new; fi; \
	  git diff --name-only HEAD -- $(FORMAT_EXT) | sed 's/^/  FORMAT (changed lines) /'; \
	fi

# compile_commands.json for editors and tools, from the commands make would run for
# config=$(config) (make -n -B: nothing is compiled).
compdb:
	$(Q)$(MAKE) --no-print-directory -n -B config=$(config) all tests-built 2>/dev/null | \
	  awk -v dir="$(CURDIR)" 'BEGIN { print "["; n = 0 } \
	    ($$1 == "$(CC)" || $$1 == "$(CXX)") && / -c / { \
	      for (i = 1; i <= NF; i++) if ($$i == "-c") file = $$(i + 1); \
	      gsub(/\\/, "\\\\"); gsub(/"/, "\\\""); \
	      printf "%s  {\"directory\": \"%s\", \"file\": \"%s\", \"command\": \"%s\"}", \
	        (n++ ? ",\n" : ""), dir, file, $$0 } \
	    END { print "\n]" }' > compile_commands.json
	@echo "compile_commands.json: $$(grep -c '"file"' compile_commands.json) files" >&2

# Static analysis of the library and the CLI; clean means no finding outside the
# reasoned list in .cppcheck-suppressions. Needs the generated sources' folder for
# includes only.
LINT_FLAGS := --quiet --error-exitcode=1 --std=c11 --enable=warning,performance,portability \
              --inline-suppr --suppressions-list=.cppcheck-suppressions \
              --template='{file}:{line}: {severity} [{id}] {message}' -j$(NPROC)
lint: deps
	$(Q)cppcheck $(LINT_FLAGS) -Isrc -Icli -I$(BUILD)/gen src cli

clean:
	rm -rf build

-include $(shell find $(BUILD) build/cgal build/fuzz -name '*.d' 2>/dev/null)
