# Makefile: builds ./pp5 (the Pixel-Planes 5 emulator, its firmware, the native
# renderer and the gaze tools) and the test runner.  Plain GNU make, C11.
#
#   make            build ./pp5
#   make test       install missing system packages (as root), build, run all tests
#   make demo       run the default demo (no external data needed)
#   make bench      print speed figures (never fails on speed)
#   make deps       install the Debian packages pp5 needs (apt-get, as root)
#   make SAN=1 test the same under AddressSanitizer + UBSan (separate build dir)
#   make MPI=0 ...  build without MPI even when mpicc is there (build/*-serial,
#                   binary build/*-serial/pp5); MPI=1 insists on MPI
#   make SAN=thread test   the threaded tests under ThreadSanitizer (build/tsan)
#   make fuzz FUZZ_SECONDS=N   every libFuzzer target for N seconds (clang-14)
#   make soak       long replay and live-recording runs, peak memory (not in CI)
#   make install PREFIX=DIR   install bin/pp5 and share/man/man1/pp5.1 under DIR
#
# The program is every .c file in the folders that LIB_SRC, FW_SRC and CLI_SRC
# list below (emu/, emu/util/, emu/cli/, render/, render/mesh/, tracker/, firmware/host/ and
# the firmware programs in firmware/ and its subfolders); a module adds
# sources by adding files, but a new subfolder of emu/, render/ or tracker/
# must be added to LIB_SRC.  tests/*.c make the test runner.

CC      ?= cc
SAN     ?= 0
DEBUG   ?= 0
MPI     ?= auto

# Debian packages: what each is for is in README.md ("Dependencies").
# Debian's libniftiio-dev ships nifti1_io.h but not the nifti1.h it includes:
# that header comes with libnifti2-dev.  `make deps-audit` checks that every
# system header the build includes belongs to one of these or their dependencies.
DEB_PKGS := gcc libc6-dev make pkg-config libpng-dev zlib1g-dev libteem-dev \
            libniftiio-dev libnifti2-dev libhidapi-dev libusb-1.0-0-dev \
            umockdev libumockdev-dev libopenmpi-dev openmpi-bin \
            libcairo2-dev libfontconfig-dev fonts-dejavu-core libjansson-dev \
            libsdl2-dev xvfb libxtst-dev groff-base

ifeq ($(SAN),1)
BUILD   := build/san
OPT     := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
LDSAN   := -fsanitize=address,undefined
else ifeq ($(SAN),thread)
# ThreadSanitizer (gcc's, libtsan2 comes with gcc): only the tests that run
# threads are run under it (TSAN_TESTS below).
BUILD   := build/tsan
OPT     := -O1 -g -fno-omit-frame-pointer -fsanitize=thread
LDSAN   := -fsanitize=thread
# The tests that run more than one thread: native renderer threads (render/
# parallel.c), the emulator's host threads (emu/renderer_node.c), and the
# determinism tests that compare 1, 2 and 3 threads.  A TSan report makes the
# test process exit non-zero (halt_on_error), so the test fails.
TSAN_TESTS := render_threads_identical gaze_flag_array_casts_each_ray_once \
              gaze_progressive_converges machine_results_identical_for_1_2_and_4_host_threads \
              machine_threaded_firmware_error render_cli_writes_image_figures_and_report \
              determinism_threads_
TESTS   ?= $(TSAN_TESTS)
export TSAN_OPTIONS ?= halt_on_error=1:exitcode=66:second_deadlock_stack=1
else ifeq ($(SAN),fuzz)
# libFuzzer targets (tests/fuzz): the library is instrumented for coverage
# with ASan + UBSan; each target links libFuzzer's main.  Needs clang-14 and
# libclang-rt-14-dev (installed by `make fuzz` when root, never by make test).
CC      := clang-14
BUILD   := build/fuzz
OPT     := -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined \
           -fno-sanitize-recover=undefined
