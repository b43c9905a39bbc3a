// The sub-step stages less their checks, for PfxWorld: it checks a group's constraints when
// the group is added or loaded and its particles once per step (pfxDetectParticleContacts),
// and the checks of every particle and constraint in each sub-step cost a fifth of a
// cloth's step. Each runs exactly as its public stage does after the checks pass.
#pragma once

#include "pfx/low_level/particle/pfx_integrate_particles.h"
#include "pfx/low_level/particle/pfx_solve_particle_constraints.h"

namespace pfx {

PfxInt32 pfxIntegrateCheckedParticles(const PfxIntegrateParticlesParam& param,
                                      PfxTaskManager* taskManager);

PfxInt32 pfxSolveCheckedParticleConstraints(const PfxSolveParticleConstraintsParam& param,
                                            PfxTaskManager* taskManager);

}  // namespace pfx
