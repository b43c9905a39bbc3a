#include "pfx/low_level/broadphase/pfx_find_pairs.h"

#include <algorithm>

#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/low_level/sort/pfx_parallel_sort.h"
#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

// The sweep stops at the first proxy that starts past the current one's end, which is
// only right when the array is ordered by minimum along the sweep axis.
bool isSortedAlongAxis(const PfxBroadphaseProxy* proxies, PfxUInt32 numProxies, int axis) {
  for (PfxUInt32 i = 1; i < numProxies; ++i) {
    if (pfxGetXMin(proxies[i], axis) < pfxGetXMin(proxies[i - 1], axis)) return false;
  }
  return true;
}

// A proxy's intervals on the two axes other than the sweep axis, unpacked from the
// proxy's 16-bit fields (the current proxy's only once per sweep step).
struct CrossSection {
  PfxUInt16 min1, max1, min2, max2;
};

CrossSection crossSectionOf(const PfxBroadphaseProxy& p, int axis1, int axis2) {
  return {pfxGetXMin(p, axis1), pfxGetXMax(p, axis1), pfxGetXMin(p, axis2),
          pfxGetXMax(p, axis2)};
}

bool crossSectionsOverlap(const CrossSection& a, const CrossSection& b) {
  return a.min1 <= b.max1 && b.min1 <= a.max1 && a.min2 <= b.max2 && b.min2 <= a.max2;
}

// A sleeping body is woken by a moving neighbour, so a pair matters while at least one
// side is awake and that side is not a fixed body, which never wakes anything.
bool eitherSideCanMove(const PfxBroadphaseProxy& a, const PfxBroadphaseProxy& b) {
  const bool sleepA = pfxGetSleeping(a);
  const bool sleepB = pfxGetSleeping(b);
  if (sleepA && sleepB) return false;
  if (sleepA && pfxGetMotionType(b) == kPfxMotionTypeFixed) return false;
  if (sleepB && pfxGetMotionType(a) == kPfxMotionTypeFixed) return false;
  return true;
}

