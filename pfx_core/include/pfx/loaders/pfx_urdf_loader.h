// URDF robots (through urdfdom) into a PfxWorld: links become bodies, joints become joints,
// <mimic> becomes a joint coupling. No ROS here: package:// URIs are resolved through
// ROS_PACKAGE_PATH when it is set, else relative to the URDF's folder.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

struct PfxUrdfLoadParam {
  // Pose of the root link in the world.
  PfxVector3 rootPosition = PfxVector3::Zero();
  PfxQuat rootOrientation = PfxQuat::Identity();
  // A fixed root (an arm bolted to a table) instead of a free-floating one (a ragdoll).
  bool fixedBase = false;
  // Links joined by fixed joints become one compound body; false keeps fixed joints.
  bool lumpFixedJoints = true;
  // Massless helper links between revolute joints meeting at one point become one
  // universal or ball joint.
  bool collapseMasslessChains = true;
  // Links joined by a joint never collide with each other; this also stops every other
  // pair of links of the robot from colliding.
  bool disableSelfCollision = false;
  PfxFloat friction = PfxFloat(0.6);
  PfxFloat restitution = 0;
  // Folder that package:// URIs are resolved in when ROS_PACKAGE_PATH does not name the
  // package; empty: the URDF's own folder and its parents.
  std::string packageRoot;
};

// What one URDF link became.
struct PfxUrdfLink {
  std::string name;
  PfxUInt32 bodyId = 0;  // the body carrying it (several links share one when lumped)
  // Pose of the link's frame in the body's frame (bodies sit at their centre of mass), so
  // link pose in the world = body transform * linkInBody.
  PfxTransform3 linkInBody = PfxTransform3::Identity();
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
  // floating, planar). Collapsed chains share one world joint, each on its own axis.
  PfxUInt32 jointId = 0;
  PfxUInt32 axis = 0;
  // URDF coordinate = sign * world joint coordinate on `axis` + offset.
  PfxFloat sign = 1;
  PfxFloat offset = 0;
  PfxFloat lowerLimit = 0;  // rad or m; -inf/inf for continuous
  PfxFloat upperLimit = 0;
  PfxFloat effortLimit = 0;    // N or N m; 0 = none given
  PfxFloat velocityLimit = 0;  // rad/s or m/s; 0 = none given
  // <mimic>: index into PfxUrdfModel::joints of the leader, or -1.
  PfxInt32 mimicLeader = -1;
  PfxFloat mimicMultiplier = 1;
  PfxFloat mimicOffset = 0;
};

constexpr PfxUInt32 kPfxUrdfNoJoint = 0xffffffffu;

// A loaded robot. Owns the convex and large meshes its bodies' shapes point to: keep it
// alive as long as the world holds the robot.
struct PfxUrdfModel {
  std::string name;
  std::vector<PfxUrdfLink> links;
  std::vector<PfxUrdfJoint> joints;
  std::vector<std::string> warnings;  // e.g. a link with no inertial and no child joint
  PfxUInt32 firstBodyId = 0;  // bodies and joints the load added, contiguous
  PfxUInt32 numBodies = 0;
  PfxUInt32 firstJointId = 0;
  PfxUInt32 numJoints = 0;
  std::vector<std::unique_ptr<PfxConvexMesh>> convexMeshes;
  std::vector<PfxLargeTriMesh> largeMeshes;  // released by the model's destructor
  PfxUrdfModel() = default;
  PfxUrdfModel(const PfxUrdfModel&) = delete;
  PfxUrdfModel& operator=(const PfxUrdfModel&) = delete;
  PfxUrdfModel(PfxUrdfModel&&) = default;
  PfxUrdfModel& operator=(PfxUrdfModel&&) = default;
  ~PfxUrdfModel();
};

// Loads a URDF file (or the XML text, with `basePath` the folder meshes are resolved
// against) into the world. On error returns a PFX_ERR_* code, writes
// "<file>: <element> '<name>': <reason>" into *message, and leaves the world and `model`
// as they were.
PfxInt32 pfxLoadUrdfFile(PfxWorld& world, const std::string& path, const PfxUrdfLoadParam& param,
                         PfxUrdfModel& model, std::string* message = nullptr);
PfxInt32 pfxLoadUrdfString(PfxWorld& world, const std::string& xml, const std::string& basePath,
                           const PfxUrdfLoadParam& param, PfxUrdfModel& model,
                           std::string* message = nullptr);

// Link pose in the world.
PfxTransform3 pfxGetUrdfLinkPose(const PfxWorld& world, const PfxUrdfLink& link);
// Index of a link or joint by name, or -1.
PfxInt32 pfxFindUrdfLink(const PfxUrdfModel& model, const std::string& name);
PfxInt32 pfxFindUrdfJoint(const PfxUrdfModel& model, const std::string& name);
// Position (rad or m) and velocity of every joint in model.joints order; 0 for joints
// without a coordinate (fixed, floating, planar).
void pfxGetUrdfJointStates(const PfxWorld& world, const PfxUrdfModel& model,
                           std::vector<double>& positions, std::vector<double>& velocities);
// Motor command on one joint: a target position or velocity, with the force limited by
// the joint's effort limit (or maxForce when that is > 0). Rejects joints without a
// coordinate, mimic followers and NaN targets (PFX_ERR_INVALID_VALUE); nothing changes then.
PfxInt32 pfxSetUrdfJointCommand(PfxWorld& world, const PfxUrdfModel& model, PfxUInt32 jointIndex,
                                PfxJointDrive drive, PfxFloat target, PfxFloat maxForce = 0);

}  // namespace pfx
