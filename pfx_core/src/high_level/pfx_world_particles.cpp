// PfxWorld's particle groups (seed sample 9): adding and removing them, their stages in the
// world's step, sleep, statistics and queries.
#include <algorithm>
#include <cmath>
#include <limits>

#include "high_level/pfx_world_stage_timer.h"
#include "low_level/particle/pfx_particle_stages_checked.h"
#include "low_level/pfx_param_checks.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx/low_level/particle/pfx_batch_particle_constraints.h"
#include "pfx/low_level/particle/pfx_collide_particle_groups.h"
#include "pfx/low_level/particle/pfx_detect_particle_contacts.h"
#include "pfx/low_level/particle/pfx_integrate_particles.h"
#include "pfx/low_level/particle/pfx_refresh_particle_contacts.h"
#include "pfx/low_level/particle/pfx_solve_particle_constraints.h"
#include "pfx/low_level/particle/pfx_update_particles.h"

namespace pfx {

namespace {

// The first contact buffer of a group: room for a particle resting on a body and touching a
// neighbour or two; a step that finds more grows it.
constexpr PfxUInt32 kInitialContactsPerParticle = 4;

// Two groups' particles and the contacts between them, as the stages that solve and
// update those contacts take them.
PfxSolveParticleGroupContactsParam groupContactsParam(PfxParticleGroup& a, PfxParticleGroup& b,
                                                      PfxParticleContact* contacts,
                                                      PfxUInt32 numContacts) {
  PfxSolveParticleGroupContactsParam param;
  param.particlesA = a.particles.data();
  param.numParticlesA = static_cast<PfxUInt32>(a.particles.size());
  param.particlesB = b.particles.data();
  param.numParticlesB = static_cast<PfxUInt32>(b.particles.size());
  param.contacts = contacts;
  param.numContacts = numContacts;
  return param;
}

template <typename T>
void copyInto(std::vector<T>& to, const T* from, PfxUInt32 count) {
  to.assign(from, from + count);
}

void pointBatchesAtBuffers(PfxParticleGroup& g) {
  g.distanceBatches.order = g.distanceOrder.data();
  g.distanceBatches.chainStart = g.distanceChainStart.data();
  g.angleBatches.order = g.angleOrder.data();
  g.angleBatches.chainStart = g.angleChainStart.data();
}

PfxInt32 batchConstraints(PfxParticleGroup& g) {
  g.distanceOrder.resize(g.distanceConstraints.size());
  g.angleOrder.resize(g.angleConstraints.size());
  g.distanceChainStart.resize(g.distanceConstraints.size() + 1);
  g.angleChainStart.resize(g.angleConstraints.size() + 1);
  pointBatchesAtBuffers(g);
  const PfxUInt32 numParticles = static_cast<PfxUInt32>(g.particles.size());
  const PfxUInt32 numConstraints =
      static_cast<PfxUInt32>(std::max(g.distanceConstraints.size(), g.angleConstraints.size()));
  std::vector<PfxVector4> work(
      (pfxGetWorkBytesOfBatchParticleConstraints(numParticles, numConstraints) +
       sizeof(PfxVector4) - 1) / sizeof(PfxVector4));
  PfxBatchParticleConstraintsParam param;
  param.workBuff = work.data();
  param.workBytes = static_cast<PfxUInt32>(work.size() * sizeof(PfxVector4));
  param.numParticles = numParticles;
  param.distanceConstraints = g.distanceConstraints.data();
  param.numDistanceConstraints = static_cast<PfxUInt32>(g.distanceConstraints.size());
  param.angleConstraints = g.angleConstraints.data();
  param.numAngleConstraints = static_cast<PfxUInt32>(g.angleConstraints.size());
  param.distanceBatches = &g.distanceBatches;
  param.angleBatches = &g.angleBatches;
  const PfxInt32 err = pfxBatchParticleConstraints(param);
  g.batched = err == PFX_OK;
  return err;
}

bool bodyMoves(const PfxRigidState& s, const PfxWorldParam& param) {
  return s.isAwake() && s.getMotionType() != kPfxMotionTypeFixed &&
         (s.getLinearVelocity().norm() > param.sleepLinearVelocity ||
          s.getAngularVelocity().norm() > param.sleepAngularVelocity);
}

// The group's particles' bounds, each widened by its radius and `margin`.
void boundsOf(const PfxParticleGroup& group, PfxFloat margin, PfxVector3& lo, PfxVector3& hi) {
  lo = PfxVector3::Constant(std::numeric_limits<PfxFloat>::max());
  hi = -lo;
  for (const PfxParticle& p : group.particles) {
    lo = lo.cwiseMin(p.m_position - PfxVector3::Constant(p.m_radius + margin));
    hi = hi.cwiseMax(p.m_position + PfxVector3::Constant(p.m_radius + margin));
  }
}

bool boundsMeet(const PfxVector3& loA, const PfxVector3& hiA, const PfxVector3& loB,
                const PfxVector3& hiB) {
  return (loA.array() <= hiB.array()).all() && (loB.array() <= hiA.array()).all();
}

}  // namespace

PfxInt32 PfxWorld::addParticleGroup(const PfxParticleGroupDesc& desc, PfxUInt32* outId) {
  const PfxParamNames at{"PfxWorld::addParticleGroup", "PfxParticleGroupDesc"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckValue(at, "iteration", desc.iteration,
                           desc.iteration > 0 && desc.iteration <= PFX_MAX_ITERATIONS,
                           "1 to PFX_MAX_ITERATIONS (1000)")) !=
          PFX_OK ||
      (err = pfxCheckValue(at, "linearDamping", desc.linearDamping,
                           desc.linearDamping >= 0 && pfxIsFinite(desc.linearDamping),
                           "zero or positive and finite")) != PFX_OK ||
      (err = pfxCheckRequired(at, {{desc.triangleIndices, "triangleIndices"}}, "numTriangles",
                              desc.numTriangles)) != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < 3 * desc.numTriangles; ++i) {
    if (desc.triangleIndices[i] >= desc.numParticles) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "PfxWorld::addParticleGroup: PfxParticleGroupDesc::triangleIndices[%u] "
                            "is %u, but numParticles is %u",
                            i, desc.triangleIndices[i], desc.numParticles);
    }
  }
  // The solve stage's own checks, run once here on the description as given.
  PfxSolveParticleConstraintsParam check;
  check.particles = const_cast<PfxParticle*>(desc.particles);
  check.numParticles = desc.numParticles;
  check.distanceConstraints = const_cast<PfxParticleDistanceConstraint*>(desc.distanceConstraints);
  check.numDistanceConstraints = desc.numDistanceConstraints;
  check.angleConstraints = const_cast<PfxParticleAngleConstraint*>(desc.angleConstraints);
  check.numAngleConstraints = desc.numAngleConstraints;
  check.tethers = desc.tethers;
  check.numTethers = desc.numTethers;
  check.pins = const_cast<PfxParticlePin*>(desc.pins);
  check.numPins = desc.numPins;
  check.offsetRigidStates = m_states.data();
  check.offsetRigidBodies = m_bodies.data();
  check.numRigidBodies = getNumRigidBodies();
  check.timeStep = m_param.timeStep;
  check.iteration = desc.iteration;
  if ((err = pfxCheckParticleConstraints(check)) != PFX_OK) return err;
  for (PfxUInt32 i = 0; i < desc.numPins + desc.numTethers; ++i) {
    const PfxUInt32 body = i < desc.numPins ? desc.pins[i].m_rigidBodyId
                                            : desc.tethers[i - desc.numPins].m_rigidBodyId;
    if (body != PFX_PARTICLE_PIN_WORLD && !hasRigidBody(body)) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "PfxWorld::addParticleGroup: a pin or tether names body %u, which "
                            "was removed",
                            body);
    }
  }

  auto group = std::make_unique<PfxParticleGroup>();
  copyInto(group->particles, desc.particles, desc.numParticles);
  copyInto(group->distanceConstraints, desc.distanceConstraints, desc.numDistanceConstraints);
  copyInto(group->angleConstraints, desc.angleConstraints, desc.numAngleConstraints);
  copyInto(group->tethers, desc.tethers, desc.numTethers);
  copyInto(group->pins, desc.pins, desc.numPins);
  copyInto(group->triangleIndices, desc.triangleIndices, 3 * desc.numTriangles);
  group->linearDamping = desc.linearDamping;
  group->iteration = desc.iteration;
  group->selfCollision = desc.selfCollision;
  group->contacts.resize(std::max<std::size_t>(16, kInitialContactsPerParticle * desc.numParticles));
  const std::size_t workBytes = pfxGetWorkBytesOfDetectParticleContacts(desc.numParticles);
  group->detectWork.resize((workBytes + sizeof(PfxVector4) - 1) / sizeof(PfxVector4));

  const auto freeSlot = std::find(m_particleGroups.begin(), m_particleGroups.end(), nullptr);
  const PfxUInt32 id = static_cast<PfxUInt32>(freeSlot - m_particleGroups.begin());
  if (freeSlot == m_particleGroups.end()) {
    m_particleGroups.push_back(std::move(group));
  } else {
    *freeSlot = std::move(group);
  }
  m_rayProxiesStale = true;
  if (outId) *outId = id;
  return PFX_OK;
}

