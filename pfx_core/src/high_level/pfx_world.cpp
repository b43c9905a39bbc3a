#include "pfx/high_level/pfx_world.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/low_level/broadphase/pfx_decompose_pairs.h"
#include "pfx/low_level/broadphase/pfx_find_pairs.h"
#include "pfx/low_level/collision/pfx_detect_collision.h"
#include "pfx/low_level/collision/pfx_refresh_contacts.h"
#include "pfx/low_level/rigidbody/pfx_apply_external_force.h"
#include "pfx/low_level/rigidbody/pfx_apply_joint_efforts.h"
#include "pfx/low_level/rigidbody/pfx_update_rigid_states.h"
#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/low_level/solver/pfx_correct_joint_positions.h"
#include "pfx/low_level/solver/pfx_setup_contact_constraints.h"
#include "pfx/low_level/solver/pfx_setup_joint_constraints.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"
#include "pfx/low_level/solver/pfx_solve_constraints.h"
#include "high_level/pfx_island_groups.h"
#include "high_level/pfx_world_stage_timer.h"

namespace pfx {

namespace {

using Clock = std::chrono::steady_clock;

using StageTimer = PfxStageTimer;

// A point may move this far (squared, in A's frame) between frames and keep its impulses.
constexpr PfxFloat kMatchDistanceSq = PfxFloat(0.02 * 0.02);

template <typename T>
void growTo(std::vector<T>& v, std::size_t n) {
  if (v.size() < n) v.resize(std::max(n, v.size() * 2));
}

}  // namespace

const char* pfxStageName(PfxStage stage) {
  static const char* const kNames[kPfxStageCount] = {
      "apply_external_force", "update_broadphase_proxies", "find_pairs",
      "decompose_pairs",      "refresh_contacts",          "detect_collision",
      "setup_solver_bodies",  "setup_contact_constraints", "setup_joint_constraints",
      "solve_constraints",    "update_rigid_states",       "correct_joint_positions",
      "generate_island",      "detect_particle_contacts",  "integrate_particles",
      "solve_particle_constraints", "update_particles"};
  return stage < kPfxStageCount ? kNames[stage] : "unknown";
}

PfxWorld::PfxWorld() { initialize(PfxWorldParam()); }
PfxWorld::~PfxWorld() = default;

PfxInt32 PfxWorld::checkParam(const PfxWorldParam& param) {
  const bool valid =
      pfxIsFinite(param.worldCenter) && pfxIsFinite(param.worldExtent) &&
      param.worldExtent.minCoeff() > 0 && pfxIsFinite(param.gravity) && param.timeStep > 0 &&
      pfxIsFinite(param.timeStep) &&
      // The velocity gravity adds in one step, held to the rule of body velocities
      // (PfxRigidState::isValid): a time step of 3.4e38 s made every body infinite at once.
      pfxIsFinite(PfxVector3(param.gravity * param.timeStep).squaredNorm()) && param.iteration > 0 && param.subStep > 0 && param.separateBias >= 0 &&
      param.separateBias <= 1 && param.contactSlop >= 0 && pfxIsFinite(param.contactSlop) &&
      param.contactMargin >= 0 && pfxIsFinite(param.contactMargin) &&
      param.restitutionThreshold >= 0 && pfxIsFinite(param.restitutionThreshold) &&
      param.sleepLinearVelocity >= 0 && pfxIsFinite(param.sleepLinearVelocity) &&
      param.sleepAngularVelocity >= 0 && pfxIsFinite(param.sleepAngularVelocity) &&
      param.sleepTime >= 0 && std::ceil(double(param.sleepTime) / param.timeStep) <= 0xffff;
  if (!valid) return PFX_ERR_INVALID_VALUE;
  if (param.timeStep > PFX_MAX_TIME_STEP || param.numThreads > PFX_MAX_THREADS ||
      param.subStep > PFX_MAX_SUB_STEPS || param.iteration > PFX_MAX_ITERATIONS) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  if (param.pipeline > kPfxPipelineStable ||
      (param.outOfWorldBehavior & ~PfxUInt32(PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION |
                                             PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY)) != 0) {
    return PFX_ERR_INVALID_FLAG;
  }
  return PFX_OK;
}

PfxInt32 PfxWorld::initialize(const PfxWorldParam& param) {
  if (const PfxInt32 err = checkParam(param); err != PFX_OK) return err;
  m_taskManager.initialize(param.numThreads);
  m_param = param;
  m_stats = PfxWorldStats();
  m_simulatedTime = 0;
  m_states.clear();
  m_bodies.clear();
  m_collidables.clear();
  m_solverBodies.clear();
  m_forces.clear();
  m_torques.clear();
  m_compoundShapes.clear();
  m_compoundShapeIds.clear();
  m_removedBodies.clear();
  m_removedJoints.clear();
  m_removedCouplings.clear();
  m_numRemovedBodies = 0;
  m_numRemovedJoints = 0;
  m_numProxies = 0;
  m_sleepingProxies.clear();
  m_skipForAwakeProxies.clear();
  m_skipForSleepingProxies.clear();
  m_numSleepingProxies = m_numSleepingOutOfWorld = 0;
  m_sleepingProxiesStale = true;
  m_rayProxiesStale = true;
  m_numPairs = 0;
  m_numFoundPairs = 0;
  m_manifolds.clear();
  m_freeManifolds.clear();
  m_onePointBlocks.clear();
  m_fourPointBlocks.clear();
  m_sharedEmptyManifold = 0;
  m_manifolds.emplace_back(nullptr, 0);
  m_joints.clear();
  m_jointPairs.clear();
  m_jointCouplings.clear();
  m_jointedPairKeys.clear();
  m_excludedPairKeys.clear();
  m_solverWork.clear();
  m_particleGroups.clear();
  m_numSleepingPairs = 0;
  m_numSleepingBodies = 0;
  countSleepingContacts();
  return generateIslands();
}

PfxInt32 PfxWorld::setStepParam(PfxFloat timeStep, PfxUInt32 subStep, PfxUInt32 iteration,
                                const PfxVector3& gravity) {
  PfxWorldParam param = m_param;
  param.timeStep = timeStep;
  param.subStep = subStep;
  param.iteration = iteration;
  param.gravity = gravity;
  if (const PfxInt32 err = checkParam(param); err != PFX_OK) return err;
  m_param = param;
  return PFX_OK;
}

PfxInt32 PfxWorld::setSimulatedTime(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return PFX_ERR_INVALID_VALUE;
  m_simulatedTime = seconds;
  return PFX_OK;
}

PfxInt32 PfxWorld::validateBody(const PfxRigidState& state, const PfxRigidBody& body) {
  if (!state.isValid()) return PFX_ERR_INVALID_VALUE;
  if (pfxMotionTypeIsDynamic(state.getMotionType()) && !body.isValid()) {
    return PFX_ERR_INVALID_VALUE;
  }
  // A body forces do not move needs no usable mass, but the world must still save it.
  if (!pfxIsFinite(body.getMass()) || !body.getInertia().allFinite()) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!(body.getFriction() >= 0) || !pfxIsFinite(body.getFriction()) ||
      !(body.getRestitution() >= 0) || !(body.getRestitution() <= 1)) {
    return PFX_ERR_INVALID_VALUE;
  }
  return PFX_OK;
}

void PfxWorld::reserveRigidBodies(PfxUInt32 numBodies) {
  if (m_states.capacity() >= numBodies) return;
  reserveBodies(numBodies, numBodies);
  sizeBodyArraysToCapacity();
}

void PfxWorld::reserveBodies(std::size_t n, std::size_t capacity) {
  if (m_states.capacity() >= n) return;
  m_states.reserve(capacity);
  m_bodies.reserve(capacity);
  m_collidables.reserve(capacity);
  m_forces.reserve(capacity);
  m_torques.reserve(capacity);
  m_compoundShapes.reserve(capacity);
  m_compoundShapeIds.reserve(capacity);
  m_removedBodies.reserve(capacity);
}

