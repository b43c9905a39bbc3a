// Stage (2c): this frame's pairs against the last frame's: new, kept and removed
// (seed chapter 4, "Compose Intersecting Pairs").
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"

namespace pfx {

struct PfxDecomposePairsParam {
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  void* pairBuff = nullptr;
  PfxUInt32 pairBytes = 0;
  const PfxBroadphasePair* previousPairs = nullptr;  // sorted by key
  PfxUInt32 numPreviousPairs = 0;
  const PfxBroadphasePair* currentPairs = nullptr;   // sorted by key
  PfxUInt32 numCurrentPairs = 0;
};

// The three arrays live in pairBuff, each sorted by key. A kept pair carries this frame's
// flags and the previous frame's contact id; a new pair's contact id is for the caller to
// set (pfxSetContactId).
struct PfxDecomposePairsResult {
  PfxBroadphasePair* outNewPairs = nullptr;
  PfxUInt32 numOutNewPairs = 0;
  PfxBroadphasePair* outKeepPairs = nullptr;
  PfxUInt32 numOutKeepPairs = 0;
  PfxBroadphasePair* outRemovePairs = nullptr;
  PfxUInt32 numOutRemovePairs = 0;
};

PfxUInt32 pfxGetWorkBytesOfDecomposePairs(PfxUInt32 numPreviousPairs, PfxUInt32 numCurrentPairs);
PfxUInt32 pfxGetPairBytesOfDecomposePairs(PfxUInt32 numPreviousPairs, PfxUInt32 numCurrentPairs);

PfxInt32 pfxDecomposePairs(const PfxDecomposePairsParam& param, PfxDecomposePairsResult& result);

}  // namespace pfx