PfxInt32 PfxWorld::removeParticleGroup(PfxUInt32 id) {
  if (!getParticleGroup(id)) return PFX_ERR_OUT_OF_RANGE;
  m_particleGroups[id].reset();
  m_numParticleGroupPairs = 0;
  while (!m_particleGroups.empty() && !m_particleGroups.back()) m_particleGroups.pop_back();
  m_rayProxiesStale = true;
  return PFX_OK;
}

PfxInt32 PfxWorld::setParticlePosition(PfxUInt32 groupId, PfxUInt32 particle,
                                       const PfxVector3& position) {
  PfxParticleGroup* group = groupId < m_particleGroups.size() ? m_particleGroups[groupId].get()
                                                               : nullptr;
  if (!group || particle >= group->particles.size()) return PFX_ERR_OUT_OF_RANGE;
  if (!pfxIsFinite(position)) return PFX_ERR_INVALID_VALUE;
  group->particles[particle].m_position = position;
  group->particles[particle].m_previousPosition = position;
  group->asleep = false;
  group->sleepCount = 0;
  m_rayProxiesStale = true;
  return PFX_OK;
}

bool PfxWorld::particlesPinBodyIn(PfxUInt32 first, PfxUInt32 last) const {
  const auto inRange = [&](PfxUInt32 id) {
    return id != PFX_PARTICLE_PIN_WORLD && id >= first && id < last;
  };
  for (const auto& group : m_particleGroups) {
    if (!group) continue;
    for (const PfxParticlePin& pin : group->pins) {
      if (inRange(pin.m_rigidBodyId)) return true;
    }
    for (const PfxParticleTether& tether : group->tethers) {
      if (inRange(tether.m_rigidBodyId)) return true;
    }
  }
  return false;
}

