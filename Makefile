# cube5 build. Everything lands in $(BUILD) (build/ by default; build/asan for `make asan`).
# The first build runs scripts/setup-deps.sh, which apt-get installs what is missing: the demo
# profile (scripts/deps/demo.txt) for build/cube5, the test profile (deps/test.txt) for the
# driver, the emulated board and `make test`.

BUILD    ?= build
CC       ?= gcc
CXX      ?= g++
OPT      ?= -O2
# The board model's objects are its inner loop (the sample pipeline inlined in processor.c):
# -O3 there is 12 % more host throughput on brain_mirrors (docs/board-model.md, "Host speed");
# integer arithmetic only, so the same bits. `make asan` sets OPT on the command line, which
# overrides this for every object.
MODEL_OPT ?= -O3
SAN      ?=
# The board model (rtl_model/README.md): the board, and a folder each for the ray processor's
# blocks, the DSP's work, the memory system and the offline analysis of schedules.
MODEL_DIRS := rtl_model rtl_model/proc rtl_model/dsp rtl_model/mem rtl_model/analysis
# One version for the three programs, the libraries' SONAMEs and pkg-config files: VERSION.
C5_VERSION := $(shell cat VERSION)
CPPFLAGS += -D_DEFAULT_SOURCE -DC5_VERSION='"$(C5_VERSION)"' -Itests -Icommon -Icref -Icref/cast $(MODEL_DIRS:%=-I%) -Ivectors/gen -Isweep -I$(BUILD)/gen
CFLAGS   += -std=c11 $(OPT) -g -Wall -Wextra -Werror -pthread $(SAN)
CXXFLAGS += -std=c++17 $(OPT) -g -Wall -Wextra -Werror $(SAN)
LDFLAGS  += -pthread $(SAN)
LDLIBS   += $(shell pkg-config --libs jansson 2>/dev/null) -lteem -lz -lm -ldl