PfxInt32 PfxWorld::addRigidBody(const PfxRigidState& state, const PfxRigidBody& body,
                                const PfxShape* shapes, PfxUInt32 numShapes, PfxUInt32* outId) {
  if (!shapes) return PFX_ERR_NULL_POINTER;
  if (numShapes == 0 || numShapes > PFX_MAX_SHAPES_PER_COLLIDABLE) return PFX_ERR_OUT_OF_RANGE;
  if (const PfxInt32 err = validateBody(state, body); err != PFX_OK) return err;
  for (PfxUInt32 i = 0; i < numShapes; ++i) {
    if (const PfxInt32 err = shapes[i].validate(); err != PFX_OK) return err;
  }

  // Build the collidable aside, so that a failure leaves the world untouched.
  PfxCollidable collidable;
  std::unique_ptr<PfxShape[]> compound;
  std::unique_ptr<PfxUInt16[]> compoundIds;
  if (numShapes == 1) {
    collidable.reset();
  } else {
    compound.reset(new PfxShape[numShapes]);
    compoundIds.reset(new PfxUInt16[numShapes]);
    for (PfxUInt32 i = 0; i < numShapes; ++i) compoundIds[i] = static_cast<PfxUInt16>(i);
    collidable.reset(compound.get(), compoundIds.get(), numShapes);
  }
  for (PfxUInt32 i = 0; i < numShapes; ++i) collidable.addShape(shapes[i]);
  collidable.finish();

  const PfxUInt32 id = getNumRigidBodies();
  reserveBodies(id + 1, std::max<std::size_t>(id + 1, m_states.capacity() * 2));
  m_states.push_back(state);
  m_states.back().setRigidBodyId(id);
  m_states.back().wakeup();
  m_bodies.push_back(body);
  m_collidables.push_back(collidable);
  m_forces.push_back(PfxVector3::Zero());
  m_torques.push_back(PfxVector3::Zero());
  m_compoundShapes.push_back(std::move(compound));
  m_compoundShapeIds.push_back(std::move(compoundIds));
  m_removedBodies.push_back(0);
  sizeBodyArraysToCapacity();
  m_rayProxiesStale = true;
  if (outId) *outId = id;
  return PFX_OK;
}

PfxInt32 PfxWorld::setRigidState(PfxUInt32 id, const PfxRigidState& state) {
  if (!hasRigidBody(id)) return PFX_ERR_OUT_OF_RANGE;
  if (const PfxInt32 err = validateBody(state, m_bodies[id]); err != PFX_OK) return err;
  // Woken as it was: what rested on it when it was fixed or keyframe wakes too.
  wakeAfterChange(id);
  m_states[id] = state;
  m_states[id].setRigidBodyId(id);
  m_states[id].wakeup();
  m_rayProxiesStale = true;
  return PFX_OK;
}

PfxInt32 PfxWorld::updateLargeTriMesh(PfxUInt32 id, PfxLargeTriMesh& mesh,
                                      const PfxFloat* vertices, PfxUInt32 numVertices) {
  if (!hasRigidBody(id)) return PFX_ERR_OUT_OF_RANGE;
  const PfxCollidable& collidable = m_collidables[id];
  bool holdsMesh = false;
  for (PfxUInt32 i = 0; i < collidable.getNumShapes(); ++i) {
    holdsMesh = holdsMesh || collidable.getShape(i).getLargeTriMesh() == &mesh;
  }
  if (!holdsMesh) return PFX_ERR_INVALID_VALUE;
  if (const PfxInt32 err = pfxUpdateLargeTriMeshVertices(mesh, vertices, numVertices);
      err != PFX_OK) {
    return err;
  }
  m_collidables[id].finish();
  m_rayProxiesStale = true;
  // The points of sleeping pairs on the mesh must move with it too.
  wakeAfterChange(id);

  for (PfxUInt32 p = 0; p < m_numPairs; ++p) {
    PfxContactManifold& manifold = m_manifolds[pfxGetContactId(m_pairs[p])];
    const PfxUInt32 idA = manifold.getRigidBodyIdA();
    const PfxUInt32 idB = manifold.getRigidBodyIdB();
    if (idA != id && idB != id) continue;
    const PfxTransform3 transformA = m_states[idA].getTransform();
    const PfxTransform3 transformB = m_states[idB].getTransform();
    const auto separation = [&](const PfxContactPoint& point) {
      return (transformB * point.m_localPointB - transformA * point.m_localPointA)
          .dot(point.getNormal());
    };
    PfxFloat before[PFX_NUM_CONTACTS_PER_MANIFOLD];
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      before[i] = separation(manifold.getContactPoint(i));
    }
    manifold.carryMeshContacts(m_collidables[idA], m_collidables[idB]);
    // The largest depth the move added, measured from where each point was (or from
    // touching, for a point that was still apart).
    PfxFloat push = 0;
    PfxVector3 normal = PfxVector3::Zero();
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      PfxContactPoint& point = manifold.getContactPoint(i);
      point.m_distance = separation(point);
      const PfxFloat added = std::min(before[i], PfxFloat(0)) - point.m_distance;
      if (point.m_triangleIndex != PFX_CONTACT_NO_TRIANGLE && added > push) {
        push = added;
        normal = point.getNormal();
      }
    }
    const PfxUInt32 other = idA == id ? idB : idA;
    if (push <= 0 || other == id || m_states[other].getMotionType() != kPfxMotionTypeActive) {
      continue;
    }
    // The normal points from A to B: B moves along it, A against it.
    const PfxVector3 move = normal * (other == idB ? push : -push);
    m_states[other].setPosition(m_states[other].getPosition() + move);
    const PfxTransform3 movedA = m_states[idA].getTransform();
    const PfxTransform3 movedB = m_states[idB].getTransform();
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      PfxContactPoint& point = manifold.getContactPoint(i);
      point.m_distance = (movedB * point.m_localPointB - movedA * point.m_localPointA)
                             .dot(point.getNormal());
    }
  }
  return PFX_OK;
}

PfxInt32 PfxWorld::setRigidBody(PfxUInt32 id, const PfxRigidBody& body) {
  if (!hasRigidBody(id)) return PFX_ERR_OUT_OF_RANGE;
  if (const PfxInt32 err = validateBody(m_states[id], body); err != PFX_OK) return err;
  m_bodies[id] = body;
  wakeAfterChange(id);
  return PFX_OK;
}

PfxInt32 PfxWorld::applyForce(PfxUInt32 id, const PfxVector3& force, const PfxVector3& torque) {
  if (!hasRigidBody(id)) return PFX_ERR_OUT_OF_RANGE;
  const PfxVector3 forceSum = m_forces[id] + force, torqueSum = m_torques[id] + torque;
  if (!pfxIsFinite(forceSum) || !pfxIsFinite(torqueSum)) return PFX_ERR_INVALID_VALUE;
  m_forces[id] = forceSum;
  m_torques[id] = torqueSum;
  if (pfxMotionTypeIsDynamic(m_states[id].getMotionType()) &&
      (!force.isZero(0) || !torque.isZero(0))) {
    wakeIslandOf(id);
    restoreWokenPairs();
  }
  return PFX_OK;
}

PfxInt32 PfxWorld::setKeyframeTarget(PfxUInt32 id, const PfxVector3& position,
                                     const PfxQuat& orientation) {
  if (!hasRigidBody(id)) return PFX_ERR_OUT_OF_RANGE;
  if (m_states[id].getMotionType() != kPfxMotionTypeKeyframe) return PFX_ERR_INVALID_FLAG;
  PfxRigidState target = m_states[id];
  if (const PfxInt32 err = pfxSetKeyframeTarget(target, position, orientation, m_param.timeStep);
      err != PFX_OK) {
    return err;
  }
  if (!target.getLinearVelocity().isZero(0) || !target.getAngularVelocity().isZero(0)) {
    wakeAfterChange(id);
  }
  m_states[id].setLinearVelocity(target.getLinearVelocity());
  m_states[id].setAngularVelocity(target.getAngularVelocity());
  return PFX_OK;
}