void PfxWorld::wakeSleepingParticleGroups() {
  const PfxFloat margin = m_param.contactMargin;
  for (const auto& group : m_particleGroups) {
    if (!group || !group->asleep) continue;
    bool wake = false;
    for (const PfxParticlePin& pin : group->pins) {
      wake = wake || (pin.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD &&
                      bodyMoves(m_states[pin.m_rigidBodyId], m_param));
    }
    if (!wake && !group->particles.empty()) {
      PfxVector3 lo, hi;
      boundsOf(*group, margin, lo, hi);
      // An awake group coming near wakes it, so that the two can collide.
      for (const auto& other : m_particleGroups) {
        if (wake || !other || other->asleep || other->particles.empty()) continue;
        PfxVector3 otherLo, otherHi;
        boundsOf(*other, margin, otherLo, otherHi);
        wake = boundsMeet(lo, hi, otherLo, otherHi);
      }
      for (PfxUInt32 id = 0; id < getNumRigidBodies() && !wake; ++id) {
        if (!bodyMoves(m_states[id], m_param)) continue;
        PfxVector3 center, half;
        m_collidables[id].getWorldAabb(m_states[id].getTransform(), center, half);
        wake = ((center - half).array() <= hi.array()).all() &&
               ((center + half).array() >= lo.array()).all();
      }
    }
    if (wake) {
      group->asleep = false;
      group->sleepCount = 0;
    }
  }
}

PfxInt32 PfxWorld::detectGroupContacts(PfxParticleGroup& group, PfxFloat bodyReach) {
  const PfxUInt32 numParticles = static_cast<PfxUInt32>(group.particles.size());
  PfxDetectParticleContactsParam param;
  param.workBuff = group.detectWork.data();
  param.workBytes = static_cast<PfxUInt32>(group.detectWork.size() * sizeof(PfxVector4));
  param.particles = group.particles.data();
  param.numParticles = numParticles;
  param.rigidBodies.offsetRigidStates = m_states.data();
  param.rigidBodies.offsetCollidables = m_collidables.data();
  param.rigidBodies.numProxies = m_numRayProxies;
  param.rigidBodies.rangeCenter = m_param.worldCenter;
  param.rigidBodies.rangeExtent = m_param.worldExtent;
  if (m_numRayProxies > 0) {
    param.rigidBodies.bvhNodes = m_rayBvh.data();
    param.rigidBodies.bvhProxies = m_rayProxies.data();
  }
  param.offsetRigidBodies = m_bodies.data();
  param.detectParticleContacts = group.selfCollision;
  param.contactMargin = m_param.contactMargin + bodyReach;
  param.timeStep = m_param.timeStep;
  for (;;) {
    param.contacts = group.contacts.data();
    param.maxContacts = static_cast<PfxUInt32>(group.contacts.size());
    PfxDetectParticleContactsResult result;
    if (const PfxInt32 err = pfxDetectParticleContacts(param, result, &m_taskManager);
        err != PFX_OK) {
      return err;
    }
    if (!result.truncated) {
      group.numContacts = result.numContacts;
      return PFX_OK;
    }
    group.contacts.resize(group.contacts.size() * 2);
  }
}