LDSAN   := -fsanitize=address,undefined
else ifeq ($(DEBUG),1)
BUILD   := build/debug
OPT     := -O0 -g
else
BUILD   := build/release
OPT     := -O2 -g
endif
ifeq ($(MPI),0)
BUILD   := $(BUILD)-serial
endif

WARN    := -Wall -Wextra -Wundef -Wshadow -Wno-unused-parameter -Wstrict-prototypes -Wmissing-prototypes
ifneq ($(CI),)
WARN    += -Werror
endif

# System libraries.  libpng and zlib publish pkg-config files; Debian's Teem and
# niftiio do not, so their flags are spelled out (checked by `make deps`).  An
# optional library is built in only when every header pp5 includes from it is
# present.
# cairo with fontconfig (plots, the viewer's heads-up display) and jansson
# (ParaView presets) are required like libpng; SDL2 (the viewer's window) is
# optional.
REQUIRED_PC := libpng zlib cairo fontconfig jansson
PKG_CFLAGS := $(shell pkg-config --cflags $(REQUIRED_PC) 2>/dev/null)
PKG_LIBS   := $(shell pkg-config --libs $(REQUIRED_PC) 2>/dev/null)
MISSING_PC := $(strip $(foreach m,$(REQUIRED_PC),$(if $(shell pkg-config --exists $(m) 2>/dev/null && echo y),,$(m))))
HAVE_TEEM  := $(shell test -f /usr/include/teem/nrrd.h && echo 1)
HAVE_NIFTI := $(shell test -f /usr/include/nifti/nifti1_io.h && test -f /usr/include/nifti/nifti1.h && echo 1)
HAVE_HID   := $(shell pkg-config --exists hidapi-hidraw 2>/dev/null && echo 1)
HAVE_USB   := $(shell pkg-config --exists libusb-1.0 2>/dev/null && echo 1)
HAVE_SDL2  := $(shell pkg-config --exists sdl2 2>/dev/null && echo 1)
ifeq ($(HAVE_TEEM),1)
FEATURE_CFLAGS += -I/usr/include/teem
PKG_LIBS   += -lteem
endif
ifeq ($(HAVE_NIFTI),1)
FEATURE_CFLAGS += -I/usr/include/nifti
PKG_LIBS   += -lniftiio -lznz
endif
ifeq ($(HAVE_HID),1)
FEATURE_CFLAGS += $(shell pkg-config --cflags hidapi-hidraw)
PKG_LIBS   += $(shell pkg-config --libs hidapi-hidraw)
endif
ifeq ($(HAVE_USB),1)
FEATURE_CFLAGS += $(shell pkg-config --cflags libusb-1.0)
PKG_LIBS   += $(shell pkg-config --libs libusb-1.0)
endif
ifeq ($(HAVE_SDL2),1)
FEATURE_CFLAGS += $(patsubst -I%,-isystem %,$(shell pkg-config --cflags sdl2))
PKG_LIBS   += $(shell pkg-config --libs sdl2)
endif
# MPI: `mpirun -n N ./pp5 sweep|replay --batch` share a batch's units among
# N ranks (emu/util/workunit_mpi.c, the only file that includes <mpi.h>).
# Built in when mpicc can preprocess <mpi.h> (Debian: libopenmpi-dev), with
# the flags its wrapper reports (Open MPI's --showme, MPICH's -compile_info);
# without it, or with MPI=0, the same commands run serially.
ifneq ($(MPI),0)
HAVE_MPI := $(shell printf '\043include <mpi.h>\n' | mpicc -x c -E - >/dev/null 2>&1 && echo 1)
endif
ifeq ($(MPI)$(HAVE_MPI),1)
$(error MPI=1, but mpicc cannot compile against <mpi.h>: install libopenmpi-dev)
endif
ifeq ($(HAVE_MPI),1)
MPI_CFLAGS := $(shell mpicc --showme:compile 2>/dev/null || mpicc -compile_info 2>/dev/null | cut -d' ' -f2-)
MPI_LIBS   := $(shell mpicc --showme:link 2>/dev/null || mpicc -link_info 2>/dev/null | cut -d' ' -f2-)
MPI_CFLAGS := $(patsubst -I%,-isystem %,$(filter -I% -D% -pthread,$(MPI_CFLAGS)))
PKG_LIBS   += $(MPI_LIBS)
endif
yesno = $(if $(filter 1,$(1)),yes,no)
FEATURES := NRRD=$(call yesno,$(HAVE_TEEM)) NIfTI=$(call yesno,$(HAVE_NIFTI)) \
            HID=$(call yesno,$(HAVE_HID)) USB=$(call yesno,$(HAVE_USB)) MPI=$(call yesno,$(HAVE_MPI)) \
            SDL2=$(call yesno,$(HAVE_SDL2))