bool isPair(const PfxBroadphaseProxy& a, const PfxBroadphaseProxy& b) {
  return pfxMotionTypesCollide(pfxGetMotionType(a), pfxGetMotionType(b)) &&
         pfxContactFiltersMatch(pfxGetSelf(a), pfxGetTarget(a), pfxGetSelf(b), pfxGetTarget(b)) &&
         eitherSideCanMove(a, b);
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfFindPairs(PfxUInt32 maxPairs, PfxUInt32 /*maxTasks*/) {
  // The tasks share the work buffer: each collects its pairs in its own part of it before
  // they are copied out in order, and the sort then uses the whole buffer.
  return static_cast<PfxUInt32>(pfxAlignBytes(sizeof(PfxBroadphasePair) * maxPairs));
}

PfxUInt32 pfxGetPairBytesOfFindPairs(PfxUInt32 maxPairs) {
  return static_cast<PfxUInt32>(pfxAlignBytes(sizeof(PfxBroadphasePair) * maxPairs));
}

namespace {

// The sleeping proxies and the longest of their boxes along the sweep axis: a sleeping
// box that overlaps a box starting at `min` starts at `min - longest` or later.
struct SleepingProxies {
  const PfxBroadphaseProxy* proxies = nullptr;
  PfxUInt32 count = 0;
  PfxUInt16 longest = 0;
};

// Writes the pair to `out` while there is room; returns the count with it.
PfxUInt32 record(const PfxBroadphaseProxy& a, const PfxBroadphaseProxy& b,
                 PfxBroadphasePair* out, PfxUInt32 numFound, PfxUInt32 capacity) {
  if (numFound < capacity) {
    pfxInitializePair(out[numFound], pfxGetObjectId(a), pfxGetMotionType(a), pfxGetObjectId(b),
                      pfxGetMotionType(b));
  }
  return numFound + 1;
}

// Sweeps the proxies [begin, end) against those after them and against the sleeping ones;
// writes the first `capacity` pairs found to `out` and returns how many there are. The axis
// is a constant of each instance, so that the inner loop unpacks the proxies' 16-bit
// fields with fixed shifts.
template <int axis>
PfxUInt32 sweepAlong(const PfxBroadphaseProxy* proxies, PfxUInt32 numProxies,
                     const SleepingProxies& sleeping, PfxUInt32 begin, PfxUInt32 end,
                     PfxBroadphasePair* out, PfxUInt32 capacity) {
  PfxUInt32 numFound = 0;
  constexpr int axis1 = (axis + 1) % 3;
  constexpr int axis2 = (axis + 2) % 3;
  const auto startsBefore = [](const PfxBroadphaseProxy& p, PfxUInt16 value) {
    return pfxGetXMin(p, axis) < value;
  };
  for (PfxUInt32 i = begin; i < end; ++i) {
    const PfxBroadphaseProxy& a = proxies[i];
    const PfxUInt16 first = pfxGetXMin(a, axis);
    const PfxUInt16 last = pfxGetXMax(a, axis);
    const CrossSection sectionA = crossSectionOf(a, axis1, axis2);
    for (PfxUInt32 j = i + 1; j < numProxies && pfxGetXMin(proxies[j], axis) <= last; ++j) {
      const PfxBroadphaseProxy& b = proxies[j];
      if (crossSectionsOverlap(sectionA, crossSectionOf(b, axis1, axis2)) && isPair(a, b)) {
        numFound = record(a, b, out, numFound, capacity);
      }
    }
    // A fixed body wakes nothing, and a sleeping one nothing asleep.
    if (sleeping.count == 0 || pfxGetSleeping(a) ||
        pfxGetMotionType(a) == kPfxMotionTypeFixed) {
      continue;
    }
    const PfxUInt16 from = first > sleeping.longest ? PfxUInt16(first - sleeping.longest) : 0;
    for (const PfxBroadphaseProxy* b =
             std::lower_bound(sleeping.proxies, sleeping.proxies + sleeping.count, from,
                              startsBefore);
         b < sleeping.proxies + sleeping.count && pfxGetXMin(*b, axis) <= last; ++b) {
      if (pfxGetXMax(*b, axis) >= first &&
          crossSectionsOverlap(sectionA, crossSectionOf(*b, axis1, axis2)) && isPair(a, *b)) {
        numFound = record(a, *b, out, numFound, capacity);
      }
    }
  }
  return numFound;
}

PfxUInt32 sweep(const PfxBroadphaseProxy* proxies, PfxUInt32 numProxies,
                const SleepingProxies& sleeping, int axis, PfxUInt32 begin, PfxUInt32 end,
                PfxBroadphasePair* out, PfxUInt32 capacity) {
  switch (axis) {
    case 0: return sweepAlong<0>(proxies, numProxies, sleeping, begin, end, out, capacity);
    case 1: return sweepAlong<1>(proxies, numProxies, sleeping, begin, end, out, capacity);
    default: return sweepAlong<2>(proxies, numProxies, sleeping, begin, end, out, capacity);
  }
}

// Chunks of at least this many proxies are swept as separate tasks.
constexpr PfxUInt32 kMinProxiesPerChunk = 256;
constexpr PfxUInt32 kMaxChunks = 64;

// The sweep in chunks of proxies, each collecting its pairs in its share of the work
// buffer; the pairs are then laid out chunk after chunk, which is the order of the sweep
// over all proxies at once, up to maxPairs of them. A chunk that found more than its share
// sweeps again straight into its place. Returns the number of pairs found.
PfxUInt32 sweepInChunks(const PfxFindPairsParam& param, const SleepingProxies& sleeping,
                        PfxBroadphasePair* pairs, PfxUInt32 numChunks,
                        PfxTaskManager* taskManager) {
  PfxBroadphasePair* work = static_cast<PfxBroadphasePair*>(param.workBuff);
  const PfxUInt32 share = param.maxPairs / numChunks;
  auto chunkBegin = [&](PfxUInt32 c) { return pfxChunkBegin(param.numProxies, numChunks, c); };
  PfxUInt32 found[kMaxChunks];
  pfxParallelFor(taskManager, numChunks, 1, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 c = first; c < last; ++c) {
      found[c] = sweep(param.proxies, param.numProxies, sleeping, param.axis, chunkBegin(c),
                       chunkBegin(c + 1), work + std::size_t(c) * share, share);
    }
  });
  PfxUInt32 offsets[kMaxChunks];
  PfxUInt32 numFound = 0;
  for (PfxUInt32 c = 0; c < numChunks; ++c) {
    offsets[c] = numFound;
    numFound += found[c];
  }
  pfxParallelFor(taskManager, numChunks, 1, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 c = first; c < last; ++c) {
      if (offsets[c] >= param.maxPairs) continue;
      const PfxUInt32 room = std::min(found[c], param.maxPairs - offsets[c]);
      if (found[c] <= share) {
        const PfxBroadphasePair* collected = work + std::size_t(c) * share;
        std::copy(collected, collected + room, pairs + offsets[c]);
      } else {
        sweep(param.proxies, param.numProxies, sleeping, param.axis, chunkBegin(c),
              chunkBegin(c + 1), pairs + offsets[c], room);
      }
    }
  });
  return numFound;
}

}  // namespace

