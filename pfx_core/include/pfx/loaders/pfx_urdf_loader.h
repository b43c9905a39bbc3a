// URDF robots (through urdfdom) into a PfxWorld: links become bodies, joints become joints,
// <mimic> becomes a joint coupling. No ROS here: package:// URIs are resolved through
// ROS_PACKAGE_PATH when it is set, else relative to the URDF's folder.
//
// URDF is Z-up and the world's default gravity is -Y: the loader never changes the world's
// parameters, so give a world that holds URDF robots gravity (0, 0, -9.81).
//
// What each part of a URDF becomes:
// - A link with an <inertial> of positive mass is a body at its centre of mass, with the
//   inertia tensor turned by the inertial origin. Links joined by fixed joints are lumped
//   into one body (masses, centres and inertias added with the parallel-axis theorem).
// - <collision> elements are the body's shapes (several make a compound): box, sphere,
//   cylinder and capsule (both along the link's Z, turned onto the shape's X; a capsule's
//   length is its cylinder part between the hemispheres' centres, as Bullet's URDF importer
//   reads it) and mesh, which becomes a convex hull on a moving body and a large triangle
//   mesh on a fixed one (the fixed base and the links lumped into it). The loader reads the
//   collision elements itself, since urdfdom drops all of a link's when it does not know one;
//   a geometry pfx does not know, or none, is left out with a warning naming the link and
//   line, and a mesh without a filename is a missing mesh. A body without collision geometry
//   carries a small sphere whose contact filters match nothing, so neither bodies nor rays
//   ever meet it.
// - revolute: hinge with limits (limits beyond +-pi are cut to +-pi with a warning, since
//   the hinge's angle wraps there); continuous: hinge without limits (its angle reads in
//   (-pi, pi]); prismatic: slider with limits; fixed: lumped, or a fixed joint;
//   floating: no joint; planar: free translations in the plane and rotation about its
//   normal. Anchors sit at the joint origin; the joint frame's X axis is the URDF axis.
// - <dynamics damping> (viscous, N m s/rad or N s/m) becomes the axis damping, which the
//   solver applies as the fraction of the axis velocity removed per sub-step h:
//   1 - exp(-damping h / I), with I the inertia (or mass) that the joint moves when it alone
//   moves in the load pose: the child's subtree against the rest of the robot, or against
//   nothing on a fixed base. <dynamics friction> is the axis friction (N m or N). The
//   fraction follows the world's time step at load; reload after changing it.
// - A link without mass (no <inertial>, or mass 0) never enters the solver:
//   * on a fixed base root it is simply part of the fixed body;
//   * across a fixed joint it is lumped into its neighbour (even with lumpFixedJoints off);
//   * between two or three revolute or continuous joints whose origins coincide and whose
//     axes are perpendicular (a shoulder built as three revolutes through two empty
//     links), the chain collapses into one universal joint (two axes) or one ball joint
//     with a limit on each rotation (three axes) between the real bodies, measuring its
//     rotations as Euler angles along the chain's axes; see PfxUrdfJoint::collapsed;
//   * with no joint below it (a leaf), it is carried by its parent's body as a frame, its
//     joint held at zero, and a warning says so;
//   * anywhere else (two joints whose axes do not meet, such as an ankle of two hinges
//     4 cm apart, or a slider below it) it becomes a light body, so that every joint acts
//     where the URDF puts it: a tenth of the mass of its lighter massive neighbour, an even
//     inertia with that neighbour's smallest radius of gyration, its centre amid its
//     joints' origins; a warning says so. With collapseMasslessChains off it is an error.
// - A root link named "world" (Gazebo's convention) fixes the base like fixedBase; so does a
//   root without mass (which cannot float), with a warning. PfxUrdfModel::fixedBase says
//   which the robot got.
// - Text with xacro left in it (<xacro:...> elements, ${...} or $(...) in attributes) is
//   refused with a message that says to run xacro first.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

constexpr PfxUInt32 kPfxUrdfNoJoint = 0xffffffffu;