// The arrays a step fills per body, sized with the bodies' own arrays (not to the bodies
// there are now), so that adding a body does not move them each time.
void PfxWorld::sizeBodyArraysToCapacity() {
  const std::size_t capacity = m_states.capacity();
  m_solverBodies.resize(capacity);
  m_islandMarks.resize(capacity);
  m_contactCheckedBodies.resize(capacity);
  m_proxies.resize(capacity);
  m_proxySortWork.resize(capacity);
  if (m_param.enableSleep) reserveSleepingProxies();
}

// Room for every body to sleep, taken with the bodies' own arrays so that a step in which
// bodies fall asleep allocates nothing.
void PfxWorld::reserveSleepingProxies() {
  m_sleepingProxies.resize(m_states.capacity());
  m_skipForAwakeProxies.resize(m_states.capacity());
  m_skipForSleepingProxies.resize(m_states.capacity());
  m_sleepingProxiesStale = true;
}

// Sized in the step for the bodies, joints and pairs there are then, not each time a body
// or joint is added (whose doubling left up to twice the memory needed); grows only while
// the first steps find more pairs.
void PfxWorld::reserveSolverWork(PfxUInt32 numContactPairs) {
  // The position correction after the integration works in the same buffer.
  const std::size_t workBytes = std::max<std::size_t>(
      pfxGetWorkBytesOfSolveConstraints(getNumRigidBodies(), numContactPairs, getNumJoints(), 1,
                                        m_contactTreeNodes),
      pfxGetWorkBytesOfCorrectJointPositions(getNumRigidBodies(), getNumJoints(),
                                             numContactPairs));
  growTo(m_solverWork, (workBytes + sizeof(PfxSortData16) - 1) / sizeof(PfxSortData16));
}

PfxInt32 PfxWorld::validateJoint(const PfxJoint& joint) const {
  if (!hasRigidBody(joint.m_rigidBodyIdA) || !hasRigidBody(joint.m_rigidBodyIdB)) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  return pfxCheckJoint(joint);
}

PfxInt32 PfxWorld::addJoint(const PfxJoint& joint, PfxUInt32* outId) {
  if (const PfxInt32 err = validateJoint(joint); err != PFX_OK) return err;
  const PfxUInt32 id = getNumJoints();
  m_joints.push_back(joint);
  m_jointPairs.emplace_back();
  m_removedJoints.push_back(0);
  const PfxUInt64 key = pfxCreatePairKey(std::min(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB),
                                         std::max(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB));
  m_jointedPairKeys.insert(
      std::lower_bound(m_jointedPairKeys.begin(), m_jointedPairKeys.end(), key), key);
  wakeJointBodies(id);
  if (outId) *outId = id;
  return PFX_OK;
}

PfxInt32 PfxWorld::excludeCollision(PfxUInt32 bodyIdA, PfxUInt32 bodyIdB) {
  if (!hasRigidBody(bodyIdA) || !hasRigidBody(bodyIdB)) return PFX_ERR_OUT_OF_RANGE;
  if (bodyIdA == bodyIdB) return PFX_ERR_INVALID_VALUE;
  const PfxUInt64 key = pfxCreatePairKey(std::min(bodyIdA, bodyIdB), std::max(bodyIdA, bodyIdB));
  const auto at = std::lower_bound(m_excludedPairKeys.begin(), m_excludedPairKeys.end(), key);
  if (at == m_excludedPairKeys.end() || *at != key) m_excludedPairKeys.insert(at, key);
  return PFX_OK;
}

PfxInt32 PfxWorld::setJoint(PfxUInt32 id, const PfxJoint& joint) {
  if (!hasJoint(id)) return PFX_ERR_OUT_OF_RANGE;
  const PfxJoint& old = m_joints[id];
  if (joint.m_rigidBodyIdA != old.m_rigidBodyIdA || joint.m_rigidBodyIdB != old.m_rigidBodyIdB) {
    return PFX_ERR_INVALID_VALUE;  // a joint keeps its bodies; add another for others
  }
  if (const PfxInt32 err = validateJoint(joint); err != PFX_OK) return err;
  for (const PfxJointCoupling& coupling : m_jointCouplings) {
    const bool locksLeader = coupling.m_leaderJointId == id &&
                             joint.m_constraints[coupling.m_leaderAxis].m_lock == kPfxJointLockLocked;
    const bool locksFollower =
        coupling.m_followerJointId == id &&
        joint.m_constraints[coupling.m_followerAxis].m_lock == kPfxJointLockLocked;
    if (locksLeader || locksFollower) return PFX_ERR_INVALID_VALUE;
  }
  m_joints[id] = joint;
  wakeJointBodies(id);
  return PFX_OK;
}

// The coupling with its solver state cleared and its coordinates measured at the bodies'
// current poses.
PfxJointCoupling PfxWorld::measuredCoupling(const PfxJointCoupling& coupling) const {
  PfxJointCoupling measured = coupling;
  measured.m_numBodies = 0;
  measured.m_row.m_normal.setZero();
  measured.m_row.m_rhs = measured.m_row.m_jacDiagInv = 0;
  measured.m_row.m_lowerLimit = measured.m_row.m_upperLimit = measured.m_row.m_accumImpulse = 0;
  measured.m_pushRhs = measured.m_pushImpulse = 0;
  PfxFloat coordinates[6];
  const PfxJoint& leader = m_joints[coupling.m_leaderJointId];
  pfxCalcJointCoordinates(leader, m_states[leader.m_rigidBodyIdA], m_states[leader.m_rigidBodyIdB],
                          coordinates);
  measured.m_leaderPosition = coordinates[coupling.m_leaderAxis];
  const PfxJoint& follower = m_joints[coupling.m_followerJointId];
  pfxCalcJointCoordinates(follower, m_states[follower.m_rigidBodyIdA],
                          m_states[follower.m_rigidBodyIdB], coordinates);
  measured.m_followerPosition = coordinates[coupling.m_followerAxis];
  measured.m_error = measured.m_followerPosition -
                     measured.m_multiplier * measured.m_leaderPosition - measured.m_offset;
  return measured;
}

PfxInt32 PfxWorld::addJointCoupling(const PfxJointCoupling& coupling, PfxUInt32* outId) {
  if (!couplesLiveJoints(coupling)) return PFX_ERR_OUT_OF_RANGE;
  if (const PfxInt32 err = pfxCheckJointCoupling(coupling, m_joints.data(), getNumJoints());
      err != PFX_OK) {
    return err;
  }
  const PfxUInt32 id = getNumJointCouplings();
  m_jointCouplings.push_back(measuredCoupling(coupling));
  m_removedCouplings.push_back(0);
  wakeJointBodies(coupling.m_leaderJointId);
  wakeJointBodies(coupling.m_followerJointId);
  if (outId) *outId = id;
  return PFX_OK;
}

PfxInt32 PfxWorld::setJointCoupling(PfxUInt32 id, const PfxJointCoupling& coupling) {
  if (!hasJointCoupling(id) || !couplesLiveJoints(coupling)) return PFX_ERR_OUT_OF_RANGE;
  if (const PfxInt32 err = pfxCheckJointCoupling(coupling, m_joints.data(), getNumJoints());
      err != PFX_OK) {
    return err;
  }
  wakeJointBodies(m_jointCouplings[id].m_leaderJointId);
  wakeJointBodies(m_jointCouplings[id].m_followerJointId);
  m_jointCouplings[id] = measuredCoupling(coupling);
  wakeJointBodies(coupling.m_leaderJointId);
  wakeJointBodies(coupling.m_followerJointId);
  return PFX_OK;
}