PfxInt32 PfxWorld::detectParticleContacts() {
  if (m_particleGroups.empty()) return PFX_OK;
  wakeSleepingParticleGroups();
  const bool anyAwake = std::any_of(m_particleGroups.begin(), m_particleGroups.end(),
                                    [](const auto& g) { return g && !g->asleep; });
  if (!anyAwake) return PFX_OK;
  if (const PfxInt32 err = updateRayProxies(); err != PFX_OK) return err;
  // How far a body may move toward a particle during the step: contacts within it are kept.
  PfxFloat bodyReach = 0;
  for (PfxUInt32 id = 0; id < getNumRigidBodies(); ++id) {
    const PfxRigidState& s = m_states[id];
    if (s.isAsleep() || s.getMotionType() == kPfxMotionTypeFixed) continue;
    const PfxFloat radius = m_collidables[id].getHalf().norm();
    bodyReach = std::max(bodyReach, (s.getLinearVelocity().norm() +
                                     s.getAngularVelocity().norm() * radius) * m_param.timeStep);
  }
  for (const auto& group : m_particleGroups) {
    if (!group || group->asleep) continue;
    if (const PfxInt32 err = detectGroupContacts(*group, bodyReach); err != PFX_OK) return err;
    // A moving group wakes the bodies it touches or hangs from, so that they can respond.
    PfxFloat maxSpeed = 0;
    for (const PfxParticle& p : group->particles) maxSpeed = std::max(maxSpeed, p.m_velocity.norm());
    if (maxSpeed <= m_param.sleepLinearVelocity) continue;
    for (PfxUInt32 i = 0; i < group->numContacts; ++i) {
      const PfxParticleContact& c = group->contacts[i];
      if (c.m_kind == kPfxParticleContactRigidBody && m_states[c.m_other].isAsleep()) {
        wakeIslandOf(c.m_other);
      }
    }
    for (const PfxParticlePin& pin : group->pins) {
      if (pin.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD && m_states[pin.m_rigidBodyId].isAsleep()) {
        wakeIslandOf(pin.m_rigidBodyId);
      }
    }
  }
  return detectContactsBetweenGroups();
}

PfxInt32 PfxWorld::detectContactsBetweenGroups() {
  // Pairs of two sleeping groups stay, as a sleeping group keeps its contacts with bodies:
  // moved to the front, their buffers swapped rather than copied.
  PfxUInt32 kept = 0;
  for (PfxUInt32 k = 0; k < m_numParticleGroupPairs; ++k) {
    ParticleGroupPair& pair = m_particleGroupPairs[k];
    if (m_particleGroups[pair.groupA]->asleep && m_particleGroups[pair.groupB]->asleep) {
      std::swap(pair, m_particleGroupPairs[kept++]);
    }
  }
  m_numParticleGroupPairs = kept;
  const PfxUInt32 numGroups = getParticleGroupCapacity();
  for (PfxUInt32 a = 0; a < numGroups; ++a) {
    const PfxParticleGroup* groupA = getParticleGroup(a);
    if (!groupA || groupA->asleep || groupA->particles.empty()) continue;
    PfxVector3 loA, hiA;
    boundsOf(*groupA, m_param.contactMargin, loA, hiA);
    for (PfxUInt32 b = a + 1; b < numGroups; ++b) {
      const PfxParticleGroup* groupB = getParticleGroup(b);
      if (!groupB || groupB->asleep || groupB->particles.empty()) continue;
      PfxVector3 loB, hiB;
      boundsOf(*groupB, m_param.contactMargin, loB, hiB);
      if (!boundsMeet(loA, hiA, loB, hiB)) continue;
      if (m_numParticleGroupPairs == m_particleGroupPairs.size()) {
        m_particleGroupPairs.emplace_back();
      }
      ParticleGroupPair& pair = m_particleGroupPairs[m_numParticleGroupPairs];
      pair.groupA = a;
      pair.groupB = b;
      const PfxUInt32 numB = static_cast<PfxUInt32>(groupB->particles.size());
      pair.work.resize((pfxGetWorkBytesOfDetectParticleGroupContacts(numB) + sizeof(PfxVector4) -
                        1) / sizeof(PfxVector4));
      if (pair.contacts.empty()) pair.contacts.resize(kInitialContactsPerParticle * numB);
      PfxDetectParticleGroupContactsParam param;
      param.workBuff = pair.work.data();
      param.workBytes = static_cast<PfxUInt32>(pair.work.size() * sizeof(PfxVector4));
      param.particlesA = groupA->particles.data();
      param.numParticlesA = static_cast<PfxUInt32>(groupA->particles.size());
      param.particlesB = groupB->particles.data();
      param.numParticlesB = numB;
      param.contactMargin = m_param.contactMargin;
      param.timeStep = m_param.timeStep;
      for (;;) {
        param.contacts = pair.contacts.data();
        param.maxContacts = static_cast<PfxUInt32>(pair.contacts.size());
        PfxDetectParticleGroupContactsResult result;
        if (const PfxInt32 err = pfxDetectParticleGroupContacts(param, result); err != PFX_OK) {
          return err;
        }
        if (!result.truncated) {
          pair.numContacts = result.numContacts;
          break;
        }
        pair.contacts.resize(pair.contacts.size() * 2);
      }
      if (pair.numContacts > 0) ++m_numParticleGroupPairs;
    }
  }
  return PFX_OK;
}