struct PfxUrdfLoadParam {
  // Pose of the root link in the world.
  PfxVector3 rootPosition = PfxVector3::Zero();
  PfxQuat rootOrientation = PfxQuat::Identity();
  // Set: the root's height (world Z) is chosen instead, so that the lowest point of the
  // robot's collision shapes in its load pose lies groundClearance above z = groundHeight
  // (rootPosition's x and y and rootOrientation stay). For a free robot dropped onto a
  // ground, or a fixed one standing on it, instead of starting inside it.
  bool placeAboveGround = false;
  PfxFloat groundHeight = 0;
  PfxFloat groundClearance = PfxFloat(0.05);
  // A fixed root (an arm bolted to a table) instead of a free-floating one (a ragdoll).
  bool fixedBase = false;
  // Links joined by fixed joints become one compound body; false keeps fixed joints.
  bool lumpFixedJoints = true;
  // Massless helper links between revolute joints meeting at one point become one
  // universal or ball joint, other massless links with joints below them light bodies;
  // false makes every massless link with joints below it an error.
  bool collapseMasslessChains = true;
  // Links joined by a joint (or through a light helper body) never collide with each other,
  // nor do links that overlap where the robot is loaded (PfxWorld::excludeCollision, listed
  // in a warning); this stops every other pair of links of the robot from colliding too,
  // through the contact filters: the robot's bodies get self = selfCollisionGroup and
  // target = ~selfCollisionGroup. Bodies of other robots loaded with the same group do not
  // meet them either; give each its own bit.
  bool disableSelfCollision = false;
  PfxUInt32 selfCollisionGroup = 1u << 31;
  PfxFloat friction = PfxFloat(0.6);
  PfxFloat restitution = 0;
  // Folder that package:// URIs are resolved in when ROS_PACKAGE_PATH does not name the
  // package; empty: the URDF's own folder and its parents.
  std::string packageRoot;
  // A collision mesh whose file is missing fails the load; with this set it is left out
  // and a warning names it instead (for descriptions copied without all of their meshes,
  // such as bullet3's r2d2.urdf, whose gripper meshes are not shipped beside it).
  bool allowMissingMeshes = false;
};

// What one URDF link became.
struct PfxUrdfLink {
  std::string name;
  PfxUInt32 bodyId = 0;  // the body carrying it (several links share one when lumped)
  // Pose of the link's frame in the body's frame (bodies sit at their centre of mass), so
  // link pose in the world = body transform * linkInBody.
  PfxTransform3 linkInBody = PfxTransform3::Identity();
  // A helper link inside a collapsed chain has no body of its own: bodyId is the body on
  // the chain's parent side, linkInBody its pose there with the chain at zero, and the link
  // turns with the first collapsedAxes (1 or 2) URDF joints of world joint
  // collapsedJointId. kPfxUrdfNoJoint and 0 for every other link.
  PfxUInt32 collapsedJointId = kPfxUrdfNoJoint;
  PfxUInt32 collapsedAxes = 0;
};

enum PfxUrdfJointType : PfxUInt8 {
  kPfxUrdfRevolute = 0,
  kPfxUrdfContinuous,
  kPfxUrdfPrismatic,
  kPfxUrdfFixed,
  kPfxUrdfFloating,
  kPfxUrdfPlanar,
};

// What one URDF joint became.
struct PfxUrdfJoint {
  std::string name;
  std::string parentLink;
  std::string childLink;
  PfxUrdfJointType type = kPfxUrdfFixed;
  // The world joint carrying this joint's coordinate and the axis (0..5) it is on; for
  // revolute, continuous and prismatic joints only, kPfxUrdfNoJoint otherwise (lumped,
  // floating, planar) and for a joint held at zero under a massless leaf link.
  PfxUInt32 jointId = kPfxUrdfNoJoint;
  PfxUInt32 axis = 0;
  // URDF coordinate = sign * world joint coordinate on `axis` + offset.
  PfxFloat sign = 1;
  PfxFloat offset = 0;
  // One of the joints of a collapsed chain. Its world joint measures rotations as Euler
  // angles along the chain's axes (kPfxJointRotationEulerYZX): the first URDF axis is its
  // Y (swing1), the second +-Z (swing2, through `sign`) and a third X (twist); a universal
  // joint locks the twist. So each URDF angle is exactly sign * that coordinate, and each
  // URDF joint's limits are exactly the limits of its axis. The coordinates are singular
  // where the second angle reaches +-pi/2 (gimbal lock), as the URDF chain is.
  bool collapsed = false;
  PfxFloat lowerLimit = 0;  // rad or m; -inf/inf for continuous
  PfxFloat upperLimit = 0;
  PfxFloat effortLimit = 0;    // N or N m; 0 = none given
  PfxFloat velocityLimit = 0;  // rad/s or m/s; 0 = none given
  // <mimic>: index into PfxUrdfModel::joints of the leader, or -1, and the world coupling
  // that holds follower = multiplier * leader + offset (kPfxUrdfNoJoint when none).
  PfxInt32 mimicLeader = -1;
  PfxFloat mimicMultiplier = 1;
  PfxFloat mimicOffset = 0;
  PfxUInt32 couplingId = kPfxUrdfNoJoint;
};

// Free the meshes the model owns, which come from the utility allocator
// (pfx_utility_allocator.h) like every mesh the library allocates.
struct PfxLargeTriMeshRelease {
  void operator()(PfxLargeTriMesh* mesh) const;
};
struct PfxConvexMeshRelease {
  void operator()(PfxConvexMesh* mesh) const;
};

