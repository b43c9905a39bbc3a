// Stage: splits a group's distance and angle constraints into chains, and the chains into
// phases in which no two chains share a particle (a greedy graph colouring), run once when
// the constraints are set. pfxSolveParticleConstraints then solves a phase's chains in
// parallel, each chain's constraints one after another: the chains move different particles,
// so the result is the same bits whatever the thread count, as the seed's parallel solver
// does with its contact batches.
//
// A chain is a run of constraints listed one after another, each starting where the one
// before ended (a distance constraint's A is the previous one's B; an angle constraint's A
// and B are the previous one's B and C): a rope's links, a cloth's row, column or diagonal
// as PfxParticleGroupBuilder lists them. A chain of distance constraints is solved as one
// tridiagonal system, every link of it at once (pfx_solve_particle_constraints.cpp); one of
// angle constraints in sequence, which carries a correction from end to end in one pass,
// every other chain of a phase from its end, so that neighbouring chains carry their
// corrections opposite ways. A 128 x 128 cloth of rigid links draped over a sphere at 4
// sub-steps of one iteration ended 10.4 % stretched in phases of single links, 7.8 % in
// chains solved link after link, 0.34 % with each chain solved at once.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

// Phases beyond this many are not made: the chains that would need more share a particle
// with chains of every phase (a particle on more than this many chains) and are solved one
// by one after the phases.
constexpr PfxUInt32 PFX_MAX_PARTICLE_PHASES = 64;

// The solve order of one kind of constraint: constraint indices chain by chain, the chains
// phase by phase, each phase's chains in the order their constraints are listed.
struct PfxParticleConstraintBatches {
  PfxUInt32* order = nullptr;       // numConstraints entries, the caller's
  PfxUInt32* chainStart = nullptr;  // numConstraints + 1 entries, the caller's
  PfxUInt32 numConstraints = 0;
  PfxUInt32 numChains = 0;
  PfxUInt32 numPhases = 0;
  // Chain c is order[chainStart[c]] .. order[chainStart[c + 1] - 1]; phase k is chains
  // phaseStart[k] .. phaseStart[k + 1] - 1; the chains from phaseStart[numPhases] to
  // numChains are the ones left over, solved serially.
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
  // Filled: their order arrays must hold numDistanceConstraints and numAngleConstraints
  // entries, their chainStart arrays one more.
  PfxParticleConstraintBatches* distanceBatches = nullptr;
  PfxParticleConstraintBatches* angleBatches = nullptr;
};

PfxUInt32 pfxGetWorkBytesOfBatchParticleConstraints(PfxUInt32 numParticles,
                                                    PfxUInt32 numConstraints);

// Rejects null arrays with a count or null batches, orders or chain starts
// (PFX_ERR_NULL_POINTER), a work buffer that is too small (PFX_ERR_OUT_OF_BUFFER) or
// misaligned (PFX_ERR_INVALID_ALIGNMENT) and a constraint naming a particle beyond
// numParticles (PFX_ERR_OUT_OF_RANGE); the batches are untouched then. The same constraints give the same batches. Allocates nothing.
PfxInt32 pfxBatchParticleConstraints(const PfxBatchParticleConstraintsParam& param);

}  // namespace pfx