PfxInt32 PfxWorld::particleSubStep(PfxFloat timeStep) {
  PfxUInt32 maxIteration = 0;
  for (const auto& group : m_particleGroups) {
    if (!group || group->asleep) continue;
    PfxParticleGroup& g = *group;
    maxIteration = std::max(maxIteration, g.iteration);
    const PfxUInt32 numParticles = static_cast<PfxUInt32>(g.particles.size());
    {
      PfxStageTimer timer(m_stats, kPfxStageIntegrateParticles, m_param.measureStages);
      PfxIntegrateParticlesParam param;
      param.particles = g.particles.data();
      param.numParticles = numParticles;
      param.gravity = m_param.gravity;
      param.linearDamping = g.linearDamping;
      param.timeStep = timeStep;
      if (const PfxInt32 err = pfxIntegrateCheckedParticles(param, &m_taskManager);
          err != PFX_OK) {
        return err;
      }
    }
    if (g.numContacts > 0) {
      PfxStageTimer timer(m_stats, kPfxStageDetectParticleContacts, m_param.measureStages);
      PfxRefreshParticleContactsParam param;
      param.particles = g.particles.data();
      param.numParticles = numParticles;
      param.contacts = g.contacts.data();
      param.numContacts = g.numContacts;
      param.offsetRigidStates = m_states.data();
      param.offsetCollidables = m_collidables.data();
      param.numRigidBodies = getNumRigidBodies();
      if (const PfxInt32 err = pfxRefreshParticleContacts(param, &m_taskManager); err != PFX_OK) {
        return err;
      }
    }
    if (!g.batched) {
      PfxStageTimer timer(m_stats, kPfxStageSolveParticleConstraints, m_param.measureStages);
      if (const PfxInt32 err = batchConstraints(g); err != PFX_OK) return err;
    }
  }
  // Iteration by iteration: each group's own constraints, then the contacts between groups,
  // so that a rope's links and its contacts with a cloth converge together (solved once per
  // sub-step after the rope's iterations, its links pulled it back into the cloth). Groups
  // in contact iterate as often as the one of the most: a cloth of 2 iterations under a
  // cable of 20 would otherwise be pushed by the contacts in 18 iterations that its own
  // links do not answer, and the cable parts its particles and slips through. Groups in id
  // order and pairs in the order found: the same bits on any thread count. Without contacts
  // between groups, all of a group's iterations are one call.
  const PfxUInt32 rounds = m_numParticleGroupPairs > 0 ? maxIteration : 1;
  const auto iterationsOf = [&](PfxUInt32 id) {
    PfxUInt32 iterations = m_particleGroups[id]->iteration;
    for (PfxUInt32 k = 0; k < m_numParticleGroupPairs; ++k) {
      const ParticleGroupPair& pair = m_particleGroupPairs[k];
      if (pair.groupA == id || pair.groupB == id) {
        iterations = std::max({iterations, m_particleGroups[pair.groupA]->iteration,
                               m_particleGroups[pair.groupB]->iteration});
      }
    }
    return iterations;
  };
  for (PfxUInt32 round = 0; round < rounds; ++round) {
    for (PfxUInt32 id = 0; id < getParticleGroupCapacity(); ++id) {
      PfxParticleGroup* group = m_particleGroups[id].get();
      if (!group || group->asleep || round >= iterationsOf(id)) continue;
      PfxParticleGroup& g = *group;
      PfxStageTimer timer(m_stats, kPfxStageSolveParticleConstraints, m_param.measureStages);
      pointBatchesAtBuffers(g);
      PfxSolveParticleConstraintsParam param;
      param.particles = g.particles.data();
      param.numParticles = static_cast<PfxUInt32>(g.particles.size());
      param.distanceConstraints = g.distanceConstraints.data();
      param.numDistanceConstraints = static_cast<PfxUInt32>(g.distanceConstraints.size());
      param.angleConstraints = g.angleConstraints.data();
      param.numAngleConstraints = static_cast<PfxUInt32>(g.angleConstraints.size());
      param.distanceBatches = &g.distanceBatches;
      param.angleBatches = &g.angleBatches;
      param.tethers = g.tethers.data();
      param.numTethers = static_cast<PfxUInt32>(g.tethers.size());
      param.pins = g.pins.data();
      param.numPins = static_cast<PfxUInt32>(g.pins.size());
      param.contacts = g.contacts.data();
      param.numContacts = g.numContacts;
      param.offsetRigidStates = m_states.data();
      param.offsetRigidBodies = m_bodies.data();
      param.numRigidBodies = getNumRigidBodies();
      param.timeStep = timeStep;
      param.iteration = rounds > 1 ? 1 : g.iteration;
      param.continueSubStep = round > 0;
      param.iterationsDone = round;
      if (const PfxInt32 err = pfxSolveCheckedParticleConstraints(param, &m_taskManager);
          err != PFX_OK) {
        return err;
      }
    }
    for (PfxUInt32 k = 0; k < m_numParticleGroupPairs; ++k) {
      ParticleGroupPair& pair = m_particleGroupPairs[k];
      PfxParticleGroup& a = *m_particleGroups[pair.groupA];
      PfxParticleGroup& b = *m_particleGroups[pair.groupB];
      if (a.asleep || round >= std::max(a.iteration, b.iteration)) continue;
      PfxStageTimer timer(m_stats, kPfxStageSolveParticleConstraints, m_param.measureStages);
      PfxSolveParticleGroupContactsParam param =
          groupContactsParam(a, b, pair.contacts.data(), pair.numContacts);
      param.continueSubStep = round > 0;
      if (const PfxInt32 err = pfxSolveParticleGroupContacts(param); err != PFX_OK) return err;
    }
  }
  for (const auto& group : m_particleGroups) {
    if (!group || group->asleep) continue;
    PfxParticleGroup& g = *group;
    const PfxUInt32 numParticles = static_cast<PfxUInt32>(g.particles.size());
    {
      PfxStageTimer timer(m_stats, kPfxStageUpdateParticles, m_param.measureStages);
      PfxUpdateParticlesParam param;
      param.particles = g.particles.data();
      param.numParticles = numParticles;
      param.timeStep = timeStep;
      param.contacts = g.contacts.data();
      param.numContacts = g.numContacts;
      param.offsetRigidStates = m_states.data();
      if (const PfxInt32 err = pfxUpdateParticles(param, &m_taskManager); err != PFX_OK) {
        return err;
      }
    }
  }
  for (PfxUInt32 k = 0; k < m_numParticleGroupPairs; ++k) {
    ParticleGroupPair& pair = m_particleGroupPairs[k];
    PfxParticleGroup& a = *m_particleGroups[pair.groupA];
    PfxParticleGroup& b = *m_particleGroups[pair.groupB];
    if (a.asleep) continue;
    PfxStageTimer timer(m_stats, kPfxStageUpdateParticles, m_param.measureStages);
    const PfxSolveParticleGroupContactsParam param =
        groupContactsParam(a, b, pair.contacts.data(), pair.numContacts);
    if (const PfxInt32 err = pfxUpdateParticleGroupContacts(param); err != PFX_OK) return err;
  }
  return PFX_OK;
}

