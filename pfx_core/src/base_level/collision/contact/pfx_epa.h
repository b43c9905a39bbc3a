// Expanding Polytope Algorithm (van den Bergen 2001): the penetration depth and direction
// of two overlapping cores, grown from the simplex where GJK found the overlap.
#pragma once

#include "base_level/collision/contact/pfx_gjk.h"

namespace pfx {

struct PfxEpaResult {
  PfxVector3 normal;  // unit, from A to B: moving B by depth * normal separates the cores
  PfxFloat depth;
  PfxVector3 pointA;  // deepest points of the cores (world)
  PfxVector3 pointB;
};

// `tolerance` is the accepted error of the depth. Returns false when the Minkowski
// difference is flat (zero-size or coplanar cores), where no polytope can be built; the
// result is then untouched.
bool pfxEpaPenetration(const PfxConvexCore& a, const PfxConvexCore& b,
                       const PfxSimplexVertex* simplex, PfxUInt32 simplexSize,
                       PfxFloat tolerance, PfxEpaResult& result);

}  // namespace pfx
