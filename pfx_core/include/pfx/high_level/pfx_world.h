// The high-level world: owns every buffer, grows them as bodies are added, and runs the
// simple or the stable pipeline of seed chapter 4 over them, with simulation islands and
// sleep (seed 3_sleep). After the first steps have sized the pair and contact buffers, a
// step allocates no memory.
#pragma once

#include <memory>
#include <vector>

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/high_level/pfx_contact_point_pool.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_tbb_task_manager.h"
#include "pfx/high_level/pfx_particle_group.h"
#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"
#include "pfx/low_level/collision/pfx_detect_collision.h"
#include "pfx/low_level/collision/pfx_query_contacts.h"
#include "pfx/low_level/particle/pfx_query_particles.h"
#include "pfx/low_level/raycast/pfx_cast_rays.h"
#include "pfx/low_level/solver/pfx_island_generation.h"

namespace pfx {

class PfxIslandGroups;
struct PfxIslandGroupsWorld;

enum PfxPipelineType : PfxUInt8 {
  // No data kept between frames: fastest, but stacks are not stable (seed 1_simple).
  kPfxPipelineSimple = 0,
  // Pairs, contact points and impulses carried over, solver warm started (seed 2_stable).
  kPfxPipelineStable,
};

// Bounds on PfxWorldParam::subStep and ::iteration, refused above with PFX_ERR_OUT_OF_RANGE:
// a robot needs a few sub-steps of tens of iterations, and a file or call asking for
// billions would make one step run for minutes. At both maximums a step solves 100000
// times.
constexpr PfxUInt32 PFX_MAX_SUB_STEPS = 100;
constexpr PfxUInt32 PFX_MAX_ITERATIONS = 1000;
// Bound on PfxWorldParam::timeStep (seconds), refused above with PFX_ERR_OUT_OF_RANGE: a body
// at the speed limit (kPfxMaxLinearSpeed) moves at most kPfxMaxShapeReach in a step. A time
// step of 1.6e17 s, whose gravity alone was finite, turned hinged bars NaN in their first
// step at two sub-steps, and one of 1e10 s at four.
constexpr PfxFloat PFX_MAX_TIME_STEP = PfxFloat(100);

struct PfxWorldParam {
  PfxVector3 worldCenter = PfxVector3::Zero();
  PfxVector3 worldExtent = PfxVector3::Constant(1000);
  PfxVector3 gravity = PfxVector3(0, PfxFloat(-9.80665), 0);
  PfxFloat timeStep = PfxFloat(1) / 60;  // above 0, at most PFX_MAX_TIME_STEP
  // The solver and the integrator run subStep times per step, at timeStep / subStep, on
  // the contacts found once per step: small steps converge stacks and chains far better
  // than more iterations of one large step.
  PfxUInt32 subStep = 1;      // 1 .. PFX_MAX_SUB_STEPS
  PfxUInt32 iteration = 10;  // per sub-step, 1 .. PFX_MAX_ITERATIONS
  PfxPipelineType pipeline = kPfxPipelineStable;
  PfxFloat separateBias = PfxFloat(0.2);
  // Overlap tolerated without correction, so that resting contacts do not jitter.
  PfxFloat contactSlop = PfxFloat(0.005);
  // Shapes closer than this become speculative contacts (plus what velocity closes in a step).
  PfxFloat contactMargin = PfxFloat(0.02);
  PfxFloat restitutionThreshold = PfxFloat(0.2);
  // After the iterations, one pass over the contacts that hold bodies up (normal within
  // 45 degrees of gravity), from the ground upwards, each as if its lower body could not
  // move: piles then carry their weight at few iterations instead of sinking into
  // themselves. The pass's impulses act on the upper bodies alone, so momentum is not
  // balanced at those contacts within the step, and small stacks at rest creep sideways by
  // millimetres before they sleep: off unless a scene has deep piles at few iterations.
  // Steps with joints or couplings go without it.
  bool enableShockPropagation = false;
  // Measure the total energy and momentum before and after each step (two passes over the
  // bodies) and report their change in PfxWorldStats.
  bool measureConservation = false;
  // Time each stage of the step into PfxWorldStats::stageSeconds (stepSeconds is timed
  // always). Off by default: two clock reads a stage, 26 a step without joints and 30 with,
  // were a third of the step of a world of one body (the spinner of pfx_bench), and 3 % of
  // a robot arm's.
  bool measureStages = false;
  PfxUInt32 outOfWorldBehavior = PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION;
  // Sleep (seed 3_sleep): an island (pfx_island_generation.h) whose active, one-way and
  // keyframe bodies have all moved slower than both velocities for sleepTime falls asleep
  // as a whole: its velocities are zeroed, and its bodies cost neither collision detection
  // nor solving until something wakes them. A keyframe body counts as still only at zero
  // velocity, as sleeping would stop a motion the application prescribed; likewise the
  // bodies of a joint whose drive has a velocity to keep or a position still to reach
  // (further than 1 mm or 1 mrad). What wakes an island: an awake body that forces move
  // touching it (they form one island), a moving keyframe body touching it, and any change
  // the application makes to one of its bodies, joints or couplings or to a body it rests
  // on (see the setters). sleepTime / timeStep may not exceed 65535 steps. Turn sleep off
  // to measure the solver's long-term behaviour.
  bool enableSleep = true;
  PfxFloat sleepLinearVelocity = PfxFloat(0.15);  // m/s
  PfxFloat sleepAngularVelocity = PfxFloat(0.15);  // rad/s
  PfxFloat sleepTime = PfxFloat(0.5);              // s
  // Threads that run the step and batches of rays, the calling thread included; 0 takes
  // every core the process may use; at most PFX_MAX_THREADS. The results are the same bits
  // with any number. One by default: a world is often one of many (simulations run side
  // by side, a ROS node beside other nodes), and the caller knows best what the machine
  // has to spare.
  PfxUInt32 numThreads = 1;
};

// The stages of a step, named as in the seed; index of PfxWorldStats::stageSeconds. The
// broad phase, collision detection and islands run once per step, the rest once per
// sub-step.
enum PfxStage : PfxUInt8 {
  kPfxStageApplyExternalForce = 0,
  kPfxStageUpdateBroadphaseProxies,
  kPfxStageFindPairs,
  kPfxStageDecomposePairs,
  kPfxStageRefreshContacts,
  kPfxStageDetectCollision,
  kPfxStageSetupSolverBodies,
  kPfxStageSetupContactConstraints,
  kPfxStageSetupJointConstraints,
  kPfxStageSolveConstraints,
  kPfxStageUpdateRigidStates,
  kPfxStageCorrectJointPositions,
  // Once per step, after collision detection: islands, then waking and putting them to sleep.
  kPfxStageGenerateIsland,
  // Particles (pfx_particle_group.h): contacts once per step (their planes' per-sub-step
  // refresh, pfxRefreshParticleContacts, counts here too), the rest once per sub-step.
  kPfxStageDetectParticleContacts,
  kPfxStageIntegrateParticles,
  kPfxStageSolveParticleConstraints,
  kPfxStageUpdateParticles,
  kPfxStageCount
};

const char* pfxStageName(PfxStage stage);

struct PfxWorldStats {
  // With PfxWorldParam::measureStages: the wall time of each stage in the last step, summed
  // over its sub-steps; zero without.
  double stageSeconds[kPfxStageCount] = {};
  double stepSeconds = 0;
  // Broadphase pairs the step worked on: a pair whose bodies all sleep (or are fixed) costs
  // nothing and is counted in numSleepingPairs instead.
  PfxUInt32 numPairs = 0;
  // Contacts as they stand after the step, those of sleeping bodies included.
  PfxUInt32 numContactPairs = 0;   // pairs with at least one contact point
  PfxUInt32 numContactPoints = 0;
  PfxUInt32 numOutOfWorld = 0;
  // Broadphase proxies the step built and sorted: one per body awake or fixed, and, in a
  // step after bodies fell asleep or woke, one per sleeping body too; a sleeping body's
  // proxy is otherwise kept as it was.
  PfxUInt32 numProxiesUpdated = 0;
  PfxFloat maxPenetration = 0;     // deepest overlap among contact points (m, >= 0)
  // Largest distance between the two anchors of a joint whose translations are all locked,
  // after the step (m); 0 without such joints.
  PfxFloat maxJointGap = 0;
  // With PfxWorldParam::measureConservation: how much the step changed the totals of
  // PfxConservedQuantities (J, kg m/s, kg m^2/s). Gravity, forces, contacts with fixed or
  // keyframe bodies and inelastic collisions change them; a free body must not.
  double energyChange = 0;
  double linearMomentumChange = 0;
  double angularMomentumChange = 0;
  // Sleep, after the step: islands (bodies that are not fixed, grouped as in
  // pfx_island_generation.h), those asleep, the bodies that are not fixed awake and asleep,
  // and the pairs set aside because all their bodies sleep or are fixed.
  PfxUInt32 numIslands = 0;
  PfxUInt32 numSleepingIslands = 0;
  PfxUInt32 numAwakeBodies = 0;
  PfxUInt32 numSleepingBodies = 0;
  PfxUInt32 numSleepingPairs = 0;
  // The groups of islands the step solved one a task (0: the world as a whole). With two
  // threads or more, a world of several islands is solved, integrated and corrected a group
  // of islands at a time, with the same bits; the three stages' seconds are then summed
  // over the groups, which run at the same time.
  PfxUInt32 numIslandGroups = 0;
  // Particles, after the step: in all groups, the groups awake and asleep, the contacts the
  // step solved (with bodies and among particles), and the deepest overlap of a particle
  // with a body at the end of the step (m, >= 0).
  PfxUInt32 numParticles = 0;
  PfxUInt32 numAwakeParticleGroups = 0;
  PfxUInt32 numSleepingParticleGroups = 0;
  PfxUInt32 numParticleContacts = 0;
  PfxFloat maxParticlePenetration = 0;
};

// Totals over the bodies that forces move (active and one-way, awake or asleep).
struct PfxConservedQuantities {
  double energy = 0;  // kinetic plus potential in the world's gravity (J)
  PfxVector3 linearMomentum = PfxVector3::Zero();
  PfxVector3 angularMomentum = PfxVector3::Zero();  // about the world origin
};

class PfxWorld {
 public:
  PfxWorld();
  ~PfxWorld();
  PfxWorld(const PfxWorld&) = delete;
  PfxWorld& operator=(const PfxWorld&) = delete;

