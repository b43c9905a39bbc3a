// Stage (2b): pairs of bodies whose bounds overlap, by sort and sweep (seed chapter 4).
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxFindPairsParam {
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  void* pairBuff = nullptr;
  PfxUInt32 pairBytes = 0;
  const PfxBroadphaseProxy* proxies = nullptr;  // sorted by minimum along `axis`
  PfxUInt32 numProxies = 0;
  PfxUInt32 maxPairs = 0;
  int axis = 0;
  // Optional: proxies of sleeping bodies, also sorted by minimum along `axis`, paired with
  // `proxies` but not among themselves, so that a caller keeps them from the step the
  // bodies fell asleep until one wakes, with no update or sort in between. Each must have
  // its sleeping flag set; pairs of two sleeping bodies are the caller's to keep.
  const PfxBroadphaseProxy* sleepingProxies = nullptr;
  PfxUInt32 numSleepingProxies = 0;
};

struct PfxFindPairsResult {
  PfxBroadphasePair* pairs = nullptr;  // in pairBuff, sorted by pair key
  PfxUInt32 numPairs = 0;
  // All overlapping pairs, also those that did not fit: on PFX_ERR_OUT_OF_MAX_PAIRS, a
  // second call with maxPairs >= numPairsFound succeeds.
  PfxUInt32 numPairsFound = 0;
};

PfxUInt32 pfxGetWorkBytesOfFindPairs(PfxUInt32 maxPairs, PfxUInt32 maxTasks = 1);
PfxUInt32 pfxGetPairBytesOfFindPairs(PfxUInt32 maxPairs);

// A pair is reported when the boxes overlap on all three axes, the two motion types
// collide (seed chapter 10), the contact filters match, and not both bodies are asleep
// (or one asleep and the other fixed). The sleeping proxies are read only by the proxies of
// bodies that can move, each looking among those that start within its own box or at most
// the longest sleeping box before it. With a task manager the proxies are swept in chunks
// in parallel; the pairs come out the same.
PfxInt32 pfxFindPairs(const PfxFindPairsParam& param, PfxFindPairsResult& result,
                      PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
