// Batches of constraint pairs in which no moving body appears twice, so that the pairs of a
// batch can be solved at the same time.
//
// Pairs are given batches greedily in pair order: each takes the first batch after every
// batch that one of its moving bodies is in already. Every body therefore meets its
// constraints in pair order, exactly as in a sweep over the pairs one by one, and since a
// pair reads and writes only its own two bodies, solving batch after batch gives the very
// bits of that serial sweep, on any number of threads. (Bodies that impulses do not move,
// with zero inverse mass: fixed, keyframe, asleep, may appear in every batch; the solver
// only reads them.) Colouring each pair with the first batch free of its bodies would make
// fewer batches, but changes the order: measured on a 30-box tower, the top drifted
// 0.099 m in 5 s instead of 0.0045 m, since a stack solved in alternating batches passes
// its weight on one box per sweep.
//
// Sweeps run as one parallel loop: the threads take chunks of pairs in batch order (sweep
// after sweep) from a shared counter, and before a pair is solved, the chunks that hold the
// pairs before it on its two bodies must be done. Waiting for those alone, and not for
// whole batches, lets a thread go on past a batch that another is still finishing. A
// thread only ever waits for chunks taken before its own, by threads that are running
// them, so the loop finishes however few threads the task manager really runs; and several
// sweeps in one loop keep the threads busy instead of starting them again for each.
#pragma once

#include <atomic>
#include <new>
#include <thread>

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

class PfxConstraintBatches {
 public:
  static std::size_t getWorkBytes(PfxUInt32 numPairs);

  // Sorts the pairs for which include(pairIndex) holds into batches; include() runs in
  // parallel with a task manager. A pair counts as acting on bodies actingOn(idA) and
  // actingOn(idB) (a body id, for work that reaches beyond the pair's own two bodies).
  // `bodyScratch` holds one word per body, and may be shared between builds. False when
  // the work buffer is too small.
  template <typename Include, typename ActingOn>
  bool build(void* workBuff, std::size_t workBytes, PfxUInt32* bodyScratch,
             const PfxConstraintPair* pairs, PfxUInt32 numPairs,
             const PfxSolverBody* solverBodies, PfxUInt32 numRigidBodies,
             const Include& include, const ActingOn& actingOn, PfxTaskManager* taskManager);

  // Calls work(sweep, pair, pairIndex) for every pair, batch after batch, for sweep = 0 to
  // numSweeps - 1 in turn; the pairs of a batch run in parallel with a task manager. The
  // pairs are copies laid out batch after batch, so that a sweep reads them in one stream.
  // Built for one thread, or with batches too narrow for the threads to share
  // (kMinChunksPerThreadInABatch), the pairs stay in pair order instead, which gives the
  // same bits (see above) and visits the bodies in the order the broad phase found their
  // pairs: on 4,000 bodies, batch order reaches a new body, far from the last, at nearly
  // every pair.
  template <typename Work>
  void sweep(PfxTaskManager* taskManager, PfxUInt32 numSweeps, const Work& work) const;

  PfxUInt32 getNumBatches() const { return m_numBatches; }  // 0 when swept in pair order

 private:
  static constexpr PfxUInt32 kExcluded = 0xffffffffu;
  static constexpr PfxUInt32 kStill = 0xffffffffu;  // a body that impulses do not move
  // What a pair waits for on one body: nothing, or the chunk holding the body's pair
  // before it in this sweep, or (flagged) its last pair of the sweep before.
  static constexpr PfxUInt32 kNoWait = 0xffffffffu;
  static constexpr PfxUInt32 kSweepBefore = 0x80000000u;
  static constexpr PfxUInt32 kNoPairYet = 0xfffffffeu;  // a moving body's word, at first
  // Pairs per chunk of a sweep: a contact pair takes about a microsecond.
  static constexpr PfxUInt32 kPairsPerChunk = 8;
  // Batches narrower than this many chunks per thread, on average, are swept on the calling
  // thread, in pair order: the threads would spend the sweep waiting for each other's
  // chunks and passing the bodies' cache lines back and forth. On two threads the 210-box
  // pyramid (4 pairs a batch) stepped in 2.7 ms against 2.0 ms on one, the piled ragdolls'
  // joints and contacts (8 and 6) and the robots' joints (54) were slower too, while the
  // rain's 4,000 bodies (120 pairs a batch) gained.
  static constexpr PfxUInt32 kMinChunksPerThreadInABatch = 4;
  // Spins on a chunk that is not done yet before giving the core to another thread.
  static constexpr int kSpinsBeforeYield = 256;