  // Validates and takes the parameters; removes every body. PFX_ERR_INVALID_VALUE for a
  // value that is not finite, not positive or not within its rule above; PFX_ERR_OUT_OF_RANGE
  // for a longer time step, more threads, sub-steps or iterations than PFX_MAX_TIME_STEP,
  // PFX_MAX_THREADS, PFX_MAX_SUB_STEPS, PFX_MAX_ITERATIONS; PFX_ERR_INVALID_FLAG for an unknown
  // pipeline or behaviour. On error nothing changes.
  PfxInt32 initialize(const PfxWorldParam& param);
  // Between steps: a new time step, sub-steps, iterations and gravity, with the bodies,
  // joints, contacts and sleep kept. Checked as initialize() checks them; on error
  // nothing changes. A body asleep stays asleep in a new gravity until something wakes it.
  PfxInt32 setStepParam(PfxFloat timeStep, PfxUInt32 subStep, PfxUInt32 iteration,
                        const PfxVector3& gravity);
  const PfxWorldParam& getParam() const { return m_param; }
  // The threads the world runs on, for the caller's own calls of the low-level stages
  // between steps (pfxCastRays with many rays, for example).
  PfxTaskManager* getTaskManager() { return &m_taskManager; }

  // Adds a body with one shape or a compound of up to 64 (the shapes are copied). The
  // state's rigid body id is set to the new id, and the body starts awake (the world alone
  // puts bodies to sleep). Rejects an invalid state (NaN, non-unit orientation), an invalid
  // mass or inertia on a body that forces move (PfxRigidBody::isValid), a non-finite one on
  // any other, invalid shapes and too many shapes; the world is unchanged then.
  PfxInt32 addRigidBody(const PfxRigidState& state, const PfxRigidBody& body,
                        const PfxShape* shapes, PfxUInt32 numShapes, PfxUInt32* outId = nullptr);
  // Room for `numBodies` bodies in all, taken at once: the world's per-body arrays then hold
  // exactly that many, where adding bodies one by one doubles them (up to twice the memory
  // needed). Adding beyond it still works and grows them as before; a count at or below the
  // room there is changes nothing.
  void reserveRigidBodies(PfxUInt32 numBodies);

