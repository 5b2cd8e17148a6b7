# hovox - heterogeneous-object modeling for multi-material 3D printing.
#   make            library, CLI (build/hovox) and plugins
#   make test       unit, header, CLI, sample, Python and browser tests (installs missing packages as root)
#   make sanitize   the whole test suite built with ASan + UBSan (build-san/)
#   make bench      benchmarks against the anchors named in the issues
#   make python     the Python package hovox, built in place (python/); make python-tests runs its tests
#   make demo       the gear sample end to end
#   make deps       install every Debian package (build, test, bench)
# Options: WERROR=1 (warnings are errors, as in CI; a build keeps it until WERROR=0), BUILD=dir,
#          SHARED=tests/data (holds meshes/: copies of the shared test meshes).

BUILD   ?= build
SHARED  ?= tests/data
CC      ?= gcc
CXX     ?= g++
# Not given: what $(BUILD) was last built with, so `make demo` or `make bench` after a
# `make WERROR=1` reuses the build instead of compiling everything again without -Werror.
WERROR  ?= $(if $(shell grep -qs -- ' -Werror ' $(BUILD)/.flags && echo y),1,0)
SAN     ?= 0
OPT     ?= -O2

ifeq ($(origin CC),default)
CC := gcc
endif

# -Wmissing-prototypes: a function that is not static is declared in a header (an unused export
# declared nowhere, as hv_layers_mode_enum was, fails the build)
WARN    := -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion -Wformat=2 -Wundef -Wmissing-prototypes
ifeq ($(WERROR),1)
WARN    += -Werror
endif
ifeq ($(SAN),1)
SANFLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
OPT      := -O1
endif

ROOT    := $(abspath .)
PLUGDIR := $(ROOT)/$(BUILD)/plugins
CPPFLAGS_ALL := -Iinclude -Isrc -I. -D_GNU_SOURCE -DHV_PLUGIN_BUILD_DIR='"$(PLUGDIR)"' -MMD -MP
CFLAGS_ALL   := -std=c11 $(OPT) -g -fPIC -fvisibility=hidden -fopenmp -fno-math-errno -fno-trapping-math $(WARN) $(SANFLAGS) $(EXTRA_CFLAGS)
# Bridges keep default visibility: OpenVDB's template statics must unify with libopenvdb's
# (with -fvisibility=hidden openvdb::initialize() crashes); plugins load RTLD_LOCAL anyway.
CXXFLAGS_ALL := -std=c++17 $(OPT) -g -fPIC -Wall -Wextra -Wshadow \
                $(if $(filter 1,$(WERROR)),-Werror) $(SANFLAGS)
PKG_CFLAGS   := $(shell pkg-config --cflags libpng zlib lua5.4 cairo jansson libzip libxml-2.0 blosc libjpeg lcms2 2>/dev/null)
PKG_LIBS     := $(shell pkg-config --libs libpng libdeflate zlib lua5.4 cairo jansson libzip libxml-2.0 blosc libjpeg lcms2 2>/dev/null)
LIBS         := $(PKG_LIBS) -lm -ldl -lpthread -fopenmp $(SANFLAGS)