# umockdev (tests only): the device integration tests (tests/test_track_umockdev*.c,
# with tests/umockdev_bed.c) emulate USB and hidraw devices with the libumockdev
# testbed API; TEST_CFLAGS and TEST_LIBS apply to every tests/*.c.  Its GLib
# headers are included as system headers so that our warning flags do not
# apply to them.
HAVE_UMOCKDEV := $(shell pkg-config --exists umockdev-1.0 2>/dev/null && echo 1)
ifeq ($(HAVE_UMOCKDEV),1)
TEST_CFLAGS += -DPP5_HAVE_UMOCKDEV=1 $(patsubst -I%,-isystem %,$(shell pkg-config --cflags umockdev-1.0))
TEST_LIBS   += $(shell pkg-config --libs umockdev-1.0)
endif
# X11 with the XTEST extension (tests only): tests/test_view.c moves the
# pointer, presses keys and closes the viewer's window on an Xvfb server.
HAVE_XTEST := $(shell pkg-config --exists x11 xtst 2>/dev/null && echo 1)
ifeq ($(HAVE_XTEST),1)
TEST_CFLAGS += -DPP5_HAVE_XTEST=1 $(shell pkg-config --cflags x11 xtst)
TEST_LIBS   += $(shell pkg-config --libs x11 xtst)
endif

# Generated files, in $(BUILD)/gen, rewritten only when their text changes, so
# that make rebuilds exactly what depends on them:
#   pp5_features.h  the feature probes above (PP5_HAVE_TEEM 0/1 ...): the
#                   loaders and device code that test a feature include it, so
#                   installing e.g. libteem-dev after a build rebuilds the NRRD
#                   loader, and -Wundef catches a file that forgot the include;
#   pp5_version.c   the commit being built (git describe) and the feature list,
#                   read through emu/util/version.h by reports and `pp5 help`;
#   cflags.stamp, ldflags.stamp   the compile and link command lines: a change
#                   of flags (OPT, CFLAGS, SAN, a library's path) rebuilds all.
#                   An optional library's include path is left out of the
#                   compile stamp: pp5_features.h already rebuilds the files
#                   that use it, and the path is harmless to the others.
GEN := $(BUILD)/gen
PP5_VERSION := $(shell git describe --always --dirty 2>/dev/null || echo unknown)
define gen_file
$(shell mkdir -p $(GEN))$(file >$(GEN)/$(1).new,$(2))$(shell cmp -s $(GEN)/$(1).new $(GEN)/$(1) \
    && rm -f $(GEN)/$(1).new || mv -f $(GEN)/$(1).new $(GEN)/$(1))
