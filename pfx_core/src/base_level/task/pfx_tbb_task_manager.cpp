#include "pfx/base_level/task/pfx_tbb_task_manager.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

namespace pfx {

struct PfxTbbTaskManager::Arena {
  // oneTBB keeps one worker per core in the whole process unless told otherwise; more
  // threads than cores are asked for deliberately (to check that results do not depend on
  // them), so the limit is raised while this manager lives.
  explicit Arena(int concurrency)
      : workerLimit(concurrency > oneapi::tbb::info::default_concurrency()
                        ? new oneapi::tbb::global_control(
                              oneapi::tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(concurrency))
                        : nullptr),
        arena(concurrency) {}
  std::unique_ptr<oneapi::tbb::global_control> workerLimit;
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
  m_arena->arena.execute([&] {
    oneapi::tbb::parallel_for(
        oneapi::tbb::blocked_range<PfxUInt32>(0, numPieces),
        [&](const oneapi::tbb::blocked_range<PfxUInt32>& pieces) {
          task(context, pfxChunkBegin(count, numPieces, pieces.begin()),
               pfxChunkBegin(count, numPieces, pieces.end()));
        });
  });
  return PFX_OK;
}

}  // namespace pfx
