// The task manager the world runs its stages on: a oneTBB task arena of a fixed number of
// threads. oneTBB (Debian's libtbb-dev) was chosen over OpenMP because an arena is an
// object: each world keeps its own thread count without touching process-wide settings,
// a parallel-for called from inside a task (the caller's own, or another stage's) shares
// the threads instead of oversubscribing them, and work stealing balances items of very
// uneven cost (a box-box pair costs many times a sphere-sphere pair).
#pragma once

#include <memory>

#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

class PfxTbbTaskManager final : public PfxTaskManager {
 public:
  PfxTbbTaskManager();  // one thread: every parallel-for runs on the calling thread
  ~PfxTbbTaskManager() override;
  PfxTbbTaskManager(const PfxTbbTaskManager&) = delete;
  PfxTbbTaskManager& operator=(const PfxTbbTaskManager&) = delete;

  // Runs later parallel-fors on numThreads threads, the calling thread included; 0 takes
  // as many as the process may use (its CPU affinity). PFX_ERR_OUT_OF_RANGE above
  // PFX_MAX_THREADS, with the manager unchanged. Must not be called while a parallel-for
  // of this manager runs. The threads start on the first parallel-for. More threads than
  // the process has cores split the work as asked but run on one thread per core: more
  // would only wait for each other.
  PfxInt32 initialize(PfxUInt32 numThreads);

  PfxUInt32 getNumThreads() const override { return m_numThreads; }
  PfxInt32 parallelFor(PfxUInt32 count, PfxUInt32 grainSize, PfxTaskFunction task,
                       void* context) override;

 private:
  struct Arena;
  std::unique_ptr<Arena> m_arena;  // null with one thread
  PfxUInt32 m_numThreads = 1;
};

}  // namespace pfx