  // Ids run below getNumRigidBodies(), removed ones included (see removeRigidBody).
  PfxUInt32 getNumRigidBodies() const { return static_cast<PfxUInt32>(m_states.size()); }
  // Whether `id` names a body: below getNumRigidBodies() and not removed.
  bool hasRigidBody(PfxUInt32 id) const { return id < getNumRigidBodies() && !m_removedBodies[id]; }
  PfxUInt32 getNumRemovedRigidBodies() const { return m_numRemovedBodies; }
  const PfxRigidState& getRigidState(PfxUInt32 id) const { return m_states[id]; }
  const PfxRigidBody& getRigidBody(PfxUInt32 id) const { return m_bodies[id]; }
  const PfxCollidable& getCollidable(PfxUInt32 id) const { return m_collidables[id]; }
  const PfxRigidState* getRigidStates() const { return m_states.data(); }

  // Replaces a body's state (its id is kept, it is stored awake) or attributes, after the
  // same checks as addRigidBody. Wakes the body's island and, for a fixed or keyframe
  // body, the islands touching it or jointed to it (they may rest on it).
  PfxInt32 setRigidState(PfxUInt32 id, const PfxRigidState& state);
  PfxInt32 setRigidBody(PfxUInt32 id, const PfxRigidBody& body);

  // A force and torque (world frame, about the centre of mass) applied during the next
  // step only; calls add up. A force or torque other than zero wakes the body's island.
  // Refuses non-finite values and a call whose sum with the earlier ones overflows
  // (PFX_ERR_INVALID_VALUE, the sum kept as it was).
  PfxInt32 applyForce(PfxUInt32 id, const PfxVector3& force, const PfxVector3& torque);
  // Moves a keyframe body to the pose over the next step (seed 4_motion_type). A target
  // other than the current pose wakes the body and the islands touching it; a keyframe
  // body held at its pose can fall asleep.
  PfxInt32 setKeyframeTarget(PfxUInt32 id, const PfxVector3& position,
                             const PfxQuat& orientation);

