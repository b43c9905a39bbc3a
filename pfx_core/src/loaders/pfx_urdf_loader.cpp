// Loading a URDF: check the text, parse it with urdfdom, build everything outside the world,
// then add it. Only the last step touches the world, and it undoes itself if an addition is
// refused, so a failed load leaves the world and the model as they were.
#include "pfx/loaders/pfx_urdf_loader.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "loaders/pfx_urdf_internal.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

PfxInt32 reportUrdfFailure(PfxInt32 code, const std::string& file, const std::string& text,
                           std::string* message) {
  if (message) *message = file + ": " + text;
  return code;
}

PfxInt32 checkParam(const PfxUrdfLoadParam& param, PfxUrdfError& error) {
  error.code = PFX_ERR_INVALID_VALUE;
  if (!pfxIsFinite(param.rootPosition) || !pfxIsUnitQuat(param.rootOrientation)) {
    error.text =
        "load parameters: the root pose is not finite, or its orientation not a unit "
        "quaternion";
  } else if (!(param.friction >= 0) || !pfxIsFinite(param.friction) ||
             !(param.restitution >= 0 && param.restitution <= 1)) {
    error.text = "load parameters: friction must be finite and >= 0, restitution in [0, 1]";
  } else if (param.placeAboveGround &&
             (!pfxIsFinite(param.groundHeight) || !pfxIsFinite(param.groundClearance))) {
    error.text = "load parameters: groundHeight and groundClearance must be finite";
  } else if (param.disableSelfCollision && param.selfCollisionGroup == 0) {
    error.text = "load parameters: disableSelfCollision needs a non-zero selfCollisionGroup";
  } else {
    error.code = PFX_OK;
  }
  return error.code;
}

// Moves the built robot along Z so that its lowest collision point lies at `height`; the
// joints hold their bodies in the bodies' frames, so a move of every body keeps them.
void placeLowestPointAt(PfxUrdfBuild& build, PfxFloat height) {
  PfxFloat lowest = std::numeric_limits<PfxFloat>::infinity();
  for (const PfxUrdfBuildBody& body : build.bodies) {
    const PfxRigidState& state = body.state;
    if (state.getContactFilterSelf() == 0 && state.getContactFilterTarget() == 0) continue;
    for (const PfxShape& shape : body.shapes) {
      const PfxVector3 point = pfxGetSupportPoint(
          shape, state.getTransform() * shape.getOffsetTransform(), PfxVector3(0, 0, -1));
      lowest = std::min(lowest, point.z());
    }
  }
  if (!pfxIsFinite(lowest)) return;  // nothing to place
  for (PfxUrdfBuildBody& body : build.bodies) {
    body.state.setPosition(body.state.getPosition() + PfxVector3(0, 0, height - lowest));
  }
}

// Overlaps this shallow are surfaces that touch, drawn to meet.
constexpr PfxFloat kOverlapTolerance = PfxFloat(1e-4);

// Bodies of the robot that overlap where it starts never collide with each other, as in
// simulators that let a robot's links overlap (Gazebo's, which does not collide the links
// of one model): descriptions written for them draw fingertips, wrists and covers into each
// other, and pushing them apart would fight the joints from the first step. A warning lists
// the pairs. Bodies already held apart (by a joint, or around a light body) are left alone.
PfxInt32 excludeOverlappingLinks(PfxWorld& world, PfxUInt32 firstBody, PfxUrdfBuild& build) {
  const PfxUInt32 numBodies = static_cast<PfxUInt32>(build.bodies.size());
  std::vector<std::string> names(numBodies);
  for (const PfxUrdfLink& link : build.model.links) {
    if (names[link.bodyId].empty()) names[link.bodyId] = link.name;
  }
  std::vector<std::pair<PfxUInt32, PfxUInt32>> jointed;
  for (const PfxJoint& joint : build.joints) {
    jointed.emplace_back(std::min(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB),
                         std::max(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB));
  }
  for (const auto& [a, b] : build.noCollision) jointed.emplace_back(std::min(a, b), std::max(a, b));
  std::sort(jointed.begin(), jointed.end());
  const auto meets = [&](PfxUInt32 id) {
    const PfxRigidState& state = world.getRigidState(firstBody + id);
    return state.getContactFilterSelf() != 0 || state.getContactFilterTarget() != 0;
  };
  std::string pairs;
  PfxContactCandidate candidates[PFX_MAX_CONTACT_CANDIDATES];
  for (PfxUInt32 a = 0; a < numBodies; ++a) {
    for (PfxUInt32 b = a + 1; b < numBodies; ++b) {
      if (!meets(a) || !meets(b) ||
          std::binary_search(jointed.begin(), jointed.end(), std::make_pair(a, b))) {
        continue;
      }
      const PfxTransform3 ta = world.getRigidState(firstBody + a).getTransform();
      const PfxTransform3 tb = world.getRigidState(firstBody + b).getTransform();
      const PfxUInt32 found = pfxContactCollidables(world.getCollidable(firstBody + a), ta,
                                                    world.getCollidable(firstBody + b), tb, 0,
                                                    candidates, PFX_MAX_CONTACT_CANDIDATES);
      PfxFloat depth = 0;
      for (PfxUInt32 i = 0; i < found; ++i) depth = std::max(depth, -candidates[i].m_distance);
      if (!(depth > kOverlapTolerance)) continue;  // apart, or touching
      if (const PfxInt32 err = world.excludeCollision(firstBody + a, firstBody + b);
          err != PFX_OK) {
        return err;
      }
      std::ostringstream text;
      text << (pairs.empty() ? "" : ", ") << "'" << names[a] << "' and '" << names[b] << "' ("
           << depth << " m)";
      pairs += text.str();
    }
  }
  if (!pairs.empty()) {
    build.model.warnings.push_back(
        "links that overlap where the robot starts never collide with each other: " + pairs);
  }
  return PFX_OK;
}

