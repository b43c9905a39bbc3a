#include "pfx/base_level/task/pfx_tbb_task_manager.h"

#include <algorithm>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

// ThreadSanitizer sees only what instrumented code does, and the system's oneTBB is not
// instrumented: the hand-over of a piece to a worker and the join at the end happen inside
// it, unseen, so every read of the caller's data in a task looked like a race. These calls
// state exactly what TBB guarantees, no more: a piece starts after the call that launched
// it, and the call returns after every piece ends. Pieces are not ordered among themselves,
// so a race between two of them is still reported.
// GCC says it builds with ThreadSanitizer by __SANITIZE_THREAD__, clang only through
// __has_feature: without the second, clang's build reported such a race in castRays.
#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PFX_THREAD_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_THREAD__) || defined(PFX_THREAD_SANITIZER)
extern "C" void __tsan_acquire(void* address);
extern "C" void __tsan_release(void* address);
#define PFX_TSAN_ACQUIRE(address) __tsan_acquire(address)
#define PFX_TSAN_RELEASE(address) __tsan_release(address)
#else
#define PFX_TSAN_ACQUIRE(address) static_cast<void>(address)
#define PFX_TSAN_RELEASE(address) static_cast<void>(address)
#endif

namespace pfx {

struct PfxTbbTaskManager::Arena {
  // At most one thread per core the process may use: the solver's sweeps hand chunks out in
  // order and a chunk waits for the chunks before it that move its bodies, so a thread that
  // holds one and has no core stalls every other. With 4 threads on 2 cores the rain of
  // pfx_bench (4,000 bodies) took 4 to 5 times as long per step as on one thread, in millions
  // of yields. The work is still split for the thread count asked for (getNumThreads), and
  // the results never depend on either.
  explicit Arena(int concurrency)
      : arena(std::min(concurrency, oneapi::tbb::info::default_concurrency())) {}
  oneapi::tbb::task_arena arena;
};

PfxTbbTaskManager::PfxTbbTaskManager() = default;
PfxTbbTaskManager::~PfxTbbTaskManager() = default;

PfxInt32 PfxTbbTaskManager::initialize(PfxUInt32 numThreads) {
  if (numThreads > PFX_MAX_THREADS) return PFX_ERR_OUT_OF_RANGE;
  if (numThreads == 0) {
    const int available = oneapi::tbb::info::default_concurrency();
    numThreads = available < 1 ? 1
                 : PfxUInt32(available) > PFX_MAX_THREADS ? PFX_MAX_THREADS
                                                          : PfxUInt32(available);
  }
  if (numThreads == m_numThreads) return PFX_OK;
  m_arena.reset(numThreads > 1 ? new Arena(static_cast<int>(numThreads)) : nullptr);
  m_numThreads = numThreads;
  return PFX_OK;
}

PfxInt32 PfxTbbTaskManager::parallelFor(PfxUInt32 count, PfxUInt32 grainSize,
                                        PfxTaskFunction task, void* context) {
  if (grainSize == 0) return PFX_ERR_INVALID_VALUE;
  if (count == 0) return PFX_OK;
  if (!task) return PFX_ERR_NULL_POINTER;
  // Pieces of at least grainSize items; TBB then hands out runs of consecutive pieces.
  const PfxUInt32 numPieces = count / grainSize > 0 ? count / grainSize : 1;
  if (!m_arena || numPieces == 1) {
    task(context, 0, count);
    return PFX_OK;
  }
  // Two distinct addresses, so that the pieces' ends never order the pieces' starts.
  char launched = 0, finished = 0;
  PFX_TSAN_RELEASE(&launched);
  m_arena->arena.execute([&] {
    oneapi::tbb::parallel_for(
        oneapi::tbb::blocked_range<PfxUInt32>(0, numPieces),
        [&](const oneapi::tbb::blocked_range<PfxUInt32>& pieces) {
          PFX_TSAN_ACQUIRE(&launched);
          task(context, pfxChunkBegin(count, numPieces, pieces.begin()),
               pfxChunkBegin(count, numPieces, pieces.end()));
          PFX_TSAN_RELEASE(&finished);
        });
  });
  PFX_TSAN_ACQUIRE(&finished);
  return PFX_OK;
}

}  // namespace pfx