  // Deforms a large mesh that body `id` holds, between steps (seed 8_deform_mesh): moves its
  // vertices (pfxUpdateLargeTriMeshVertices), refreshes the body's bounds, carries the
  // contact points on the mesh to the moved triangles by their corner weights, and puts a
  // body that the move pushed deeper back onto the surface (moved along the contact normal
  // by the added depth), waking the islands on it. Rejects an id out of range
  // (PFX_ERR_OUT_OF_RANGE), a body without a shape naming `mesh` (PFX_ERR_INVALID_VALUE) and
  // whatever the vertex update rejects; nothing changes then. Allocates nothing.
  PfxInt32 updateLargeTriMesh(PfxUInt32 id, PfxLargeTriMesh& mesh, const PfxFloat* vertices,
                              PfxUInt32 numVertices);

  // Adds a joint between two bodies of this world, made with pfxInitialize...Joint. Rejects
  // unknown or equal body ids and anything pfxCheckJoint rejects; the world is unchanged
  // then. Bodies held by a joint do not collide with each other. Adding or replacing a joint
  // or a coupling wakes the islands of its bodies.
  PfxInt32 addJoint(const PfxJoint& joint, PfxUInt32* outId = nullptr);
  PfxUInt32 getNumJoints() const { return static_cast<PfxUInt32>(m_joints.size()); }
  const PfxJoint& getJoint(PfxUInt32 id) const { return m_joints[id]; }
  // Replaces a joint (same checks as addJoint); use it to change limits or drives. An axis
  // that a coupling uses cannot be locked (PFX_ERR_INVALID_VALUE).
  PfxInt32 setJoint(PfxUInt32 id, const PfxJoint& joint);

  // Bodies A and B never collide with each other from now on, as if a joint held them (the
  // links of a robot that overlap where it starts, for one). Rejects unknown ids
  // (PFX_ERR_OUT_OF_RANGE) and equal ones (PFX_ERR_INVALID_VALUE); the world is unchanged
  // then. truncate drops the exclusions of the bodies it removes.
  PfxInt32 excludeCollision(PfxUInt32 bodyIdA, PfxUInt32 bodyIdB);

  // Couples two joint axes: follower = multiplier * leader + offset (URDF <mimic>). Rejects
  // what pfxCheckJointCoupling rejects (unknown joints or axes: PFX_ERR_OUT_OF_RANGE; a
  // locked axis, NaN, a bias outside [0, 1]: PFX_ERR_INVALID_VALUE); the world is unchanged
  // then. The coordinates are measured now, so that rotations are followed across turns
  // from here on.
  PfxInt32 addJointCoupling(const PfxJointCoupling& coupling, PfxUInt32* outId = nullptr);
  PfxUInt32 getNumJointCouplings() const { return static_cast<PfxUInt32>(m_jointCouplings.size()); }
  const PfxJointCoupling& getJointCoupling(PfxUInt32 id) const { return m_jointCouplings[id]; }
  // Replaces a coupling (same checks); its impulse starts afresh.
  PfxInt32 setJointCoupling(PfxUInt32 id, const PfxJointCoupling& coupling);

  // Keeps the first numBodies bodies, numJoints joints and numJointCouplings couplings and
  // removes the rest, as if they had never been added: their contact pairs go, bodies they
  // held apart may collide again, and rays no longer see them (a loader undoing a load that
  // failed half way). Kept bodies that touched or were jointed to removed ones wake with
  // their islands, so that nothing sleeps on a support that is gone. Rejects a count above
  // the current one and a kept joint or coupling that names a removed body or joint
  // (PFX_ERR_OUT_OF_RANGE); nothing changes then.
  PfxInt32 truncate(PfxUInt32 numBodies, PfxUInt32 numJoints, PfxUInt32 numJointCouplings);

  // Removal, between steps. Ids are the indices that every caller keeps (a URDF model's
  // link-to-body map, a ROS node's names, a saved file), so a removed body or joint leaves
  // its slot behind instead of moving another into it: every other id keeps naming what it
  // named, and removal costs a pass over the pairs and joints, not a rebuild. The slot is
  // inert: a fixed body at the world's centre with no shape memory of its own, contact
  // filters 0 and no broadphase or ray proxy, so that no pair, ray, contact query, particle
  // or statistic sees it, and it costs a step only the loops over all bodies. A removed id
  // is never given out again (addRigidBody and addJoint append), so a stale id held by an
  // application is rejected with PFX_ERR_OUT_OF_RANGE by every call that takes an id rather
  // than naming a newer body; initialize() or truncate() below the slot reclaims it.
  // getRigidState() of a removed id gives the inert slot. Saved files keep the slots
  // (pfx_serialize.h), so ids survive a save and load.
  //
  // Removing a body removes, as a physics engine's user expects of a body that is gone:
  // the joints that name it (and the couplings that name those), its contact pairs and
  // their manifolds, the collision exclusions that name it, its pending force. The islands
  // it touched or was jointed to wake, so that nothing sleeps on a support that is gone.
  // Rejected, with nothing changed: an id without a body (PFX_ERR_OUT_OF_RANGE), and a body
  // that particles are pinned or tethered to (PFX_ERR_INVALID_VALUE: remove the particle
  // group first). A character controller (pfx_character_controller.h) driving the body
  // must be dropped by the application first; its calls on a removed body fail.
  PfxInt32 removeRigidBody(PfxUInt32 id);
  // Removes a joint and the couplings that name it; its bodies may collide again and their
  // islands wake. PFX_ERR_OUT_OF_RANGE for an id without a joint.
  PfxInt32 removeJoint(PfxUInt32 id);
  bool hasJoint(PfxUInt32 id) const { return id < getNumJoints() && !m_removedJoints[id]; }
  PfxUInt32 getNumRemovedJoints() const { return m_numRemovedJoints; }
  bool hasJointCoupling(PfxUInt32 id) const {
    return id < getNumJointCouplings() && !m_removedCouplings[id];
  }