void PfxWorld::updateParticleSleep() {
  const PfxUInt32 stepsToSleep =
      static_cast<PfxUInt32>(std::ceil(double(m_param.sleepTime) / m_param.timeStep));
  for (const auto& group : m_particleGroups) {
    if (!group || group->asleep) continue;
    if (!m_param.enableSleep) {
      group->sleepCount = 0;
      continue;
    }
    bool still = true;
    for (const PfxParticle& p : group->particles) {
      still = still && p.m_velocity.norm() <= m_param.sleepLinearVelocity;
    }
    // A group hanging from a moving body moves with it.
    for (const PfxParticlePin& pin : group->pins) {
      still = still && (pin.m_rigidBodyId == PFX_PARTICLE_PIN_WORLD ||
                        !bodyMoves(m_states[pin.m_rigidBodyId], m_param));
    }
    group->sleepCount = still ? group->sleepCount + 1 : 0;
  }
  // Groups whose bounds meet fall asleep together, when the last of them has been still long
  // enough: one asleep beside an awake one would be woken by it on the next step, and two that
  // came to rest a step apart then took turns waking each other and never slept.
  const PfxFloat margin = m_param.contactMargin;
  for (const auto& group : m_particleGroups) {
    if (!group || group->asleep || group->sleepCount < stepsToSleep) continue;
    PfxVector3 lo, hi;
    boundsOf(*group, margin, lo, hi);
    bool neighboursStill = true;
    for (const auto& other : m_particleGroups) {
      if (!neighboursStill || !other || other == group || other->asleep ||
          other->sleepCount >= stepsToSleep || other->particles.empty()) {
        continue;
      }
      PfxVector3 otherLo, otherHi;
      boundsOf(*other, margin, otherLo, otherHi);
      neighboursStill = !boundsMeet(lo, hi, otherLo, otherHi);
    }
    if (!neighboursStill) continue;
    // Its contacts stay as they are, for the queries, until it wakes and finds new ones.
    group->asleep = true;
    for (PfxParticle& p : group->particles) p.m_velocity.setZero();
  }
}

