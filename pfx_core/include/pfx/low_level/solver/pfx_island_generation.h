// Stage: simulation islands (seed chapter 2, "Simulation Island"): the groups of bodies that
// contacts and joints connect, so that a group can fall asleep and wake up as a whole
// (seed 3_sleep). The low level only finds the groups; deciding when one sleeps is the
// caller's (PfxWorld does it when PfxWorldParam::enableSleep is set).
//
// Who belongs to which island:
// - Every body that is not fixed belongs to exactly one island; fixed bodies to none.
// - Contact pairs that the solver works on (pfxGetActive) and that hold at least one point
//   (pfxGetNumConstraints > 0), active joints and active joint couplings link the bodies
//   that forces move (active and one-way). Fixed and keyframe bodies link nothing: they pass
//   no motion on, so two piles on one floor, or on one moving platform, stay two islands. A
//   keyframe or trigger body is an island of its own.
// - An island's contact pairs and joints are those with at least one body that forces move,
//   listed under that body's island.
// - Numbering depends only on the input, not on its order or on timing: islands are numbered
//   by their lowest body id, and each island lists its bodies by ascending id and its pairs
//   and joints in input order.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

namespace pfx {

// The islands, in the caller's buffer (opaque; read it through the functions below).
struct PfxIsland;

// The island of a body that belongs to none (a fixed body, or an id out of range).
constexpr PfxUInt32 PFX_ISLAND_NONE = 0xffffffffu;

struct PfxGenerateIslandParam {
  void* islandBuff = nullptr;  // holds the islands afterwards; 16-byte aligned
  PfxUInt32 islandBytes = 0;
  const PfxRigidState* offsetRigidStates = nullptr;  // their motion types decide who links
  PfxUInt32 numRigidBodies = 0;
  const PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  const PfxJoint* offsetJoints = nullptr;
  PfxUInt32 numJoints = 0;
  // A coupling links the bodies of its leader and follower joints.
  const PfxJointCoupling* offsetJointCouplings = nullptr;
  PfxUInt32 numJointCouplings = 0;
};

struct PfxGenerateIslandResult {
  const PfxIsland* island = nullptr;  // in islandBuff
  PfxUInt32 numIslands = 0;
};

// Bytes of islandBuff for these many bodies, contact pairs and joints (0xffffffff when that
// does not fit in 32 bits).
PfxUInt32 pfxGetIslandBytes(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs,
                            PfxUInt32 numJoints);

// Union-find over the links, then each island's bodies, contact pairs and joints gathered in
// place; allocates nothing. Rejects null arrays with a count (PFX_ERR_NULL_POINTER), a buffer
// that is missing or small (PFX_ERR_OUT_OF_BUFFER) or misaligned
// (PFX_ERR_INVALID_ALIGNMENT), a buffer that overlaps an input (PFX_ERR_INVALID_VALUE), and a
// pair, joint or coupling naming a body or joint out of range (PFX_ERR_OUT_OF_RANGE); the
// buffer is not written then.
PfxInt32 pfxGenerateIsland(const PfxGenerateIslandParam& param, PfxGenerateIslandResult& result);

PfxUInt32 pfxGetNumIslands(const PfxIsland& island);
// The island of a body, or PFX_ISLAND_NONE.
PfxUInt32 pfxGetIslandId(const PfxIsland& island, PfxUInt32 rigidBodyId);
// The bodies of island `islandId`, by ascending id; `count` is 0 (and the result null) for an
// id out of range.
const PfxUInt32* pfxGetRigidBodiesInIsland(const PfxIsland& island, PfxUInt32 islandId,
                                           PfxUInt32& count);
// Copies of the island's contact pairs, in the order given.
const PfxConstraintPair* pfxGetContactPairsInIsland(const PfxIsland& island, PfxUInt32 islandId,
                                                    PfxUInt32& count);
// Indices of the island's joints in offsetJoints, ascending.
const PfxUInt32* pfxGetJointsInIsland(const PfxIsland& island, PfxUInt32 islandId,
                                      PfxUInt32& count);

}  // namespace pfx
