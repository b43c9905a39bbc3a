// A loaded robot as it moves: link poses, URDF joint positions and velocities, and motor
// commands, all read from and written to the world's bodies and joints.
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "pfx/loaders/pfx_urdf_loader.h"

namespace pfx {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

Mat3 turn(double angle, const Vec3& axis) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

// The rates of a collapsed chain's Euler angles (swing1, swing2, twist) from the relative
// angular velocity w in A's joint frame: w = s1' Y + s2' Ry(s1) Z + t' Ry(s1) Rz(s2) X.
Vec3 eulerRates(const PfxFloat coordinates[6], const Vec3& w) {
  const double s1 = coordinates[kPfxJointAxisSwing1], s2 = coordinates[kPfxJointAxisSwing2];
  Mat3 basis;
  basis.col(0) = Vec3::UnitY();
  basis.col(1) = turn(s1, Vec3::UnitY()) * Vec3::UnitZ();
  basis.col(2) = turn(s1, Vec3::UnitY()) * turn(s2, Vec3::UnitZ()) * Vec3::UnitX();
  const Vec3 rates = basis.colPivHouseholderQr().solve(w);
  Vec3 byAxis;
  byAxis[kPfxJointAxisSwing1 - 3] = rates[0];
  byAxis[kPfxJointAxisSwing2 - 3] = rates[1];
  byAxis[kPfxJointAxisTwist - 3] = rates[2];
  return byAxis;
}

bool isValidJoint(const PfxWorld& world, PfxUInt32 id) {
  if (id >= world.getNumJoints()) return false;
  const PfxJoint& joint = world.getJoint(id);
  return joint.m_rigidBodyIdA < world.getNumRigidBodies() &&
         joint.m_rigidBodyIdB < world.getNumRigidBodies();
}

const char* driveName(PfxJointDrive drive) {
  switch (drive) {
    case kPfxJointDrivePosition: return "position";
    case kPfxJointDriveVelocity: return "velocity";
    case kPfxJointDriveEffort: return "effort";
    default: return "no";
  }
}

}  // namespace

PfxTransform3 pfxGetUrdfLinkPose(const PfxWorld& world, const PfxUrdfLink& link) {
  if (link.bodyId >= world.getNumRigidBodies()) return PfxTransform3::Identity();
  const PfxTransform3 body = world.getRigidState(link.bodyId).getTransform();
  if (link.collapsedJointId == kPfxUrdfNoJoint || !isValidJoint(world, link.collapsedJointId)) {
    return body * link.linkInBody;
  }
  // A helper link turns about the joint point with the chain's first joints.
  const PfxJoint& joint = world.getJoint(link.collapsedJointId);
  PfxFloat coordinates[6];
  pfxCalcJointCoordinates(joint, world.getRigidState(joint.m_rigidBodyIdA),
                          world.getRigidState(joint.m_rigidBodyIdB), coordinates);
  Mat3 rotation = turn(coordinates[kPfxJointAxisSwing1], Vec3::UnitY());
  if (link.collapsedAxes >= 2)
    rotation = rotation * turn(coordinates[kPfxJointAxisSwing2], Vec3::UnitZ());
  PfxTransform3 frame = PfxTransform3::Identity();
  frame.linear() = joint.m_frameA;
  frame.translation() = joint.m_anchorA;
  PfxTransform3 turned = PfxTransform3::Identity();
  turned.linear() = rotation.cast<PfxFloat>();
  return body * frame * turned * frame.inverse() * link.linkInBody;
}

PfxInt32 pfxFindUrdfLink(const PfxUrdfModel& model, const std::string& name) {
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    if (model.links[i].name == name) return static_cast<PfxInt32>(i);
  }
  return -1;
}

PfxInt32 pfxFindUrdfJoint(const PfxUrdfModel& model, const std::string& name) {
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    if (model.joints[i].name == name) return static_cast<PfxInt32>(i);
  }
  return -1;
}

void pfxGetUrdfJointStates(const PfxWorld& world, const PfxUrdfModel& model,
                           std::vector<double>& positions, std::vector<double>& velocities) {
  positions.assign(model.joints.size(), 0);
  velocities.assign(model.joints.size(), 0);
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    const PfxUrdfJoint& urdfJoint = model.joints[i];
    if (urdfJoint.jointId == kPfxUrdfNoJoint || !isValidJoint(world, urdfJoint.jointId)) continue;
    const PfxJoint& joint = world.getJoint(urdfJoint.jointId);
    const PfxRigidState& a = world.getRigidState(joint.m_rigidBodyIdA);
    const PfxRigidState& b = world.getRigidState(joint.m_rigidBodyIdB);
    const Mat3 frameA = (a.getOrientation().toRotationMatrix() * joint.m_frameA).cast<double>();
    const Vec3 relativeAngular = (b.getAngularVelocity() - a.getAngularVelocity()).cast<double>();
    PfxFloat coordinates[6];
    pfxCalcJointCoordinates(joint, a, b, coordinates);
    const double position = coordinates[urdfJoint.axis];
    double velocity;
    if (urdfJoint.collapsed) {
      velocity = eulerRates(coordinates, frameA.transpose() * relativeAngular)[urdfJoint.axis - 3];
    } else if (urdfJoint.axis < 3) {
      const PfxVector3 armA = a.getOrientation() * joint.m_anchorA;
      const PfxVector3 armB = b.getOrientation() * joint.m_anchorB;
      const PfxVector3 relative = b.getLinearVelocity() + b.getAngularVelocity().cross(armB) -
                                  a.getLinearVelocity() - a.getAngularVelocity().cross(armA);
      velocity = relative.cast<double>().dot(frameA.col(urdfJoint.axis));
    } else {
      velocity = relativeAngular.dot(frameA.col(0));
    }
    positions[i] = urdfJoint.sign * position + urdfJoint.offset;
    velocities[i] = urdfJoint.sign * velocity;
  }
}

