// The world's solver stages a group of islands at a time. Islands share no body that
// impulses move, so each group is solved, integrated and corrected on its own, in one task,
// from copies of its bodies numbered from zero: a world of many robots runs one parallel
// loop over its groups per sub-step, where solving it as a whole ran a hundred parallel
// loops over pairs, trees and bodies, most of them too small to pay for the threads, and
// every per-body table of a stage spanned the whole world.
//
// Every group does what the whole world's solve does to its bodies, in the same order, so
// the bits are the same: a body meets its contacts and joints in the world's pair order;
// what the stages decide for the whole call is decided for the whole world and passed on
// (a group without joints in a world with them takes no shock propagation, as the joint
// solve takes none; a group without contacts takes the contacts' correction pass when the
// world has contacts). A coupling's two joints lie in one island, so in one group. A body
// that impulses do not move (the ground, a keyframe body) is copied into every group that
// touches it, read there and written back by its own group alone; integrating a copy gives
// what its own group's integration gives.
#pragma once

#include <vector>

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/base/pfx_sort_data.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx/low_level/solver/pfx_island_generation.h"

namespace pfx {

// The world's arrays the groups read and write, and the step's settings.
struct PfxIslandGroupsWorld {
  PfxRigidState* states = nullptr;
  const PfxRigidBody* bodies = nullptr;
  PfxSolverBody* solverBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  const PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* manifolds = nullptr;
  PfxUInt32 numManifolds = 0;
  const PfxConstraintPair* jointPairs = nullptr;
  PfxJoint* joints = nullptr;
  PfxUInt32 numJoints = 0;
  PfxJointCoupling* couplings = nullptr;
  PfxUInt32 numCouplings = 0;
  PfxFloat timeStep = 0;
  PfxUInt32 iteration = 0;
  PfxFloat restitutionThreshold = 0;
  PfxVector3 shockGravity = PfxVector3::Zero();  // zero: no shock propagation
  bool measureStages = false;                    // time the groups' stages into the stats
};

class PfxIslandGroups {
 public:
  // Sorts the step's islands into groups, each about `targetWeight` bodies, contacts and
  // joints or one larger island; false when that makes fewer than two groups (the world then
  // solves as a whole). Reads the bodies, the contact pairs and manifolds, and the joints
  // (whose pairs may not be up to date yet); the lists of pairs and joints must stay as they
  // are until the step ends.
  bool build(const PfxIsland& island, const PfxIslandGroupsWorld& world,
             PfxUInt32 targetWeight);

  PfxUInt32 numGroups() const { return static_cast<PfxUInt32>(m_groups.size()); }

  // pfxSolveConstraints, pfxUpdateRigidStates and pfxCorrectJointPositions for every group,
  // the groups in parallel with a task manager, after the world's setups. `contactTreeNodes`
  // is the room each group's contacts' direct solve starts with, raised to the largest tree
  // met. Adds each stage's time, summed over the groups, to `stats`. Returns the first error
  // of a stage; the groups that failed have written nothing to the world then.
  PfxInt32 solve(const PfxIslandGroupsWorld& world, PfxUInt32& contactTreeNodes,
                 PfxWorldStats& stats, PfxTaskManager* taskManager);

 private:
  struct Group {
    PfxUInt32 firstBody, numOwnBodies, numBodies;  // into m_bodyIds; own bodies first
    PfxUInt32 firstContact, numContacts;           // into m_contactIndices
    PfxUInt32 firstJoint, numJoints;               // into m_jointIndices
    // Into m_couplingIndices. A group with couplings works on copies of its joints too:
    // a coupling names its joints by id and its bodies by theirs, both renumbered.
    PfxUInt32 firstCoupling, numCouplings;
    std::size_t workOffset, workBytes;             // into m_work
    bool threaded;                                 // large enough for the task manager
  };
  // What a group's solve came to: its error, the nodes its contacts' largest tree asked
  // for, and the time of its three stages.
  struct Result {
    PfxInt32 err = PFX_OK;
    PfxUInt32 contactTreeNodes = 0;
    double seconds[3] = {};
  };
  void layOutWork(PfxUInt32 contactTreeNodes);
  PfxUInt32 localId(const Group& group, PfxUInt32 groupIndex, PfxUInt32 rigidBodyId) const;
  // Gathers, solves, integrates, corrects and scatters one group; on an error, returns it
  // having written nothing to the world.
  PfxInt32 solveGroup(PfxUInt32 groupIndex, const PfxIslandGroupsWorld& world, Result& result,
                      PfxTaskManager* taskManager);

  std::vector<Group> m_groups;
  std::vector<PfxUInt32> m_groupOfBody;    // per world body: its group, or kNoGroup
  std::vector<PfxUInt32> m_localIdOfBody;  // per world body in a group: its id there
  std::vector<PfxUInt32> m_bodyIds;        // the groups' bodies, by world id; the foreign sorted
  std::vector<PfxUInt32> m_contactIndices;  // into the world's contact pairs, in their order
  std::vector<PfxUInt32> m_jointIndices;    // into the world's joint pairs, in their order
  std::vector<PfxUInt32> m_couplingIndices;  // into the world's couplings, in their order
  std::vector<PfxUInt32> m_localJointOf;     // per world joint of a group with couplings
  std::vector<PfxRigidState> m_states;      // per group body, in the groups' order
  std::vector<PfxRigidBody> m_bodies;
  std::vector<PfxSolverBody> m_solverBodies;
  std::vector<PfxConstraintPair> m_contactPairs;  // per group contact, renumbered
  std::vector<PfxConstraintPair> m_jointPairs;    // per group joint, renumbered
  std::vector<PfxJoint> m_joints;                 // per group joint, with couplings
  std::vector<PfxJointCoupling> m_couplings;      // per group coupling, renumbered
  std::vector<PfxUInt32> m_starts;  // scratch of build()
  std::vector<PfxUInt32> m_ownIds;  // scratch of build()
  std::vector<Result> m_results;     // per group
  std::vector<PfxSortData16> m_work;
  PfxUInt32 m_workContactTreeNodes = 0;  // what m_work was laid out for
  bool m_contactsInWorld = false;        // a pair with points somewhere in the world
};

}  // namespace pfx