  template <typename Work>
  void runChunk(PfxUInt32 sweep, PfxUInt32 chunk, const Work& work) const;

  PfxConstraintPair* m_pairs = nullptr;  // batch after batch
  PfxUInt32* m_order = nullptr;          // their indices in the caller's array
  PfxUInt32* m_waitA = nullptr;          // what each waits for on its bodies
  PfxUInt32* m_waitB = nullptr;
  PfxUInt32 m_numPairs = 0;
  PfxUInt32 m_numBatches = 0;
  // Chunk c holds m_pairs[m_chunkBegin[c], m_chunkBegin[c + 1]); m_chunkDone[c] counts
  // the sweeps it has finished in the running loop.
  PfxUInt32* m_chunkBegin = nullptr;
  std::atomic<PfxUInt32>* m_chunkDone = nullptr;
  PfxUInt32 m_numChunks = 0;
  bool m_serial = false;  // pairs in pair order, swept one by one on the calling thread
};

// --- implementation ---

inline std::size_t PfxConstraintBatches::getWorkBytes(PfxUInt32 numPairs) {
  // Per pair: its copy, its index, its batch, its two waits, and at most one batch start,
  // one chunk start and one chunk's count; then the closing entries and alignment slack.
  return (sizeof(PfxConstraintPair) + 7 * sizeof(PfxUInt32) +
          sizeof(std::atomic<PfxUInt32>)) * std::size_t(numPairs) +
         2 * sizeof(PfxUInt32) + alignof(PfxConstraintPair) + alignof(std::atomic<PfxUInt32>);
}

