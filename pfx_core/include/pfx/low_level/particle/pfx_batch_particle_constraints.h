// Stage: splits a group's distance and angle constraints into phases in which no two
// constraints share a particle (a greedy graph colouring), run once when the constraints
// are set. pfxSolveParticleConstraints then solves a phase's constraints in parallel: they
// move different particles, so the result is the same bits whatever the thread count, as
// the seed's parallel solver does with its contact batches.
//
// The order matters beyond speed. Solved one after another in the order a builder lists
// them (each particle's links, row after row), one Gauss-Seidel sweep carries a correction
// along a whole row of a cloth in a single pass; where a cloth lands, the corrections pile
// up at the far end of the sweep and become velocity, and at one iteration per sub-step a
// cloth of rigid links gains energy until it overflows. In phases a correction travels at
// most one link per phase, alike in every direction.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

// Phases beyond this many are not made: the constraints that would need more share a
// particle with constraints of every phase (a particle with more than this many links) and
// are solved one by one after the phases.
constexpr PfxUInt32 PFX_MAX_PARTICLE_PHASES = 64;

// The solve order of one kind of constraint: constraint indices phase by phase, each phase in
// increasing index order.
struct PfxParticleConstraintBatches {
  PfxUInt32* order = nullptr;  // numConstraints entries, the caller's
  PfxUInt32 numConstraints = 0;
  PfxUInt32 numPhases = 0;
  // Phase k is order[phaseStart[k]] .. order[phaseStart[k + 1] - 1]; those from
  // phaseStart[numPhases] to numConstraints are the ones left over, solved serially.
  PfxUInt32 phaseStart[PFX_MAX_PARTICLE_PHASES + 1] = {};
};

struct PfxBatchParticleConstraintsParam {
  // Scratch of pfxGetWorkBytesOfBatchParticleConstraints(numParticles, the larger of the two
  // constraint counts) bytes, 16-byte aligned.
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  PfxUInt32 numParticles = 0;
  const PfxParticleDistanceConstraint* distanceConstraints = nullptr;
  PfxUInt32 numDistanceConstraints = 0;
  const PfxParticleAngleConstraint* angleConstraints = nullptr;
  PfxUInt32 numAngleConstraints = 0;
  // Filled: their order arrays must hold numDistanceConstraints and numAngleConstraints.
  PfxParticleConstraintBatches* distanceBatches = nullptr;
  PfxParticleConstraintBatches* angleBatches = nullptr;
};

PfxUInt32 pfxGetWorkBytesOfBatchParticleConstraints(PfxUInt32 numParticles,
                                                    PfxUInt32 numConstraints);

// Rejects null arrays with a count or null batches (PFX_ERR_NULL_POINTER), a work buffer
// that is too small (PFX_ERR_OUT_OF_BUFFER) or misaligned (PFX_ERR_INVALID_ALIGNMENT) and a
// constraint naming a particle beyond numParticles (PFX_ERR_OUT_OF_RANGE); the batches are
// untouched then. The same constraints give the same batches. Allocates nothing.
PfxInt32 pfxBatchParticleConstraints(const PfxBatchParticleConstraintsParam& param);

}  // namespace pfx
