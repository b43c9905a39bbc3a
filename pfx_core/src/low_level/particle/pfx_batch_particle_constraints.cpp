#include "pfx/low_level/particle/pfx_batch_particle_constraints.h"

#include <algorithm>
#include <array>

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

const PfxParamNames kAt{"pfxBatchParticleConstraints", "PfxBatchParticleConstraintsParam"};
constexpr PfxUInt32 kLeftOver = PFX_MAX_PARTICLE_PHASES;

struct ConstraintBatchWork {
  PfxUInt64* phasesOfParticle;  // bit k: the particle is in a constraint of phase k
  PfxUInt8* phaseOfConstraint;
};

std::size_t constraintBatchWorkBytes(PfxUInt32 numParticles, PfxUInt32 numConstraints, ConstraintBatchWork* work, void* base) {
  const std::size_t particleBytes = pfxAlignBytes(sizeof(PfxUInt64) * numParticles);
  if (work) {
    work->phasesOfParticle = static_cast<PfxUInt64*>(base);
    work->phaseOfConstraint = static_cast<PfxUInt8*>(base) + particleBytes;
  }
  return particleBytes + pfxAlignBytes(numConstraints);
}

PfxUInt32 lowestFreePhase(PfxUInt64 taken) {
  PfxUInt32 phase = 0;
  while (phase < PFX_MAX_PARTICLE_PHASES && (taken & (PfxUInt64(1) << phase))) ++phase;
  return phase;
}

// Greedy colouring in constraint order: each constraint takes the lowest phase none of its
// particles is in yet. Then a stable counting sort by phase writes the order, so that a
// phase lists its constraints in index order (neighbours in memory stay neighbours).
template <std::size_t N, typename ParticlesOf>
void batch(PfxUInt32 numConstraints, const ParticlesOf& particlesOf, PfxUInt32 numParticles,
           const ConstraintBatchWork& work, PfxParticleConstraintBatches& batches) {
  std::fill(work.phasesOfParticle, work.phasesOfParticle + numParticles, PfxUInt64(0));
  std::array<PfxUInt32, PFX_MAX_PARTICLE_PHASES + 1> count{};
  for (PfxUInt32 i = 0; i < numConstraints; ++i) {
    const std::array<PfxUInt32, N> members = particlesOf(i);
    PfxUInt64 taken = 0;
    for (const PfxUInt32 p : members) taken |= work.phasesOfParticle[p];
    const PfxUInt32 phase = lowestFreePhase(taken);
    if (phase != kLeftOver) {
      for (const PfxUInt32 p : members) work.phasesOfParticle[p] |= PfxUInt64(1) << phase;
    }
    work.phaseOfConstraint[i] = static_cast<PfxUInt8>(phase);
    ++count[phase];
  }
  PfxUInt32 numPhases = 0;
  while (numPhases < PFX_MAX_PARTICLE_PHASES && count[numPhases] > 0) ++numPhases;
  batches.numConstraints = numConstraints;
  batches.numPhases = numPhases;
  // Phases are made lowest first, so the empty ones are all after numPhases and start
  // where the left-over ones do.
  std::array<PfxUInt32, PFX_MAX_PARTICLE_PHASES + 1> cursor{};
  PfxUInt32 start = 0;
  for (PfxUInt32 phase = 0; phase <= PFX_MAX_PARTICLE_PHASES; ++phase) {
    batches.phaseStart[phase] = start;
    cursor[phase] = start;
    start += count[phase];
  }
  for (PfxUInt32 i = 0; i < numConstraints; ++i) {
    batches.order[cursor[work.phaseOfConstraint[i]]++] = i;
  }
}