PfxInt32 pfxFindPairs(const PfxFindPairsParam& param, PfxFindPairsResult& result,
                      PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxFindPairs", "PfxFindPairsParam"};
  const int axis = param.axis;
  const PfxUInt64 pairBytes = PfxUInt64(sizeof(PfxBroadphasePair)) * param.maxPairs;
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckValue(at, "axis", axis, axis >= 0 && axis <= 2, "0, 1 or 2")) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.proxies, "proxies"}}, "numProxies",
                              param.numProxies)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.sleepingProxies, "sleepingProxies"}},
                              "numSleepingProxies", param.numSleepingProxies)) != PFX_OK ||
      (err = pfxCheckBuffer(at, "pairBuff", param.pairBuff, param.pairBytes, pairBytes)) !=
          PFX_OK ||
      (err = pfxCheckBuffer(at, "workBuff", param.workBuff, param.workBytes, pairBytes)) !=
          PFX_OK) {
    return err;
  }
  if (pfxRangesOverlap(param.pairBuff, pairBytes, param.workBuff, pairBytes)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxFindPairs: PfxFindPairsParam::pairBuff and workBuff share bytes");
  }
  const struct {
    const PfxBroadphaseProxy* proxies;
    PfxUInt32 count;
    const char* field;
  } proxyArrays[2] = {{param.proxies, param.numProxies, "proxies"},
                      {param.sleepingProxies, param.numSleepingProxies, "sleepingProxies"}};
  for (const auto& array : proxyArrays) {
    const PfxUInt64 bytes = PfxUInt64(sizeof(PfxBroadphaseProxy)) * array.count;
    if (pfxRangesOverlap(param.pairBuff, pairBytes, array.proxies, bytes) ||
        pfxRangesOverlap(param.workBuff, pairBytes, array.proxies, bytes)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxFindPairs: PfxFindPairsParam::%s share bytes with pairBuff or "
                            "workBuff",
                            array.field);
    }
    if (!isSortedAlongAxis(array.proxies, array.count, axis)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxFindPairs: PfxFindPairsParam::%s are not sorted along axis %d "
                            "(pfxParallelSort them after pfxUpdateBroadphaseProxy)",
                            array.field, axis);
    }
  }
  SleepingProxies sleeping;
  sleeping.proxies = param.sleepingProxies;
  sleeping.count = param.numSleepingProxies;
  for (PfxUInt32 i = 0; i < sleeping.count; ++i) {
    const PfxBroadphaseProxy& p = sleeping.proxies[i];
    if (!pfxGetSleeping(p)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxFindPairs: PfxFindPairsParam::sleepingProxies[%u] (body %u) is "
                            "not marked asleep",
                            i, pfxGetObjectId(p));
    }
    sleeping.longest = std::max<PfxUInt16>(
        sleeping.longest, PfxUInt16(pfxGetXMax(p, axis) - pfxGetXMin(p, axis)));
  }

  PfxBroadphasePair* pairs = static_cast<PfxBroadphasePair*>(param.pairBuff);
  const PfxUInt32 numChunks =
      pfxNumChunks(taskManager, param.numProxies, kMinProxiesPerChunk, kMaxChunks);
  const PfxUInt32 numFound =
      numChunks == 1 ? sweep(param.proxies, param.numProxies, sleeping, axis, 0,
                             param.numProxies, pairs, param.maxPairs)
                     : sweepInChunks(param, sleeping, pairs, numChunks, taskManager);

  const PfxUInt32 numStored = numFound < param.maxPairs ? numFound : param.maxPairs;
  pfxParallelSort(pairs, numStored, param.workBuff, param.workBytes, taskManager);
  result.pairs = pairs;
  result.numPairs = numStored;
  result.numPairsFound = numFound;
  return numFound > param.maxPairs ? PFX_ERR_OUT_OF_MAX_PAIRS : PFX_OK;
}

}  // namespace pfx