// A loaded robot. Owns the convex and large meshes its bodies' shapes point to: keep it
// alive as long as the world holds the robot.
struct PfxUrdfModel {
  std::string name;
  bool fixedBase = false;  // the root is fixed: asked for, a root named "world", or no mass
  std::vector<PfxUrdfLink> links;     // in the order of the URDF file
  std::vector<PfxUrdfJoint> joints;   // likewise
  std::vector<std::string> warnings;  // e.g. a link with no inertial and no child joint
  // The link whose <collision> each shape came from, as an index into links:
  // shapeLinks[bodyId - firstBodyId][shape index], the index that contact points
  // (m_shapeIdA, m_shapeIdB) and ray hits (m_shapeId) carry. A body that lumps several
  // links holds the shapes of all of them; the placeholder sphere of a body without
  // geometry has -1. See pfxFindUrdfShapeLink.
  std::vector<std::vector<PfxInt32>> shapeLinks;
  PfxUInt32 firstBodyId = 0;          // bodies, joints and couplings the load added, contiguous
  PfxUInt32 numBodies = 0;
  PfxUInt32 firstJointId = 0;
  PfxUInt32 numJoints = 0;
  PfxUInt32 firstCouplingId = 0;
  PfxUInt32 numCouplings = 0;
  std::vector<std::unique_ptr<PfxConvexMesh, PfxConvexMeshRelease>> convexMeshes;
  std::vector<std::unique_ptr<PfxLargeTriMesh, PfxLargeTriMeshRelease>> largeMeshes;
};

// Loads a URDF file (or the XML text, with `basePath` the folder meshes are resolved
// against) into the world. On error returns a PFX_ERR_* code, writes
// "<file>: <element> '<name>': <reason>" into *message, and leaves the world and `model`
// as they were. A string has the file name "<urdf string>".
PfxInt32 pfxLoadUrdfFile(PfxWorld& world, const std::string& path, const PfxUrdfLoadParam& param,
                         PfxUrdfModel& model, std::string* message = nullptr);
PfxInt32 pfxLoadUrdfString(PfxWorld& world, const std::string& xml, const std::string& basePath,
                           const PfxUrdfLoadParam& param, PfxUrdfModel& model,
                           std::string* message = nullptr);

// Link pose in the world (helper links of collapsed chains included).
PfxTransform3 pfxGetUrdfLinkPose(const PfxWorld& world, const PfxUrdfLink& link);
// Index of a link or joint by name, or -1.
PfxInt32 pfxFindUrdfLink(const PfxUrdfModel& model, const std::string& name);
PfxInt32 pfxFindUrdfJoint(const PfxUrdfModel& model, const std::string& name);
// Index into model.links of the link that gave body `bodyId` its shape `shapeIndex` (the
// link whose collision element a contact point or a ray hit lies on), or -1 for a body or
// shape the model did not make, or the placeholder of a body without geometry.
inline PfxInt32 pfxFindUrdfShapeLink(const PfxUrdfModel& model, PfxUInt32 bodyId,
                                     PfxUInt32 shapeIndex) {
  if (bodyId < model.firstBodyId || bodyId - model.firstBodyId >= model.shapeLinks.size()) {
    return -1;
  }
  const std::vector<PfxInt32>& links = model.shapeLinks[bodyId - model.firstBodyId];
  return shapeIndex < links.size() ? links[shapeIndex] : -1;
}
// Position (rad or m) and velocity of every joint in model.joints order; 0 for joints
// without a coordinate (fixed, floating, planar, held at zero).
void pfxGetUrdfJointStates(const PfxWorld& world, const PfxUrdfModel& model,
                           std::vector<double>& positions, std::vector<double>& velocities);
// Lowest point (world z) of the robot's collision shapes in their current poses; +infinity
// for a robot without any.
PfxFloat pfxGetUrdfLowestPoint(const PfxWorld& world, const PfxUrdfModel& model);
// A target the joint can reach: a position target outside the joint's URDF limits is cut to
// the nearer limit, a velocity target to +-the velocity limit and an effort to +-the effort
// limit (when the URDF gives them). When it cuts, writes into *note which joint, which
// limit and the target asked for.
PfxFloat pfxClampUrdfJointTarget(const PfxUrdfJoint& joint, PfxJointDrive drive, PfxFloat target,
                                 std::string* note = nullptr);
// Motor command on one joint: a target position or velocity, or an effort (N m or N along
// the URDF axis, kPfxJointDriveEffort), cut by pfxClampUrdfJointTarget (*note says so, and
// is cleared when nothing was cut), with the force limited by the joint's URDF effort limit
// and by maxForce when that is > 0 (the smaller wins; unlimited when neither is given), or
// kPfxJointDriveNone to let the joint go. Rejects an index out of range
// (PFX_ERR_OUT_OF_RANGE), joints without a coordinate, mimic followers, NaN targets and a
// negative or NaN maxForce (PFX_ERR_INVALID_VALUE); nothing changes then.
PfxInt32 pfxSetUrdfJointCommand(PfxWorld& world, const PfxUrdfModel& model, PfxUInt32 jointIndex,
                                PfxJointDrive drive, PfxFloat target, PfxFloat maxForce = 0,
                                std::string* note = nullptr);

}  // namespace pfx