template <typename Include, typename ActingOn>
bool PfxConstraintBatches::build(void* workBuff, std::size_t workBytes, PfxUInt32* bodyScratch,
                                 const PfxConstraintPair* pairs, PfxUInt32 numPairs,
                                 const PfxSolverBody* solverBodies, PfxUInt32 numRigidBodies,
                                 const Include& include, const ActingOn& actingOn,
                                 PfxTaskManager* taskManager) {
  m_numPairs = m_numBatches = m_numChunks = 0;
  if (numPairs == 0) return true;
  if (!workBuff || workBytes < getWorkBytes(numPairs) || !bodyScratch) return false;
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(workBuff);
  m_pairs = reinterpret_cast<PfxConstraintPair*>(
      (at + alignof(PfxConstraintPair) - 1) & ~std::uintptr_t(alignof(PfxConstraintPair) - 1));
  m_order = reinterpret_cast<PfxUInt32*>(m_pairs + numPairs);
  m_waitA = m_order + numPairs;
  m_waitB = m_waitA + numPairs;
  PfxUInt32* batchOf = m_waitB + numPairs;
  PfxUInt32* batchStart = batchOf + numPairs;  // numBatches + 1 entries
  m_chunkBegin = batchStart + numPairs + 1;    // numChunks + 1 entries
  const std::uintptr_t done = reinterpret_cast<std::uintptr_t>(m_chunkBegin + numPairs + 1);
  constexpr std::uintptr_t kDoneAlign = alignof(std::atomic<PfxUInt32>);
  m_chunkDone = reinterpret_cast<std::atomic<PfxUInt32>*>((done + kDoneAlign - 1) & ~(kDoneAlign - 1));

  // What can be found pair by pair and body by body is found in parallel first, so that
  // the batching, which goes in pair order, reads only these words.
  constexpr PfxUInt32 kItemsPerTask = 1024;
  pfxParallelFor(taskManager, numPairs, kItemsPerTask, [&](PfxUInt32 begin, PfxUInt32 end) {
    for (PfxUInt32 i = begin; i < end; ++i) batchOf[i] = include(i) ? 0 : kExcluded;
  });
  auto layOutInPairOrder = [&] {
    m_serial = true;
    m_numBatches = 0;
    PfxUInt32 k = 0;
    for (PfxUInt32 i = 0; i < numPairs; ++i) {
      if (batchOf[i] == kExcluded) continue;
      m_pairs[k] = pairs[i];
      m_order[k++] = i;
    }
    m_numPairs = k;
    return true;
  };
  const PfxUInt32 numThreads = taskManager ? taskManager->getNumThreads() : 1;
  if (numThreads < 2) return layOutInPairOrder();
  m_serial = false;
  auto resetBodies = [&](PfxUInt32 moving) {
    pfxParallelFor(taskManager, numRigidBodies, kItemsPerTask, [&](PfxUInt32 begin, PfxUInt32 end) {
      for (PfxUInt32 b = begin; b < end; ++b) {
        bodyScratch[b] = solverBodies[b].m_massInv > 0 ? moving : kStill;
      }
    });
  };
  // Each moving body's word holds the first batch it is not in yet.
  resetBodies(0);
  PfxUInt32 numIncluded = 0;
  for (PfxUInt32 i = 0; i < numPairs; ++i) {
    if (batchOf[i] == kExcluded) continue;
    ++numIncluded;
    PfxUInt32& nextA = bodyScratch[actingOn(pfxGetObjectIdA(pairs[i]))];
    PfxUInt32& nextB = bodyScratch[actingOn(pfxGetObjectIdB(pairs[i]))];
    const PfxUInt32 fromA = nextA == kStill ? 0 : nextA;
    const PfxUInt32 fromB = nextB == kStill ? 0 : nextB;
    const PfxUInt32 batch = fromA > fromB ? fromA : fromB;
    // Both may be the same word (two bodies of one tree).
    if (nextA != kStill) nextA = batch + 1;
    if (nextB != kStill) nextB = batch + 1;
    batchOf[i] = batch;
    if (batch + 1 > m_numBatches) m_numBatches = batch + 1;
  }
  if (numIncluded < PfxUInt64(kMinChunksPerThreadInABatch) * kPairsPerChunk * numThreads *
                        m_numBatches) {
    return layOutInPairOrder();
  }

  // A counting sort by batch, keeping pair order within each.
  for (PfxUInt32 b = 0; b <= m_numBatches; ++b) batchStart[b] = 0;
  for (PfxUInt32 i = 0; i < numPairs; ++i) {
    if (batchOf[i] != kExcluded) ++batchStart[batchOf[i] + 1];
  }
  for (PfxUInt32 b = 0; b < m_numBatches; ++b) batchStart[b + 1] += batchStart[b];
  m_numPairs = batchStart[m_numBatches];
  // Chunks, each within one batch.
  for (PfxUInt32 b = 0; b < m_numBatches; ++b) {
    for (PfxUInt32 k = batchStart[b]; k < batchStart[b + 1]; k += kPairsPerChunk) {
      m_chunkBegin[m_numChunks++] = k;
    }
  }
  m_chunkBegin[m_numChunks] = m_numPairs;
  for (PfxUInt32 i = 0; i < numPairs; ++i) {
    if (batchOf[i] == kExcluded) continue;
    const PfxUInt32 k = batchStart[batchOf[i]]++;
    m_pairs[k] = pairs[i];
    m_order[k] = i;
  }

  // What each pair waits for: each moving body's word now holds the chunk of its last pair
  // so far; a body's first pair waits for its last one of the sweep before. A pair acting
  // twice on one word (two bodies of one tree) waits for it once.
  resetBodies(kNoPairYet);
  auto bodyWords = [&](PfxUInt32 k, PfxUInt32*& wordA, PfxUInt32*& wordB) {
    const PfxUInt32 a = actingOn(pfxGetObjectIdA(m_pairs[k]));
    const PfxUInt32 b = actingOn(pfxGetObjectIdB(m_pairs[k]));
    wordA = &bodyScratch[a];
    wordB = b == a ? nullptr : &bodyScratch[b];
  };
  for (PfxUInt32 c = 0; c < m_numChunks; ++c) {
    for (PfxUInt32 k = m_chunkBegin[c]; k < m_chunkBegin[c + 1]; ++k) {
      PfxUInt32 *wordA, *wordB;
      bodyWords(k, wordA, wordB);
      m_waitA[k] = *wordA == kStill || *wordA == kNoPairYet ? kNoWait : *wordA;
      m_waitB[k] = !wordB || *wordB == kStill || *wordB == kNoPairYet ? kNoWait : *wordB;
      if (*wordA != kStill) *wordA = c;
      if (wordB && *wordB != kStill) *wordB = c;
    }
  }
  for (PfxUInt32 k = 0; k < m_numPairs; ++k) {
    PfxUInt32 *wordA, *wordB;
    bodyWords(k, wordA, wordB);
    for (PfxUInt32* word : {wordA, wordB}) {
      PfxUInt32& wait = word == wordA ? m_waitA[k] : m_waitB[k];
      if (!word || *word == kStill) {
        wait = kNoWait;
      } else if (wait == kNoWait) {
        wait = kSweepBefore | *word;
      }
    }
  }
  for (PfxUInt32 c = 0; c < m_numChunks; ++c) new (&m_chunkDone[c]) std::atomic<PfxUInt32>(0);
  return true;
}