endef
define FEATURES_H
/* pp5_features.h: generated by the Makefile from its probes; do not edit. */
#define PP5_HAVE_TEEM $(if $(HAVE_TEEM),1,0)
#define PP5_HAVE_NIFTI $(if $(HAVE_NIFTI),1,0)
#define PP5_HAVE_HIDAPI $(if $(HAVE_HID),1,0)
#define PP5_HAVE_LIBUSB $(if $(HAVE_USB),1,0)
#define PP5_HAVE_MPI $(if $(HAVE_MPI),1,0)
#define PP5_HAVE_SDL2 $(if $(HAVE_SDL2),1,0)
endef
define VERSION_C
/* pp5_version.c: generated by the Makefile on every build; do not edit. */
#include "version.h"
const char pp5_version[] = "$(PP5_VERSION)";
const char pp5_features[] = "$(FEATURES)";
endef

# Project headers are found with -iquote, so that a project header can never
# shadow a system header of the same name (<sched.h>, <time.h>).  The GP/PP
# programs (firmware/ except firmware/host/) see only the firmware API in
# emu/api/ and their own folders.  A relative path such as
# "../../emu/machine.h" gets past -iquote, so two checks make the boundary a
# fact: tests/test_layers.c checks every include (it gets these folder lists,
# so it resolves includes the way the compiler does), and the link check below
# allows the programs only symbols that emu/api/ declares.
LIB_IQUOTE := . emu emu/api emu/util
FW_IQUOTE  := emu/api firmware
CFLAGS_ALL := -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -pthread $(OPT) $(WARN) \
              $(addprefix -iquote ,$(LIB_IQUOTE)) -iquote $(GEN) $(PKG_CFLAGS) \
              $(FEATURE_CFLAGS) $(CFLAGS)
LDLIBS_ALL := $(PKG_LIBS) -lm -pthread $(LDSAN) $(LDFLAGS)
FW_CFLAGS  := -std=c11 -D_DEFAULT_SOURCE -pthread $(OPT) $(WARN) $(addprefix -iquote ,$(FW_IQUOTE)) $(CFLAGS)

# A required library that is missing stops the build with one line (the
# targets that install packages first re-enter make, which checks then).
ifneq ($(filter-out deps deps-check deps-audit clean help test demo bench bench-peers,$(or $(MAKECMDGOALS),all)),)
ifneq ($(MISSING_PC),)
$(error pp5 needs $(MISSING_PC) (pkg-config finds no such library): run `make deps` as root, or `make test`, which installs what is missing)
endif
endif
ifneq ($(filter-out deps deps-check clean help,$(or $(MAKECMDGOALS),all)),)
$(call gen_file,pp5_features.h,$(FEATURES_H))
$(call gen_file,pp5_version.c,$(VERSION_C))
$(call gen_file,cflags.stamp,$(CC) $(filter-out $(FEATURE_CFLAGS),$(CFLAGS_ALL)) $(TEST_CFLAGS) | $(FW_CFLAGS))
$(call gen_file,ldflags.stamp,$(CC) $(OPT) $(LDLIBS_ALL) $(TEST_LIBS))
endif

