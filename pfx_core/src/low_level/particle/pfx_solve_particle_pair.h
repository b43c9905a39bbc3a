// One contact between two particles: solved on positions, then its velocities updated. Shared
// by the contacts within a group and those between two groups.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

// Pushed apart along the line between their centres by inverse mass, their sliding undone as
// far as friction allows.
void pfxSolveParticlePairContact(PfxParticleContact& contact, PfxParticle& a, PfxParticle& b);

// After the step's positions: the two particles' velocity apart along the line between their
// centres removed, shared by inverse mass, so that a contact that pushed does not bounce.
void pfxRemoveParticlePairSeparation(PfxParticle& a, PfxParticle& b);

}  // namespace pfx