PfxInt32 PfxWorld::truncate(PfxUInt32 numBodies, PfxUInt32 numJoints,
                            PfxUInt32 numJointCouplings) {
  if (numBodies > getNumRigidBodies() || numJoints > getNumJoints() ||
      numJointCouplings > getNumJointCouplings()) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  for (PfxUInt32 i = 0; i < numJoints; ++i) {
    if (m_joints[i].m_rigidBodyIdA >= numBodies || m_joints[i].m_rigidBodyIdB >= numBodies) {
      return PFX_ERR_OUT_OF_RANGE;
    }
  }
  for (PfxUInt32 i = 0; i < numJointCouplings; ++i) {
    const PfxJointCoupling& coupling = m_jointCouplings[i];
    if (coupling.m_leaderJointId >= numJoints || coupling.m_followerJointId >= numJoints) {
      return PFX_ERR_OUT_OF_RANGE;
    }
  }
  if (particlesPinBodyIn(numBodies, getNumRigidBodies())) return PFX_ERR_OUT_OF_RANGE;
  wakeBeforeTruncate(numBodies, numJoints, numJointCouplings);
  m_jointCouplings.erase(m_jointCouplings.begin() + numJointCouplings, m_jointCouplings.end());
  m_removedCouplings.resize(numJointCouplings);
  for (PfxUInt32 i = numJoints; i < getNumJoints(); ++i) {
    if (!m_removedJoints[i]) eraseJointedPairKey(m_joints[i]);
  }
  m_joints.erase(m_joints.begin() + numJoints, m_joints.end());
  m_removedJoints.resize(numJoints);
  m_numRemovedJoints = static_cast<PfxUInt32>(
      std::count(m_removedJoints.begin(), m_removedJoints.end(), PfxUInt8(1)));
  m_jointPairs.erase(m_jointPairs.begin() + numJoints, m_jointPairs.end());
  // The larger id of a pair is the key's low half.
  m_excludedPairKeys.erase(
      std::remove_if(m_excludedPairKeys.begin(), m_excludedPairKeys.end(),
                     [numBodies](PfxUInt64 key) { return PfxUInt32(key) >= numBodies; }),
      m_excludedPairKeys.end());

  // Pairs stay sorted by key when some are taken out, and the manifolds of the removed
  // ones are reused.
  const auto dropRemovedPairs = [&](std::vector<PfxBroadphasePair>& pairs, PfxUInt32& numPairs) {
    PfxUInt32 kept = 0;
    for (PfxUInt32 i = 0; i < numPairs; ++i) {
      if (pfxGetObjectIdA(pairs[i]) < numBodies && pfxGetObjectIdB(pairs[i]) < numBodies) {
        pairs[kept++] = pairs[i];
      } else {
        releaseManifold(pfxGetContactId(pairs[i]));
      }
    }
    numPairs = kept;
  };
  dropRemovedPairs(m_pairs, m_numPairs);
  dropRemovedPairs(m_sleepingPairs, m_numSleepingPairs);
  countSleepingContacts();
  for (PfxUInt32 i = numBodies; i < getNumRigidBodies(); ++i) {
    if (m_states[i].isAsleep()) --m_numSleepingBodies;
  }
  m_states.erase(m_states.begin() + numBodies, m_states.end());
  m_bodies.erase(m_bodies.begin() + numBodies, m_bodies.end());
  m_collidables.erase(m_collidables.begin() + numBodies, m_collidables.end());
  m_forces.erase(m_forces.begin() + numBodies, m_forces.end());
  m_torques.erase(m_torques.begin() + numBodies, m_torques.end());
  m_compoundShapes.erase(m_compoundShapes.begin() + numBodies, m_compoundShapes.end());
  m_compoundShapeIds.erase(m_compoundShapeIds.begin() + numBodies, m_compoundShapeIds.end());
  m_removedBodies.resize(numBodies);
  m_numRemovedBodies = static_cast<PfxUInt32>(
      std::count(m_removedBodies.begin(), m_removedBodies.end(), PfxUInt8(1)));
  m_numProxies = 0;
  m_sleepingProxiesStale = true;
  m_rayProxiesStale = true;
  return generateIslands();
}

// Bodies held together by a joint would otherwise push each other apart where their shapes
// meet at the joint.
void PfxWorld::dropJointedPairs() {
  if (m_jointedPairKeys.empty() && m_excludedPairKeys.empty()) return;
  PfxUInt32 kept = 0;
  for (PfxUInt32 i = 0; i < m_numFoundPairs; ++i) {
    const PfxUInt64 key = m_foundPairs[i].key;
    if (!std::binary_search(m_jointedPairKeys.begin(), m_jointedPairKeys.end(), key) &&
        !std::binary_search(m_excludedPairKeys.begin(), m_excludedPairKeys.end(), key)) {
      m_foundPairs[kept++] = m_foundPairs[i];
    }
  }
  m_numFoundPairs = kept;
}

// Every stage that works on the contact pairs (or the joints) names them the same way.
template <typename Param>
void PfxWorld::bindContacts(Param& param) {
  param.contactPairs = m_pairs.data();
  param.numContactPairs = m_numPairs;
  param.offsetContactManifolds = m_manifolds.data();
  param.numContactManifolds = static_cast<PfxUInt32>(m_manifolds.size());
}

template <typename Param>
void PfxWorld::bindJoints(Param& param) {
  param.jointPairs = m_jointPairs.data();
  param.numJointPairs = getNumJoints();
  param.offsetJoints = m_joints.data();
  param.numJoints = getNumJoints();
  param.offsetJointCouplings = m_jointCouplings.data();
  param.numJointCouplings = getNumJointCouplings();
}

// Builds and sorts along the sweep axis the proxies of the bodies `skip` leaves in;
// returns how many there are and how many lie outside the world.
PfxInt32 PfxWorld::buildProxies(const PfxUInt8* skip, PfxBroadphaseProxy* proxies,
                                PfxUInt32& numProxies, PfxUInt32& numOutOfWorld) {
  PfxUpdateBroadphaseProxiesParam param;
  param.workBuff = m_proxySortWork.data();
  param.workBytes = static_cast<PfxUInt32>(m_proxySortWork.size() * sizeof(PfxSortData32));
  param.offsetRigidStates = m_states.data();
  param.offsetCollidables = m_collidables.data();
  param.numRigidBodies = getNumRigidBodies();
  param.skipBodies = skip;
  PfxBroadphaseProxy** arrays[3] = {&param.proxiesX, &param.proxiesY, &param.proxiesZ};
  *arrays[m_sweepAxis] = proxies;
  param.worldCenter = m_param.worldCenter;
  param.worldExtent = m_param.worldExtent;
  param.outOfWorldBehavior = m_param.outOfWorldBehavior;
  param.timeStep = m_param.timeStep;
  PfxUpdateBroadphaseProxiesResult result;
  const PfxInt32 err = pfxUpdateBroadphaseProxies(param, result, &m_taskManager);
  numProxies = result.numProxies;
  numOutOfWorld = result.numOutOfWorldProxies;
  m_stats.numProxiesUpdated += result.numProxies;
  return err;
}

// The sleeping bodies' proxies, built and sorted once for as long as the same bodies sleep.
// The sweep axis is chosen here too, over all bodies, and kept until the next build: the
// pairs come out the same along any axis, and a new axis would need this build again.
PfxInt32 PfxWorld::buildSleepingProxies() {
  const PfxUInt32 numBodies = getNumRigidBodies();
  for (PfxUInt32 i = 0; i < numBodies; ++i) {
    const bool removed = m_removedBodies[i] != 0;
    m_skipForAwakeProxies[i] = removed || m_states[i].isAsleep();
    m_skipForSleepingProxies[i] = removed || !m_states[i].isAsleep();
  }
  m_sweepAxis = pfxChooseSweepAxis(m_states.data(), numBodies);
  const PfxInt32 err = buildProxies(m_skipForSleepingProxies.data(), m_sleepingProxies.data(),
                                    m_numSleepingProxies, m_numSleepingOutOfWorld);
  m_sleepingProxiesStale = err != PFX_OK;
  return err;
}