PfxFloat pfxGetUrdfLowestPoint(const PfxWorld& world, const PfxUrdfModel& model) {
  PfxFloat lowest = std::numeric_limits<PfxFloat>::infinity();
  const PfxUInt32 end = std::min(model.firstBodyId + model.numBodies, world.getNumRigidBodies());
  for (PfxUInt32 id = model.firstBodyId; id < end; ++id) {
    const PfxRigidState& state = world.getRigidState(id);
    // The placeholder of a body without geometry meets nothing.
    if (state.getContactFilterSelf() == 0 && state.getContactFilterTarget() == 0) continue;
    const PfxTransform3 body = state.getTransform();
    const PfxCollidable& collidable = world.getCollidable(id);
    for (PfxUInt32 i = 0; i < collidable.getNumShapes(); ++i) {
      const PfxShape& shape = collidable.getShape(i);
      const PfxVector3 point =
          pfxGetSupportPoint(shape, body * shape.getOffsetTransform(), PfxVector3(0, 0, -1));
      lowest = std::min(lowest, point.z());
    }
  }
  return lowest;
}

PfxFloat pfxClampUrdfJointTarget(const PfxUrdfJoint& joint, PfxJointDrive drive, PfxFloat target,
                                 std::string* note) {
  PfxFloat lower = -std::numeric_limits<PfxFloat>::infinity();
  PfxFloat upper = std::numeric_limits<PfxFloat>::infinity();
  const char* what = "limit";
  if (drive == kPfxJointDrivePosition &&
      (joint.type == kPfxUrdfRevolute || joint.type == kPfxUrdfPrismatic)) {
    lower = joint.lowerLimit;
    upper = joint.upperLimit;
  } else if (drive == kPfxJointDriveVelocity && joint.velocityLimit > 0) {
    lower = -joint.velocityLimit;
    upper = joint.velocityLimit;
    what = "velocity limit";
  } else if (drive == kPfxJointDriveEffort && joint.effortLimit > 0) {
    lower = -joint.effortLimit;
    upper = joint.effortLimit;
    what = "effort limit";
  }
  const PfxFloat clamped = std::clamp(target, lower, upper);
  if (note) {
    note->clear();
    if (clamped != target) {
      std::ostringstream text;
      text << "joint '" << joint.name
           << "': " << driveName(drive) << " target "
           << target << " cut to its " << (target < lower ? "lower " : "upper ") << what << " "
           << clamped;
      *note = text.str();
    }
  }
  return clamped;
}

PfxInt32 pfxSetUrdfJointCommand(PfxWorld& world, const PfxUrdfModel& model, PfxUInt32 jointIndex,
                                PfxJointDrive drive, PfxFloat target, PfxFloat maxForce,
                                std::string* note) {
  if (note) note->clear();
  if (jointIndex >= model.joints.size()) return PFX_ERR_OUT_OF_RANGE;
  const PfxUrdfJoint& urdfJoint = model.joints[jointIndex];
  if (drive > kPfxJointDriveEffort) return PFX_ERR_INVALID_FLAG;
  if (urdfJoint.jointId == kPfxUrdfNoJoint || urdfJoint.mimicLeader >= 0 ||
      !isValidJoint(world, urdfJoint.jointId) || !pfxIsFinite(target) || !pfxIsFinite(maxForce) ||
      !(maxForce >= 0)) {
    return PFX_ERR_INVALID_VALUE;
  }
  PfxJoint joint = world.getJoint(urdfJoint.jointId);
  PfxJointConstraint& axis = joint.m_constraints[urdfJoint.axis];
  axis.m_drive = drive;
  if (drive == kPfxJointDriveNone) {
    axis.m_driveTarget = 0;
    axis.m_driveMaxForce = 0;
    return world.setJoint(urdfJoint.jointId, joint);
  }
  std::string cut;
  target = pfxClampUrdfJointTarget(urdfJoint, drive, target, &cut);
  axis.m_driveTarget = drive == kPfxJointDrivePosition
                           ? (target - urdfJoint.offset) / urdfJoint.sign
                           : target / urdfJoint.sign;
  // The URDF's effort limit is the actuator's: a larger force asked for does not lift it.
  const PfxFloat effortLimit =
      urdfJoint.effortLimit > 0 ? urdfJoint.effortLimit : std::numeric_limits<PfxFloat>::max();
  axis.m_driveMaxForce = maxForce > 0 ? std::min(maxForce, effortLimit) : effortLimit;
  const PfxInt32 err = world.setJoint(urdfJoint.jointId, joint);
  if (err == PFX_OK && note) *note = cut;
  return err;
}

}  // namespace pfx
