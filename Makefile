# sepal - one Makefile for everything. `make help` lists the targets.
#
# Layout of outputs: build/bin (sepal, sepal-view, sepal-tests), build/lib (static
# libraries), build/obj (objects + dependency files), build/gen (embedded shaders).
# Sanitizer builds live in build/asan with the same layout.

CXX      ?= g++
# Each compiler gets its own tree so `make CXX=clang++` really rebuilds everything.
BUILD    ?= build$(if $(findstring clang,$(CXX)),/clang)
SAN      ?=
NPROC    := $(shell nproc 2>/dev/null || echo 2)
# `make V=1` prints whole compiler command lines.
ifeq ($(V),1)
  Q :=
  say = @true
else
  Q := @
  say = @printf '  %-5s %s\n' $(1) $(2)
endif

# Debian packages the project needs: compilers and make are assumed only as far as
# running this Makefile goes; everything else is checked and installed by `make deps`.
DEB_PACKAGES := g++ make pkg-config libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri \
                libglm-dev libstb-dev doctest-dev libeigen3-dev \
                nlohmann-json3-dev libcli11-dev libtinygltf-dev libx11-dev xvfb xauth xdotool emscripten chromium

WARN     := -Wall -Wextra -Werror
CXXSTD   := -std=c++17
OPT      ?= -O2 -g
# GCC's -fsanitize=undefined leaves out float-cast-overflow (a double beyond int's range
# converted to int): named on its own so make test-asan catches it.
ifeq ($(SAN),1)
  OPT    := -O1 -g -fno-omit-frame-pointer
  SANFLAGS := -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=undefined,float-cast-overflow
endif
# make fuzz's tree (clang): every object instrumented for libFuzzer; the harnesses link with
# -fsanitize=fuzzer. No -Werror: clang warns about things g++ does not, and the g++ build
# (make, make test) is the one that holds the warning line.
ifeq ($(SAN),fuzz)
  OPT    := -O1 -g -fno-omit-frame-pointer
  FUZZ_SAN := address,undefined,float-cast-overflow
  SANFLAGS := -fsanitize=fuzzer-no-link,$(FUZZ_SAN) -fno-sanitize-recover=all
  WARN   := -Wall -Wextra
endif
# Tests and benchmarks read ../shared (the research data beside a checkout); a worktree
# elsewhere points SHARED at it.
SHARED   ?= $(abspath $(CURDIR)/../shared)
# Include roots: public runtime API as "sepal/...", offline stages as "brdf/...",
# ports as "headless/..." and "common/...", generated shader text as "shaders/...".
CPPFLAGS := -isystem /usr/include/eigen3 -Iruntime/include -Ioffline -Iports -I$(BUILD)/gen \
            -DSEPAL_SOURCE_DIR='"$(CURDIR)"' -DSEPAL_BIN_DIR='"$(CURDIR)/$(BUILD)/bin"' \
            -DSEPAL_SHARED_DIR='"$(SHARED)"'
# Tests (only they) may reach the runtime's private headers.
TEST_CPPFLAGS := -Itests -Iruntime/src
CXXFLAGS_ALL := $(CXXSTD) $(OPT) $(WARN) $(SANFLAGS) -MMD -MP
# The runtime is shipped to constrained targets: no exceptions, no RTTI.
RUNTIME_FLAGS := -fno-exceptions -fno-rtti
LDFLAGS  := $(SANFLAGS)
GL_LIBS  := -lEGL -lGLESv1_CM -lGLESv2
LIBS     := $(GL_LIBS) -lpthread