PfxInt32 PfxWorld::updateBroadphase() {
  m_stats.numProxiesUpdated = 0;
  const bool keepSleeping = m_numSleepingBodies > 0 && !m_skipForAwakeProxies.empty();
  if (!keepSleeping) {
    m_numSleepingProxies = m_numSleepingOutOfWorld = 0;
    m_sleepingProxiesStale = true;
    m_sweepAxis = pfxChooseSweepAxis(m_states.data(), getNumRigidBodies());
  } else if (m_sleepingProxiesStale) {
    if (const PfxInt32 err = buildSleepingProxies(); err != PFX_OK) return err;
  }
  PfxUInt32 numOutOfWorld = 0;
  const PfxInt32 err =
      buildProxies(keepSleeping ? m_skipForAwakeProxies.data() : skippedBodies(),
                   m_proxies.data(), m_numProxies, numOutOfWorld);
  m_stats.numOutOfWorld = numOutOfWorld + m_numSleepingOutOfWorld;
  return err;
}

PfxInt32 PfxWorld::findPairs() {
  for (;;) {
    PfxFindPairsParam param;
    param.workBuff = m_pairWork.data();
    param.workBytes = pfxGetWorkBytesOfFindPairs(m_maxPairs);
    param.pairBuff = m_foundPairs.data();
    param.pairBytes = pfxGetPairBytesOfFindPairs(m_maxPairs);
    param.proxies = m_proxies.data();
    param.numProxies = m_numProxies;
    param.maxPairs = m_maxPairs;
    param.axis = m_sweepAxis;
    param.sleepingProxies = m_sleepingProxies.data();
    param.numSleepingProxies = m_numSleepingProxies;
    PfxFindPairsResult result;
    const PfxInt32 err = pfxFindPairs(param, result, &m_taskManager);
    if (err == PFX_ERR_OUT_OF_MAX_PAIRS || (err != PFX_OK && m_maxPairs == 0)) {
      // Only while the scene grows: room for twice the pairs found, as a pile still falling
      // into place (bodies landing, then settling closer) gains half as many pairs again
      // after its first overflow.
      m_maxPairs = std::max<PfxUInt32>(64, 2 * result.numPairsFound);
      m_foundPairs.resize(m_maxPairs);
      growTo(m_pairWork, m_maxPairs);
      continue;
    }
    if (err != PFX_OK) return err;
    m_numFoundPairs = result.numPairs;
    dropJointedPairs();
    return PFX_OK;
  }
}

// Room for the manifolds of `numNewPairs` more pairs, those the free slots cannot take:
// a quarter more than needed when the pool first grows (a scene built at once finds most
// of its pairs in its first step; doubling from 64 left 10,001 resting spheres with 16,384
// slots of 836 bytes, and exactly as many as needed had a settling pile allocate again in
// a later step; an eighth more saved 1,045 / 8 bytes a resting sphere, but then the
// threaded pile, still landing after 30 steps, allocated in its next five), then half as
// many again each time, so that a growing scene seldom moves them. The free list can hold
// every slot, so that freeing one never allocates, and the one-point pool has a block for
// every slot, so that it grows only with them.
void PfxWorld::reserveManifolds(PfxUInt32 numNewPairs) {
  const std::size_t numFree = m_freeManifolds.size();
  const std::size_t needed = m_manifolds.size() + (numNewPairs > numFree ? numNewPairs - numFree : 0);
  if (needed <= m_manifolds.capacity()) return;
  const std::size_t capacity = std::max(needed + needed / 4, m_manifolds.capacity() * 3 / 2);
  m_manifolds.reserve(capacity);
  m_freeManifolds.reserve(capacity);
  m_onePointBlocks.reserve(static_cast<PfxUInt32>(m_manifolds.capacity()), m_manifolds.data(),
                           static_cast<PfxUInt32>(m_manifolds.size()));
}

// Twice the blocks needed when the pool grows, as the pair buffer takes twice the pairs
// found: the pairs that may touch at several points come and go with the pairs, and a
// pile still falling into place gains half as many pairs again.
void PfxWorld::reserveFourPointBlocks(PfxUInt32 numMoreBlocks) {
  const PfxUInt32 needed = m_fourPointBlocks.getNumBlocksInUse() + numMoreBlocks;
  if (needed <= m_fourPointBlocks.getCapacity()) return;
  m_fourPointBlocks.reserve(2 * needed, m_manifolds.data(),
                            static_cast<PfxUInt32>(m_manifolds.size()));
}

// A sphere meets a sphere, box, capsule or cylinder at one point (their routines give one
// candidate for it); a body of several shapes, a convex mesh (clipped faces) or a large
// mesh (several triangles) may give more.
bool PfxWorld::mayTouchAtSeveralPoints(PfxUInt32 idA, PfxUInt32 idB) const {
  const auto onlyShape = [&](PfxUInt32 id) -> PfxShapeType {
    const PfxCollidable& collidable = m_collidables[id];
    return collidable.getNumShapes() == 1 ? collidable.getShape(0).getType()
                                          : kPfxShapeLargeTriMesh;
  };
  const PfxShapeType typeA = onlyShape(idA);
  const PfxShapeType typeB = onlyShape(idB);
  const auto primitive = [](PfxShapeType type) {
    return type == kPfxShapeSphere || type == kPfxShapeBox || type == kPfxShapeCapsule ||
           type == kPfxShapeCylinder;
  };
  return !((typeA == kPfxShapeSphere && primitive(typeB)) ||
           (typeB == kPfxShapeSphere && primitive(typeA)));
}

PfxUInt32 PfxWorld::roomForPoints(PfxUInt32 idA, PfxUInt32 idB, PfxUInt32 numPoints) const {
  if (numPoints == 0) return 0;
  return mayTouchAtSeveralPoints(idA, idB) ? PFX_NUM_CONTACTS_PER_MANIFOLD : numPoints;
}

// A manifold slot for a new pair: a freed one, or a new one at the end (reserveManifolds
// made room for it).
PfxUInt32 PfxWorld::takeManifold() {
  if (!m_freeManifolds.empty()) {
    const PfxUInt32 contactId = m_freeManifolds.back();
    m_freeManifolds.pop_back();
    return contactId;
  }
  const PfxUInt32 contactId = static_cast<PfxUInt32>(m_manifolds.size());
  m_manifolds.emplace_back(nullptr, 0);
  return contactId;
}

// A manifold's room comes from one pool or the other by its size, and goes back to it.
void PfxWorld::sizeManifold(PfxUInt32 contactId, PfxUInt32 numPoints) {
  PfxContactManifold& manifold = m_manifolds[contactId];
  const PfxContactPoint* room = manifold.getContactPoints();
  PfxContactPointPool* from = m_onePointBlocks.holds(manifold)    ? &m_onePointBlocks
                              : m_fourPointBlocks.holds(manifold) ? &m_fourPointBlocks
                                                                  : nullptr;
  PfxContactPointPool* to = numPoints == 0   ? nullptr
                            : numPoints == 1 ? &m_onePointBlocks
                                             : &m_fourPointBlocks;
  if (from == to) return;
  if (to) {
    manifold.moveContactPoints(to->take(), to->getPointsPerBlock());
  } else {
    manifold.moveContactPoints(nullptr, 0);
  }
  if (from) from->give(room);
}

// Moving pairs between the awake and the sleeping lists needs room for both in each. The
// sleeping list and the scratch that moves pairs into it (and gathers both lists for the
// islands) serve sleep alone: without it they stay empty (a world that was read from a
// file with sleeping pairs still moves them).
void PfxWorld::reservePairs() {
  const std::size_t total = std::size_t(m_numPairs) + m_numSleepingPairs;
  growTo(m_pairs, total);
  if (!m_param.enableSleep && m_numSleepingPairs == 0) return;
  growTo(m_sleepingPairs, total);
  growTo(m_pairScratch, total);
}