// Adds what was built; on a refusal removes what it added and returns the refusal.
PfxInt32 addToWorld(PfxWorld& world, PfxUrdfBuild& build, bool selfCollision, PfxUrdfError& error) {
  const PfxUInt32 firstBody = world.getNumRigidBodies();
  const PfxUInt32 firstJoint = world.getNumJoints();
  const PfxUInt32 firstCoupling = world.getNumJointCouplings();
  PfxInt32 err = PFX_OK;
  for (std::size_t i = 0; err == PFX_OK && i < build.bodies.size(); ++i) {
    const PfxUrdfBuildBody& body = build.bodies[i];
    err = world.addRigidBody(body.state, body.body, body.shapes.data(),
                             static_cast<PfxUInt32>(body.shapes.size()));
  }
  for (std::size_t i = 0; err == PFX_OK && i < build.joints.size(); ++i) {
    PfxJoint joint = build.joints[i];
    joint.m_rigidBodyIdA += firstBody;
    joint.m_rigidBodyIdB += firstBody;
    err = world.addJoint(joint);
  }
  for (std::size_t i = 0; err == PFX_OK && i < build.couplings.size(); ++i) {
    PfxJointCoupling coupling = build.couplings[i];
    coupling.m_leaderJointId += firstJoint;
    coupling.m_followerJointId += firstJoint;
    err = world.addJointCoupling(coupling);
  }
  for (std::size_t i = 0; err == PFX_OK && i < build.noCollision.size(); ++i) {
    err = world.excludeCollision(firstBody + build.noCollision[i].first,
                                 firstBody + build.noCollision[i].second);
  }
  if (err == PFX_OK && selfCollision) err = excludeOverlappingLinks(world, firstBody, build);
  if (err != PFX_OK) {
    world.truncate(firstBody, firstJoint, firstCoupling);
    error.code = err;
    error.text = std::string("robot: the world refused a body, joint or coupling (") +
                 pfxErrorString(err) + ")";
    return err;
  }
  PfxUrdfModel& model = build.model;
  for (PfxUrdfLink& link : model.links) {
    link.bodyId += firstBody;
    if (link.collapsedJointId != kPfxUrdfNoJoint) link.collapsedJointId += firstJoint;
  }
  for (PfxUrdfJoint& joint : model.joints) {
    if (joint.jointId != kPfxUrdfNoJoint) joint.jointId += firstJoint;
    if (joint.couplingId != kPfxUrdfNoJoint) joint.couplingId += firstCoupling;
  }
  model.firstBodyId = firstBody;
  model.numBodies = static_cast<PfxUInt32>(build.bodies.size());
  model.firstJointId = firstJoint;
  model.numJoints = static_cast<PfxUInt32>(build.joints.size());
  model.firstCouplingId = firstCoupling;
  model.numCouplings = static_cast<PfxUInt32>(build.couplings.size());
  return PFX_OK;
}

PfxInt32 load(PfxWorld& world, const std::string& xml, const std::string& file,
              const std::string& folder, const PfxUrdfLoadParam& param, PfxUrdfModel& model,
              std::string* message) {
  PfxUrdfError error;
  PfxUrdfDocumentOrder order;
  if (checkParam(param, error) != PFX_OK || pfxCheckUrdfXml(xml, order, error) != PFX_OK) {
    return reportUrdfFailure(error.code, file, error.text, message);
  }
  const urdf::ModelInterfaceSharedPtr parsed = pfxParseUrdfModel(xml, error);
  if (!parsed) return reportUrdfFailure(error.code, file, error.text, message);
  const PfxWorldParam& worldParam = world.getParam();
  PfxUrdfBuild build;
  if (pfxBuildUrdf(*parsed, order, folder, param,
                   worldParam.timeStep / PfxFloat(worldParam.subStep), build, error) != PFX_OK) {
    return reportUrdfFailure(error.code, file, error.text, message);
  }
  if (param.placeAboveGround) {
    placeLowestPointAt(build, param.groundHeight + param.groundClearance);
  }
  if (addToWorld(world, build, !param.disableSelfCollision, error) != PFX_OK) {
    return reportUrdfFailure(error.code, file, error.text, message);
  }
  model = std::move(build.model);
  if (message) message->clear();
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxLoadUrdfFile(PfxWorld& world, const std::string& path, const PfxUrdfLoadParam& param,
                         PfxUrdfModel& model, std::string* message) {
  std::error_code error;
  std::ifstream in(path, std::ios::binary);
  if (!std::filesystem::is_regular_file(path, error) || !in) {
    return reportUrdfFailure(PFX_ERR_INVALID_VALUE, path, "cannot be read (no such file)", message);
  }
  std::ostringstream text;
  text << in.rdbuf();
  return load(world, text.str(), path, std::filesystem::path(path).parent_path().string(), param,
              model, message);
}

PfxInt32 pfxLoadUrdfString(PfxWorld& world, const std::string& xml, const std::string& basePath,
                           const PfxUrdfLoadParam& param, PfxUrdfModel& model,
                           std::string* message) {
  return load(world, xml, "<urdf string>", basePath, param, model, message);
}

}  // namespace pfx
