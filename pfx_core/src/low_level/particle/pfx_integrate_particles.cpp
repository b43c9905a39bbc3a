#include "pfx/low_level/particle/pfx_integrate_particles.h"

#include "low_level/particle/pfx_particle_checks.h"
#include "low_level/particle/pfx_particle_stages_checked.h"

namespace pfx {

namespace {
constexpr PfxUInt32 kIntegratedParticlesPerTask = 1024;
}  // namespace

PfxInt32 pfxIntegrateParticles(const PfxIntegrateParticlesParam& param,
                               PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxIntegrateParticles", "PfxIntegrateParticlesParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(at, "linearDamping", param.linearDamping,
                           param.linearDamping >= 0 && pfxIsFinite(param.linearDamping),
                           "zero or positive and finite")) != PFX_OK ||
      (err = pfxCheckParticles(at, param.particles, param.numParticles)) != PFX_OK) {
    return err;
  }
  if (!pfxIsFinite(param.gravity)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxIntegrateParticles: PfxIntegrateParticlesParam::gravity is not "
                          "finite");
  }
  return pfxIntegrateCheckedParticles(param, taskManager);
}

PfxInt32 pfxIntegrateCheckedParticles(const PfxIntegrateParticlesParam& param,
                                      PfxTaskManager* taskManager) {
  const PfxFloat h = param.timeStep;
  const PfxFloat keep = 1 / (1 + param.linearDamping * h);
  return pfxParallelFor(taskManager, param.numParticles, kIntegratedParticlesPerTask,
                        [&](PfxUInt32 begin, PfxUInt32 end) {
                          for (PfxUInt32 i = begin; i < end; ++i) {
                            PfxParticle& p = param.particles[i];
                            p.m_previousPosition = p.m_position;
                            if (p.m_massInv == 0) {
                              p.m_velocity.setZero();
                              continue;
                            }
                            p.m_velocity = p.m_velocity * keep + param.gravity * h;
                            p.m_position += p.m_velocity * h;
                          }
                        });
}

}  // namespace pfx
