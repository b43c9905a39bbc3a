#include "low_level/particle/pfx_particle_checks.h"

namespace pfx {

PfxInt32 pfxCheckParticles(const PfxParamNames& at, const PfxParticle* particles,
                           PfxUInt32 numParticles) {
  if (const PfxInt32 err = pfxCheckRequired(at, {{particles, "particles"}}, "numParticles",
                                            numParticles);
      err != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < numParticles; ++i) {
    const PfxParticle& p = particles[i];
    if (pfxIsValidParticle(p)) continue;
    const char* what = !pfxIsFinite(p.m_position)           ? "position is not finite"
                       : !pfxIsFinite(p.m_previousPosition) ? "previous position is not finite"
                       : !pfxIsFinite(p.m_velocity)         ? "velocity is not finite"
                       : !(p.m_massInv >= 0) || !pfxIsFinite(p.m_massInv)
                           ? "inverse mass is negative or not finite"
                       : !(p.m_radius > 0) || !pfxIsFinite(p.m_radius)
                           ? "radius is not positive and finite"
                           : "friction is negative or not finite";
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "%s: %s::particles[%u]: %s (mass inverse %g, radius %g, friction %g)",
                          at.stage, at.param, i, what, double(p.m_massInv), double(p.m_radius),
                          double(p.m_friction));
  }
  return PFX_OK;
}

}  // namespace pfx
