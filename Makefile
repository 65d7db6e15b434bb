# Makefile: builds ./pp5 (the Pixel-Planes 5 emulator, its firmware, the native
# renderer and the gaze tools) and the test runner.  Plain GNU make, C11.
#
#   make            build ./pp5
#   make test       install missing system packages (as root), build, run all tests
#   make demo       run the default demo (no external data needed)
#   make bench      print speed figures (never fails on speed)
#   make deps       install the Debian packages pp5 needs (apt-get, as root)
#   make SAN=1 test the same under AddressSanitizer + UBSan (separate build dir)
#
# Every .c file under emu/ render/ firmware/ tracker/ is part of the program; a
# module adds sources by adding files, never by editing this list.

CC      ?= cc
SAN     ?= 0
DEBUG   ?= 0

# Debian packages: what each is for is in README.md ("Dependencies").
DEB_PKGS := gcc make pkg-config libpng-dev zlib1g-dev libteem-dev libniftiio-dev \
            libhidapi-dev libusb-1.0-0-dev umockdev libumockdev-dev

ifeq ($(SAN),1)
BUILD   := build/san
OPT     := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
LDSAN   := -fsanitize=address,undefined
else ifeq ($(DEBUG),1)
BUILD   := build/debug
OPT     := -O0 -g
else
BUILD   := build/release
OPT     := -O2 -g
endif

WARN    := -Wall -Wextra -Wshadow -Wno-unused-parameter -Wstrict-prototypes -Wmissing-prototypes
ifneq ($(CI),)
WARN    += -Werror
endif

# System libraries.  libpng and zlib publish pkg-config files; Debian's Teem and
# niftiio do not, so their flags are spelled out (checked by `make deps`).
PKG_CFLAGS := $(shell pkg-config --cflags libpng zlib 2>/dev/null)
PKG_LIBS   := $(shell pkg-config --libs libpng zlib 2>/dev/null)
HAVE_TEEM  := $(shell test -f /usr/include/teem/nrrd.h && echo 1)
HAVE_NIFTI := $(shell test -f /usr/include/nifti/nifti1_io.h && echo 1)
HAVE_HID   := $(shell pkg-config --exists hidapi-hidraw 2>/dev/null && echo 1)
HAVE_USB   := $(shell pkg-config --exists libusb-1.0 2>/dev/null && echo 1)
ifeq ($(HAVE_TEEM),1)
PKG_CFLAGS += -DPP5_HAVE_TEEM=1 -I/usr/include/teem
PKG_LIBS   += -lteem
endif
ifeq ($(HAVE_NIFTI),1)
PKG_CFLAGS += -DPP5_HAVE_NIFTI=1 -I/usr/include/nifti
PKG_LIBS   += -lniftiio -lznz
endif
ifeq ($(HAVE_HID),1)
PKG_CFLAGS += -DPP5_HAVE_HIDAPI=1 $(shell pkg-config --cflags hidapi-hidraw)
PKG_LIBS   += $(shell pkg-config --libs hidapi-hidraw)
endif
ifeq ($(HAVE_USB),1)
PKG_CFLAGS += -DPP5_HAVE_LIBUSB=1 $(shell pkg-config --cflags libusb-1.0)
PKG_LIBS   += $(shell pkg-config --libs libusb-1.0)
endif

# umockdev (tests only): the device integration tests in tests/test_track_umockdev.c
# emulate USB and hidraw devices with the libumockdev testbed API.  Its GLib
# headers are included as system headers so that our warning flags do not
# apply to them.
HAVE_UMOCKDEV := $(shell pkg-config --exists umockdev-1.0 2>/dev/null && echo 1)
ifeq ($(HAVE_UMOCKDEV),1)
TEST_CFLAGS := -DPP5_HAVE_UMOCKDEV=1 $(patsubst -I%,-isystem %,$(shell pkg-config --cflags umockdev-1.0))
TEST_LIBS   := $(shell pkg-config --libs umockdev-1.0)
endif

PP5_VERSION := $(shell git describe --always --dirty 2>/dev/null || echo unknown)

CFLAGS_ALL := -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -pthread $(OPT) $(WARN) \
              -iquote . -iquote emu -iquote emu/api -iquote emu/util $(PKG_CFLAGS) \
              -DPP5_VERSION=\"$(PP5_VERSION)\" $(CFLAGS)
LDLIBS_ALL := $(PKG_LIBS) -lm -pthread $(LDSAN) $(LDFLAGS)

# Project headers are found with -iquote, so that a module header such as
# emu/sched.h can never shadow a system header (<sched.h>) of the same name.
# Firmware sees only the firmware API (emu/api): the include path makes it a
# compile-time fact that GP programs cannot reach into renderer memory.
FW_CFLAGS  := -std=c11 -D_DEFAULT_SOURCE -pthread $(OPT) $(WARN) -iquote emu/api -iquote firmware $(CFLAGS)

# firmware/host/ is the host workstation's side (it loads data and drives the
# machine through emu's full API); the rest of firmware/ runs on the GPs.
LIB_SRC  := $(sort $(wildcard emu/*.c emu/util/*.c render/*.c tracker/*.c firmware/host/*.c))
FW_SRC   := $(sort $(filter-out firmware/host/%,$(wildcard firmware/*.c firmware/*/*.c)))
CLI_SRC  := $(sort $(wildcard emu/cli/*.c))
TEST_SRC := $(sort $(wildcard tests/*.c))

LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o) $(FW_SRC:%.c=$(BUILD)/%.o)
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_OBJ := $(TEST_SRC:%.c=$(BUILD)/%.o)

PP5_BIN  := $(if $(filter 1,$(SAN)),$(BUILD)/pp5,pp5)
TEST_BIN := $(BUILD)/pp5-tests

.PHONY: all test test-run demo bench bench-peers deps deps-check clean help
all: $(PP5_BIN)

$(PP5_BIN): $(LIB_OBJ) $(CLI_OBJ)
	$(CC) $(OPT) -o $@ $^ $(LDLIBS_ALL)

$(BUILD)/tests/%.o: CFLAGS_ALL += $(TEST_CFLAGS)
$(TEST_BIN): LDLIBS_ALL += $(TEST_LIBS)
$(TEST_BIN): $(LIB_OBJ) $(filter-out $(BUILD)/emu/cli/main.o,$(CLI_OBJ)) $(TEST_OBJ)
	$(CC) $(OPT) -o $@ $^ $(LDLIBS_ALL)

$(BUILD)/firmware/host/%.o: firmware/host/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c -o $@ $<

$(BUILD)/firmware/%.o: firmware/%.c
	@mkdir -p $(dir $@)
	$(CC) $(FW_CFLAGS) -MMD -MP -c -o $@ $<

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_ALL) -MMD -MP -c -o $@ $<

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_OBJ:.o=.d)

# `make test` first makes sure the system packages are there, then re-enters
# make so that the pkg-config probes above see them.
test: deps-check
	@$(MAKE) --no-print-directory test-run

test-run: $(TEST_BIN) $(PP5_BIN)
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

clean:
	rm -rf build pp5

help:
	@sed -n '3,10p' Makefile