LIB_SRC  := $(wildcard common/*.c cref/*.c cref/cast/*.c $(MODEL_DIRS:%=%/*.c) vectors/gen/*.c sweep/*.c)
# The host link (docs/host-protocol.md): the driver library on libusb and the emulated board
# on umockdev, each its own library so that a driver user never links umockdev. The pkg-config
# calls are deferred (=, +=) to when a rule runs: on a fresh machine the packages arrive with
# $(DEPS_TEST), after this file was read.
USB_PKGS := libusb-1.0 umockdev-1.0
CPPFLAGS += -Ihost_driver -Iboard_emu $(shell pkg-config --cflags $(USB_PKGS) 2>/dev/null)
USB_LIBS  = $(shell pkg-config --libs libusb-1.0 2>/dev/null)
EMU_LIBS  = $(shell pkg-config --libs umockdev-1.0 libusb-1.0 2>/dev/null)
DRV_SRC  := $(filter-out host_driver/cube5ctl.c,$(wildcard host_driver/*.c))
EMU_SRC  := $(filter-out board_emu/cube5_board.c,$(wildcard board_emu/*.c))
LINK_SRC := $(wildcard tests/link/*.c)
LIB_CXX  := $(wildcard common/*.cpp)
CLI_SRC  := $(wildcard cli/*.c)
TEST_SRC := $(wildcard tests/*.c)
SCENES   := $(sort $(wildcard scenes/*.json))

# cref a second time, in long double (cref/real.h): the same sources with -DC5_CREF_LONG,
# whose symbols are c5l_* and c5_cref_render_long (docs/stability.md, "Is cref itself stable?").
CREFL_SRC := cref/render.c cref/trace.c cref/sample.c cref/geometry.c
CREFL_OBJ := $(CREFL_SRC:cref/%.c=$(BUILD)/cref-long/%.o)
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o) $(BUILD)/gen/builtin_scenes.o $(CREFL_OBJ)
# The OpenImageIO shim, its own library, opened on the first image read or write
# (common/image_oiio.h says why): with its own copies of the C it calls.
IMAGE_SO  := $(BUILD)/libc5image.so
IMAGE_OBJ := $(LIB_CXX:%.cpp=$(BUILD)/pic/%.o) $(addprefix $(BUILD)/pic/common/,image.o err.o atomic_file.o)
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_OBJ := $(TEST_SRC:%.c=$(BUILD)/%.o)
# Stamps of the set-up profiles (scripts/setup-deps.sh): demo, and test on top of it.
DEPS_OK   := build/.deps-demo
DEPS_TEST := build/.deps-test
# Bit layouts: spec/layouts.toml is the one source; these are generated from it.
LAYOUTS_H   := $(BUILD)/gen/c5_layouts.h
LAYOUTS_VHD := $(BUILD)/gen/c5_layouts_pkg.vhd
GEN_LAYOUTS := python3 scripts/gen-layouts.py spec/layouts.toml
# The register map (BAR0): spec/registers.toml, through the same generator.
REGS_H      := $(BUILD)/gen/c5_regs_map.h
REGS_VHD    := $(BUILD)/gen/c5_regs_pkg.vhd
GEN_REGS    := python3 scripts/gen-layouts.py --regs spec/registers.toml

.PHONY: all demo test regress asan bench bench-boards bench-sched bench-peer tb results accuracy deps docs golden man coverage fpga-report fuzz clean
LINK_BINS := $(BUILD)/cube5ctl $(BUILD)/cube5-board $(BUILD)/tests/link-tests
# The fuzz harnesses (fuzz/, docs/fuzzing.md) built with this toolchain on a replay main:
# `make test` replays the committed corpus through them (no clang, no libFuzzer).
FUZZ_NAMES  := scene volume tlp driver
FUZZ_REPLAY := $(FUZZ_NAMES:%=$(BUILD)/fuzz/replay-%)
all: $(BUILD)/cube5 $(BUILD)/cube5-nompi $(BUILD)/tests/unit $(BUILD)/tests/cast-nosimd $(LINK_BINS) $(FUZZ_REPLAY) $(LAYOUTS_VHD) $(REGS_VHD)

deps: $(DEPS_TEST)
$(DEPS_OK): scripts/setup-deps.sh scripts/deps/demo.txt
	@mkdir -p $(@D)
	bash scripts/setup-deps.sh demo
	@touch $@
# After the demo profile, so that two apt-get never run at once under make -j.
$(DEPS_TEST): scripts/setup-deps.sh scripts/deps/demo.txt scripts/deps/test.txt | $(DEPS_OK)
	bash scripts/setup-deps.sh test
	@touch $@

# Order-only on the generated headers (layouts, register map): it exists before any source can include it; the .d
# files then rebuild exactly the objects that include it when it changes.
$(BUILD)/%.o: %.c | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/rtl_model/%.o: OPT = $(MODEL_OPT)

$(BUILD)/cref-long/%.o: cref/%.c | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) -DC5_CREF_LONG $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/%.o: %.cpp | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -MMD -MP -c $< -o $@

# The built-in scenes are the JSON files in scenes/, compiled in as strings.
$(BUILD)/gen/builtin_scenes.c: $(SCENES) scripts/embed-scenes.sh
	@mkdir -p $(@D)
	bash scripts/embed-scenes.sh $(SCENES) > $@.tmp && mv $@.tmp $@

$(BUILD)/gen/builtin_scenes.o: $(BUILD)/gen/builtin_scenes.c | $(LAYOUTS_H)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(LAYOUTS_H): spec/layouts.toml scripts/gen-layouts.py | $(DEPS_OK)
	$(GEN_LAYOUTS) --c-header $@

# VHDL package for fpga/: field positions, records, pack/unpack (tests/fpga_test.sh analyses it).
$(LAYOUTS_VHD): spec/layouts.toml scripts/gen-layouts.py | $(DEPS_OK)
	$(GEN_LAYOUTS) --vhdl $@

$(REGS_H): spec/registers.toml scripts/gen-layouts.py | $(DEPS_OK)
	$(GEN_REGS) --c-header $@

# VHDL package c5_regs_pkg: offsets, field ranges, reset values (tests/regmap_test.sh analyses it).
$(REGS_VHD): spec/registers.toml scripts/gen-layouts.py | $(DEPS_OK)
	$(GEN_REGS) --vhdl $@

# docs/bit-layouts.md and docs/register-map.md are checked in; tests/layouts_test.sh and
# tests/regmap_test.sh fail while they are stale.
docs: | $(DEPS_OK)
	$(GEN_LAYOUTS) --markdown docs/bit-layouts.md
	$(GEN_REGS) --markdown docs/register-map.md

# Whatever links the model can write images: the shim is built with it.
$(BUILD)/libcube5.a: $(LIB_OBJ) | $(IMAGE_SO)
	@rm -f $@
	ar rcs $@ $(LIB_OBJ)

$(IMAGE_SO): $(IMAGE_OBJ) common/c5image.map
	$(CXX) -shared $(LDFLAGS) -Wl,--version-script=common/c5image.map -Wl,--no-undefined -o $@ $(IMAGE_OBJ) \
	  $(shell pkg-config --libs OpenImageIO 2>/dev/null)

$(BUILD)/pic/%.o: %.cpp | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -fPIC -MMD -MP -c $< -o $@

# Where an installed program finds the shim when it is not in ../lib/cube5 of the program.
$(BUILD)/common/image_load.o: CPPFLAGS += -DC5_IMAGE_LIBDIR='"$(LIBDIR)/cube5"'

# Several boards over MPI (docs/multi-board.md): cli/mpi_link.c is the only file that calls
# MPI, built with Open MPI when pkg-config finds it (the demo profile installs it); MPI=0, or
# no Open MPI, builds without: one board, and --boards N > 1 says how to get MPI. Deferred
# (=): on a fresh machine the packages arrive with $(DEPS_OK), after this file was read.
MPI ?= 1
MPI_FOUND  = $(if $(filter 1,$(MPI)),$(shell pkg-config --exists ompi-c && echo yes))
MPI_CFLAGS = $(if $(MPI_FOUND),-DC5_HAVE_MPI $(shell pkg-config --cflags ompi-c))
MPI_LIBS   = $(if $(MPI_FOUND),$(shell pkg-config --libs ompi-c))
$(BUILD)/cli/mpi_link.o: CPPFLAGS += $(MPI_CFLAGS)

$(BUILD)/cube5: $(CLI_OBJ) $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) $(MPI_LIBS) -o $@

# cube5 once more without MPI, for tests/mpi_test.sh: what a build without Open MPI does.
$(BUILD)/nompi/cli/mpi_link.o: cli/mpi_link.c | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/cube5-nompi: $(filter-out $(BUILD)/cli/mpi_link.o,$(CLI_OBJ)) $(BUILD)/nompi/cli/mpi_link.o $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/libc5drv.a: $(DRV_SRC:%.c=$(BUILD)/%.o)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/libc5emu.a: $(EMU_SRC:%.c=$(BUILD)/%.o)
	@rm -f $@
	ar rcs $@ $^

# The driver and the emulated board need libusb and umockdev: the test profile.
$(DRV_SRC:%.c=$(BUILD)/%.o) $(EMU_SRC:%.c=$(BUILD)/%.o) $(LINK_SRC:%.c=$(BUILD)/%.o) \
  $(BUILD)/host_driver/cube5ctl.o $(BUILD)/board_emu/cube5_board.o: | $(DEPS_TEST)

$(BUILD)/cube5ctl: $(BUILD)/host_driver/cube5ctl.o $(BUILD)/libc5drv.a $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(USB_LIBS) $(LDLIBS) -o $@

# The gradient study behind docs/accuracy.md's "Gradients" (sweep/grad_study.h).
$(BUILD)/grad-study: $(BUILD)/sweep/tools/grad_study.o $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/cube5-board: $(BUILD)/board_emu/cube5_board.o $(BUILD)/libc5emu.a $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(EMU_LIBS) $(LDLIBS) -o $@

# The integration tests over real libusb against the emulated board (tests/link_test.sh runs
# it with umockdev's preload library). Not build/tests/link: that folder holds its objects.
$(BUILD)/tests/link-tests: $(LINK_SRC:%.c=$(BUILD)/%.o) $(BUILD)/tests/harness.o $(BUILD)/libc5drv.a $(BUILD)/libc5emu.a $(BUILD)/libcube5.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(EMU_LIBS) $(LDLIBS) -o $@

# The unit tests check the exact optimum against an integer program through GLPK
# (tests/tree_ilp.c, test profile): only the test binary links it.
$(BUILD)/tests/tree_ilp.o: | $(DEPS_TEST)
$(BUILD)/tests/unit: $(TEST_OBJ) $(BUILD)/libcube5.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -lglpk -o $@

# The caster's scalar definition of a sample (cref/cast/cast_sample.h), which machines without
# SSE2 run: the caster and its tests built once more without the SIMD twin.
NOSIMD_OBJ := $(patsubst %.c,$(BUILD)/nosimd/%.o,$(wildcard cref/cast/*.c) tests/test_cast.c)
$(BUILD)/nosimd/%.o: %.c | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) -DC5_CAST_NO_SIMD $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/tests/cast-nosimd: $(NOSIMD_OBJ) $(BUILD)/tests/harness.o $(BUILD)/libcube5.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -o $@

# Kept, not deleted as intermediates of the pattern rule (every make would rebuild them).
.SECONDARY: $(FUZZ_NAMES:%=$(BUILD)/fuzz/fuzz_%.o) $(BUILD)/fuzz/replay_main.o
$(BUILD)/fuzz/replay-%: $(BUILD)/fuzz/fuzz_%.o $(BUILD)/fuzz/replay_main.o $(BUILD)/libc5drv.a $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -o $@

# libFuzzer campaigns with clang and sanitizers, Teem's reader instrumented from its Debian
# source (fuzz/run.sh installs what it needs): FUZZ_SECONDS per harness (default 60),
# or FUZZ_RUNS executions; FUZZ_ONLY picks harnesses.
fuzz: $(LAYOUTS_H) $(REGS_H)
	bash fuzz/run.sh $(BUILD)

# The model's blocks as a live reference for GHDL (fpga/ref/, VHPIDIRECT; docs/vectors.md).
# Never sanitized: GHDL's process, which loads it, has no sanitizer runtime. Built with the
# rounding probe (rtl_model/proc/round_probe.h) that the coverage of the vectors reads.
REF_SO := $(BUILD)/libc5ref.so
# REF_MODEL_SRC: the model sources the references call into and what they use (the link
# fails on anything missing).
REF_MODEL_SRC := rtl_model/proc/ray_queue.c rtl_model/dsp/cell_tree.c rtl_model/proc/processor.c rtl_model/proc/ray_log.c rtl_model/proc/packet.c rtl_model/proc/fixed.c rtl_model/mem/cells.c rtl_model/proc/geom.c rtl_model/proc/shade_wide.c rtl_model/proc/value_wide.c \
  rtl_model/proc/hit_unit.c common/err.c common/supervol.c common/voxsrc.c common/volume.c common/voxel.c common/nrrd_precheck.c \
  common/generators.c common/tlp.c common/block_range.c common/cache_dir.c common/atomic_file.c common/worker_pool.c
REF_SRC := $(wildcard fpga/ref/*.c) $(REF_MODEL_SRC)
$(REF_SO): $(REF_SRC) $(wildcard fpga/ref/*.h $(MODEL_DIRS:%=%/*.h) common/*.h) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) -DC5_ROUND_PROBE -std=c11 -O2 -g -Wall -Wextra -Werror -fPIC -shared -Wl,--no-undefined -o $@ $(REF_SRC) \
	  -lteem -lz -lm

demo: $(BUILD)/cube5
	@mkdir -p out
	$(BUILD)/cube5 render default -o out/default.png

test: $(BUILD)/cube5 $(BUILD)/cube5-nompi $(BUILD)/tests/unit $(BUILD)/tests/libwritefault.so $(BUILD)/tests/cast-nosimd $(LINK_BINS) $(FUZZ_REPLAY) $(LAYOUTS_VHD) $(REGS_VHD) $(REF_SO) | $(DEPS_TEST)
	bash tests/run.sh $(BUILD)


# The full regression tier: golden replay in C and VHDL, coverage, N seeds of random vectors
# through every testbench and of the VHDL against the live model (scripts/regress.sh; env
# SEEDS, COUNT, CYCLES).
regress: $(BUILD)/cube5 $(LAYOUTS_VHD) $(REF_SO) | $(DEPS_TEST)
	bash scripts/regress.sh $(BUILD)

# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer.
# The README's promised times are the release build's; the sanitizers run about 3x slower.
asan:
	C5_README_LIMIT_S=120 $(MAKE) test BUILD=build/asan OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"

# The write shim of tests/write_fault_test.sh (LD_PRELOAD): no sanitizer, it wraps libc.
$(BUILD)/tests/libwritefault.so: tests/fault/write_fault.c
	@mkdir -p $(dir $@)
	$(CC) -shared -fPIC -O2 -std=c11 -Wall -Wextra -Werror -o $@ $< -ldl

bench: $(BUILD)/cube5 $(LINK_BINS)
	bash scripts/bench.sh $(BUILD)

# The Cell Tree against Max Work while the camera moves: every rule, orbit speeds and jumps,
# with each frame's bound (scripts/bench-sched.sh; env SIZE, FRAMES, CELLS, SPEEDS, RULES).
bench-sched: $(BUILD)/cube5
	bash scripts/bench-sched.sh $(BUILD)

# Several boards on one super volume over MPI ranks on this machine: 1, 2, 4, 8 boards, every
# scene and assignment rule (scripts/bench-boards.sh; env SIZE, CELLS, BOARDS, RULES, SCENES).
bench-boards: $(BUILD)/cube5
	bash scripts/bench-boards.sh $(BUILD)

# Our caster against VTK's vtkFixedPointVolumeRayCastMapper (../shared/bench/peer-vtk),
# interleaved rounds; env ROUNDS, ONLY, DISTS (scripts/bench-peer.sh).
bench-peer: $(BUILD)/cube5
	bash scripts/bench-peer.sh $(BUILD)

# The board model against cref on every built-in scene, 1, 8 and 27 cells (tb/README.md).
tb: $(BUILD)/cube5
	bash tb/compare_scenes.sh $(BUILD)

# The paper's Section 4 (Figures 6, 7, 10 and an animation) into docs/results/ (docs/cell-tree.md).
results: $(BUILD)/cube5
	bash scripts/results.sh $(BUILD)

# The committed golden vectors (docs/vectors.md). Regenerating them is a deliberate act:
# tests/vectors_test.sh fails until they match the model again; say why in the commit.
GOLDEN_ARGS := --seed 1 --count 128 --size 64x64 --cells 2
golden: $(BUILD)/cube5
	$(BUILD)/cube5 vectors --out vectors/golden $(GOLDEN_ARGS)

# man/cube5.1's command sections from the commands' option tables (tests/man_test.sh fails
# while the page differs from them).
man: $(BUILD)/cube5
	bash scripts/man-commands.sh $(BUILD)/cube5 man/cube5.1

# Functional coverage of the golden vectors against spec/coverage.toml (docs/vectors.md).
coverage: $(REF_SO)
	python3 scripts/vectors_coverage.py vectors/golden --ref $(REF_SO) --all

# The sweeps behind docs/accuracy.md into docs/accuracy/ (scripts/accuracy.sh, about 2 minutes).
accuracy: $(BUILD)/cube5 $(BUILD)/grad-study
	bash scripts/accuracy.sh $(BUILD)

# Synthesis estimate of fpga/rtl for an iCE40 (yosys, nextpnr) and an ECP5 (yosys) into
# docs/fpga-report.md, about 40 minutes on a loaded 2-core VM; work files in $(BUILD)/fpga. (`make test` simulates fpga/ in $(BUILD)/ghdl.)
fpga-report: $(LAYOUTS_VHD)
	bash scripts/fpga-report.sh $(BUILD)

# ---- The installable driver library and `make install` (README.md "Install", host_driver/README.md)
# libc5drv: the driver and the parts of the model it loads scenes with (scene parsing, super
# volume, cells, registers and what they use: DRV_MODEL_SRC; the link fails on anything
# missing), compiled once more with -fPIC into $(BUILD)/pic. The shared library exports only
# c5drv_* (host_driver/c5drv.map) and the static one keeps only those global, so neither
# leaks the model's c5_* symbols. The programs keep linking libcube5.a: nothing installed
# needs an rpath. The model is not an installed library: its headers are internal (generated
# layouts, structs that change with the hardware), and the programs are its interface.
PREFIX     ?= /usr/local
BINDIR     ?= $(PREFIX)/bin
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
MANDIR     ?= $(PREFIX)/share/man
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
# A program built against the installed libc5drv finds it at run time: for a LIBDIR the
# dynamic loader searches (ld.so.conf), `make install` runs ldconfig (when it installs for
# real, not into a DESTDIR); for any other, c5drv.pc's Libs carry -Wl,-rpath,LIBDIR.
SYSTEM_LIBDIRS := /lib /lib64 /usr/lib /usr/lib64 $(shell cat /etc/ld.so.conf.d/*.conf 2>/dev/null | grep '^/')
DRV_RPATH := $(if $(filter $(patsubst %/,%,$(LIBDIR)),$(SYSTEM_LIBDIRS)),,-Wl,-rpath,$${libdir} )
C5_SOVERSION := $(firstword $(subst ., ,$(C5_VERSION)))
DRV_SONAME := libc5drv.so.$(C5_SOVERSION)
DRV_SO     := $(BUILD)/libc5drv.so.$(C5_VERSION)
DRV_STATIC := $(BUILD)/pic/libc5drv.a
DRV_MODEL_SRC := common/err.c common/scene_parse.c common/supervol.c common/voxsrc.c common/tlp.c common/volume.c common/voxel.c common/nrrd_precheck.c \
  common/generators.c common/tf.c common/camera.c rtl_model/mem/cells.c rtl_model/proc/regs.c rtl_model/model_limits.c \
  rtl_model/proc/widths.c cref/render.c cref/trace.c cref/sample.c cref/geometry.c common/image.c \
  common/atomic_file.c common/block_range.c common/cache_dir.c common/worker_pool.c
DRV_PIC_OBJ := $(patsubst %.c,$(BUILD)/pic/%.o,$(DRV_SRC) $(DRV_MODEL_SRC)) $(CREFL_SRC:cref/%.c=$(BUILD)/pic/cref-long/%.o)
DRV_PUBLIC_H := host_driver/c5drv.h $(REGS_H)
MAN_PAGES  := man/cube5.1 man/cube5ctl.1 man/cube5-board.1
INSTALL_BINS := $(BUILD)/cube5 $(BUILD)/cube5ctl $(BUILD)/cube5-board
.PHONY: install uninstall
all test: $(DRV_SO) $(DRV_STATIC)

$(BUILD)/pic/%.o: %.c | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -fPIC -MMD -MP -c $< -o $@

$(BUILD)/pic/cref-long/%.o: cref/%.c | $(DEPS_OK) $(LAYOUTS_H) $(REGS_H)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) -DC5_CREF_LONG $(CFLAGS) -fPIC -MMD -MP -c $< -o $@

$(DRV_SO): $(DRV_PIC_OBJ) host_driver/c5drv.map
	$(CC) -shared $(LDFLAGS) -Wl,-soname,$(DRV_SONAME) -Wl,--version-script=host_driver/c5drv.map \
	  -Wl,--no-undefined -o $@ $(DRV_PIC_OBJ) $(USB_LIBS) $(shell pkg-config --libs jansson) -lteem -lz -lm

# One relocatable object whose only global symbols are c5drv_*.
$(DRV_STATIC): $(DRV_PIC_OBJ)
	$(LD) -r -o $(@D)/c5drv-all.o $^
	objcopy --wildcard --keep-global-symbol='c5drv_*' $(@D)/c5drv-all.o
	@rm -f $@
	ar rcs $@ $(@D)/c5drv-all.o

install: $(INSTALL_BINS) $(IMAGE_SO) $(DRV_SO) $(DRV_STATIC) $(DRV_PUBLIC_H) $(MAN_PAGES) host_driver/c5drv.pc.in
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(LIBDIR)/cube5 $(DESTDIR)$(PKGCONFIGDIR) \
	  $(DESTDIR)$(INCLUDEDIR)/cube5 $(DESTDIR)$(MANDIR)/man1
	install -m 755 $(INSTALL_BINS) $(DESTDIR)$(BINDIR)/
	install -m 755 $(IMAGE_SO) $(DESTDIR)$(LIBDIR)/cube5/
	install -m 755 $(DRV_SO) $(DESTDIR)$(LIBDIR)/
	ln -sf $(notdir $(DRV_SO)) $(DESTDIR)$(LIBDIR)/$(DRV_SONAME)
	ln -sf $(DRV_SONAME) $(DESTDIR)$(LIBDIR)/libc5drv.so
	install -m 644 $(DRV_STATIC) $(DESTDIR)$(LIBDIR)/
	install -m 644 $(DRV_PUBLIC_H) $(DESTDIR)$(INCLUDEDIR)/cube5/
	install -m 644 $(MAN_PAGES) $(DESTDIR)$(MANDIR)/man1/
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' -e 's|@INCLUDEDIR@|$(INCLUDEDIR)|' \
	  -e 's|@VERSION@|$(C5_VERSION)|' -e 's|@RPATH@|$(DRV_RPATH)|' host_driver/c5drv.pc.in \
	  > $(DESTDIR)$(PKGCONFIGDIR)/c5drv.pc
	$(if $(DESTDIR)$(DRV_RPATH),,-/sbin/ldconfig)

uninstall:
	rm -f $(addprefix $(DESTDIR)$(BINDIR)/,$(notdir $(INSTALL_BINS))) \
	  $(addprefix $(DESTDIR)$(LIBDIR)/,$(notdir $(DRV_SO)) $(DRV_SONAME) libc5drv.so libc5drv.a) \
	  $(addprefix $(DESTDIR)$(INCLUDEDIR)/cube5/,$(notdir $(DRV_PUBLIC_H))) \
	  $(addprefix $(DESTDIR)$(MANDIR)/man1/,$(notdir $(MAN_PAGES))) $(DESTDIR)$(PKGCONFIGDIR)/c5drv.pc \
	  $(DESTDIR)$(LIBDIR)/cube5/$(notdir $(IMAGE_SO))
	-rmdir $(DESTDIR)$(INCLUDEDIR)/cube5 $(DESTDIR)$(LIBDIR)/cube5
# ---- end of the install block -----------------------------------------------------------------

clean:
	rm -rf build out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