void PfxWorld::gatherParticleStats() {
  m_stats.numParticles = 0;
  m_stats.numAwakeParticleGroups = 0;
  m_stats.numSleepingParticleGroups = 0;
  m_stats.numParticleContacts = 0;
  m_stats.maxParticlePenetration = 0;
  for (const auto& group : m_particleGroups) {
    if (!group) continue;
    m_stats.numParticles += static_cast<PfxUInt32>(group->particles.size());
    if (group->asleep) {
      ++m_stats.numSleepingParticleGroups;
      continue;
    }
    ++m_stats.numAwakeParticleGroups;
    m_stats.numParticleContacts += group->numContacts;
    for (PfxUInt32 i = 0; i < group->numContacts; ++i) {
      const PfxParticleContact& c = group->contacts[i];
      if (c.m_kind != kPfxParticleContactRigidBody) continue;
      const PfxRigidState& s = m_states[c.m_other];
      const PfxParticle& p = group->particles[c.m_particle];
      const PfxVector3 point = s.getPosition() + s.getOrientation() * c.m_localPoint;
      const PfxFloat depth = p.m_radius - (p.m_position - point).dot(s.getOrientation() * c.m_localNormal);
      m_stats.maxParticlePenetration = std::max(m_stats.maxParticlePenetration, depth);
    }
  }
}

void PfxWorld::updateParticleRayBounds() {
  m_particleRayBounds.resize(2 * m_particleGroups.size());
  for (PfxUInt32 id = 0; id < getParticleGroupCapacity(); ++id) {
    PfxVector3 lo = PfxVector3::Constant(std::numeric_limits<PfxFloat>::max());
    PfxVector3 hi = -lo;
    if (const PfxParticleGroup* group = getParticleGroup(id)) {
      for (const PfxParticle& p : group->particles) {
        lo = lo.cwiseMin(p.m_position - PfxVector3::Constant(p.m_radius));
        hi = hi.cwiseMax(p.m_position + PfxVector3::Constant(p.m_radius));
      }
    }
    m_particleRayBounds[2 * id] = lo;
    m_particleRayBounds[2 * id + 1] = hi;
  }
}

namespace {

// Whether the part [0, maxFraction] of the ray meets the box, by slabs in double.
bool rayMeetsBounds(const PfxRayInput& ray, const PfxVector3& lo, const PfxVector3& hi,
                    PfxFloat maxFraction) {
  double enter = 0, leave = maxFraction;
  for (int axis = 0; axis < 3; ++axis) {
    const double start = ray.m_startPosition[axis];
    const double d = ray.m_direction[axis];
    if (d == 0) {
      if (start < lo[axis] || start > hi[axis]) return false;
      continue;
    }
    double t0 = (lo[axis] - start) / d, t1 = (hi[axis] - start) / d;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return false;
  }
  return true;
}

}  // namespace

void PfxWorld::castParticleRay(const PfxRayInput& in, PfxRayOutput& out) const {
  for (PfxUInt32 id = 0; id < getParticleGroupCapacity(); ++id) {
    const PfxParticleGroup* group = getParticleGroup(id);
    if (!group ||
        !rayMeetsBounds(in, m_particleRayBounds[2 * id], m_particleRayBounds[2 * id + 1],
                        out.m_variable)) {
      continue;
    }
    const PfxFloat closestBefore = out.m_variable;
    // The ray was checked, and the group's triangles when it was added: this cannot fail.
    pfxCastParticleRay(in, group->particles.data(), static_cast<PfxUInt32>(group->particles.size()),
                       group->triangleIndices.data(),
                       static_cast<PfxUInt32>(group->triangleIndices.size() / 3), out);
    if (out.m_variable < closestBefore) out.m_particleGroupId = id;
  }
}

