#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"

#include <utility>

namespace pfx {

void pfxInitializePair(PfxSortData16& pair, PfxUInt32 idA, PfxMotionType typeA, PfxUInt32 idB,
                       PfxMotionType typeB) {
  if (idB < idA) {
    std::swap(idA, idB);
    std::swap(typeA, typeB);
  }
  pfxInitializeOrderedPair(pair, idA, typeA, idB, typeB, true);
}

void pfxInitializeOrderedPair(PfxSortData16& pair, PfxUInt32 idA, PfxMotionType typeA,
                              PfxUInt32 idB, PfxMotionType typeB, bool enabled) {
  pair.key = pfxCreatePairKey(idA, idB);
  const bool active = enabled && pfxMotionTypesRespond(typeA, typeB);
  const bool receivesA = active && pfxMotionTypeReceivesImpulse(typeA, typeB);
  const bool receivesB = active && pfxMotionTypeReceivesImpulse(typeB, typeA);
  pair.data[0] = 0;
  pair.data[1] = PfxUInt32(typeA) | (PfxUInt32(typeB) << 4) | (PfxUInt32(active) << 8) |
                 (PfxUInt32(receivesA) << 9) | (PfxUInt32(receivesB) << 10);
}

}  // namespace pfx