PfxInt32 checkParticle(const char* array, PfxUInt32 i, const char* field, PfxUInt32 index,
                       PfxUInt32 numParticles) {
  if (index < numParticles) return PFX_OK;
  return pfxRejectParam(PFX_ERR_OUT_OF_RANGE, "%s: %s::%s[%u].%s is %u, but numParticles is %u",
                        kAt.stage, kAt.param, array, i, field, index, numParticles);
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfBatchParticleConstraints(PfxUInt32 numParticles,
                                                    PfxUInt32 numConstraints) {
  return static_cast<PfxUInt32>(constraintBatchWorkBytes(numParticles, numConstraints, nullptr, nullptr));
}

PfxInt32 pfxBatchParticleConstraints(const PfxBatchParticleConstraintsParam& param) {
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(kAt, {{param.distanceConstraints, "distanceConstraints"}},
                              "numDistanceConstraints", param.numDistanceConstraints)) != PFX_OK ||
      (err = pfxCheckRequired(kAt, {{param.angleConstraints, "angleConstraints"}},
                              "numAngleConstraints", param.numAngleConstraints)) != PFX_OK) {
    return err;
  }
  if (!param.distanceBatches || !param.angleBatches ||
      (!param.distanceBatches->order && param.numDistanceConstraints > 0) ||
      (!param.angleBatches->order && param.numAngleConstraints > 0)) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER,
                          "%s: %s::distanceBatches or angleBatches, or its order, is null",
                          kAt.stage, kAt.param);
  }
  const PfxUInt32 numConstraints = std::max(param.numDistanceConstraints, param.numAngleConstraints);
  const PfxUInt32 needed = pfxGetWorkBytesOfBatchParticleConstraints(param.numParticles, numConstraints);
  if (!param.workBuff || param.workBytes < needed) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "%s: %s::workBytes is %u, but %u particles and %u constraints need %u "
                          "(pfxGetWorkBytesOfBatchParticleConstraints)",
                          kAt.stage, kAt.param, param.workBuff ? param.workBytes : 0u,
                          param.numParticles, numConstraints, needed);
  }
  if (!pfxIsAligned(param.workBuff)) {
    return pfxRejectParam(PFX_ERR_INVALID_ALIGNMENT, "%s: %s::workBuff is not 16-byte aligned",
                          kAt.stage, kAt.param);
  }
  const PfxUInt32 n = param.numParticles;
  for (PfxUInt32 i = 0; i < param.numDistanceConstraints; ++i) {
    const PfxParticleDistanceConstraint& c = param.distanceConstraints[i];
    if ((err = checkParticle("distanceConstraints", i, "particleA", c.m_particleA, n)) != PFX_OK ||
        (err = checkParticle("distanceConstraints", i, "particleB", c.m_particleB, n)) != PFX_OK) {
      return err;
    }
  }
  for (PfxUInt32 i = 0; i < param.numAngleConstraints; ++i) {
    const PfxParticleAngleConstraint& c = param.angleConstraints[i];
    if ((err = checkParticle("angleConstraints", i, "particleA", c.m_particleA, n)) != PFX_OK ||
        (err = checkParticle("angleConstraints", i, "particleB", c.m_particleB, n)) != PFX_OK ||
        (err = checkParticle("angleConstraints", i, "particleC", c.m_particleC, n)) != PFX_OK) {
      return err;
    }
  }
  ConstraintBatchWork work;
  constraintBatchWorkBytes(n, numConstraints, &work, param.workBuff);
  batch<2>(
      param.numDistanceConstraints,
      [&](PfxUInt32 i) {
        const PfxParticleDistanceConstraint& c = param.distanceConstraints[i];
        return std::array<PfxUInt32, 2>{c.m_particleA, c.m_particleB};
      },
      n, work, *param.distanceBatches);
  batch<3>(
      param.numAngleConstraints,
      [&](PfxUInt32 i) {
        const PfxParticleAngleConstraint& c = param.angleConstraints[i];
        return std::array<PfxUInt32, 3>{c.m_particleA, c.m_particleB, c.m_particleC};
      },
      n, work, *param.angleBatches);
  return PFX_OK;
}

}  // namespace pfx