PfxInt32 PfxWorld::getParticleBodyContacts(PfxParticleBodyContact* out, PfxUInt32 maxContacts,
                                           PfxQueryContactsResult& result) const {
  if (!out && maxContacts > result.numContacts) {
    return pfxRejectNull(PfxParamNames{"PfxWorld::getParticleBodyContacts", ""}, "out",
                         "maxContacts", maxContacts);
  }
  const PfxFloat subTimeStep = m_param.timeStep / PfxFloat(m_param.subStep);
  for (PfxUInt32 id = 0; id < getParticleGroupCapacity(); ++id) {
    const PfxParticleGroup* group = getParticleGroup(id);
    if (!group) continue;
    for (PfxUInt32 i = 0; i < group->numContacts; ++i) {
      const PfxParticleContact& c = group->contacts[i];
      if (c.m_kind != kPfxParticleContactRigidBody) continue;
      if (result.numContacts == maxContacts) {
        result.truncated = true;
        return PFX_OK;
      }
      const PfxRigidState& s = m_states[c.m_other];
      const PfxParticle& p = group->particles[c.m_particle];
      const PfxVector3 surface = s.getPosition() + s.getOrientation() * c.m_localPoint;
      const PfxVector3 normal = s.getOrientation() * c.m_localNormal;
      const PfxFloat depth = p.m_radius - (p.m_position - surface).dot(normal);
      PfxParticleBodyContact& o = out[result.numContacts++];
      o.m_particleGroupId = id;
      o.m_particle = c.m_particle;
      o.m_rigidBodyId = c.m_other;
      o.m_shapeId = c.m_shapeId;
      o.m_normal = normal;
      o.m_depth = depth;
      o.m_point = surface - PfxFloat(0.5) * depth * normal;
      o.m_impulse = std::max(c.m_lambdaNormal, PfxFloat(0)) / subTimeStep;
    }
  }
  return PFX_OK;
}

PfxInt32 PfxWorld::getParticleGroupContacts(PfxParticleGroupContact* out, PfxUInt32 maxContacts,
                                            PfxQueryContactsResult& result) const {
  if (!out && maxContacts > result.numContacts) {
    return pfxRejectNull(PfxParamNames{"PfxWorld::getParticleGroupContacts", ""}, "out",
                         "maxContacts", maxContacts);
  }
  const PfxFloat subTimeStep = m_param.timeStep / PfxFloat(m_param.subStep);
  for (PfxUInt32 k = 0; k < m_numParticleGroupPairs; ++k) {
    const ParticleGroupPair& pair = m_particleGroupPairs[k];
    const PfxParticleGroup& a = *m_particleGroups[pair.groupA];
    const PfxParticleGroup& b = *m_particleGroups[pair.groupB];
    for (PfxUInt32 i = 0; i < pair.numContacts; ++i) {
      if (result.numContacts == maxContacts) {
        result.truncated = true;
        return PFX_OK;
      }
      const PfxParticleContact& c = pair.contacts[i];
      const PfxParticle& pa = a.particles[c.m_particle];
      const PfxParticle& pb = b.particles[c.m_other];
      const PfxVector3 d = pa.m_position - pb.m_position;
      const PfxFloat length = d.norm();
      // Two centres in one place have no direction between them; any will do.
      const PfxVector3 normal = length > 0 ? PfxVector3(d / length) : PfxVector3::UnitZ();
      PfxParticleGroupContact& o = out[result.numContacts++];
      o.m_particleGroupIdA = pair.groupA;
      o.m_particleA = c.m_particle;
      o.m_particleGroupIdB = pair.groupB;
      o.m_particleB = c.m_other;
      o.m_normal = normal;
      o.m_depth = pa.m_radius + pb.m_radius - length;
      o.m_point = PfxFloat(0.5) * (pb.m_position + pb.m_radius * normal + pa.m_position -
                                   pa.m_radius * normal);
      o.m_impulse = std::max(c.m_lambdaNormal, PfxFloat(0)) / subTimeStep;
    }
  }
  return PFX_OK;
}

PfxInt32 PfxWorld::queryParticleContacts(const PfxContactQueryInput& query,
                                         PfxParticleQueryContact* out, PfxUInt32 maxContacts,
                                         PfxQueryContactsResult& result) const {
  PfxQueryContactsResult found;
  if (const PfxInt32 err = pfxQueryParticleContacts(query, nullptr, 0, out, maxContacts, found);
      err != PFX_OK) {
    return err;
  }
  for (PfxUInt32 id = 0; id < getParticleGroupCapacity(); ++id) {
    const PfxParticleGroup* group = getParticleGroup(id);
    if (!group) continue;
    const PfxUInt32 first = found.numContacts;
    pfxQueryParticleContacts(query, group->particles.data(),
                             static_cast<PfxUInt32>(group->particles.size()), out, maxContacts,
                             found);
    for (PfxUInt32 i = first; i < found.numContacts; ++i) out[i].m_particleGroupId = id;
  }
  result = found;
  return PFX_OK;
}

}  // namespace pfx