# firmware/host/ is the host workstation's side (it loads data and drives the
# machine through emu's full API); the rest of firmware/ runs on the GPs.
LIB_SRC  := $(sort $(wildcard emu/*.c emu/util/*.c render/*.c render/mesh/*.c tracker/*.c firmware/host/*.c))
FW_SRC   := $(sort $(filter-out firmware/host/%,$(wildcard firmware/*.c firmware/*/*.c)))
CLI_SRC  := $(sort $(wildcard emu/cli/*.c))
TEST_SRC := $(sort $(wildcard tests/*.c))

FW_OBJ   := $(FW_SRC:%.c=$(BUILD)/%.o)
FW_CHECK := $(BUILD)/fw-boundary
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o) $(FW_OBJ) $(GEN)/pp5_version.o
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_OBJ := $(TEST_SRC:%.c=$(BUILD)/%.o)

PP5_BIN  := $(if $(filter-out 0,$(SAN))$(filter 0,$(MPI)),$(BUILD)/pp5,pp5)
TEST_BIN := $(BUILD)/pp5-tests

.PHONY: all test test-run fw-boundary-probe demo bench bench-peers deps deps-check deps-audit clean help \
        fuzz fuzz-deps fuzz-build tsan-test soak \
        install
all: $(PP5_BIN)

$(PP5_BIN): $(LIB_OBJ) $(CLI_OBJ) $(GEN)/ldflags.stamp $(FW_CHECK)/ok
	$(CC) $(OPT) -o $@.tmp $(filter %.o,$^) $(LDLIBS_ALL)
	@mv -f $@.tmp $@
	@echo "built $@ $(PP5_VERSION), optional features: $(FEATURES)"

$(BUILD)/emu/util/workunit_mpi.o: CFLAGS_ALL += $(MPI_CFLAGS)
$(BUILD)/tests/%.o: CFLAGS_ALL += $(TEST_CFLAGS)
# The tests that call the GP programs' kernels (firmware/gp/vr_*_kernels.h,
# poly_kernels.h), whose includes are written for the firmware's include path.
$(BUILD)/tests/test_fw_cost.o $(BUILD)/tests/test_fw_blend.o $(BUILD)/tests/test_fw_poly_cost.o \
$(BUILD)/tests/test_fw_poly.o $(BUILD)/tests/test_fw_poly_vrz.o $(BUILD)/tests/test_fw_poly_colours.o: CFLAGS_ALL += $(addprefix -iquote ,$(FW_IQUOTE))
$(BUILD)/tests/test_layers.o: CFLAGS_ALL += -DPP5_LAYERS_LIB_IQUOTE='"$(LIB_IQUOTE)"' \
    -DPP5_LAYERS_FW_IQUOTE='"$(FW_IQUOTE)"' -DPP5_LAYERS_GEN_DIR='"$(GEN)"'
$(TEST_BIN): LDLIBS_ALL += $(TEST_LIBS)
$(TEST_BIN): $(LIB_OBJ) $(filter-out $(BUILD)/emu/cli/main.o,$(CLI_OBJ)) $(TEST_OBJ) $(GEN)/ldflags.stamp \
            $(FW_CHECK)/ok
	$(CC) $(OPT) -o $@.tmp $(filter %.o,$^) $(LDLIBS_ALL)
	@mv -f $@.tmp $@

$(LIB_OBJ) $(CLI_OBJ) $(TEST_OBJ): $(GEN)/cflags.stamp

$(GEN)/pp5_version.o: $(GEN)/pp5_version.c
	$(CC) $(CFLAGS_ALL) -c -o $@ $<

$(BUILD)/firmware/host/%.o: firmware/host/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c -o $@ $<

$(BUILD)/firmware/%.o: firmware/%.c
	@mkdir -p $(dir $@)
	$(CC) $(FW_CFLAGS) -MMD -MP -c -o $@ $<

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c -o $@ $<

# libFuzzer targets: tests/fuzz/fuzz_NAME.c, each linked with tests/fuzz/common.c
# and an archive of the parsing layers (render/, render/mesh/, tracker/, emu/util/ and the
# parameter table), so a target pulls in only the objects it uses; the
# machine model's SIMD kernels are gcc-only and never parse input.  Built only
# under SAN=fuzz (`make fuzz`).
FUZZ_LIB_SRC := $(sort $(wildcard emu/util/*.c render/*.c render/mesh/*.c tracker/*.c) emu/params.c emu/pp_params.c)
FUZZ_LIB_OBJ := $(FUZZ_LIB_SRC:%.c=$(BUILD)/%.o) $(GEN)/pp5_version.o
FUZZ_SRC := $(sort $(wildcard tests/fuzz/fuzz_*.c))
FUZZ_OBJ := $(FUZZ_SRC:%.c=$(BUILD)/%.o) $(BUILD)/tests/fuzz/common.o
FUZZ_BIN := $(FUZZ_SRC:tests/fuzz/%.c=$(BUILD)/fuzzers/%)
$(FUZZ_OBJ): $(GEN)/cflags.stamp
$(BUILD)/libpp5-fuzz.a: $(FUZZ_LIB_OBJ)
	rm -f $@ && ar rcs $@ $^
$(BUILD)/fuzzers/fuzz_%: $(BUILD)/tests/fuzz/fuzz_%.o $(BUILD)/tests/fuzz/common.o \
                         $(BUILD)/libpp5-fuzz.a $(GEN)/ldflags.stamp
	@mkdir -p $(dir $@)
	$(CC) $(OPT) -fsanitize=fuzzer -o $@ $(filter %.o %.a,$^) $(LDLIBS_ALL)

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(FUZZ_OBJ:.o=.d)

# The firmware boundary at link time.  The GP/PP programs (FW_OBJ) are
# partially linked into one object (ld -r resolves what they call in each
# other); every symbol it still needs must be a function declared in a header
# under emu/api/ (listed from GCC's -aux-info) or come from the C runtime
# (libc, libm, libgcc; the sanitizer runtimes under SAN=1 and SAN=thread).  Anything else,
# such as machine_send or a render/ function declared by hand, stops the
# build with one line naming the symbol and the object that needs it.  `make
# test` also shows that a probe doing exactly that is rejected.
FW_PROBE     := tests/fixtures/boundary/gp_calls_machine_send.c
RUNTIME_LIBS := libc.so.6 libm.so.6 libmvec.so.1 libgcc_s.so.1 \
                $(if $(filter 1,$(SAN)),libasan.so libubsan.so) \
                $(if $(filter thread,$(SAN)),libtsan.so)
API_HEADERS  := $(sort $(wildcard emu/api/*.h))

$(FW_CHECK)/api-symbols.txt: $(API_HEADERS) $(GEN)/cflags.stamp
	@mkdir -p $(dir $@)
	@printf '$(foreach h,$(API_HEADERS),#include "$(notdir $(h))"\n)' > $(FW_CHECK)/api.c
	@$(CC) $(FW_CFLAGS) -fsyntax-only -aux-info $(FW_CHECK)/api.aux $(FW_CHECK)/api.c
	@sed -n 's|^/\* emu/api/[^ ]* \*/ extern .*[ *]\([A-Za-z_][A-Za-z0-9_]*\) (.*|\1|p' \
	    $(FW_CHECK)/api.aux | sort -u > $@.new
	@grep -qx fw_send $@.new || { echo "firmware boundary: found no fw_send among emu/api/'s declarations"; exit 1; }
	@mv $@.new $@

$(FW_CHECK)/runtime-symbols.txt: $(GEN)/ldflags.stamp
	@mkdir -p $(dir $@)
	@{ for l in $(RUNTIME_LIBS); do f=$$($(CC) -print-file-name=$$l); \
	     [ -e "$$f" ] && nm -D --defined-only "$$(readlink -f "$$f")"; done; \
	   nm --defined-only "$$($(CC) -print-libgcc-file-name)"; } 2>/dev/null \
	  | awk 'NF >= 3 {print $$3}' | sed 's/@.*//' | sort -u > $@.new
	@grep -qx memcpy $@.new || { echo "firmware boundary: cannot list the C library's symbols"; exit 1; }
	@mv $@.new $@

$(FW_CHECK)/programs.o: $(FW_OBJ)
	@mkdir -p $(dir $@)
	ld -r -o $@ $^

# $(call fw_boundary_check,PARTIAL,OBJECTS): one line per symbol that the
# partial link PARTIAL needs and neither list allows, naming those of OBJECTS
# that need it; false when there is any.
define fw_boundary_check
bad=0; for s in $$(nm -u $(1) | awk '{print $$NF}' | sed 's/@.*//' | sort -u); do \
  grep -qxF "$$s" $(FW_CHECK)/api-symbols.txt $(FW_CHECK)/runtime-symbols.txt && continue; \
  who=$$(for o in $(2); do nm -u $$o | awk '{print $$NF}' | grep -qxF "$$s" && echo $$o; done); \
  echo "firmware boundary:" $$who "needs $$s, which no header under emu/api/ declares" \
    "(firmware programs may call only the firmware API and the C library)"; bad=1; \
done; test $$bad = 0
endef

$(FW_CHECK)/ok: $(FW_CHECK)/programs.o $(FW_CHECK)/api-symbols.txt $(FW_CHECK)/runtime-symbols.txt
	@$(call fw_boundary_check,$<,$(FW_OBJ))
	@touch $@

fw-boundary-probe: $(FW_CHECK)/api-symbols.txt $(FW_CHECK)/runtime-symbols.txt
	@$(CC) $(FW_CFLAGS) -c -o $(FW_CHECK)/probe.o $(FW_PROBE)
	@ld -r -o $(FW_CHECK)/probe-partial.o $(FW_CHECK)/probe.o
	@if ($(call fw_boundary_check,$(FW_CHECK)/probe-partial.o,$(FW_CHECK)/probe.o)) \
	    > $(FW_CHECK)/probe.txt; then \
	  echo "firmware boundary: the probe $(FW_PROBE) was accepted"; exit 1; fi
	@grep -q "^firmware boundary: $(FW_CHECK)/probe.o needs machine_send, which no header" \
	    $(FW_CHECK)/probe.txt || { echo "firmware boundary: the probe's message is not" \
	    "the expected one:"; cat $(FW_CHECK)/probe.txt; exit 1; }
	@echo "firmware boundary: $(FW_PROBE) is rejected, as it must be:"; sed 's/^/  /' $(FW_CHECK)/probe.txt

# `make test` first makes sure the system packages are there, then re-enters
# make so that the pkg-config probes above see them.
test: deps-check
	@$(MAKE) --no-print-directory test-run

test-run: $(TEST_BIN) $(PP5_BIN) fw-boundary-probe
	PP5_BIN=./$(PP5_BIN) $(TEST_BIN) $(TESTS)

demo: deps-check
	@$(MAKE) --no-print-directory $(PP5_BIN)
	./$(PP5_BIN) demo

bench: deps-check
	@$(MAKE) --no-print-directory $(PP5_BIN)
	./$(PP5_BIN) bench

bench-peers: deps-check
	@$(MAKE) --no-print-directory $(PP5_BIN)
	./$(PP5_BIN) bench --peers

# `make fuzz FUZZ_SECONDS=N [FUZZ_TARGETS="volume_nrrd trace_read"]`: builds
# every target with clang-14 (SAN=fuzz) and runs each for N seconds over its
# seed corpus (tests/fuzz/corpus/NAME, new inputs go to build/fuzz/corpus);
# tests/fuzz/run fails on any crash, leak, timeout or sanitizer report and
# prints executions and edges covered per target.  Not needed by make test.
FUZZ_SECONDS ?= 60
FUZZ_PKGS := clang-14 libclang-rt-14-dev
fuzz: deps-check fuzz-deps
	@$(MAKE) --no-print-directory SAN=fuzz fuzz-build
	tests/fuzz/run $(FUZZ_SECONDS) build/fuzz/fuzzers $(FUZZ_TARGETS)

fuzz-build: $(FUZZ_BIN)

fuzz-deps:
	@$(MAKE) --no-print-directory deps-check DEB_PKGS="$(FUZZ_PKGS)"

# `make soak`: the long runs (not in CI): 30 minutes of trace replayed in
# timing-only mode through the emulated machine, and 10 minutes of live HID
# recording from an emulated device (umockdev-run), both under
# AddressSanitizer, printing peak RSS at the start and the end of each.
# SOAK_REPLAY_S / SOAK_LIVE_S shorten them for a trial.
SOAK_REPLAY_S ?= 1800
SOAK_LIVE_S ?= 600
soak: deps-check
	@$(MAKE) --no-print-directory SAN=1 build/san/pp5-tests build/san/pp5
	PP5_SOAK=1 PP5_TEST_TIMEOUT_S=14400 PP5_SOAK_REPLAY_S=$(SOAK_REPLAY_S) \
	    PP5_SOAK_LIVE_S=$(SOAK_LIVE_S) PP5_BIN=./build/san/pp5 build/san/pp5-tests soak_

deps:
	@if [ "$$(id -u)" = 0 ]; then apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y $(DEB_PKGS); \
	else echo "make deps: not root; run: sudo apt-get install -y $(DEB_PKGS)"; exit 1; fi

deps-check:
	@missing=""; for p in $(DEB_PKGS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then echo "installing:$$missing"; \
	    (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y $$missing) || exit 1; \
	  else echo "pp5 needs Debian packages that are missing; run:"; \
	    echo "  sudo apt-get install -y$$missing"; exit 1; fi; fi

# deps-audit: every system header that the build includes must belong to a
# package in DEB_PKGS or in their Depends (not Recommends) closure; otherwise a
# fresh machine would build without it.  CI runs this inside a fresh Debian 12
# tree (.ci/fresh-machine), after `make test` has installed DEB_PKGS.
deps-audit: deps-check
	@closure=$$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts \
	    --no-breaks --no-replaces --no-enhances $(DEB_PKGS) 2>/dev/null | grep -v '^ ' | sed 's/:.*//' | sort -u); \
	headers=$$(for f in $(LIB_SRC) $(CLI_SRC) $(TEST_SRC); do \
	    $(CC) $(CFLAGS_ALL) $(TEST_CFLAGS) $(MPI_CFLAGS) -M $$f; done | tr ' \\' '\n\n' | grep '^/' | xargs -r readlink -f | sort -u); \
	[ -n "$$headers" ] || { echo "deps-audit: no system headers found"; exit 1; }; \
	owners=$$(echo "$$headers" | xargs dpkg -S 2>/dev/null | sed 's/:[a-z0-9]*,/,/g;s/:[a-z0-9]*: /: /'); \
	bad=0; n=0; for h in $$headers; do n=$$((n+1)); \
	  pkgs=$$(echo "$$owners" | awk -F': ' -v h="$$h" '$$2 == h {print $$1}' | tr ',' ' '); \
	  ok=0; for p in $$pkgs; do echo "$$closure" | grep -qx "$$p" && ok=1; done; \
	  if [ -z "$$pkgs" ]; then echo "deps-audit: $$h belongs to no installed package"; bad=1; \
	  elif [ $$ok = 0 ]; then echo "deps-audit: $$h comes from $$pkgs, which DEB_PKGS does not pull in"; bad=1; fi; \
	done; [ $$bad = 0 ] && echo "deps-audit: all $$n system headers come from DEB_PKGS or their dependencies"; \
	exit $$bad

# install: the program and its manual page.  PREFIX defaults to /usr/local;
# DESTDIR is prefixed to both for staged (packaging) installs.
PREFIX  ?= /usr/local
MANDIR  ?= $(PREFIX)/share/man
install: $(PP5_BIN)
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(MANDIR)/man1
	install -m 755 $(PP5_BIN) $(DESTDIR)$(PREFIX)/bin/pp5
	install -m 644 emu/cli/pp5.1 $(DESTDIR)$(MANDIR)/man1/pp5.1
	@echo "installed $(DESTDIR)$(PREFIX)/bin/pp5 and $(DESTDIR)$(MANDIR)/man1/pp5.1 (man -l $(DESTDIR)$(MANDIR)/man1/pp5.1)"

clean:
	rm -rf build pp5

help:
	@sed -n '3,11p' Makefile
