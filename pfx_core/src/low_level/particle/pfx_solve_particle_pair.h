// One contact between two particles solved on positions: pushed apart along the line between
// their centres by inverse mass, their sliding undone as far as friction allows. Shared by
// the contacts within a group and those between two groups.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

void pfxSolveParticlePairContact(PfxParticleContact& contact, PfxParticle& a, PfxParticle& b);

}  // namespace pfx
