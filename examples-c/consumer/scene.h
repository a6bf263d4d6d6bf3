/*
 * The consumer tests' scene: two crossing squares, each made of two triangles, whose
 * contacts can be worked out by hand. Shared by consumer.c (pkg-config) and consumer.cpp
 * (CMake); both print the same lines, checked against expected.txt.
 *
 * A lies in the plane z = 0, corners (+-1, +-1), split along the diagonal y = x:
 *   A0 = (a0,a1,a2) is the half y <= x,  A1 = (a0,a2,a3) is the half y >= x.
 * B lies in the plane y = 0.5, x in [-2,2], z in [-1,1], split along z = x/2:
 *   B0 = (b0,b1,b2) is the half z <= x/2,  B1 = (b0,b2,b3) is the half z >= x/2.
 * The planes meet on the line y = 0.5, z = 0; inside both squares that is x in [-1,1].
 * On it A0 holds x >= 0.5, A1 x <= 0.5, B0 x >= 0, B1 x <= 0. So A0-B0 ([0.5,1]),
 * A1-B0 ([0,0.5]) and A1-B1 ([-1,0]) intersect, and A0-B1 do not (0.5 apart): 3 contacts.
 * With A as the reference mesh they come sorted as (0,0), (1,0), (1,1).
 * Every coordinate is exact in binary floating point, and the CPU backend with
 * epsilon = 0 is exact, so the answer does not depend on rounding.
 */
#ifndef GLCOLLIDE_CONSUMER_SCENE_H
#define GLCOLLIDE_CONSUMER_SCENE_H

#include <stdint.h>

static const float consumer_a_xyz[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
static const float consumer_b_xyz[12] = {-2, 0.5f, -1, 2, 0.5f, -1, 2, 0.5f, 1, -2, 0.5f, 1};
static const uint32_t consumer_tris[6] = {0, 1, 2, 0, 2, 3};

#endif