void PfxWorld::composeStablePairs() {
  growTo(m_pairWork, m_numPairs + m_numFoundPairs);
  PfxDecomposePairsParam param;
  param.pairBuff = m_pairWork.data();
  param.pairBytes = static_cast<PfxUInt32>(m_pairWork.size() * sizeof(PfxBroadphasePair));
  param.previousPairs = m_pairs.data();
  param.numPreviousPairs = m_numPairs;
  param.currentPairs = m_foundPairs.data();
  param.numCurrentPairs = m_numFoundPairs;
  PfxDecomposePairsResult result;
  pfxDecomposePairs(param, result);

  for (PfxUInt32 i = 0; i < result.numOutRemovePairs; ++i) {
    releaseManifold(pfxGetContactId(result.outRemovePairs[i]));
  }
  // A new pair has no points yet: it takes a manifold of its own only once it finds some
  // (settleManifolds).
  for (PfxUInt32 i = 0; i < result.numOutNewPairs; ++i) {
    pfxSetContactId(result.outNewPairs[i], m_sharedEmptyManifold);
  }

  growTo(m_pairs, m_numFoundPairs);
  auto byKey = [](const PfxBroadphasePair& a, const PfxBroadphasePair& b) { return a.key < b.key; };
  std::merge(result.outKeepPairs, result.outKeepPairs + result.numOutKeepPairs,
             result.outNewPairs, result.outNewPairs + result.numOutNewPairs, m_pairs.begin(),
             byKey);
  m_numPairs = m_numFoundPairs;
  reservePairs();
}

// Every pair starts afresh, but its manifold comes from the free list as in the stable
// pipeline, so that the pairs set aside while their bodies sleep keep theirs. Returned in
// reverse, the slots come back in pair order while the number of pairs holds.
void PfxWorld::assignSimplePairs() {
  for (PfxUInt32 i = m_numPairs; i > 0; --i) releaseManifold(pfxGetContactId(m_pairs[i - 1]));
  growTo(m_pairs, m_numFoundPairs);
  reserveManifolds(m_numFoundPairs);
  reserveFourPointBlocks(m_numFoundPairs);
  for (PfxUInt32 i = 0; i < m_numFoundPairs; ++i) {
    m_pairs[i] = m_foundPairs[i];
    const PfxUInt32 contactId = takeManifold();
    pfxSetContactId(m_pairs[i], contactId);
    sizeManifold(contactId, PFX_NUM_CONTACTS_PER_MANIFOLD);
    m_manifolds[contactId].reset(pfxGetObjectIdA(m_pairs[i]), pfxGetObjectIdB(m_pairs[i]));
  }
  m_numPairs = m_numFoundPairs;
  reservePairs();
}

PfxInt32 PfxWorld::detectCollision() {
  const bool stable = m_param.pipeline == kPfxPipelineStable;
  if (stable) {
    StageTimer timer(m_stats, kPfxStageRefreshContacts, m_param.measureStages);
    PfxRefreshContactsParam param;
    bindContacts(param);
    param.offsetRigidStates = m_states.data();
    param.numRigidBodies = getNumRigidBodies();
    param.offsetCollidables = m_collidables.data();
    if (const PfxInt32 err = pfxRefreshContacts(param, &m_taskManager); err != PFX_OK) {
      return err;
    }
  }
  StageTimer timer(m_stats, kPfxStageDetectCollision, m_param.measureStages);
  // A pair checks both its bodies, so checking every body once instead pays where there
  // are more than half as many pairs as bodies: a pile, the rain, not a hanging chain.
  const bool checkBodies = 2 * std::size_t(m_numPairs) > getNumRigidBodies();
  if (checkBodies) {
    pfxCheckContactBodies(m_states.data(), m_collidables.data(), getNumRigidBodies(),
                          m_contactCheckedBodies.data(), &m_taskManager);
  }
  PfxDetectCollisionParam param;
  bindContacts(param);
  param.checkedBodies = checkBodies ? m_contactCheckedBodies.data() : nullptr;
  param.offsetRigidStates = m_states.data();
  param.offsetCollidables = m_collidables.data();
  param.numRigidBodies = getNumRigidBodies();
  param.contactMargin = m_param.contactMargin;
  param.timeStep = m_param.timeStep;
  param.matchDistanceSq = stable ? kMatchDistanceSq : 0;
  if (!stable) return pfxDetectCollision(param, &m_taskManager);
  param.sharedEmptyContactId = m_sharedEmptyManifold;
  if (const PfxInt32 err = pfxDetectCollision(param, &m_taskManager); err != PFX_OK) return err;
  return settleManifolds(param);
}

// After the stable pipeline's collision detection: a pair left without points gives its
// manifold back and names the shared empty one; a pair that found its first points takes a
// manifold of its own, with room for one point if its contact holds no more
// (mayTouchAtSeveralPoints) and for four otherwise, and is detected again into it (the same
// points: the shared manifold had none to carry over). Neighbours that do not touch, often
// as many as the pairs that do, then cost no manifold, and a sphere on the ground the room
// of one point.
//
// A warm step allocates nothing while no more pairs touch than the manifold slots have room
// for (reserveManifolds), as before the pools: a first point takes a slot, and with it a
// block of the one-point pool, which has one for every slot, or of the four-point pool,
// which keeps one for every pair that may touch at several points, touching or not (awake
// or asleep). So a box landing on a corner and then on a face never grows a pool: its room
// for four was kept when its pair was found. A pair that found more points than its room
// holds (pfxDetectCollision left its manifold as it was) would take room for four and be
// detected again, its old points kept; no contact routine gives a sphere two points today.
PfxInt32 PfxWorld::settleManifolds(PfxDetectCollisionParam& param) {
  PfxUInt32 numFirst = 0, numOutgrown = 0;
  PfxUInt32 numAwaitingFour = m_numSleepingPairsAwaitingFour;
  for (PfxUInt32 i = 0; i < m_numPairs; ++i) {
    PfxBroadphasePair& pair = m_pairs[i];
    const PfxUInt32 numPoints = pfxGetNumConstraints(pair);
    const PfxUInt32 contactId = pfxGetContactId(pair);
    if (contactId == m_sharedEmptyManifold) {
      numFirst += numPoints > 0 ? 1 : 0;
      const bool several = mayTouchAtSeveralPoints(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
      numAwaitingFour += several || numPoints > 1 ? 1 : 0;
    } else if (numPoints == 0) {
      releaseManifold(contactId);
      pfxSetContactId(pair, m_sharedEmptyManifold);
      numAwaitingFour +=
          mayTouchAtSeveralPoints(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair)) ? 1 : 0;
    } else if (numPoints > m_manifolds[contactId].getCapacity()) {
      ++numOutgrown;
    }
  }
  reserveFourPointBlocks(numAwaitingFour + numOutgrown);
  if (numFirst + numOutgrown == 0) return PFX_OK;
  reserveManifolds(numFirst);
  for (PfxUInt32 i = 0; i < m_numPairs; ++i) {
    PfxBroadphasePair& pair = m_pairs[i];
    const PfxUInt32 numPoints = pfxGetNumConstraints(pair);
    PfxUInt32 contactId = pfxGetContactId(pair);
    if (contactId == m_sharedEmptyManifold) {
      if (numPoints == 0) continue;
      const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
      contactId = takeManifold();
      sizeManifold(contactId, roomForPoints(idA, idB, numPoints));
      m_manifolds[contactId].reset(idA, idB);
      pfxSetContactId(pair, contactId);
    } else if (numPoints > m_manifolds[contactId].getCapacity()) {
      sizeManifold(contactId, PFX_NUM_CONTACTS_PER_MANIFOLD);
    } else {
      continue;
    }
    param.contactPairs = &pair;
    param.numContactPairs = 1;
    param.offsetContactManifolds = m_manifolds.data();
    param.numContactManifolds = static_cast<PfxUInt32>(m_manifolds.size());
    if (const PfxInt32 err = pfxDetectCollision(param); err != PFX_OK) return err;
  }
  return PFX_OK;
}

void PfxWorld::releaseManifold(PfxUInt32 contactId) {
  if (contactId == m_sharedEmptyManifold) return;
  sizeManifold(contactId, 0);
  m_freeManifolds.push_back(contactId);
}

