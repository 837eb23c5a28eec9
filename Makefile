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
                nlohmann-json3-dev

WARN     := -Wall -Wextra -Werror
CXXSTD   := -std=c++17
OPT      ?= -O2 -g
ifeq ($(SAN),1)
  OPT    := -O1 -g -fno-omit-frame-pointer
  SANFLAGS := -fsanitize=address,undefined -fno-sanitize-recover=undefined
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
VIEW_MAIN    := ports/view/sepal_view.cpp
TEST_SRC     := $(filter-out tests/bench/%,$(call rwildcard,tests,*.cpp))
# Each tests/bench/<name>.cpp is one program, build/bin/sepal-bench-<name>, linked with the
# doctest-free support objects below; tests/bench/run.sh is what `make bench` runs.
BENCH_SRC    := $(wildcard tests/bench/*.cpp)
BENCH_SUPPORT_SRC := tests/extremes_runtime_cases.cpp
BENCH_BINS   := $(patsubst tests/bench/%.cpp,$(BUILD)/bin/sepal-bench-%,$(BENCH_SRC))
SHADERS      := $(wildcard shaders/*.vert shaders/*.frag)
SHADER_INCS  := $(SHADERS:%=$(BUILD)/gen/%.inc)

obj = $(patsubst %.cpp,$(BUILD)/obj/%.o,$(1))
RUNTIME_OBJ  := $(call obj,$(RUNTIME_SRC))
OFFLINE_OBJ  := $(call obj,$(OFFLINE_SRC))
HEADLESS_OBJ := $(call obj,$(HEADLESS_SRC))
TEST_OBJ     := $(call obj,$(TEST_SRC))
BENCH_OBJ    := $(call obj,$(BENCH_SRC))
BENCH_SUPPORT_OBJ := $(call obj,$(BENCH_SUPPORT_SRC))

LIB_RUNTIME  := $(BUILD)/lib/libsepal_runtime.a
LIB_OFFLINE  := $(BUILD)/lib/libsepal_offline.a
LIB_HEADLESS := $(BUILD)/lib/libsepal_headless.a
BIN_SEPAL    := $(BUILD)/bin/sepal
BIN_VIEW     := $(BUILD)/bin/sepal-view
BIN_TESTS    := $(BUILD)/bin/sepal-tests
BENCH_OUT    := $(BUILD)/bench

RUN_OUT      := $(BUILD)/out/sepal-run.png
# The default material of `make run`: an anisotropic Ward, 2 NMF terms in gs-half at
# 32x32, peaks above 2/sr capped (see README, "Dynamic range").
RUN_SPEC     := ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15
RUN_BAKE     := --param gs-half --res 32 --method nmf --terms 2 --cap 2
RUN_ASSET    := $(BUILD)/out/ward.sepal

.SECONDARY:
.PHONY: all build help deps run test test-asan update-goldens bench clean check-runtime

all: build ## the default: same as make build

build: $(BIN_SEPAL) $(BIN_VIEW) $(BIN_TESTS) $(BENCH_BINS) check-runtime ## build everything into build/ (-Wall -Wextra -Werror)

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
	@$(BIN_SEPAL) diff $(BUILD)/out/sepal-run-exact.png $(RUN_OUT) | sed -n 's/^psnr */PSNR against the exact render: /p'
	@echo $(RUN_OUT)

# Re-baked when the tool changes; the bake is deterministic.
$(RUN_ASSET): $(BIN_SEPAL)
	@mkdir -p $(dir $@)
	@echo "sepal: baking $(RUN_SPEC)"
	@$(BIN_SEPAL) bake '$(RUN_SPEC)' $(RUN_BAKE) -o $@ > $(BUILD)/out/ward.bake.txt

test: deps ## build and run every doctest suite
	@$(MAKE) --no-print-directory -j$(NPROC) build
	@sh tests/run.sh $(BIN_TESTS)

test-asan: deps ## run the test suites under AddressSanitizer + UndefinedBehaviorSanitizer
	@$(MAKE) --no-print-directory -j$(NPROC) BUILD=build/asan SAN=1 build
	@ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  sh tests/run.sh build/asan/bin/sepal-tests

update-goldens: deps ## rewrite fixtures/golden/*.png from the current renders
	@$(MAKE) --no-print-directory -j$(NPROC) build
	@SEPAL_UPDATE_GOLDENS=1 $(BIN_TESTS) -tc='*golden*'

bench: deps ## benchmarks that produce the README figures (long sweeps live here, not in tests)
	@$(MAKE) --no-print-directory -j$(NPROC) $(BENCH_BINS)
	@sh tests/bench/run.sh $(BUILD) $(BENCH_OUT)

clean: ## remove build/
	rm -rf build

# ---- rules -----------------------------------------------------------------------------
$(BUILD)/gen/shaders/%.inc: shaders/%
	@mkdir -p $(dir $@)
	@{ printf 'R"sepal_glsl('; cat $<; printf ')sepal_glsl"\n'; } > $@.tmp && mv $@.tmp $@

$(RUNTIME_OBJ): $(BUILD)/obj/%.o: %.cpp | $(SHADER_INCS)
	@mkdir -p $(dir $@)
	$(call say,CXX,$<)
	$(Q)$(CXX) $(CPPFLAGS) $(CXXFLAGS_ALL) $(RUNTIME_FLAGS) -c $< -o $@

$(TEST_OBJ) $(BENCH_OBJ) $(BENCH_SUPPORT_OBJ): CPPFLAGS += $(TEST_CPPFLAGS)

$(BUILD)/obj/%.o: %.cpp
	@mkdir -p $(dir $@)
	$(call say,CXX,$<)
	$(Q)$(CXX) $(CPPFLAGS) $(CXXFLAGS_ALL) -c $< -o $@

$(BUILD)/lib/lib%.a:
	@mkdir -p $(dir $@)
	@rm -f $@
	$(call say,AR,$@)
	$(Q)ar rcs $@ $^

$(LIB_RUNTIME): $(RUNTIME_OBJ)
$(LIB_OFFLINE): $(OFFLINE_OBJ)
$(LIB_HEADLESS): $(HEADLESS_OBJ)

$(BIN_SEPAL): $(call obj,$(SEPAL_MAIN)) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $^ $(LIBS) -o $@

# sepal-view: the runtime and the ports only, no offline code.
$(BIN_VIEW): $(call obj,$(VIEW_MAIN)) $(LIB_HEADLESS) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $^ $(LIBS) -o $@

$(BIN_TESTS): $(TEST_OBJ) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_RUNTIME) $(BIN_SEPAL)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $(TEST_OBJ) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_RUNTIME) $(LIBS) -o $@

# sepal-bench-<name>: one program per tests/bench/<name>.cpp (`make bench`).
$(BUILD)/bin/sepal-bench-%: $(BUILD)/obj/tests/bench/%.o $(BENCH_SUPPORT_OBJ) $(LIB_OFFLINE) $(LIB_HEADLESS) $(LIB_RUNTIME)
	@mkdir -p $(dir $@)
	$(call say,LINK,$@)
	$(Q)$(CXX) $(LDFLAGS) $^ $(LIBS) -o $@

# The runtime's rules, checked on every build: no iostream, no exceptions, no RTTI use,
# no std::string in its headers (it is also compiled with -fno-exceptions -fno-rtti).
check-runtime: $(LIB_RUNTIME)
	@bad=$$(grep -nE '#include *<(iostream|sstream|fstream|string)>|std::string|\bthrow\b|\bdynamic_cast\b|\btypeid\b' runtime/include/sepal/*.h runtime/src/*.h runtime/src/*.cpp | grep -vE '^[^:]+:[0-9]+: *//'); \
	if [ -n "$$bad" ]; then echo "runtime/ breaks its rules:"; echo "$$bad"; exit 1; fi

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