# ---- sources ------------------------------------------------------------------------------
# Every .c below src/ (but the CLI's), volumes/, slicing/ and renderer/ is the library; the layers
# and their order are in README's "Layout".
LIB_SRC   := $(sort $(shell find src volumes slicing renderer -name '*.c' -not -path 'src/cli/*'))
# the viewer page's HTML, CSS and JavaScript, embedded into the library (scripts/embed.sh)
VIEW_ASSETS := src/viewer/assets/page.html src/viewer/assets/viewer.css src/viewer/assets/viewer.js
VIEW_GEN  := $(BUILD)/gen/viewer_assets.c
CLI_SRC   := $(wildcard src/cli/*.c)
LIB_OBJ   := $(LIB_SRC:%.c=$(BUILD)/obj/%.o) $(BUILD)/obj/gen/viewer_assets.o
CLI_OBJ   := $(CLI_SRC:%.c=$(BUILD)/obj/%.o)
HEADERS   := $(wildcard include/hovox/*.h)

# One plugin per C++ library: <dir>/<name>_bridge.cpp -> plugins/hovox-<name>.so
VDB_LIBS  := -lopenvdb -ltbb -lImath-3_1
OIIO_LIBS  = $(shell pkg-config --libs OpenImageIO 2>/dev/null)
OIIO_CFLAGS = $(shell pkg-config --cflags OpenImageIO 2>/dev/null)
VTK_INC   := -isystem /usr/include/vtk-9.1
VTK_LIBS  := -lvtkIOXML-9.1 -lvtkIOCore-9.1 -lvtkFiltersCore-9.1 -lvtkCommonExecutionModel-9.1 \
             -lvtkCommonDataModel-9.1 -lvtkCommonCore-9.1
LIB3MF_CFLAGS := -isystem /usr/include/lib3mf
LIB3MF_LIBS   := -l3MF
PLUGINS   := $(PLUGDIR)/hovox-vdb.so $(PLUGDIR)/hovox-clipper.so
ifneq ($(wildcard src/image/oiio_bridge.cpp),)
PLUGINS   += $(PLUGDIR)/hovox-oiio.so
endif
ifneq ($(wildcard src/io/vtk/vtk_bridge.cpp),)
PLUGINS   += $(PLUGDIR)/hovox-vtk.so
endif

# ---- tests --------------------------------------------------------------------------------
TEST_C    := $(sort $(shell find tests -name 'test_*.c'))
TEST_CXX  := $(sort $(shell find tests -name 'test_*.cpp'))
TEST_BIN  := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_C)) \
             $(patsubst tests/%.cpp,$(BUILD)/tests/%,$(TEST_CXX))
BENCH_C   := $(wildcard tests/bench/*.c)
BENCH_BIN := $(patsubst tests/bench/%.c,$(BUILD)/bench-tools/%,$(BENCH_C))
TEST_SUPPORT := $(wildcard tests/support/*.c)
TEST_SUPPORT_OBJ := $(TEST_SUPPORT:%.c=$(BUILD)/obj/%.o)
CRIT_CFLAGS := $(shell pkg-config --cflags criterion 2>/dev/null)
CRIT_LIBS   := $(shell pkg-config --libs criterion 2>/dev/null)

.PHONY: all lib plugins bench-tools fuzz fuzz-tests test unit-tests header-tests cli-tests sample-tests readme-tests layering-tests long-function-tests vdb-tests mpi-tests browser-tests sanitize bench \
        demo deps clean check-deps-build check-deps-test python python-tests

all: $(BUILD)/hovox $(BUILD)/libhovox.a $(BUILD)/libhovox.so $(PLUGINS)

lib: $(BUILD)/libhovox.a

plugins: $(PLUGINS)

# ---- dependencies: installed on demand (root) or the apt command printed -----------------
$(BUILD)/.deps-build: scripts/install-deps.sh
	@mkdir -p $(BUILD)
	@sh scripts/install-deps.sh build
	@touch $@
$(BUILD)/.deps-test: scripts/install-deps.sh
	@mkdir -p $(BUILD)
	@sh scripts/install-deps.sh build test
	@touch $@

deps:
	sh scripts/install-deps.sh

# ---- build rules --------------------------------------------------------------------------
# Objects are rebuilt when the flags change. Compared when the Makefile is read, so `make -n`
# shows only what would really be compiled and writes nothing.
FLAGS_NOW := $(CC) $(CXX) $(CPPFLAGS_ALL) $(CFLAGS_ALL) $(CXXFLAGS_ALL)
ifneq ($(shell echo '$(FLAGS_NOW)' | cmp -s - $(BUILD)/.flags || echo changed),)
$(BUILD)/.flags: FORCE
endif
$(BUILD)/.flags:
	@mkdir -p $(BUILD)
	@echo '$(FLAGS_NOW)' > $@
FORCE:
# Test and fuzz objects come from chained pattern rules, so make would delete them as
# intermediates after every run and rebuild them all (minutes) in the next: keep them (only
# them: .SECONDARY would also stop a missing library object from being rebuilt).
.PRECIOUS: $(BUILD)/obj/tests/%.o

$(BUILD)/obj/%.o: %.c $(BUILD)/.flags
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS_ALL) $(PKG_CFLAGS) $(CFLAGS_ALL) -c $< -o $@

$(VIEW_GEN): $(VIEW_ASSETS) scripts/embed.sh
	@mkdir -p $(dir $@)
	sh scripts/embed.sh $@ $(VIEW_ASSETS)

$(BUILD)/obj/gen/viewer_assets.o: $(VIEW_GEN) $(BUILD)/.flags
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -c $< -o $@

$(BUILD)/libhovox.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@
	ar rcs $@ $^

$(BUILD)/libhovox.so: $(LIB_OBJ)
	$(CC) -shared -o $@ $^ $(LIBS)

$(BUILD)/hovox: $(CLI_OBJ) $(BUILD)/libhovox.a | $(PLUGINS)
	$(CC) -o $@ $(CLI_OBJ) $(BUILD)/libhovox.a $(LIBS)

# hovox-mpi: the stack commands across MPI ranks, built only when Open MPI's mpicc is there
# (the plain hovox never links MPI)
MPICC     := $(shell command -v mpicc 2>/dev/null)
ifneq ($(MPICC),)
MPI_BIN   := $(BUILD)/hovox-mpi
MPI_CFLAGS := $(shell mpicc --showme:compile 2>/dev/null)
MPI_LIBS  := $(shell mpicc --showme:link 2>/dev/null)
$(BUILD)/obj/src/cli/mpi/hovox_mpi.o: src/cli/mpi/hovox_mpi.c $(BUILD)/.flags
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS_ALL) $(PKG_CFLAGS) $(MPI_CFLAGS) $(CFLAGS_ALL) -c $< -o $@
all: $(MPI_BIN)
mpi-tests: $(MPI_BIN) $(BUILD)/hovox
	@HOVOX=$(ROOT)/$(BUILD)/hovox HOVOX_MPI=$(ROOT)/$(MPI_BIN) sh tests/mpi/run.sh
$(MPI_BIN): $(BUILD)/obj/src/cli/mpi/hovox_mpi.o $(filter-out %/main.o,$(CLI_OBJ)) $(BUILD)/libhovox.a | $(PLUGINS)
	$(CC) -o $@ $^ $(LIBS) $(MPI_LIBS)
else
mpi-tests:
	@echo "mpi: skipped (no mpicc; scripts/install-deps.sh test installs Open MPI)"
endif

$(BUILD)/obj/%.pic.o: %.cpp $(BUILD)/.flags
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS_ALL) $(CXXFLAGS_ALL) $(BRIDGE_CXXFLAGS) $(EXTRA_CXXFLAGS) -c $< -o $@

$(PLUGDIR)/hovox-vdb.so: $(BUILD)/obj/src/io/vdb/vdb_bridge.pic.o
	@mkdir -p $(dir $@)
	$(CXX) -shared -o $@ $^ $(VDB_LIBS) $(SANFLAGS)

$(PLUGDIR)/hovox-oiio.so: EXTRA_CXXFLAGS = $(OIIO_CFLAGS)
$(PLUGDIR)/hovox-oiio.so: $(BUILD)/obj/src/image/oiio_bridge.pic.o
	@mkdir -p $(dir $@)
	$(CXX) -shared -o $@ $^ $(OIIO_LIBS) $(SANFLAGS)

# Clipper (Debian libpolyclipping): the polygon Booleans of a model's Boolean tree
$(PLUGDIR)/hovox-clipper.so: $(BUILD)/obj/src/geometry/clipper_bridge.pic.o
	@mkdir -p $(dir $@)
	$(CXX) -shared -o $@ $^ -lpolyclipping $(SANFLAGS)

$(BUILD)/obj/src/io/vtk/vtk_bridge.pic.o: EXTRA_CXXFLAGS = $(VTK_INC)
$(PLUGDIR)/hovox-vtk.so: $(BUILD)/obj/src/io/vtk/vtk_bridge.pic.o
	@mkdir -p $(dir $@)
	$(CXX) -shared -o $@ $^ $(VTK_LIBS) $(SANFLAGS)

$(BUILD)/obj/src/image/oiio_bridge.pic.o: EXTRA_CXXFLAGS = $(OIIO_CFLAGS)

# ---- tests --------------------------------------------------------------------------------
$(BUILD)/obj/tests/%.o: tests/%.c $(BUILD)/.flags
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS_ALL) -Isrc -Itests $(PKG_CFLAGS) $(CRIT_CFLAGS) $(CFLAGS_ALL) -Wno-conversion -c $< -o $@

$(BUILD)/tests/%: $(BUILD)/obj/tests/%.o $(TEST_SUPPORT_OBJ) $(BUILD)/libhovox.a
	@mkdir -p $(dir $@)
	$(CC) -o $@ $< $(TEST_SUPPORT_OBJ) $(BUILD)/libhovox.a $(CRIT_LIBS) $(LIBS)

$(BUILD)/tests/%: tests/%.cpp $(TEST_SUPPORT_OBJ) $(BUILD)/libhovox.a
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS_ALL) -Isrc -Itests $(CXXFLAGS_ALL) $(CRIT_CFLAGS) -o $@ $< $(TEST_SUPPORT_OBJ) \
	    $(BUILD)/libhovox.a $(CRIT_LIBS) $(VDB_LIBS) $(LIBS)

# The 3MF tests and the mesh-format bench write their packages with lib3mf itself
# (tests/support/lib3mf_c.h)
$(BUILD)/tests/io/3mf/test_mesh_read: private LIBS += $(LIB3MF_LIBS)
$(BUILD)/bench-tools/bench_mesh_formats: private LIBS += $(LIB3MF_LIBS)
# The PNG bench compares hovox's encoder with libspng's (libpng is linked already)
$(BUILD)/bench-tools/bench_png: private LIBS += -lspng
# The lib3mf test reads hovox's 3MF Volumetric packages with the 3MF Consortium's library
$(BUILD)/tests/io/3mf/test_lib3mf: private LIBS += $(LIB3MF_LIBS)

# Benchmark drivers (tests/bench/*.c): small programs that call one kernel on a file.
$(BUILD)/bench-tools/%: $(BUILD)/obj/tests/bench/%.o $(BUILD)/libhovox.a
	@mkdir -p $(dir $@)
	$(CC) -o $@ $< $(BUILD)/libhovox.a $(LIBS)

bench-tools: $(BENCH_BIN)

# Fuzz targets (tests/fuzz/fuzz_*.c): replayed over their corpus in every test run; `make fuzz`
# builds them with clang's libFuzzer and fuzzes each for FUZZ_SECONDS.
FUZZ_C   := $(wildcard tests/fuzz/fuzz_*.c)
FUZZ_BIN := $(patsubst tests/fuzz/%.c,$(BUILD)/fuzz/%,$(FUZZ_C))
FUZZ_SECONDS ?= 60
FUZZ_ONLY ?=
$(BUILD)/fuzz/%: $(BUILD)/obj/tests/fuzz/%.o $(BUILD)/obj/tests/fuzz/replay.o $(BUILD)/libhovox.a
	@mkdir -p $(dir $@)
	$(CC) -o $@ $< $(BUILD)/obj/tests/fuzz/replay.o $(BUILD)/libhovox.a $(LIBS)

fuzz-tests: $(FUZZ_BIN)
	@for f in $(FUZZ_BIN); do n=$$(basename $$f); c=tests/fuzz/corpus/$${n#fuzz_}; \
	    printf "%s: " $$n; $$f $$c/* || exit 1; done

# The harnesses FUZZ_ONLY picks (all when empty) but fuzz_vdb, which runs in its own build below.
COMMA := ,
FUZZ_ASAN = $(filter-out tests/fuzz/fuzz_vdb.c,$(filter %$(FUZZ_ONLY).c,$(FUZZ_C)))
FUZZ_VDB  = $(if $(FUZZ_ONLY),$(filter vdb,$(FUZZ_ONLY)),vdb)

fuzz:
	@$(if $(FUZZ_ASAN)$(FUZZ_VDB),:,echo "make fuzz: no harness tests/fuzz/fuzz_*$(FUZZ_ONLY).c (FUZZ_ONLY=$(FUZZ_ONLY))" >&2; exit 2)
	@sh scripts/install-deps.sh build fuzz
	@# only what the picked harnesses need: these link build-fuzz/libhovox.a and load no plugin
	@# (fuzz_vdb, the one that loads the OpenVDB bridge, has its own build below)
	$(if $(FUZZ_ASAN),@$(MAKE) --no-print-directory BUILD=build-fuzz CC=clang CXX=clang++ SAN=1 \
	    EXTRA_CFLAGS=-fsanitize=fuzzer-no-link build-fuzz/libhovox.a)
	@for t in $(FUZZ_ASAN); do n=$$(basename $$t .c); \
	    c=tests/fuzz/corpus/$${n#fuzz_}; \
	    mkdir -p build-fuzz/libfuzzer build-fuzz/corpus-$$n; \
	    clang++ -g -O1 -fsanitize=fuzzer,address,undefined -rdynamic -Iinclude -Isrc -I. -Itests $(PKG_CFLAGS) -x c $$t -x none \
	        build-fuzz/libhovox.a $(LIBS) -o build-fuzz/libfuzzer/$$n || exit 1; \
	    LSAN_OPTIONS=suppressions=$(ROOT)/tests/lsan.supp:print_suppressions=0 ASAN_OPTIONS=allocator_may_return_null=1 \
	        build-fuzz/libfuzzer/$$n -max_total_time=$(FUZZ_SECONDS) build-fuzz/corpus-$$n $$c || exit 1; \
	done
	@# fuzz_vdb under UBSan without ASan: ASan's operator new aborts on the sizes a damaged file
	@# declares, where the plain build throws bad_alloc under the bridge's address allowance and
	@# refuses the file; the whole library and the bridge are built again for it (build-fuzz-ub).
	@# The bridge leaves out UBSan's bool check: OpenVDB reads bool values straight from the file
	@# (RootNode.h: a byte of 59 loads as a bool), which hovox cannot intercept
	$(if $(FUZZ_VDB),@$(MAKE) --no-print-directory BUILD=build-fuzz-ub CC=clang CXX=clang++ \
	    EXTRA_CFLAGS="-fsanitize=fuzzer-no-link$(COMMA)undefined -fno-sanitize-recover=undefined" \
	    EXTRA_CXXFLAGS="-fsanitize=fuzzer-no-link$(COMMA)undefined -fno-sanitize-recover=undefined -fno-sanitize=bool" \
	    build-fuzz-ub/libhovox.a $(ROOT)/build-fuzz-ub/plugins/hovox-vdb.so)
	$(if $(FUZZ_VDB),@mkdir -p build-fuzz-ub/libfuzzer build-fuzz-ub/corpus-fuzz_vdb && \
	    clang++ -g -O1 -fsanitize=fuzzer$(COMMA)undefined -fno-sanitize-recover=undefined -rdynamic -Iinclude -Isrc -I. \
	        -Itests $(PKG_CFLAGS) -x c tests/fuzz/fuzz_vdb.c -x none build-fuzz-ub/libhovox.a $(LIBS) \
	        -o build-fuzz-ub/libfuzzer/fuzz_vdb && \
	    build-fuzz-ub/libfuzzer/fuzz_vdb -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=4096 \
	        build-fuzz-ub/corpus-fuzz_vdb tests/fuzz/corpus/vdb)

# ---- Python ------------------------------------------------------------------------------
# `make python`: the package hovox (python/) built in place over libhovox.a, its plugins copied
# beside the extension; `make python-tests` runs its pytest suite (python/tests). Under SAN=1 it is
# built into $(BUILD)/python instead and run with ASan preloaded (Python itself is not
# instrumented; PYTHONMALLOC=malloc lets ASan see every allocation).
PYTHON  ?= /usr/bin/python3
ifeq ($(SAN),1)
PYDIR   := $(ROOT)/$(BUILD)/python
PY_BUILD = build --build-base $(ROOT)/$(BUILD)/python-tmp --build-lib $(PYDIR)
PY_RUN   = cat tests/lsan.supp tests/lsan-python.supp >$(BUILD)/lsan-python.supp && \
           LD_PRELOAD=$$($(CC) -print-file-name=libasan.so) PYTHONMALLOC=malloc \
           LSAN_OPTIONS=suppressions=$(ROOT)/$(BUILD)/lsan-python.supp:print_suppressions=0
else
PYDIR   := $(ROOT)/python
PY_BUILD = build_ext --inplace --build-temp $(ROOT)/$(BUILD)/python-tmp
PY_RUN   =
endif

python: $(BUILD)/libhovox.a $(PLUGINS)
	@cd python && HOVOX_BUILD=$(ROOT)/$(BUILD) HOVOX_SAN=$(SAN) HOVOX_WERROR=$(WERROR) \
	    $(PYTHON) setup.py -q $(PY_BUILD) >$(ROOT)/$(BUILD)/python-build.log 2>&1 || \
	    { cat $(ROOT)/$(BUILD)/python-build.log; exit 1; }

python-tests: python $(BUILD)/hovox
	@$(PY_RUN) PYTHONPATH=$(PYDIR) HOVOX=$(ROOT)/$(BUILD)/hovox HOVOX_SHARED=$(SHARED) \
	    $(PYTHON) -m pytest -q -p no:cacheprovider python/tests

# Every public header compiles alone as C11 and as C++17.
$(BUILD)/.headers-ok: $(HEADERS)
	@mkdir -p $(BUILD)
	@for h in $(HEADERS); do \
	    echo "#include \"$${h#include/}\"" | $(CC) -std=c11 -pedantic -Wall -Wextra -Werror \
	        -Iinclude -x c -fsyntax-only - || exit 1; \
	    echo "#include \"$${h#include/}\"" | $(CXX) -std=c++17 -pedantic -Wall -Wextra -Werror \
	        -Iinclude -x c++ -fsyntax-only - || exit 1; \
	done
	@echo "headers: $(words $(HEADERS)) public headers compile as C11 and C++17"
	@touch $@

header-tests: $(BUILD)/.headers-ok

unit-tests: $(TEST_BIN) $(PLUGINS)
	@fail=0; for t in $(TEST_BIN); do \
	    HOVOX_SHARED=$(SHARED) HOVOX_BUILD=$(BUILD) $$t --jobs 2 >$$t.log 2>&1; rc=$$?; \
	    tail -n 1 $$t.log | sed "s|^|$${t#$(BUILD)/tests/}: |"; \
	    if [ $$rc -ne 0 ]; then cat $$t.log; fail=1; fi; \
	done; exit $$fail

cli-tests: $(BUILD)/hovox $(PLUGINS)
	@HOVOX=$(ROOT)/$(BUILD)/hovox SHARED=$(SHARED) sh tests/cli/run.sh

# Damaged and hostile .vdb files end cleanly, in time and memory (not under ASan: its shadow
# memory is not the program's).
vdb-tests: $(BUILD)/hovox $(PLUGINS) $(BUILD)/fuzz/fuzz_vdb
	@HOVOX=$(ROOT)/$(BUILD)/hovox sh tests/io/vdb/corrupt_vdb.sh

# hovox view's pages in Debian's chromium, headless, driven over the DevTools protocol
# (tests/browser). With no chromium installed the test says so and passes, unless
# HOVOX_REQUIRE_BROWSER=1 (.ci/run sets it) or CI is set: then it fails.
browser-tests: $(BUILD)/hovox $(PLUGINS)
	@HOVOX=$(ROOT)/$(BUILD)/hovox /usr/bin/python3 tests/browser/test_view.py

sample-tests: $(BUILD)/hovox $(PLUGINS)
	@if [ -f tests/samples/run.sh ]; then HOVOX=$(ROOT)/$(BUILD)/hovox SHARED=$(SHARED) \
	    sh tests/samples/run.sh; fi

# every README example, verbatim (tests/readme/run.py: sh blocks, transcripts, the Lua example)
readme-tests: $(BUILD)/hovox $(PLUGINS) $(MPI_BIN)
	@/usr/bin/python3 tests/readme/run.py README.md --hovox $(ROOT)/$(BUILD)/hovox

# the includes point down the pipeline (scripts/layering.py; STYLE.md rule 1)
layering-tests:
	@/usr/bin/python3 scripts/layering.py

# no function over 120 lines outside numeric kernels that say why (scripts/long_functions.py; issue 26)
long-function-tests:
	@/usr/bin/python3 scripts/long_functions.py --self-test
	@/usr/bin/python3 scripts/long_functions.py

test: $(BUILD)/.deps-test
	@$(MAKE) --no-print-directory all
	@$(MAKE) --no-print-directory layering-tests long-function-tests header-tests unit-tests fuzz-tests cli-tests sample-tests readme-tests vdb-tests mpi-tests python-tests browser-tests

# intercept_tls_get_addr=0: GCC 12's LeakSanitizer misreads glibc 2.36's dynamic TLS blocks of
# dlopen'd plugins (a "DTLS" range of garbage) and its tracer crashes at exit ("Tracer caught
# signal 11"); without the interception it scans static TLS and every heap block as before.
sanitize: $(BUILD)/.deps-test
	@$(MAKE) --no-print-directory BUILD=build-san SAN=1 all
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=print_stacktrace=1 \
	    LSAN_OPTIONS=suppressions=$(ROOT)/tests/lsan.supp:print_suppressions=0 \
	    $(MAKE) --no-print-directory BUILD=build-san SAN=1 unit-tests fuzz-tests cli-tests sample-tests python-tests

bench: $(BUILD)/.deps-test
	@sh scripts/install-deps.sh build test bench
	@$(MAKE) --no-print-directory all bench-tools
	@HOVOX=$(ROOT)/$(BUILD)/hovox BUILD=$(BUILD) SHARED=$(SHARED) sh scripts/bench.sh

demo: $(BUILD)/.deps-build
	@$(MAKE) --no-print-directory all
	@HOVOX=$(ROOT)/$(BUILD)/hovox sh scripts/demo.sh

clean:
	rm -rf build build-san build-fuzz build-fuzz-ub
	rm -rf python/build python/*.egg-info python/hovox/plugins python/hovox/_hovox*.so

# `make -s print-LIBS`: a variable's value (the Python build links with the same libraries)
print-%:
	@echo '$($*)'

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
