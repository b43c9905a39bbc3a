// The registry of engines. A peer whose library CMake did not find is listed without a
// constructor, so that asking for it says why it is missing instead of failing silently.
#include "bench_engine.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfxbench {

const std::vector<EngineInfo>& knownEngines() {
  static const std::vector<EngineInfo> engines = {
      {"pfx", createPfxEngine, static_cast<int>(pfx::PFX_MAX_THREADS)},
#ifdef PFX_BENCH_HAVE_BULLET
      {"bullet", createBulletEngine, 1},
      {"bullet_multibody", createBulletMultiBodyEngine, 1},
#else
      {"bullet", nullptr, 0},
      {"bullet_multibody", nullptr, 0},
#endif
#ifdef PFX_BENCH_HAVE_ODE
      {"ode", createOdeEngine, 1},
#else
      {"ode", nullptr, 0},
#endif
#ifdef PFX_BENCH_HAVE_MUJOCO
      {"mujoco", createMujocoEngine, 1},
#else
      {"mujoco", nullptr, 0},
#endif
  };
  return engines;
}

}  // namespace pfxbench