# Sources are found by folder: a new file under runtime/src, offline/<stage> or tests/
# joins its library or the test binary without an edit here.
rwildcard = $(foreach d,$(wildcard $(1:=/*)),$(call rwildcard,$d,$2) $(filter $(subst *,%,$2),$d))
RUNTIME_SRC  := $(wildcard runtime/src/*.cpp)
SEPAL_MAIN   := offline/cli/sepal_main.cpp
OFFLINE_SRC  := $(filter-out $(SEPAL_MAIN),$(call rwildcard,offline,*.cpp))
HEADLESS_SRC := $(wildcard ports/headless/*.cpp ports/common/*.cpp)
# stb_image + stb_image_write, compiled once for offline/ and ports/ (third_party/stb/stb.cpp).
STB_SRC      := third_party/stb/stb.cpp
VIEW_MAIN    := ports/windowed/sepal_view_main.cpp
WINDOWED_SRC := $(filter-out $(VIEW_MAIN),$(wildcard ports/windowed/*.cpp))
TEST_SRC     := $(filter-out tests/bench/% tests/fuzz/entry/%,$(call rwildcard,tests,*.cpp))
# Each tests/bench/<name>.cpp is one program, build/bin/sepal-bench-<name>, linked with the
# doctest-free support objects below; tests/bench/run.sh is what `make bench` runs.
BENCH_SRC    := $(wildcard tests/bench/*.cpp)
BENCH_SUPPORT_SRC := tests/extremes_runtime_cases.cpp tests/gl_counter.cpp
BENCH_BINS   := $(patsubst tests/bench/%.cpp,$(BUILD)/bin/sepal-bench-%,$(BENCH_SRC))
SHADERS      := $(wildcard shaders/*.vert shaders/*.frag)
SHADER_INCS  := $(SHADERS:%=$(BUILD)/gen/%.inc)

obj = $(patsubst %.cpp,$(BUILD)/obj/%.o,$(1))
RUNTIME_OBJ  := $(call obj,$(RUNTIME_SRC))
OFFLINE_OBJ  := $(call obj,$(OFFLINE_SRC))
HEADLESS_OBJ := $(call obj,$(HEADLESS_SRC))
STB_OBJ      := $(call obj,$(STB_SRC))
WINDOWED_OBJ := $(call obj,$(WINDOWED_SRC))
TEST_OBJ     := $(call obj,$(TEST_SRC))
BENCH_OBJ    := $(call obj,$(BENCH_SRC))
BENCH_SUPPORT_OBJ := $(call obj,$(BENCH_SUPPORT_SRC))

LIB_RUNTIME  := $(BUILD)/lib/libsepal_runtime.a
# The GL ES emulator (sepal/internal/sepal_emulate.h): compiled as the runtime is, kept out of
# libsepal (static and shared); the tools, ports/common and the tests link it.
EMULATE_OBJ  := $(call obj,runtime/src/emulate_gles1.cpp)
LIB_EMULATE  := $(BUILD)/lib/libsepal_emulate.a
LIB_OFFLINE  := $(BUILD)/lib/libsepal_offline.a
LIB_HEADLESS := $(BUILD)/lib/libsepal_headless.a
LIB_STB      := $(BUILD)/lib/libsepal_stb.a
LIB_WINDOWED := $(BUILD)/lib/libsepal_windowed.a
BIN_SEPAL    := $(BUILD)/bin/sepal
BIN_VIEW     := $(BUILD)/bin/sepal-view
BIN_TESTS    := $(BUILD)/bin/sepal-tests
BENCH_OUT    := $(BUILD)/bench

RUN_OUT      := $(BUILD)/out/sepal-run.png
# The default material of `make run`: an anisotropic Ward (Ward 1992), baked with the
# defaults a new user gets (no flags: the best image on GL ES 1.1, docs/fidelity.md).
RUN_SPEC     := ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15
RUN_BAKE     :=
RUN_ASSET    := $(BUILD)/out/ward.sepal
RUN_SHEET    := $(BUILD)/out/sepal-run-sheet.png

# Installing (make install PREFIX=DIR [DESTDIR=staging]): the version is defined once, in
# the umbrella header; the shared libraries' soname carries its major number.
PREFIX     ?= /usr/local
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
SEPAL_VERSION := $(shell sed -n 's/^\#define SEPAL_VERSION_STRING "\(.*\)"/\1/p' runtime/include/sepal/sepal_version.h)
SOVERSION  := $(firstword $(subst ., ,$(SEPAL_VERSION)))
DIST       := $(BUILD)/dist
HEADLESS_PORT_OBJ := $(call obj,ports/headless/sepal_headless.cpp)
PUBLIC_HEADERS := $(wildcard runtime/include/sepal/*.h) ports/headless/sepal_headless.h
DIST_FILES := $(DIST)/libsepal.a $(DIST)/libsepal.so.$(SEPAL_VERSION) \
              $(DIST)/libsepal_headless.a $(DIST)/libsepal_headless.so.$(SEPAL_VERSION)
# make's build tree as an installed one (below, before the web port).
UNINSTALLED := $(addprefix $(BUILD)/include/sepal/,$(notdir $(PUBLIC_HEADERS))) $(BUILD)/sepal-uninstalled.pc

# The web port (make web): the runtime's GL ES 2 paths and ports/web through Emscripten
# (Debian's emcc works offline; it needs Debian's node modules on NODE_PATH). One tree
# whatever CXX or SAN say: emcc is its compiler.
EMCC       ?= emcc
EMENV      := NODE_PATH=/usr/share/nodejs
WEB_DIR    := build/web
WEB_SRC    := $(filter-out runtime/src/draw_gles1.cpp runtime/src/preview_gles1.cpp,$(RUNTIME_SRC)) \
              $(wildcard ports/web/*.cpp) ports/common/scene_flags.cpp ports/common/orbit.cpp \
              ports/common/term_prefix.cpp ports/common/scene_args.cpp ports/common/scene_draw.cpp \
              ports/common/scene_bundle.cpp ports/common/scene_motion.cpp
WEB_OBJ    := $(patsubst %.cpp,build/web-obj/%.o,$(WEB_SRC))
WEB_CXXFLAGS := -std=c++17 -O2 $(WARN) -fno-exceptions -fno-rtti -DSEPAL_NO_GLES1 -MMD -MP
WEB_EXPORTS := $(foreach f,$(shell grep -o '^EMSCRIPTEN_KEEPALIVE.* sepal_web_[a-z_]*' ports/web/sepal_web.cpp 2>/dev/null | grep -o 'sepal_web_[a-z_]*$$'),"_$(f)",)
# FULL_ES2 copies client-side vertex arrays into temporary buffers sized by the draw's index
# count times the stride: the default 128 x 64 sphere (49,152 indices x 44-byte vertices) is
# 2.1 MB, past Emscripten's default 2 MB ring, and drew nothing; 32 MB holds 760k indices.
WEB_LDFLAGS := -O2 -s FULL_ES2=1 -s GL_MAX_TEMP_BUFFER_SIZE=33554432 -s ENVIRONMENT=web -s FILESYSTEM=0 -s ALLOW_MEMORY_GROWTH=1 \
               -s EXPORTED_FUNCTIONS='[$(WEB_EXPORTS)"_malloc","_free"]' \
               -s EXPORTED_RUNTIME_METHODS='["cwrap","UTF8ToString","stringToUTF8"]'
WEB_FILES  := $(WEB_DIR)/sepal.js $(WEB_DIR)/index.html $(WEB_DIR)/app.js $(WEB_DIR)/default.sepal $(WEB_DIR)/kiosk/scene.txt

.SECONDARY:
.PHONY: all build bench-bins help deps run test test-asan update-goldens bench clean check-runtime check-c99 check-layers check-functions FORCE \
        check compdb format \
        install uninstall examples web fuzz fuzz-bins

all: build ## the default: same as make build

build: $(BIN_SEPAL) $(BIN_VIEW) $(BIN_TESTS) $(UNINSTALLED) check-runtime check-c99 check-layers check-functions ## build the tools, the libraries and the tests into build/ (-Wall -Wextra -Werror; the benches: make bench-bins)

bench-bins: $(BENCH_BINS) ## build the benchmark programs (build/bin/sepal-bench-*) without running them

help: ## list the targets
	@grep -hE '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed -E 's/^([a-z-]+):.*## (.*)/  make \1\t\2/' | expand -t 24

deps: ## install missing Debian packages (as root; otherwise print the apt-get command and fail)
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -z "$$missing" ]; then exit 0; fi; \
	cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends$$missing"; \
	if [ "$$(id -u)" != 0 ]; then echo "sepal: missing Debian packages:$$missing"; \
	  echo "sepal: run as root:  $$cmd"; exit 1; fi; \
	echo "sepal: installing$$missing"; sh -c "$$cmd"

run: deps ## build, bake the default material, render it headless on GL ES 1.1 to a PNG
	@$(MAKE) --no-print-directory -s -j$(NPROC) $(BIN_VIEW) $(BIN_SEPAL) $(RUN_ASSET)
	@$(BIN_SEPAL) render '$(RUN_SPEC)' --backend exact -o $(BUILD)/out/sepal-run-exact.png > /dev/null
	@$(BIN_VIEW) --headless $(RUN_ASSET) --backend gles1 -o $(RUN_OUT) > /dev/null
	@$(BIN_SEPAL) diff $(BUILD)/out/sepal-run-exact.png $(RUN_OUT) | sed -n 's/^psnr *\([^ ]* dB\).*/PSNR against the exact render, default scene (in-sample): \1/p'
	@# The held-out condition the bake did worst in (lights the search never saw), drawn the same way
	@# at sepal render's 512 x 512 (the bake judges at 128 x 128: its line below says so).
	@flags=$$(awk '/^  held-out/ { p = $$0; sub(/ dB,.*/, "", p); n = split(p, a, " "); \
	    if (best == "" || a[n] + 0 < best) { best = a[n] + 0; f = $$0 } } \
	    END { sub(/^[^(]*\(/, "", f); sub(/\)$$/, "", f); sub(/ --size [0-9x]+/, "", f); print f }' $(BUILD)/out/ward.bake.txt); \
	  $(BIN_SEPAL) render '$(RUN_SPEC)' --backend exact $$flags -o $(BUILD)/out/sepal-run-held-out-exact.png > /dev/null && \
	  $(BIN_VIEW) --headless $(RUN_ASSET) --backend gles1 $$flags -o $(BUILD)/out/sepal-run-held-out.png > /dev/null && \
	  $(BIN_SEPAL) diff $(BUILD)/out/sepal-run-held-out-exact.png $(BUILD)/out/sepal-run-held-out.png --sheet $(RUN_SHEET) | \
	  sed -n "s|^psnr *\([^ ]* dB\).*|PSNR against the exact render, held out (its worst condition: $$flags): \1|p"
	@sed -n 's/^held-out: /the bake: held-out /p' $(BUILD)/out/ward.bake.txt
	@echo "exact | gles1 | error heatmap, the held-out condition, and its window of the largest difference magnified: $(RUN_SHEET)"
	@echo $(RUN_OUT)

# Re-baked when the tool changes; the bake is deterministic.
$(RUN_ASSET): $(BIN_SEPAL)
	@mkdir -p $(dir $@)
	@echo "sepal: baking $(RUN_SPEC)"
	@$(BIN_SEPAL) bake '$(RUN_SPEC)' $(RUN_BAKE) -o $@ > $(BUILD)/out/ward.bake.txt

test: deps ## build and run every doctest suite (the web port's test needs `make web`, the make-bench test the benches: built here too)
	@$(MAKE) --no-print-directory -j$(NPROC) build web bench-bins
	@sh tests/run.sh $(BIN_TESTS)

# The inner loop: the test binary only (no web port, no benches, no sepal-view), filtered
# with doctest's -tc (TC='*bake*'); the suites that drive Xvfb or Chromium, and the ones that
# run the bench programs, are left out.
TC ?= *
check: ## build the test binary and run the suites matching TC (default all), without the Xvfb, Chromium and bench-program tests
	@$(MAKE) --no-print-directory -j$(NPROC) $(BIN_TESTS)
	@$(BIN_TESTS) -tc='$(TC)' -tce='*Xvfb*,*Chromium*,make bench*'

# .clang-format's house style over every C/C++ source of ours (third_party/ untouched).
format: ## apply .clang-format to every C/C++ source (clang-format, Debian's clang-format)
	@$(MAKE) --no-print-directory deps DEB_PACKAGES=clang-format
	@find runtime offline ports tests examples -name '*.cpp' -o -name '*.h' -o -name '*.c' | xargs clang-format -i

# compile_commands.json for clangd and clang-tidy, from the flags this Makefile compiles with
# (written by make itself: no tool beyond make).
compdb_json = $(subst ",\",$(1))
compdb_entry = {"directory": "$(CURDIR)", "file": "$(1)", "command": "$(call compdb_json,$(2) -c $(1) -o $(call obj,$(1)))"}
compdb_list = $(foreach f,$(1),$(call compdb_entry,$(f),$(2)))
COMPDB := $(call compdb_list,$(RUNTIME_SRC),$(CXX) $(CPPFLAGS) $(CXXFLAGS_ALL) $(RUNTIME_FLAGS)) \
          $(call compdb_list,$(OFFLINE_SRC) $(SEPAL_MAIN) $(HEADLESS_SRC) $(WINDOWED_SRC) $(VIEW_MAIN) $(STB_SRC),$(CXX) $(CPPFLAGS) $(CXXFLAGS_ALL)) \
          $(call compdb_list,$(TEST_SRC) $(BENCH_SRC),$(CXX) $(CPPFLAGS) $(TEST_CPPFLAGS) $(CXXFLAGS_ALL))
compdb: ## write compile_commands.json (clangd, clang-tidy) from this Makefile's flags
	$(file >compile_commands.json,[$(subst } {,}$(comma)$(newline) {,$(strip $(COMPDB)))]$(newline))
	@echo "compile_commands.json: $(words $(RUNTIME_SRC) $(OFFLINE_SRC) $(SEPAL_MAIN) $(HEADLESS_SRC) $(WINDOWED_SRC) $(VIEW_MAIN) $(STB_SRC) $(TEST_SRC) $(BENCH_SRC)) files"
comma := ,
define newline


endef

test-asan: deps ## run the test suites under AddressSanitizer + UndefinedBehaviorSanitizer
	@$(MAKE) --no-print-directory -j$(NPROC) BUILD=build/asan SAN=1 build web bench-bins
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  sh tests/run.sh build/asan/bin/sepal-tests

update-goldens: deps ## rewrite fixtures/golden/*.png, the ports' screenshots in docs/img and docs/cli.md from the current build
	@$(MAKE) --no-print-directory -j$(NPROC) build web
	@SEPAL_UPDATE_GOLDENS=1 $(BIN_TESTS) -tc='*golden*,*Xvfb*,*Chromium*,docs/cli.md*'

bench: deps ## benchmarks that produce the README figures (long sweeps live here, not in tests)
	@$(MAKE) --no-print-directory -j$(NPROC) $(BENCH_BINS) web
	@sh tests/bench/run.sh $(BUILD) $(BENCH_OUT)

clean: ## remove build/
	rm -rf build

install: $(BIN_SEPAL) $(BIN_VIEW) $(DIST_FILES) ## install libsepal (static + shared), headers, sepal.pc and the tools under PREFIX (default /usr/local)
	@echo "sepal: installing $(SEPAL_VERSION) into $(DESTDIR)$(PREFIX)"
	@install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCLUDEDIR)/sepal
	@install -m 755 $(BIN_SEPAL) $(BIN_VIEW) $(DESTDIR)$(PREFIX)/bin/
	@install -d $(DESTDIR)$(PREFIX)/share/sepal/merl-nbrdf
	@install -m 644 data/merl-nbrdf/* $(DESTDIR)$(PREFIX)/share/sepal/merl-nbrdf/
	@install -m 644 $(PUBLIC_HEADERS) $(DESTDIR)$(INCLUDEDIR)/sepal/
	@install -m 644 $(DIST)/libsepal.a $(DIST)/libsepal_headless.a $(DESTDIR)$(LIBDIR)/
	@for lib in libsepal libsepal_headless; do \
	  install -m 755 $(DIST)/$$lib.so.$(SEPAL_VERSION) $(DESTDIR)$(LIBDIR)/ && \
	  ln -sf $$lib.so.$(SEPAL_VERSION) $(DESTDIR)$(LIBDIR)/$$lib.so.$(SOVERSION) && \
	  ln -sf $$lib.so.$(SOVERSION) $(DESTDIR)$(LIBDIR)/$$lib.so; done
	@sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' -e 's|@INCLUDEDIR@|$(INCLUDEDIR)|' \
	  -e 's|@VERSION@|$(SEPAL_VERSION)|' packaging/sepal.pc.in > $(DESTDIR)$(LIBDIR)/pkgconfig/sepal.pc

uninstall: ## remove what `make install PREFIX=...` installed
	rm -f $(DESTDIR)$(PREFIX)/bin/sepal $(DESTDIR)$(PREFIX)/bin/sepal-view $(DESTDIR)$(LIBDIR)/pkgconfig/sepal.pc
	rm -rf $(DESTDIR)$(PREFIX)/share/sepal
	rm -f $(addprefix $(DESTDIR)$(INCLUDEDIR)/sepal/,$(notdir $(PUBLIC_HEADERS)))
	rm -f $(foreach l,libsepal libsepal_headless,$(addprefix $(DESTDIR)$(LIBDIR)/$(l),.a .so .so.$(SOVERSION) .so.$(SEPAL_VERSION)))
	-rmdir $(DESTDIR)$(INCLUDEDIR)/sepal 2>/dev/null

# examples/*.c built in a fresh folder against the installed tree only (pkg-config), once
# with the shared libraries and once with the static ones, and run on an asset the
# installed `sepal` bakes.
examples: ## build examples/ against an installed tree (PREFIX) through pkg-config, and run them
	@test -f $(LIBDIR)/pkgconfig/sepal.pc || { echo "make examples: $(LIBDIR)/pkgconfig/sepal.pc is missing: run make install PREFIX=$(PREFIX) first"; exit 1; }
	@rm -rf $(BUILD)/examples && mkdir -p $(BUILD)/examples && cp examples/*.c $(BUILD)/examples/
	@cd $(BUILD)/examples && export PKG_CONFIG_PATH=$(LIBDIR)/pkgconfig && set -e && \
	  for c in *.c; do n=$${c%.c}; \
	    echo "  CC    $$n (shared) and $$n-static: pkg-config --cflags --libs sepal"; \
	    $(CC) -std=c99 -Wall -Wextra -pedantic -Werror $$c $$(pkg-config --cflags --libs sepal glesv1_cm) -lm -o $$n; \
	    $(CC) -std=c99 -Wall -Wextra -pedantic -Werror $$c $$(pkg-config --cflags sepal) \
	      $$(pkg-config --static --libs sepal | sed 's/-lsepal_headless -lsepal/-l:libsepal_headless.a -l:libsepal.a/') -o $$n-static; \
	  done && \
	  $(PREFIX)/bin/sepal bake '$(RUN_SPEC)' $(RUN_BAKE) -o ward.sepal > bake.txt && \
	  echo "  RUN   $(PREFIX)/bin/sepal eval nbrdf:gold-paint (the installed data, from /)" && \
	  (cd / && env -u SEPAL_DATA_DIR $(abspath $(PREFIX))/bin/sepal eval nbrdf:gold-paint 30 0 30 180) && \
	  LD_LIBRARY_PATH=$(LIBDIR) ./minimal ward.sepal 2 minimal.ppm && ./minimal-static ward.sepal 1 && \
	  LD_LIBRARY_PATH=$(LIBDIR) ./two_objects ward.sepal two_objects.ppm && ./two_objects-static ward.sepal

# libFuzzer harnesses (tests/fuzz/fuzz_<name>.cpp; tests/fuzz/fuzz.h says what each holds a
# reader to), built with Debian's clang (installed here, by deps, for this target only) into
# build/fuzz/bin/fuzz-<name>, each run for FUZZ_SECONDS on a corpus seeded from fixtures/;
# tests/fuzz/run.sh prints the exec counts and keeps crashers in build/fuzz/crashes/<name>/
# (after the fix, add them to fixtures/fuzz/<name>/: make test replays that folder).
FUZZ_SECONDS ?= 60
FUZZ_TIMEOUT ?= 1
FUZZ_DEB_PACKAGES := clang libclang-rt-dev
FUZZ_NAMES   := $(patsubst tests/fuzz/fuzz_%.cpp,%,$(wildcard tests/fuzz/fuzz_*.cpp))
FUZZ_BUILD   := build/fuzz
fuzz: deps ## build the libFuzzer harnesses (clang, ASan + UBSan) and run each for FUZZ_SECONDS (default 60)
	@$(MAKE) --no-print-directory deps DEB_PACKAGES='$(FUZZ_DEB_PACKAGES)'
	@$(MAKE) --no-print-directory -j$(NPROC) CXX=clang++ CC=clang BUILD=$(FUZZ_BUILD) SAN=fuzz fuzz-bins
	@sh tests/fuzz/run.sh $(FUZZ_BUILD) $(FUZZ_SECONDS) $(FUZZ_TIMEOUT) $(FUZZ_NAMES)

web: $(WEB_FILES) ## the web port into build/web/ (Emscripten, WebGL 1): open index.html through any static server
	@printf '  %-5s %s (%s bytes)\n' WASM $(WEB_DIR)/sepal.wasm $$(stat -c %s $(WEB_DIR)/sepal.wasm)

# ---- rules -----------------------------------------------------------------------------
$(BUILD)/gen/shaders/%.inc: shaders/%
	@mkdir -p $(dir $@)
	@{ printf 'R"sepal_glsl('; cat $<; printf ')sepal_glsl"\n'; } > $@.tmp && mv $@.tmp $@

# The analytic models' table (names, documentation, parameter ranges) is data, compiled in.
$(BUILD)/gen/brdf/%.json.inc: offline/brdf/%.json
	@mkdir -p $(dir $@)
	@{ printf 'R"sepal_json('; cat $<; printf ')sepal_json"\n'; } > $@.tmp && mv $@.tmp $@
$(call obj,offline/brdf/brdf_models.cpp): $(BUILD)/gen/brdf/models.json.inc

$(RUNTIME_OBJ): $(BUILD)/obj/%.o: %.cpp | $(SHADER_INCS)
	@mkdir -p $(dir $@)
	$(call say,CXX,$<)
	$(Q)$(CXX) $(CPPFLAGS) $(CXXFLAGS_ALL) $(RUNTIME_FLAGS) -c $< -o $@

# The per-vertex set-up runs for every vertex and light of every frame and dominates the CPU
# side of a frame (make bench: runtime): its three files get -O3 (set-up 1.2x faster at one
# light, about 1.6x at four; the same floats: no -ffast-math); the rest of the runtime stays
# at -O2 for its size.
ifeq ($(SAN),)
$(call obj,runtime/src/vertex_setup.cpp runtime/src/param.cpp runtime/src/common.cpp): RUNTIME_FLAGS += -O3
endif
# No a * b + c fused into one rounding (FMA targets: aarch64, x86 with -mfma): the batched
# set-up and the one-vertex reference it must equal bit for bit would fuse differently.
$(call obj,runtime/src/vertex_setup.cpp runtime/src/param.cpp runtime/src/common.cpp): RUNTIME_FLAGS += -ffp-contract=off
# The batched set-up loops vectorize only when sqrtf need not set errno and a division may be
# computed before the select that picks it (neither changes a result: the same IEEE floats).
$(call obj,runtime/src/vertex_setup.cpp): RUNTIME_FLAGS += -fno-math-errno -fno-trapping-math

# Offline hot loops at -O3, where GCC then vectorizes element-wise loops (axpys, ratios) that
# -O2 leaves scalar: the same floats (no reassociation without -ffast-math, no FMA without
# -mfma), so the same outputs. KL-NMF's fused updates (sampling's fits: a quarter of its
# bench) and the MERL network's layers (every nbrdf: evaluation); check a change with
# `sepal-bench-sampling table1 --only ni` (processor-seconds side by side, identical tables).
OFFLINE_HOT := offline/sampling/nmf_kl.cpp offline/measured/nbrdf.cpp
ifeq ($(SAN),)
$(call obj,$(OFFLINE_HOT)): OFFLINE_FLAGS += -O3
endif

$(TEST_OBJ) $(BENCH_OBJ) $(BENCH_SUPPORT_OBJ): CPPFLAGS += $(TEST_CPPFLAGS)

$(BUILD)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(call say,CXX,$<)
	$(Q)$(CXX) $(CPPFLAGS) $(CXXFLAGS_ALL) $(OFFLINE_FLAGS) -c $< -o $@

$(BUILD)/lib/lib%.a:
	@mkdir -p $(dir $@)
	@rm -f $@
	$(call say,AR,$@)
	$(Q)ar rcs $@ $^

$(LIB_RUNTIME): $(filter-out $(EMULATE_OBJ),$(RUNTIME_OBJ))
$(LIB_EMULATE): $(EMULATE_OBJ)
$(LIB_OFFLINE): $(OFFLINE_OBJ)
$(LIB_HEADLESS): $(HEADLESS_OBJ)
$(LIB_STB): $(STB_OBJ)
$(LIB_WINDOWED): $(WINDOWED_OBJ)

$(BIN_SEPAL): $(call obj,$(SEPAL_MAIN)) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_STB) $(LIB_EMULATE) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $^ $(LIBS) -o $@

# sepal-view: the runtime and the ports only, no offline code (the window through Xlib).
$(BIN_VIEW): $(call obj,$(VIEW_MAIN)) $(LIB_WINDOWED) $(LIB_HEADLESS) $(LIB_STB) $(LIB_EMULATE) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $^ $(LIBS) -lX11 -o $@

$(BIN_TESTS): $(TEST_OBJ) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_STB) $(LIB_EMULATE) $(LIB_RUNTIME) $(BIN_SEPAL)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $(TEST_OBJ) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_STB) $(LIB_EMULATE) $(LIB_RUNTIME) $(LIBS) -o $@

# sepal-bench-<name>: one program per tests/bench/<name>.cpp (`make bench`).
$(BUILD)/bin/sepal-bench-%: $(BUILD)/obj/tests/bench/%.o $(BENCH_SUPPORT_OBJ) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_STB) $(LIB_EMULATE) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $^ $(LIBS) -o $@

# make fuzz's programs: libFuzzer's entry compiled once per harness, naming its function.
FUZZ_BINS := $(FUZZ_NAMES:%=$(BUILD)/bin/fuzz-%)
fuzz-bins: $(FUZZ_BINS)
$(BUILD)/obj/tests/fuzz/entry/libfuzzer-%.o: tests/fuzz/entry/libfuzzer.cpp
	@mkdir -p $(dir $@)
	$(call say,CXX,$@)
	$(Q)$(CXX) $(CPPFLAGS) $(TEST_CPPFLAGS) $(CXXFLAGS_ALL) -DSEPAL_FUZZ_TARGET=sepal_fuzz_$* -c $< -o $@
$(BUILD)/bin/fuzz-%: $(BUILD)/obj/tests/fuzz/entry/libfuzzer-%.o $(BUILD)/obj/tests/fuzz/fuzz_%.o \
                     $(call obj,tests/fuzz/common.cpp) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_STB) $(LIB_EMULATE) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) -fsanitize=fuzzer,$(FUZZ_SAN) $^ $(LIBS) -o $@

# ---- the installed libraries -----------------------------------------------------------
# Objects of the shared libraries are position-independent. PIC_FLAGS is recorded in a
# file that changes only when the flags do, so objects built without them are rebuilt.
PIC_FLAGS := -fPIC
$(RUNTIME_OBJ) $(HEADLESS_PORT_OBJ): CXXFLAGS_ALL += $(PIC_FLAGS)
$(RUNTIME_OBJ) $(HEADLESS_PORT_OBJ): $(BUILD)/obj/pic.flags
$(BUILD)/obj/pic.flags: FORCE
	@mkdir -p $(dir $@) && echo '$(PIC_FLAGS)' | cmp -s - $@ || echo '$(PIC_FLAGS)' > $@
# The sources that compile the checkout's paths in (SEPAL_SOURCE_DIR, SEPAL_BIN_DIR,
# SEPAL_SHARED_DIR) are rebuilt when the paths change: a build/ copied from another
# checkout must not test that checkout's binaries and fixtures.
DIR_FLAGS := $(CURDIR) $(BUILD) $(SHARED)
DIR_USERS := $(shell grep -rlE 'SEPAL_(SOURCE|BIN|SHARED)_DIR' offline runtime ports tests --include='*.cpp' --include='*.c' 2>/dev/null)
$(patsubst %.cpp,$(BUILD)/obj/%.o,$(filter %.cpp,$(DIR_USERS))): $(BUILD)/obj/dirs.flags
$(BUILD)/obj/dirs.flags: FORCE
	@mkdir -p $(dir $@) && echo '$(DIR_FLAGS)' | cmp -s - $@ || echo '$(DIR_FLAGS)' > $@
FORCE:

$(DIST)/libsepal.a: $(LIB_RUNTIME)
	@mkdir -p $(dir $@) && cp $< $@
$(DIST)/libsepal_headless.a: $(HEADLESS_PORT_OBJ)
	@mkdir -p $(dir $@) && rm -f $@
	$(call say,AR,$@)
	$(Q)ar rcs $@ $^
# Exports are the C API only (packaging/*.map); --no-undefined: every GL symbol resolved;
# -z text: refuse objects that are not position-independent instead of shipping them.
$(DIST)/libsepal.so.$(SEPAL_VERSION): $(filter-out $(EMULATE_OBJ),$(RUNTIME_OBJ)) packaging/libsepal.map
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) -shared -Wl,-soname,libsepal.so.$(SOVERSION) -Wl,--version-script=packaging/libsepal.map \
	  -Wl,--no-undefined -Wl,-z,text $(LDFLAGS) $(filter-out $(EMULATE_OBJ),$(RUNTIME_OBJ)) -lGLESv1_CM -lGLESv2 -lm -o $@
$(DIST)/libsepal_headless.so.$(SEPAL_VERSION): $(HEADLESS_PORT_OBJ) packaging/libsepal_headless.map
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) -shared -Wl,-soname,libsepal_headless.so.$(SOVERSION) -Wl,--version-script=packaging/libsepal_headless.map \
	  -Wl,--no-undefined -Wl,-z,text $(LDFLAGS) $(HEADLESS_PORT_OBJ) -lEGL -lGLESv2 -o $@

# The public headers are C99 (every build checks, as a C compiler sees them).
# Every public header, and the usage block each opens with, compiles as C99 (-pedantic -Werror).
check-c99:
	@CC="$(CC)" sh tests/check_c99.sh

# The build tree as an installed one, for programs built against it without make install:
# the public headers in build/include/sepal/ and build/sepal-uninstalled.pc, which
# pkg-config prefers to sepal.pc when build/ is on PKG_CONFIG_PATH:
#   PKG_CONFIG_PATH=build cc -std=c99 examples/minimal.c $(pkg-config --cflags --libs sepal)
$(BUILD)/include/sepal/%.h: runtime/include/sepal/%.h
	@mkdir -p $(dir $@) && cp $< $@
$(BUILD)/include/sepal/sepal_headless.h: ports/headless/sepal_headless.h
	@mkdir -p $(dir $@) && cp $< $@
$(BUILD)/sepal-uninstalled.pc: packaging/sepal.pc.in $(DIST_FILES)
	@for lib in libsepal libsepal_headless; do \
	  ln -sf $$lib.so.$(SEPAL_VERSION) $(DIST)/$$lib.so.$(SOVERSION) && ln -sf $$lib.so.$(SOVERSION) $(DIST)/$$lib.so; done
	@sed -e 's|@PREFIX@|$(CURDIR)/$(BUILD)|' -e 's|@LIBDIR@|$(CURDIR)/$(DIST)|' -e 's|@INCLUDEDIR@|$(CURDIR)/$(BUILD)/include|' \
	  -e 's|@VERSION@|$(SEPAL_VERSION)|' $< > $@

# ---- the web port ----------------------------------------------------------------------
$(WEB_OBJ): build/web-obj/%.o: %.cpp | $(SHADER_INCS)
	@mkdir -p $(dir $@)
	$(call say,EMCC,$<)
	$(Q)$(EMENV) $(EMCC) -Iruntime/include -Iports -I$(BUILD)/gen $(WEB_CXXFLAGS) -c $< -o $@
$(WEB_DIR)/sepal.js: $(WEB_OBJ)
	@mkdir -p $(dir $@)
	$(call say,EMCC,$@)
	$(Q)$(EMENV) $(EMCC) $(WEB_LDFLAGS) $(WEB_OBJ) -o $@
$(WEB_DIR)/%: ports/web/%
	@mkdir -p $(dir $@) && cp $< $@
$(WEB_DIR)/default.sepal: $(RUN_ASSET)
	@mkdir -p $(dir $@) && cp $< $@
# The kiosk scene as a bundle the page fetches (?scene=kiosk/scene.txt; docs/scenes.md).
$(WEB_DIR)/kiosk/scene.txt: $(BIN_SEPAL) examples/kiosk.json fixtures/gltf/vase.glb fixtures/gltf/vase.gltf
	$(call say,SCENE,$@)
	$(Q)$(BIN_SEPAL) render --scene examples/kiosk.json --export $(WEB_DIR)/kiosk > /dev/null

# Include directions between folders (tests/check_layers.sh): no loop, and
# tools -> offline -> runtime, ports -> runtime. Checked on every build.
check-layers:
	@sh tests/check_layers.sh

# No function in offline/ or runtime/ over 150 lines
# (tests/check_functions.sh, counted by tests/function_length.awk). Checked on every build.
check-functions:
	@sh tests/check_functions.sh

# The runtime's rules, checked on every build: no iostream, no exceptions, no RTTI use,
# no std::string in its headers (it is also compiled with -fno-exceptions -fno-rtti).
check-runtime: $(LIB_RUNTIME)
	@bad=$$(grep -nE '#include *<(iostream|sstream|fstream|string)>|std::string|\bthrow\b|\bdynamic_cast\b|\btypeid\b' runtime/include/sepal/*.h runtime/src/*.h runtime/src/*.cpp | grep -vE '^[^:]+:[0-9]+: *//'); \
	if [ -n "$$bad" ]; then echo "runtime/ breaks its rules:"; echo "$$bad"; exit 1; fi

-include $(shell find $(BUILD)/obj build/web-obj -name '*.d' 2>/dev/null)
