#include "pfx/base_level/rigidbody/pfx_motion_type.h"

namespace pfx {

namespace {

// Rows and columns: fixed, active, keyframe, one-way, trigger (seed chapter 10).
constexpr bool kCollide[kPfxMotionTypeCount][kPfxMotionTypeCount] = {
    {false, true, false, true, true},
    {true, true, true, true, true},
    {false, true, false, true, true},
    {true, true, true, false, true},
    {true, true, true, true, false},
};

constexpr bool kRespond[kPfxMotionTypeCount][kPfxMotionTypeCount] = {
    {false, true, false, true, false},
    {true, true, true, true, false},
    {false, true, false, true, false},
    {true, true, true, false, false},
    {false, false, false, false, false},
};

bool isKnownMotionType(PfxMotionType t) { return t < kPfxMotionTypeCount; }

}  // namespace

bool pfxMotionTypesCollide(PfxMotionType a, PfxMotionType b) {
  return isKnownMotionType(a) && isKnownMotionType(b) && kCollide[a][b];
}

bool pfxMotionTypesRespond(PfxMotionType a, PfxMotionType b) {
  return isKnownMotionType(a) && isKnownMotionType(b) && kRespond[a][b];
}

bool pfxMotionTypeReceivesImpulse(PfxMotionType self, PfxMotionType other) {
  if (!pfxMotionTypeIsDynamic(self)) return false;
  return !(other == kPfxMotionTypeOneWay && self != kPfxMotionTypeOneWay);
}

}  // namespace pfx