template <typename Work>
void PfxConstraintBatches::runChunk(PfxUInt32 sweep, PfxUInt32 chunk, const Work& work) const {
  // Done `needed` sweeps: the wait's chunk in this sweep, or in the sweep before.
  auto waitFor = [&](PfxUInt32 wait) {
    if (wait == kNoWait) return;
    const PfxUInt32 needed = (wait & kSweepBefore) ? sweep : sweep + 1;
    const std::atomic<PfxUInt32>& done = m_chunkDone[wait & ~kSweepBefore];
    for (int spins = 0; done.load(std::memory_order_acquire) < needed;) {
      if (++spins >= kSpinsBeforeYield) {
        std::this_thread::yield();
        spins = 0;
      }
    }
  };
  for (PfxUInt32 k = m_chunkBegin[chunk]; k < m_chunkBegin[chunk + 1]; ++k) {
    waitFor(m_waitA[k]);
    waitFor(m_waitB[k]);
    work(sweep, m_pairs[k], m_order[k]);
  }
  // Kept from going back: a chunk whose pairs move nothing waits for nobody, and may finish
  // a sweep before it finished the one before.
  std::atomic<PfxUInt32>& done = m_chunkDone[chunk];
  PfxUInt32 seen = done.load(std::memory_order_relaxed);
  while (seen < sweep + 1 &&
         !done.compare_exchange_weak(seen, sweep + 1, std::memory_order_release,
                                     std::memory_order_relaxed)) {
  }
}

template <typename Work>
void PfxConstraintBatches::sweep(PfxTaskManager* taskManager, PfxUInt32 numSweeps,
                                 const Work& work) const {
  const PfxUInt32 numThreads = taskManager ? taskManager->getNumThreads() : 1;
  if (m_serial || numThreads < 2 || m_numChunks < 2) {
    for (PfxUInt32 s = 0; s < numSweeps; ++s) {
      for (PfxUInt32 k = 0; k < m_numPairs; ++k) work(s, m_pairs[k], m_order[k]);
    }
    return;
  }
  for (PfxUInt32 c = 0; c < m_numChunks; ++c) m_chunkDone[c].store(0, std::memory_order_relaxed);
  // Chunk g is chunk g % m_numChunks of sweep g / m_numChunks.
  const PfxUInt64 numChunks = PfxUInt64(m_numChunks) * numSweeps;
  std::atomic<PfxUInt64> nextChunk{0};
  pfxParallelFor(taskManager, numThreads, 1, [&](PfxUInt32, PfxUInt32) {
    for (;;) {
      const PfxUInt64 g = nextChunk.fetch_add(1, std::memory_order_relaxed);
      if (g >= numChunks) return;
      runChunk(static_cast<PfxUInt32>(g / m_numChunks), static_cast<PfxUInt32>(g % m_numChunks),
               work);
    }
  });
}

}  // namespace pfx