  // Particle groups (seed sample 9; pfx_particle_group.h), stepped with the bodies in every
  // step: at each sub-step after the bodies, so that a rope pinned to a body pulls it and a
  // body a rope rests on pushes it in the same sub-step. A group gets the lowest free id.
  // Rejects what pfxCheckParticleConstraints rejects (invalid particles, constraints or pins
  // naming particles or bodies that do not exist, negative compliance, ...), an iteration
  // count of 0 and a negative damping, with the detail in pfxGetLastErrorDetail(); the world
  // is unchanged then. Pins and tethers to bodies keep the bodies from being truncated away.
  PfxInt32 addParticleGroup(const PfxParticleGroupDesc& desc, PfxUInt32* outId = nullptr);
  // Removes a group; its id becomes free. PFX_ERR_OUT_OF_RANGE for an id without a group.
  PfxInt32 removeParticleGroup(PfxUInt32 id);
  // Ids run below getParticleGroupCapacity(); getParticleGroup is null for a free id.
  PfxUInt32 getParticleGroupCapacity() const {
    return static_cast<PfxUInt32>(m_particleGroups.size());
  }
  const PfxParticleGroup* getParticleGroup(PfxUInt32 id) const {
    return id < m_particleGroups.size() ? m_particleGroups[id].get() : nullptr;
  }
  // Moves one particle (and its sub-step start, so it gains no velocity), waking its group:
  // how an application drives particles of zero mass. Rejects an unknown group or particle
  // (PFX_ERR_OUT_OF_RANGE) and a non-finite position (PFX_ERR_INVALID_VALUE).
  PfxInt32 setParticlePosition(PfxUInt32 groupId, PfxUInt32 particle, const PfxVector3& position);
  // The points where particles touch bodies as the last step left them (a sleeping group
  // keeps those it had when it fell asleep, as sleeping bodies keep theirs), speculative
  // ones within the contact margin included: appended to out[result.numContacts ..
  // maxContacts - 1], group by group, with result.truncated set when some do not fit.
  // Rejects a null out with room in it (PFX_ERR_NULL_POINTER); nothing is written then.
  PfxInt32 getParticleBodyContacts(PfxParticleBodyContact* out, PfxUInt32 maxContacts,
                                   PfxQueryContactsResult& result) const;
  // The same for particles of two groups touching (a cable lying on a cloth): the pairs
  // of particles of the last step's contacts between groups, speculative ones included,
  // group A's id below group B's; two groups that fell asleep touching keep theirs.
  PfxInt32 getParticleGroupContacts(PfxParticleGroupContact* out, PfxUInt32 maxContacts,
                                    PfxQueryContactsResult& result) const;
  // The particles within the query's threshold of a collidable at a pose, as queryContacts
  // gives bodies (pfx_query_particles.h).
  PfxInt32 queryParticleContacts(const PfxContactQueryInput& query, PfxParticleQueryContact* out,
                                 PfxUInt32 maxContacts, PfxQueryContactsResult& result) const;

  // One step of param.timeStep.
  PfxInt32 step();
  // Seconds simulated since initialize(): the sum of the steps taken (a loaded world goes
  // on from the saved one's time).
  double getSimulatedTime() const { return m_simulatedTime; }
  // Sets the clock that steps advance, for a world rebuilt to continue another's time (a
  // simulator's reset whose time stamps must not go back). PFX_ERR_INVALID_VALUE and
  // nothing changed for a time that is negative, NaN or infinite.
  PfxInt32 setSimulatedTime(double seconds);
  const PfxWorldStats& getStats() const { return m_stats; }
  PfxConservedQuantities measureConservedQuantities() const;

  // The closest hit of a ray, or of each of `numRays` rays, on the bodies and particles as
  // they are now (seed chapter 5; rules in pfx_ray.h, pfx_cast_rays.h and, for particles,
  // pfx_query_particles.h: ropes are their particles' spheres, cloths their triangles). A
  // particle's hit names its group and particle (PfxRayOutput::m_particleGroupId,
  // m_particleIndex) and has no body; of a body and a particle hit at the same fraction
  // the body wins. Particles are searched group by group, inside each group's bounding box
  // one by one: a ray that misses a group's box costs one box test. The first cast after a step
  // or a change to the bodies updates the bodies' proxies and the hierarchy over them that
  // rays descend (pfx_build_ray_bvh.h: about ten times the rays per second of the seed's
  // sorted arrays among 1,000 bodies), so a world that casts no rays never pays for them,
  // and all casts between two steps share one update. Rays see every body, also those
  // outside the world's bounds. Rejects what pfxCastSingleRay and pfxCastRays reject, and a
  // body whose state is no longer valid (PFX_ERR_INVALID_VALUE), with the output untouched.
  // castRays casts a batch of 64 rays or more in the Morton order of their start points
  // (PfxRayCastParam::workBuff), which finds the same hits faster on large meshes, on the
  // world's threads (PfxWorldParam::numThreads), each ray writing only its own output.
  // Allocates only after bodies were added, and when a batch is larger than any before.
  PfxInt32 castRay(const PfxRayInput& in, PfxRayOutput& out);
  PfxInt32 castRays(const PfxRayInput* in, PfxRayOutput* out, PfxUInt32 numRays);

