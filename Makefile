# cube5 build. Everything lands in $(BUILD) (build/ by default; build/asan for `make asan`).
# The first build runs scripts/setup-deps.sh, which apt-get installs what is missing.

BUILD    ?= build
CC       ?= gcc
CXX      ?= g++
OPT      ?= -O2
SAN      ?=
CPPFLAGS += -D_DEFAULT_SOURCE -Icommon -Icref -Irtl_model -I$(BUILD)/gen
CFLAGS   += -std=c11 $(OPT) -g -Wall -Wextra -Werror -pthread $(SAN)
CXXFLAGS += -std=c++17 $(OPT) -g -Wall -Wextra -Werror $(SAN)
LDFLAGS  += -pthread $(SAN)
LDLIBS   += $(shell pkg-config --libs OpenImageIO jansson 2>/dev/null) -lteem -lz -lm

LIB_SRC  := $(wildcard common/*.c cref/*.c rtl_model/*.c)
LIB_CXX  := $(wildcard common/*.cpp)
CLI_SRC  := $(wildcard cli/*.c)
TEST_SRC := $(wildcard tests/*.c)
SCENES   := $(sort $(wildcard scenes/*.json))

LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o) $(LIB_CXX:%.cpp=$(BUILD)/%.o) $(BUILD)/gen/builtin_scenes.o
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_OBJ := $(TEST_SRC:%.c=$(BUILD)/%.o)
DEPS_OK  := build/.deps-ok

.PHONY: all demo test asan bench deps clean
all: $(BUILD)/cube5 $(BUILD)/tests/unit

deps: $(DEPS_OK)
$(DEPS_OK): scripts/setup-deps.sh
	@mkdir -p $(@D)
	bash scripts/setup-deps.sh
	@touch $@

$(BUILD)/%.o: %.c | $(DEPS_OK)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/%.o: %.cpp | $(DEPS_OK)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -MMD -MP -c $< -o $@

# The built-in scenes are the JSON files in scenes/, compiled in as strings.
$(BUILD)/gen/builtin_scenes.c: $(SCENES) scripts/embed-scenes.sh
	@mkdir -p $(@D)
	bash scripts/embed-scenes.sh $(SCENES) > $@.tmp && mv $@.tmp $@

$(BUILD)/gen/builtin_scenes.o: $(BUILD)/gen/builtin_scenes.c
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/libcube5.a: $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/cube5: $(CLI_OBJ) $(BUILD)/libcube5.a
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/tests/unit: $(TEST_OBJ) $(BUILD)/libcube5.a
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(LDLIBS) -o $@

demo: $(BUILD)/cube5
	@mkdir -p out
	$(BUILD)/cube5 render default -o out/default.png

test: $(BUILD)/cube5 $(BUILD)/tests/unit
	bash tests/run.sh $(BUILD)

# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer.
asan:
	$(MAKE) test BUILD=build/asan OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all"

bench: $(BUILD)/cube5
	bash scripts/bench.sh $(BUILD)

clean:
	rm -rf build out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