// Each manifold read takes the room settleManifolds would give it (roomForPoints).
void PfxWorld::adoptManifolds(const std::vector<PfxContactManifold>& manifolds) {
  m_manifolds.clear();
  m_onePointBlocks.clear();
  m_fourPointBlocks.clear();
  const auto roomFor = [&](const PfxContactManifold& manifold) {
    return roomForPoints(manifold.getRigidBodyIdA(), manifold.getRigidBodyIdB(),
                         manifold.getNumContacts());
  };
  PfxUInt32 numFourPoint = 0;
  for (const PfxContactManifold& manifold : manifolds) {
    numFourPoint += roomFor(manifold) > 1 ? 1 : 0;
  }
  m_manifolds.reserve(manifolds.size());
  m_onePointBlocks.reserve(static_cast<PfxUInt32>(m_manifolds.capacity()), nullptr, 0);
  reserveFourPointBlocks(numFourPoint);
  for (const PfxContactManifold& manifold : manifolds) {
    const auto contactId = static_cast<PfxUInt32>(m_manifolds.size());
    m_manifolds.emplace_back(nullptr, 0);
    sizeManifold(contactId, roomFor(manifold));
    m_manifolds[contactId] = manifold;
  }
}

// Islands over the awake pairs, the sleeping ones (so that a sleeping island stays whole),
// the joints and the couplings.
PfxInt32 PfxWorld::generateIslands() {
  const PfxUInt32 numPairs = m_numPairs + m_numSleepingPairs;
  const PfxConstraintPair* pairs = m_pairs.data();
  if (m_numSleepingPairs > 0) {
    std::copy(m_pairs.begin(), m_pairs.begin() + m_numPairs, m_pairScratch.begin());
    std::copy(m_sleepingPairs.begin(), m_sleepingPairs.begin() + m_numSleepingPairs,
              m_pairScratch.begin() + m_numPairs);
    pairs = m_pairScratch.data();
  }
  const PfxUInt32 bytes = pfxGetIslandBytes(getNumRigidBodies(), numPairs, getNumJoints());
  growTo(m_islandBuff, (bytes + sizeof(PfxSortData16) - 1) / sizeof(PfxSortData16));
  PfxGenerateIslandParam param;
  param.islandBuff = m_islandBuff.data();
  param.islandBytes = static_cast<PfxUInt32>(m_islandBuff.size() * sizeof(PfxSortData16));
  param.offsetRigidStates = m_states.data();
  param.numRigidBodies = getNumRigidBodies();
  param.contactPairs = pairs;
  param.numContactPairs = numPairs;
  param.offsetJoints = m_joints.data();
  param.numJoints = getNumJoints();
  param.offsetJointCouplings = m_jointCouplings.data();
  param.numJointCouplings = getNumJointCouplings();
  PfxGenerateIslandResult result;
  if (const PfxInt32 err = pfxGenerateIsland(param, result); err != PFX_OK) return err;
  m_island = result.island;
  return PFX_OK;
}

PfxInt32 PfxWorld::subStep(PfxFloat timeStep) {
  const PfxUInt32 numBodies = getNumRigidBodies();
  {
    StageTimer timer(m_stats, kPfxStageApplyExternalForce, m_param.measureStages);
    PfxApplyExternalForceParam param;
    param.states = m_states.data();
    param.bodies = m_bodies.data();
    param.numRigidBodies = numBodies;
    param.forces = m_forces.data();
    param.torques = m_torques.data();
    param.gravity = m_param.gravity;
    param.timeStep = timeStep;
    if (const PfxInt32 err = pfxApplyExternalForce(param, &m_taskManager); err != PFX_OK) {
      return err;
    }
    PfxApplyJointEffortsParam effortParam;
    effortParam.joints = m_joints.data();
    effortParam.numJoints = getNumJoints();
    effortParam.states = m_states.data();
    effortParam.bodies = m_bodies.data();
    effortParam.numRigidBodies = numBodies;
    effortParam.timeStep = timeStep;
    if (const PfxInt32 err = pfxApplyJointEfforts(effortParam); err != PFX_OK) return err;
  }
  {
    StageTimer timer(m_stats, kPfxStageSetupSolverBodies, m_param.measureStages);
    PfxSetupSolverBodiesParam param;
    param.states = m_states.data();
    param.bodies = m_bodies.data();
    param.solverBodies = m_solverBodies.data();
    param.numRigidBodies = numBodies;
    if (const PfxInt32 err = pfxSetupSolverBodies(param, &m_taskManager); err != PFX_OK) {
      return err;
    }
  }
  {
    StageTimer timer(m_stats, kPfxStageSetupContactConstraints, m_param.measureStages);
    PfxSetupContactConstraintsParam param;
    bindContacts(param);
    param.offsetRigidStates = m_states.data();
    param.offsetRigidBodies = m_bodies.data();
    param.offsetSolverBodies = m_solverBodies.data();
    param.numRigidBodies = numBodies;
    param.timeStep = timeStep;
    param.separateBias = m_param.separateBias;
    param.contactSlop = m_param.contactSlop;
    param.warmStartFactor = m_param.pipeline == kPfxPipelineStable ? param.warmStartFactor : 0;
    if (const PfxInt32 err = pfxSetupContactConstraints(param, &m_taskManager); err != PFX_OK) {
      return err;
    }
  }
  if (!m_joints.empty()) {
    StageTimer timer(m_stats, kPfxStageSetupJointConstraints, m_param.measureStages);
    for (PfxUInt32 i = 0; i < getNumJoints(); ++i) {
      const PfxJoint& joint = m_joints[i];
      pfxUpdateJointPairs(m_jointPairs[i], i, joint, m_states[joint.m_rigidBodyIdA],
                          m_states[joint.m_rigidBodyIdB]);
    }
    PfxSetupJointConstraintsParam param;
    bindJoints(param);
    param.offsetRigidStates = m_states.data();
    param.offsetRigidBodies = m_bodies.data();
    param.offsetSolverBodies = m_solverBodies.data();
    param.numRigidBodies = numBodies;
    param.timeStep = timeStep;
    if (const PfxInt32 err = pfxSetupJointConstraints(param, &m_taskManager); err != PFX_OK) {
      return err;
    }
  }
  if (m_solveInGroups) return solveIslandGroups(timeStep);
  {
    StageTimer timer(m_stats, kPfxStageSolveConstraints, m_param.measureStages);
    PfxSolveConstraintsParam param;
    param.workBuff = m_solverWork.data();
    param.workBytes = static_cast<PfxUInt32>(m_solverWork.size() * sizeof(PfxSortData16));
    bindJoints(param);
    bindContacts(param);
    param.offsetRigidStates = m_states.data();
    param.offsetSolverBodies = m_solverBodies.data();
    param.numRigidBodies = numBodies;
    param.iteration = m_param.iteration;
    param.timeStep = timeStep;
    param.restitutionThreshold = m_param.restitutionThreshold;
    if (m_param.enableShockPropagation) param.gravity = m_param.gravity;
    PfxUInt32 contactTreeNodes = 0;
    param.outContactTreeNodes = &contactTreeNodes;
    PfxInt32 err = pfxSolveConstraints(param, &m_taskManager);
    if (err == PFX_ERR_OUT_OF_BUFFER && contactTreeNodes > m_contactTreeNodes) {
      // A contact tree larger than any before, which the rejected solve left untouched:
      // room for it and a quarter more, so that a pile that settles into larger trees
      // does not grow the buffer step after step, and the solve again.
      m_contactTreeNodes = contactTreeNodes + contactTreeNodes / 4;
      reserveSolverWork(m_numPairs);
      param.workBuff = m_solverWork.data();
      param.workBytes = static_cast<PfxUInt32>(m_solverWork.size() * sizeof(PfxSortData16));
      err = pfxSolveConstraints(param, &m_taskManager);
    }
    if (err != PFX_OK) return err;
  }
  {
    StageTimer timer(m_stats, kPfxStageUpdateRigidStates, m_param.measureStages);
    PfxUpdateRigidStatesParam param;
    param.states = m_states.data();
    param.bodies = m_bodies.data();
    param.numRigidBodies = numBodies;
    param.timeStep = timeStep;
    if (const PfxInt32 err = pfxUpdateRigidStates(param, &m_taskManager); err != PFX_OK) {
      return err;
    }
  }
  if (m_joints.empty()) return PFX_OK;
  StageTimer timer(m_stats, kPfxStageCorrectJointPositions, m_param.measureStages);
  PfxCorrectJointPositionsParam param;
  param.workBuff = m_solverWork.data();
  param.workBytes = static_cast<PfxUInt32>(m_solverWork.size() * sizeof(PfxSortData16));
  bindJoints(param);
  bindContacts(param);
  param.offsetRigidStates = m_states.data();
  param.offsetRigidBodies = m_bodies.data();
  param.offsetSolverBodies = m_solverBodies.data();
  param.numRigidBodies = numBodies;
  param.timeStep = timeStep;
  param.iteration = m_param.iteration;
  return pfxCorrectJointPositions(param, &m_taskManager);
}