  // The contact points between a collidable placed at a pose and the bodies as they are now
  // (pfx_query_contacts.h: normals from the query to the body, negative distances where
  // they overlap), found through the same hierarchy as rays and sharing its update: what a
  // character controller asks for its ground, its walls and the room to step up. Every body
  // is seen, also those outside the world's bounds. Rejects what pfxQueryContacts rejects
  // and a body whose state is no longer valid (PFX_ERR_INVALID_VALUE), with the output and
  // result untouched. Allocates as castRay does.
  PfxInt32 queryContacts(const PfxContactQueryInput& query, PfxQueryContact* out,
                         PfxUInt32 maxContacts, PfxQueryContactsResult& result);

  // The pairs of the last step and their contact manifolds: those with an awake body that is
  // not fixed, sorted by key, then those set aside while all their bodies sleep (or are
  // fixed), sorted by key. A sleeping pair keeps the points it had when it fell asleep. A
  // pair without points may name the empty manifold that all such pairs share, whose body
  // ids are not the pair's: take the bodies from the pair.
  PfxUInt32 getNumContactPairs() const { return m_numPairs + m_numSleepingPairs; }
  const PfxConstraintPair& getContactPair(PfxUInt32 i) const {
    return i < m_numPairs ? m_pairs[i] : m_sleepingPairs[i - m_numPairs];
  }
  const PfxContactManifold& getContactManifold(const PfxConstraintPair& pair) const {
    return m_manifolds[pfxGetContactId(pair)];
  }

  // The simulation islands of the last step (pfx_island_generation.h), over all the pairs
  // above, the joints and the couplings; an island is asleep when its bodies are. Bodies
  // added since belong to none (pfxGetIslandId gives PFX_ISLAND_NONE).
  const PfxIsland& getIsland() const { return *m_island; }

 private:
  // pfxSaveWorld and pfxLoadWorld (pfx_serialize.h) read and restore the private state that
  // a step carries over: pairs, manifolds and their free slots, sleep.
  friend class PfxSerializeAccess;

