#include "pfx/low_level/particle/pfx_batch_particle_constraints.h"

#include <algorithm>
#include <array>

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

const PfxParamNames kAt{"pfxBatchParticleConstraints", "PfxBatchParticleConstraintsParam"};
constexpr PfxUInt32 kLeftOver = PFX_MAX_PARTICLE_PHASES;
// The chains pfxSolveParticleConstraints solves side by side on one thread.
constexpr PfxUInt32 kChainsSideBySide = 4;

struct ConstraintBatchWork {
  PfxUInt64* phasesOfParticle;  // bit k: the particle is in a chain of phase k
  PfxUInt32* firstOfChain;      // chains in list order: chain c is firstOfChain[c] ..
  PfxUInt8* phaseOfChain;
};

std::size_t constraintBatchWorkBytes(PfxUInt32 numParticles, PfxUInt32 numConstraints,
                                     ConstraintBatchWork* work, void* base) {
  const std::size_t particleBytes = pfxAlignBytes(sizeof(PfxUInt64) * numParticles);
  const std::size_t chainBytes = pfxAlignBytes(sizeof(PfxUInt32) * (std::size_t(numConstraints) + 1));
  if (work) {
    work->phasesOfParticle = static_cast<PfxUInt64*>(base);
    work->firstOfChain =
        reinterpret_cast<PfxUInt32*>(static_cast<PfxUInt8*>(base) + particleBytes);
    work->phaseOfChain = static_cast<PfxUInt8*>(base) + particleBytes + chainBytes;
  }
  return particleBytes + chainBytes + pfxAlignBytes(numConstraints);
}

PfxUInt32 lowestFreePhase(PfxUInt64 taken) {
  PfxUInt32 phase = 0;
  while (phase < PFX_MAX_PARTICLE_PHASES && (taken & (PfxUInt64(1) << phase))) ++phase;
  return phase;
}

// Whether constraint `next` starts where `previous` ended: its first N - 1 particles are the
// previous one's last N - 1.
template <std::size_t N>
bool continues(const std::array<PfxUInt32, N>& previous, const std::array<PfxUInt32, N>& next) {
  return std::equal(previous.begin() + 1, previous.end(), next.begin());
}

// Chains from the list order, then a greedy colouring in chain order: each chain takes the
// lowest phase none of its particles is in yet. A stable counting sort by phase writes the
// order, so that a phase lists its chains in list order (neighbours in memory stay
// neighbours).
template <std::size_t N, typename ParticlesOf>
void batch(PfxUInt32 numConstraints, const ParticlesOf& particlesOf, PfxUInt32 numParticles,
           const ConstraintBatchWork& work, PfxParticleConstraintBatches& batches) {
  PfxUInt32 numChains = 0;
  for (PfxUInt32 i = 0; i < numConstraints; ++i) {
    if (i == 0 || !continues<N>(particlesOf(i - 1), particlesOf(i))) {
      work.firstOfChain[numChains++] = i;
    }
  }
  // A chain's constraints wait for each other, and the solve overlaps only those of
  // different chains: a lone rope solved as one chain of 40 links cost 24.5 ms per simulated
  // second at 20 sub-steps of 20 iterations, in phases of single links 19.3 ms, to the same
  // error (pfx_bench --scene rope). Fewer chains than the solve runs side by side are taken link by link.
  if (numChains < kChainsSideBySide) {
    numChains = numConstraints;
    for (PfxUInt32 i = 0; i < numConstraints; ++i) work.firstOfChain[i] = i;
  }
  work.firstOfChain[numChains] = numConstraints;
  std::fill(work.phasesOfParticle, work.phasesOfParticle + numParticles, PfxUInt64(0));
  std::array<PfxUInt32, PFX_MAX_PARTICLE_PHASES + 1> chainCount{}, constraintCount{};
  for (PfxUInt32 c = 0; c < numChains; ++c) {
    PfxUInt64 taken = 0;
    for (PfxUInt32 i = work.firstOfChain[c]; i < work.firstOfChain[c + 1]; ++i) {
      for (const PfxUInt32 p : particlesOf(i)) taken |= work.phasesOfParticle[p];
    }
    const PfxUInt32 phase = lowestFreePhase(taken);
    if (phase != kLeftOver) {
      for (PfxUInt32 i = work.firstOfChain[c]; i < work.firstOfChain[c + 1]; ++i) {
        for (const PfxUInt32 p : particlesOf(i)) work.phasesOfParticle[p] |= PfxUInt64(1) << phase;
      }
    }
    work.phaseOfChain[c] = static_cast<PfxUInt8>(phase);
    ++chainCount[phase];
    constraintCount[phase] += work.firstOfChain[c + 1] - work.firstOfChain[c];
  }
  PfxUInt32 numPhases = 0;
  while (numPhases < PFX_MAX_PARTICLE_PHASES && chainCount[numPhases] > 0) ++numPhases;
  batches.numConstraints = numConstraints;
  batches.numChains = numChains;
  batches.numPhases = numPhases;
  // Phases are made lowest first, so the empty ones are all after numPhases and start
  // where the left-over ones do.
  std::array<PfxUInt32, PFX_MAX_PARTICLE_PHASES + 1> chainCursor{}, constraintCursor{};
  PfxUInt32 chainsBefore = 0, constraintsBefore = 0;
  for (PfxUInt32 phase = 0; phase <= PFX_MAX_PARTICLE_PHASES; ++phase) {
    batches.phaseStart[phase] = chainsBefore;
    chainCursor[phase] = chainsBefore;
    constraintCursor[phase] = constraintsBefore;
    chainsBefore += chainCount[phase];
    constraintsBefore += constraintCount[phase];
  }
  for (PfxUInt32 c = 0; c < numChains; ++c) {
    const PfxUInt32 phase = work.phaseOfChain[c];
    PfxUInt32& at = constraintCursor[phase];
    batches.chainStart[chainCursor[phase]++] = at;
    for (PfxUInt32 i = work.firstOfChain[c]; i < work.firstOfChain[c + 1]; ++i) {
      batches.order[at++] = i;
    }
  }
  batches.chainStart[numChains] = numConstraints;
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
  if (!param.distanceBatches || !param.angleBatches || !param.distanceBatches->chainStart ||
      !param.angleBatches->chainStart ||
      (!param.distanceBatches->order && param.numDistanceConstraints > 0) ||
      (!param.angleBatches->order && param.numAngleConstraints > 0)) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER,
                          "%s: %s::distanceBatches or angleBatches, or its order or "
                          "chainStart, is null",
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
