// A pair of rigid bodies whose bounding boxes overlap (PfxBroadphasePair) or that are held
// by a contact or a joint (PfxConstraintPair). Both are the same PfxSortData16, so every
// stage accepts either (seed chapter 2, "Pair"). The key is (idA << 32 | idB) with
// idA < idB, so sorting pairs by key orders them by body, deterministically.
// data[0] holds the index of the pair's contact manifold (or joint); data[1] packs the
// two motion types, whether the solver responds, which side receives impulses, and the
// number of constraints.
#pragma once

#include "pfx/base_level/base/pfx_sort_data.h"
#include "pfx/base_level/rigidbody/pfx_motion_type.h"

namespace pfx {

using PfxBroadphasePair = PfxSortData16;
using PfxConstraintPair = PfxSortData16;

inline PfxUInt64 pfxCreatePairKey(PfxUInt32 idA, PfxUInt32 idB) {
  return (PfxUInt64(idA) << 32) | idB;
}
inline PfxUInt32 pfxGetObjectIdA(const PfxSortData16& pair) {
  return static_cast<PfxUInt32>(pair.key >> 32);
}
inline PfxUInt32 pfxGetObjectIdB(const PfxSortData16& pair) {
  return static_cast<PfxUInt32>(pair.key);
}
inline PfxUInt32 pfxGetContactId(const PfxSortData16& pair) { return pair.data[0]; }
inline PfxUInt32 pfxGetConstraintId(const PfxSortData16& pair) { return pair.data[0]; }
inline PfxMotionType pfxGetMotionTypeA(const PfxSortData16& pair) {
  return static_cast<PfxMotionType>(pair.data[1] & 0xf);
}
inline PfxMotionType pfxGetMotionTypeB(const PfxSortData16& pair) {
  return static_cast<PfxMotionType>((pair.data[1] >> 4) & 0xf);
}
// Whether the solver works on this pair (seed chapter 10, "Constraint Solver").
inline bool pfxGetActive(const PfxSortData16& pair) { return ((pair.data[1] >> 8) & 1) != 0; }
inline bool pfxGetReceivesA(const PfxSortData16& pair) { return ((pair.data[1] >> 9) & 1) != 0; }
inline bool pfxGetReceivesB(const PfxSortData16& pair) { return ((pair.data[1] >> 10) & 1) != 0; }
inline PfxUInt32 pfxGetNumConstraints(const PfxSortData16& pair) { return pair.data[1] >> 16; }

inline void pfxSetContactId(PfxSortData16& pair, PfxUInt32 id) { pair.data[0] = id; }
inline void pfxSetConstraintId(PfxSortData16& pair, PfxUInt32 id) { pair.data[0] = id; }
inline void pfxSetNumConstraints(PfxSortData16& pair, PfxUInt32 n) {
  pair.data[1] = (pair.data[1] & 0xffffu) | (n << 16);
}

// Fills the key and the motion flags of a pair from the two bodies' ids and motion types;
// the smaller id becomes A. The contact id and number of constraints start at zero.
void pfxInitializePair(PfxSortData16& pair, PfxUInt32 idA, PfxMotionType typeA, PfxUInt32 idB,
                       PfxMotionType typeB);

// The same with A and B kept in the order given (joints name their bodies), and the solver
// response switched off when `enabled` is false.
void pfxInitializeOrderedPair(PfxSortData16& pair, PfxUInt32 idA, PfxMotionType typeA,
                              PfxUInt32 idB, PfxMotionType typeB, bool enabled);

}  // namespace pfx
