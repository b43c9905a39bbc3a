#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

bool pfxIsValidParticle(const PfxParticle& particle) {
  return pfxIsFinite(particle.m_position) && pfxIsFinite(particle.m_previousPosition) &&
         pfxIsFinite(particle.m_velocity) && pfxIsFinite(particle.m_massInv) &&
         particle.m_massInv >= 0 && pfxIsFinite(particle.m_radius) && particle.m_radius > 0 &&
         pfxIsFinite(particle.m_friction) && particle.m_friction >= 0;
}

}  // namespace pfx
