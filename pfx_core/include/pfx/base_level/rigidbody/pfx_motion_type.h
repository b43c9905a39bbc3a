// The five motion types of seed chapter 2 and the two tables of chapter 10 that say which
// pairs of them collide and which get a solver response.
#pragma once

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

enum PfxMotionType : PfxUInt8 {
  kPfxMotionTypeFixed = 0,
  kPfxMotionTypeActive,
  kPfxMotionTypeKeyframe,
  kPfxMotionTypeOneWay,
  kPfxMotionTypeTrigger,
  kPfxMotionTypeCount
};

// Seed chapter 10, "Collision Detection": symmetric.
bool pfxMotionTypesCollide(PfxMotionType a, PfxMotionType b);

// Seed chapter 10, "Constraint Solver": symmetric.
bool pfxMotionTypesRespond(PfxMotionType a, PfxMotionType b);

// Whether body `self` receives impulses from a constraint with body `other`. Fixed and
// keyframe bodies never move by impulses; a one-way body receives but never gives, so a
// body facing a one-way body acts as if it had infinite mass.
bool pfxMotionTypeReceivesImpulse(PfxMotionType self, PfxMotionType other);

// Whether external forces and integration move the body at all.
inline bool pfxMotionTypeIsDynamic(PfxMotionType t) {
  return t == kPfxMotionTypeActive || t == kPfxMotionTypeOneWay;
}

}  // namespace pfx