  static PfxInt32 checkParam(const PfxWorldParam& param);
  static PfxInt32 validateBody(const PfxRigidState& state, const PfxRigidBody& body);
  // Room for n bodies; when there is less, `capacity` (at least n) is taken.
  void reserveBodies(std::size_t n, std::size_t capacity);
  void sizeBodyArraysToCapacity();
  PfxInt32 updateBroadphase();
  PfxInt32 findPairs();
  void reserveManifolds(PfxUInt32 numNewPairs);
  // Room in the four-point pool for `numMoreBlocks` blocks beyond those in use.
  void reserveFourPointBlocks(PfxUInt32 numMoreBlocks);
  PfxUInt32 takeManifold();
  // Whether the contact of bodies idA and idB may hold more than one point: all but a
  // sphere against one sphere, box, capsule or cylinder (a body of one shape each).
  bool mayTouchAtSeveralPoints(PfxUInt32 idA, PfxUInt32 idB) const;
  // The room a manifold of idA and idB holding `numPoints` points takes: none without
  // points, four where they may touch at several, else as many as it holds.
  PfxUInt32 roomForPoints(PfxUInt32 idA, PfxUInt32 idB, PfxUInt32 numPoints) const;
  // Gives manifold `contactId` room for `numPoints` points from the pool of their size,
  // moving those it holds; the room it had goes back to its pool.
  void sizeManifold(PfxUInt32 contactId, PfxUInt32 numPoints);
  // Returns a pair's manifold, and its points' room, to the free lists, unless it is the
  // shared empty one.
  void releaseManifold(PfxUInt32 contactId);
  // The manifolds read from a file, each holding room from the pools for its points.
  void adoptManifolds(const std::vector<PfxContactManifold>& manifolds);
  PfxInt32 settleManifolds(PfxDetectCollisionParam& param);
  void composeStablePairs();
  void assignSimplePairs();
  void reservePairs();
  PfxInt32 detectCollision();
  PfxInt32 subStep(PfxFloat timeStep);
  // Whether this step solves the islands a group at a time (pfx_world_groups.cpp).
  bool buildIslandGroups();
  // The world's arrays as the groups read them; the step's settings left at their defaults.
  PfxIslandGroupsWorld islandGroupsWorld();
  PfxInt32 solveIslandGroups(PfxFloat timeStep);
  PfxInt32 validateJoint(const PfxJoint& joint) const;
  PfxJointCoupling measuredCoupling(const PfxJointCoupling& coupling) const;
  template <typename Param>
  void bindContacts(Param& param);
  template <typename Param>
  void bindJoints(Param& param);
  void reserveSolverWork(PfxUInt32 numContactPairs);
  void dropJointedPairs();
  void gatherStats();
  PfxInt32 generateIslands();
  // Sleep (pfx_world_sleep.cpp).
  void wakeTouchedIslands();
  void updateSleep();
  bool isDormant(const PfxConstraintPair& pair) const;
  void putToSleep(PfxUInt32 id);
  void wakeBody(PfxUInt32 id);
  void wakeIslandOf(PfxUInt32 id);
  void wakeIslandsTouching(PfxUInt32 id);
  void wakeAfterChange(PfxUInt32 id);
  void wakeJointBodies(PfxUInt32 jointId);
  void restoreWokenPairs();
  void setAsideDormantPairs();
  void countSleepingContacts();
  void wakeBeforeTruncate(PfxUInt32 numBodies, PfxUInt32 numJoints, PfxUInt32 numJointCouplings);
  void gatherSleepStats();
  PfxInt32 updateRayProxies();
  PfxRayCastParam rayCastParam() const;
  void updateParticleRayBounds();
  void castParticleRay(const PfxRayInput& in, PfxRayOutput& out) const;
  // Particles (pfx_world_particles.cpp).
  PfxInt32 detectParticleContacts();
  PfxInt32 detectGroupContacts(PfxParticleGroup& group, PfxFloat bodyReach);
  PfxInt32 detectContactsBetweenGroups();
  PfxInt32 particleSubStep(PfxFloat timeStep);
  void updateParticleSleep();
  void wakeSleepingParticleGroups();
  void gatherParticleStats();
  // Whether a pin or tether of a particle group names a body in [first, last).
  bool particlesPinBodyIn(PfxUInt32 first, PfxUInt32 last) const;
  bool couplesLiveJoints(const PfxJointCoupling& coupling) const;
  // Removal (pfx_world_removal.cpp).
  void dropPairsOf(PfxUInt32 id);
  void removeJointSlot(PfxUInt32 id);
  void removeCouplingSlot(PfxUInt32 id);
  void eraseJointedPairKey(const PfxJoint& joint);
  void reserveSleepingProxies();
  PfxInt32 buildProxies(const PfxUInt8* skip, PfxBroadphaseProxy* proxies,
                        PfxUInt32& numProxies, PfxUInt32& numOutOfWorld);
  PfxInt32 buildSleepingProxies();
  const PfxUInt8* skippedBodies() const {
    return m_numRemovedBodies > 0 ? m_removedBodies.data() : nullptr;
  }

  PfxWorldParam m_param;
  PfxWorldStats m_stats;
  double m_simulatedTime = 0;
  PfxTbbTaskManager m_taskManager;

  std::vector<PfxRigidState> m_states;
  std::vector<PfxRigidBody> m_bodies;
  std::vector<PfxCollidable> m_collidables;
  std::vector<PfxSolverBody> m_solverBodies;
  std::vector<PfxUInt8> m_contactCheckedBodies;  // pfxCheckContactBodies, each detection
  std::vector<PfxVector3> m_forces;
  std::vector<PfxVector3> m_torques;
  // Compound shapes live here, one block per body, so that collidables can refer to them.
  std::vector<std::unique_ptr<PfxShape[]>> m_compoundShapes;
  std::vector<std::unique_ptr<PfxUInt16[]>> m_compoundShapeIds;
  // One flag per slot: 1 where the body, joint or coupling was removed (removeRigidBody).
  std::vector<PfxUInt8> m_removedBodies;
  std::vector<PfxUInt8> m_removedJoints;
  std::vector<PfxUInt8> m_removedCouplings;
  PfxUInt32 m_numRemovedBodies = 0;
  PfxUInt32 m_numRemovedJoints = 0;

  std::vector<PfxBroadphaseProxy> m_proxies;
  std::vector<PfxSortData32> m_proxySortWork;
  PfxUInt32 m_numProxies = 0;
  int m_sweepAxis = 0;
  // The sleeping bodies' proxies, sorted along m_sweepAxis, built when bodies fall asleep
  // or wake and kept while they sleep, so that a sleeping body costs the broad phase no
  // update and no sort. The masks tell the two builds which bodies to leave out; all three
  // are sized only once sleep is enabled and used.
  std::vector<PfxBroadphaseProxy> m_sleepingProxies;
  std::vector<PfxUInt8> m_skipForAwakeProxies;     // removed or asleep
  std::vector<PfxUInt8> m_skipForSleepingProxies;  // removed or awake
  PfxUInt32 m_numSleepingProxies = 0;
  PfxUInt32 m_numSleepingOutOfWorld = 0;
  bool m_sleepingProxiesStale = true;

