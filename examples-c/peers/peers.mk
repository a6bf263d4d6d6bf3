# The peer harness (README.md beside this file), included by the drivers' Makefiles:
#   examples-c/crosscheck/Makefile   PROGRAM = crosscheck    ENGINES = fcl bullet
#   bench/peers/Makefile             PROGRAM = glcol_peers   ENGINES = fcl bullet embree gl
#   examples-c/contact_check/Makefile PROGRAM = contact_check ENGINES = (none)
#   bench/contact/Makefile           PROGRAM = contact_cost  ENGINES = fcl bullet (+ its own FCL with contacts)
# The including Makefile sets PROGRAM, ENGINES and DRIVER (its own directory, which holds
# main.cpp and gets build/PROGRAM) first. The harness's objects are built once, with one set of flags, in
# examples-c/peers/build/ and linked into every program.
# Peers are found with pkg-config: `fcl` (its .pc injects -std=c++11, so -std=c++17 comes
# after it) and `bullet-float64` (double build: -DBT_USE_DOUBLE_PRECISION must match the
# -float64 libraries); Embree 3 has no .pc (-lembree3). CGAL 5.5 is header-only (no .pc):
# -lgmp -lmpfr. glcollide: cargo's target directory ($CARGO_TARGET_DIR when set, as cargo
# does), or LIBDIR=... on the command line.
PEERS := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
ROOT := $(abspath $(PEERS)/../..)
DRIVER ?= $(CURDIR)
PROFILE ?= release
LIBDIR ?= $(or $(CARGO_TARGET_DIR),$(ROOT)/target)/$(PROFILE)
BUILD := $(DRIVER)/build
PBUILD := $(PEERS)/build
CXX ?= g++
PKG_CONFIG ?= pkg-config
BULLET_PC ?= bullet-float64

CXXFLAGS ?= -O2 -g -march=x86-64-v2
BASE := -std=c++17 -Wall -Wextra -DNDEBUG -I$(ROOT)/include -I$(PEERS) -MMD -MP
FCL_CFLAGS := $(patsubst -I%,-isystem %,$(shell $(PKG_CONFIG) --cflags fcl))
FCL_LIBS := $(shell $(PKG_CONFIG) --libs fcl)
BULLET_CFLAGS := $(patsubst -I%,-isystem %,$(shell $(PKG_CONFIG) --cflags $(BULLET_PC)))
BULLET_LIBS := -lBulletCollision$(if $(findstring float64,$(BULLET_PC)),-float64) \
               -lLinearMath$(if $(findstring float64,$(BULLET_PC)),-float64)

# What every program links, then each engine's objects and libraries.
CORE := common meshes scenes exact glcol_engine
LIBS := -L$(LIBDIR) -Wl,-rpath,$(LIBDIR) -lglcollide
OBJ_fcl := fcl_engine
LIB_fcl := $(FCL_LIBS)
OBJ_bullet := bullet_engine
LIB_bullet := $(BULLET_LIBS)
OBJ_embree := embree_engine
LIB_embree := -lembree3 -lpthread
OBJ_gl := gl_context
LIB_gl := -lEGL
OBJS := $(BUILD)/main.o $(patsubst %,$(PBUILD)/%.o,$(CORE) $(foreach e,$(ENGINES),$(OBJ_$(e))))

all: $(BUILD)/$(PROGRAM)

$(BUILD)/$(PROGRAM): $(OBJS) $(LIBDIR)/libglcollide.so
	$(CXX) $(OBJS) -o $@ $(LIBS) $(foreach e,$(ENGINES),$(LIB_$(e))) -lgmp -lmpfr

$(BUILD)/main.o: $(DRIVER)/main.cpp | $(BUILD)
	$(CXX) $(CXXFLAGS) $(BASE) -c $< -o $@

# The harness's objects may be wanted by both drivers at once: each is written under a
# name of its own and then renamed.
$(PBUILD)/fcl_engine.o: EXTRA := $(FCL_CFLAGS)
$(PBUILD)/bullet_engine.o: EXTRA := $(BULLET_CFLAGS)
$(PBUILD)/%.o: $(PEERS)/%.cpp | $(PBUILD)
	$(CXX) $(EXTRA) $(CXXFLAGS) $(BASE) -MT $@ -MF $(@:.o=.d) -c $< -o $@.$$$$ && mv -f $@.$$$$ $@

$(BUILD) $(PBUILD):
	mkdir -p $@

-include $(OBJS:.o=.d)

clean:
	rm -rf $(BUILD) $(PBUILD)

.PHONY: all clean
