#include "pfx/low_level/broadphase/pfx_decompose_pairs.h"

#include <tuple>

#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

// The merge walk relies on both arrays ascending; a repeated key would be matched twice.
bool isStrictlyAscending(const PfxBroadphasePair* pairs, PfxUInt32 numPairs) {
  for (PfxUInt32 i = 1; i < numPairs; ++i) {
    if (pairs[i].key <= pairs[i - 1].key) return false;
  }
  return true;
}

// Visits the two arrays in key order and hands every pair to one of the three callbacks.
template <class OnNew, class OnKeep, class OnRemove>
void mergeWalk(const PfxDecomposePairsParam& param, OnNew onNew, OnKeep onKeep,
               OnRemove onRemove) {
  PfxUInt32 p = 0;
  PfxUInt32 c = 0;
  while (p < param.numPreviousPairs && c < param.numCurrentPairs) {
    const PfxBroadphasePair& previous = param.previousPairs[p];
    const PfxBroadphasePair& current = param.currentPairs[c];
    if (previous.key < current.key) {
      onRemove(previous);
      ++p;
    } else if (current.key < previous.key) {
      onNew(current);
      ++c;
    } else {
      onKeep(previous, current);
      ++p;
      ++c;
    }
  }
  for (; p < param.numPreviousPairs; ++p) onRemove(param.previousPairs[p]);
  for (; c < param.numCurrentPairs; ++c) onNew(param.currentPairs[c]);
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfDecomposePairs(PfxUInt32 /*numPreviousPairs*/,
                                          PfxUInt32 /*numCurrentPairs*/) {
  // A merge walk of two sorted arrays needs no scratch; the parameter stays for callers
  // that follow the seed's sequence of calls.
  return 0;
}

// Layout: new pairs, then kept pairs (together exactly the current pairs, so the caller
// can sort them in place into next frame's array), then removed pairs.
PfxUInt32 pfxGetPairBytesOfDecomposePairs(PfxUInt32 numPreviousPairs, PfxUInt32 numCurrentPairs) {
  return static_cast<PfxUInt32>(
      pfxAlignBytes(sizeof(PfxBroadphasePair) * (PfxUInt64(numPreviousPairs) + numCurrentPairs)));
}

PfxInt32 pfxDecomposePairs(const PfxDecomposePairsParam& param, PfxDecomposePairsResult& result) {
  const PfxParamNames at{"pfxDecomposePairs", "PfxDecomposePairsParam"};
  const PfxUInt64 previousBytes = PfxUInt64(sizeof(PfxBroadphasePair)) * param.numPreviousPairs;
  const PfxUInt64 currentBytes = PfxUInt64(sizeof(PfxBroadphasePair)) * param.numCurrentPairs;
  const PfxUInt64 requiredBytes = previousBytes + currentBytes;
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at, {{param.previousPairs, "previousPairs"}}, "numPreviousPairs",
                              param.numPreviousPairs)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.currentPairs, "currentPairs"}}, "numCurrentPairs",
                              param.numCurrentPairs)) != PFX_OK ||
      (err = pfxCheckBuffer(at, "pairBuff", param.pairBuff, param.pairBytes, requiredBytes)) !=
          PFX_OK) {
    return err;
  }
  for (const auto& [pairs, bytes, field] :
       {std::tuple(param.previousPairs, previousBytes, "previousPairs"),
        std::tuple(param.currentPairs, currentBytes, "currentPairs")}) {
    if (pfxRangesOverlap(param.pairBuff, requiredBytes, pairs, bytes)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxDecomposePairs: PfxDecomposePairsParam::pairBuff shares bytes "
                            "with %s",
                            field);
    }
  }
  if (!isStrictlyAscending(param.previousPairs, param.numPreviousPairs)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxDecomposePairs: PfxDecomposePairsParam::previousPairs are not "
                          "sorted by key without repeats");
  }
  if (!isStrictlyAscending(param.currentPairs, param.numCurrentPairs)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxDecomposePairs: PfxDecomposePairsParam::currentPairs are not "
                          "sorted by key without repeats");
  }

  PfxUInt32 numNew = 0;
  PfxUInt32 numKeep = 0;
  PfxUInt32 numRemove = 0;
  mergeWalk(
      param, [&](const PfxBroadphasePair&) { ++numNew; },
      [&](const PfxBroadphasePair&, const PfxBroadphasePair&) { ++numKeep; },
      [&](const PfxBroadphasePair&) { ++numRemove; });

  PfxBroadphasePair* const base = static_cast<PfxBroadphasePair*>(param.pairBuff);
  PfxBroadphasePair* const newPairs = base;
  PfxBroadphasePair* const keepPairs = base + numNew;
  PfxBroadphasePair* const removePairs = base + param.numCurrentPairs;
  PfxUInt32 n = 0, k = 0, r = 0;
  mergeWalk(
      param, [&](const PfxBroadphasePair& current) { newPairs[n++] = current; },
      [&](const PfxBroadphasePair& previous, const PfxBroadphasePair& current) {
        // The motion types may have changed since last frame; the contact manifold and
        // its constraint count belong to the pair and carry over.
        PfxBroadphasePair& kept = keepPairs[k++];
        kept = current;
        pfxSetContactId(kept, pfxGetContactId(previous));
        pfxSetNumConstraints(kept, pfxGetNumConstraints(previous));
      },
      [&](const PfxBroadphasePair& previous) { removePairs[r++] = previous; });

  result.outNewPairs = newPairs;
  result.numOutNewPairs = numNew;
  result.outKeepPairs = keepPairs;
  result.numOutKeepPairs = numKeep;
  result.outRemovePairs = removePairs;
  result.numOutRemovePairs = numRemove;
  return PFX_OK;
}

}  // namespace pfx