  // Pairs of the current frame (m_pairs), the pairs found, and one scratch for the two
  // stages after: pfxFindPairs sorts in it, then pfxDecomposePairs writes its lists there.
  std::vector<PfxBroadphasePair> m_pairs;
  std::vector<PfxBroadphasePair> m_foundPairs;
  std::vector<PfxBroadphasePair> m_pairWork;
  PfxUInt32 m_numPairs = 0;
  PfxUInt32 m_numFoundPairs = 0;
  PfxUInt32 m_maxPairs = 0;

  std::vector<PfxContactManifold> m_manifolds;
  std::vector<PfxUInt32> m_freeManifolds;
  // The manifolds' points: a pair whose contact holds one point at most (a sphere on the
  // ground) holds room for one, others room for four from their first point, and a pair
  // without points none. The one-point pool has a block for each manifold slot, the
  // four-point pool one for each pair that may touch at several points, touching or not:
  // a contact that begins, or grows from one point to four, takes room kept for it.
  PfxContactPointPool m_onePointBlocks{1};
  PfxContactPointPool m_fourPointBlocks{PFX_NUM_CONTACTS_PER_MANIFOLD};
  // Sleeping pairs on the shared empty manifold whose contact may hold several points
  // (countSleepingContacts): the four-point pool keeps room for them as for awake ones.
  PfxUInt32 m_numSleepingPairsAwaitingFour = 0;
  // The manifold that the stable pipeline's pairs without points name, all of them: it
  // stays empty and is never freed (pfxDetectCollision's sharedEmptyContactId).
  PfxUInt32 m_sharedEmptyManifold = 0;

  // Pairs that findPairs no longer reports because all their bodies sleep (or are fixed),
  // sorted by key and kept with their manifolds until a body wakes: a woken island gets
  // its contacts back, impulses and all, in the same step, and islands stay whole while
  // they sleep. m_pairs and m_sleepingPairs each have room for both together.
  std::vector<PfxBroadphasePair> m_sleepingPairs;
  PfxUInt32 m_numSleepingPairs = 0;
  PfxUInt32 m_numSleepingBodies = 0;
  // The contacts of the sleeping pairs, counted when pairs are set aside or come back (a
  // sleeping manifold does not change), so that a step's statistics need not visit them.
  PfxUInt32 m_sleepingContactPairs = 0;
  PfxUInt32 m_sleepingContactPoints = 0;
  PfxFloat m_sleepingMaxPenetration = 0;
  bool m_pairsToRestore = false;  // a body woke since the sleeping pairs were last sorted out
  // The islands (in m_islandBuff), their input and moving pairs' scratch (m_pairScratch),
  // and one mark per island.
  std::vector<PfxSortData16> m_islandBuff;
  const PfxIsland* m_island = nullptr;
  std::vector<PfxConstraintPair> m_pairScratch;
  std::vector<PfxUInt8> m_islandMarks;

  std::vector<PfxJoint> m_joints;
  std::vector<PfxConstraintPair> m_jointPairs;
  std::vector<PfxJointCoupling> m_jointCouplings;
  std::vector<PfxUInt64> m_jointedPairKeys;  // sorted keys of body pairs held by joints
  std::vector<PfxUInt64> m_excludedPairKeys;  // sorted keys of body pairs that never collide
  std::vector<PfxSortData16> m_solverWork;   // the direct solves and the solver's batches
  // The nodes m_solverWork holds for the contacts' direct solve, which factors its trees
  // through them a batch at a time: at first a batch of small trees, then room for the
  // largest tree a step has had.
  PfxUInt32 m_contactTreeNodes = 256;
  // The step's groups of islands, when it solves them a group at a time.
  std::unique_ptr<PfxIslandGroups> m_islandGroups;
  bool m_solveInGroups = false;

  // The proxies that rays find bodies by, then their sort scratch (two blocks of
  // m_rayProxyStride), and the hierarchy over them. Stale after anything that moves or
  // changes a body.
  std::vector<PfxBroadphaseProxy> m_rayProxies;
  std::vector<PfxRayBvhNode> m_rayBvh;
  std::size_t m_rayProxyStride = 0;
  PfxUInt32 m_numRayProxies = 0;
  bool m_rayProxiesStale = true;
  std::vector<PfxSortData16> m_rayOrderWork;  // castRays' Morton order
  // Each particle group's bounds (lower, upper corner) by id, updated with the proxies.
  std::vector<PfxVector3> m_particleRayBounds;

  // Particle groups by id; null for a removed group's id.
  std::vector<std::unique_ptr<PfxParticleGroup>> m_particleGroups;
  // The contacts between two groups' particles, the first m_numParticleGroupPairs entries:
  // found this step between two awake groups, or kept while both groups sleep; the others
  // keep their buffers for later steps.
  struct ParticleGroupPair {
    PfxUInt32 groupA = 0, groupB = 0;
    std::vector<PfxParticleContact> contacts;
    PfxUInt32 numContacts = 0;
    std::vector<PfxVector4> work;
  };
  std::vector<ParticleGroupPair> m_particleGroupPairs;
  PfxUInt32 m_numParticleGroupPairs = 0;
};

}  // namespace pfx
