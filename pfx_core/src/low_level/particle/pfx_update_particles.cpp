#include "pfx/low_level/particle/pfx_update_particles.h"

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {
constexpr PfxUInt32 kParticlesPerTask = 1024;
}  // namespace

PfxInt32 pfxUpdateParticles(const PfxUpdateParticlesParam& param, PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxUpdateParticles", "PfxUpdateParticlesParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.particles, "particles"}}, "numParticles",
                              param.numParticles)) != PFX_OK) {
    return err;
  }
  const PfxFloat inverseStep = 1 / param.timeStep;
  return pfxParallelFor(taskManager, param.numParticles, kParticlesPerTask,
                        [&](PfxUInt32 begin, PfxUInt32 end) {
                          for (PfxUInt32 i = begin; i < end; ++i) {
                            PfxParticle& p = param.particles[i];
                            p.m_velocity = (p.m_position - p.m_previousPosition) * inverseStep;
                          }
                        });
}

}  // namespace pfx