PfxConservedQuantities PfxWorld::measureConservedQuantities() const {
  PfxConservedQuantities totals;
  Eigen::Vector3d linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
  for (PfxUInt32 i = 0; i < getNumRigidBodies(); ++i) {
    const PfxRigidState& s = m_states[i];
    if (!pfxMotionTypeIsDynamic(s.getMotionType())) continue;
    const PfxRigidBody& b = m_bodies[i];
    const Eigen::Vector3d v = s.getLinearVelocity().cast<double>();
    const Eigen::Vector3d w = s.getAngularVelocity().cast<double>();
    const Eigen::Vector3d x = s.getPosition().cast<double>();
    const Eigen::Matrix3d inertia =
        pfxRotateInertia(s.getOrientation().toRotationMatrix(), b.getInertia()).cast<double>();
    const Eigen::Vector3d p = double(b.getMass()) * v;
    totals.energy += 0.5 * (p.dot(v) + w.dot(inertia * w)) -
                     double(b.getMass()) * m_param.gravity.cast<double>().dot(x);
    linear += p;
    angular += x.cross(p) + inertia * w;
  }
  totals.linearMomentum = linear.cast<PfxFloat>();
  totals.angularMomentum = angular.cast<PfxFloat>();
  return totals;
}

void PfxWorld::gatherStats() {
  m_stats.maxJointGap = 0;
  for (PfxUInt32 id = 0; id < getNumJoints(); ++id) {
    if (m_removedJoints[id]) continue;
    const PfxJoint& joint = m_joints[id];
    bool anchored = true;
    for (int axis = 0; axis < 3; ++axis) {
      anchored = anchored && joint.m_constraints[axis].m_lock == kPfxJointLockLocked;
    }
    if (!anchored) continue;
    const PfxRigidState& a = m_states[joint.m_rigidBodyIdA];
    const PfxRigidState& b = m_states[joint.m_rigidBodyIdB];
    const PfxFloat gap = ((a.getPosition() + a.getOrientation() * joint.m_anchorA) -
                          (b.getPosition() + b.getOrientation() * joint.m_anchorB))
                             .norm();
    m_stats.maxJointGap = std::max(m_stats.maxJointGap, gap);
  }
  m_stats.numPairs = m_numPairs;
  // Every manifold is read, so chunks of pairs are counted in parallel: sums of counts and
  // a maximum come out the same however the pairs are split.
  struct ContactTally {
    PfxUInt32 pairs = 0;
    PfxUInt32 points = 0;
    PfxFloat deepest = 0;
  };
  constexpr PfxUInt32 kMaxChunks = 64;
  ContactTally tallies[kMaxChunks];
  const PfxUInt32 numChunks = pfxNumChunks(&m_taskManager, m_numPairs, 1024, kMaxChunks);
  pfxParallelFor(&m_taskManager, numChunks, 1, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 c = first; c < last; ++c) {
      ContactTally& tally = tallies[c];
      for (PfxUInt32 i = pfxChunkBegin(m_numPairs, numChunks, c);
           i < pfxChunkBegin(m_numPairs, numChunks, c + 1); ++i) {
        const PfxContactManifold& manifold = m_manifolds[pfxGetContactId(m_pairs[i])];
        if (manifold.getNumContacts() == 0) continue;
        ++tally.pairs;
        tally.points += manifold.getNumContacts();
        tally.deepest = std::max(tally.deepest, manifold.getPenetrationDepth());
      }
    }
  });
  m_stats.numContactPairs = 0;
  m_stats.numContactPoints = 0;
  m_stats.maxPenetration = 0;
  for (PfxUInt32 c = 0; c < numChunks; ++c) {
    m_stats.numContactPairs += tallies[c].pairs;
    m_stats.numContactPoints += tallies[c].points;
    m_stats.maxPenetration = std::max(m_stats.maxPenetration, tallies[c].deepest);
  }
}

PfxInt32 PfxWorld::step() {
  const Clock::time_point start = Clock::now();
  PfxConservedQuantities before;
  if (m_param.measureConservation) before = measureConservedQuantities();
  m_rayProxiesStale = true;
  for (double& seconds : m_stats.stageSeconds) seconds = 0;
  {
    StageTimer timer(m_stats, kPfxStageDetectParticleContacts, m_param.measureStages);
    if (const PfxInt32 err = detectParticleContacts(); err != PFX_OK) return err;
  }
  {
    StageTimer timer(m_stats, kPfxStageUpdateBroadphaseProxies, m_param.measureStages);
    if (const PfxInt32 err = updateBroadphase(); err != PFX_OK) return err;
  }
  {
    StageTimer timer(m_stats, kPfxStageFindPairs, m_param.measureStages);
    if (const PfxInt32 err = findPairs(); err != PFX_OK) return err;
  }
  {
    StageTimer timer(m_stats, kPfxStageDecomposePairs, m_param.measureStages);
    if (m_param.pipeline == kPfxPipelineStable) {
      composeStablePairs();
    } else {
      assignSimplePairs();
    }
  }
  if (const PfxInt32 err = detectCollision(); err != PFX_OK) return err;
  {
    StageTimer timer(m_stats, kPfxStageGenerateIsland, m_param.measureStages);
    if (const PfxInt32 err = generateIslands(); err != PFX_OK) return err;
    wakeTouchedIslands();
  }
  reserveSolverWork(m_numPairs);
  m_solveInGroups = buildIslandGroups();
  const PfxFloat subTimeStep = m_param.timeStep / PfxFloat(m_param.subStep);
  for (PfxUInt32 i = 0; i < m_param.subStep; ++i) {
    if (const PfxInt32 err = subStep(subTimeStep); err != PFX_OK) return err;
    if (const PfxInt32 err = particleSubStep(subTimeStep); err != PFX_OK) return err;
  }
  // The particles moved bodies, and the rays' hierarchy was built for their contacts.
  m_rayProxiesStale = true;
  std::fill(m_forces.begin(), m_forces.end(), PfxVector3::Zero());
  std::fill(m_torques.begin(), m_torques.end(), PfxVector3::Zero());
  m_simulatedTime += m_param.timeStep;
  {
    StageTimer timer(m_stats, kPfxStageGenerateIsland, m_param.measureStages);
    updateSleep();
  }
  updateParticleSleep();
  gatherStats();
  gatherSleepStats();
  gatherParticleStats();
  if (m_param.measureConservation) {
    const PfxConservedQuantities after = measureConservedQuantities();
    m_stats.energyChange = after.energy - before.energy;
    m_stats.linearMomentumChange = (after.linearMomentum - before.linearMomentum).norm();
    m_stats.angularMomentumChange = (after.angularMomentum - before.angularMomentum).norm();
  }
  m_stats.stepSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  return PFX_OK;
}

}  // namespace pfx
