// The scene loaders' entry points and what both readers share: adding a built scene to the
// world so that a refusal undoes itself, mesh shapes, and picking the reader of a file.
#include "pfx/loaders/pfx_scene_loader.h"

#include <tinyxml2.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "loaders/pfx_scene_internal.h"
#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_mesh_loader.h"

namespace pfx {

namespace {

// Radius of the placeholder sphere of a body without geometry.
constexpr PfxFloat kPlaceholderRadius = PfxFloat(0.01);

PfxInt32 report(PfxInt32 code, const std::string& file, const std::string& text,
                std::string* message) {
  // Texts that start with a line number attach to the file name without a space.
  if (message) *message = file + (!text.empty() && std::isdigit(text[0]) ? ":" : ": ") + text;
  return code;
}

bool readFile(const std::string& path, std::string& text) {
  std::error_code error;
  std::ifstream in(path, std::ios::binary);
  if (!std::filesystem::is_regular_file(path, error) || !in) return false;
  std::ostringstream out;
  out << in.rdbuf();
  text = out.str();
  return true;
}

bool sameParam(const PfxWorldParam& a, const PfxWorldParam& b) {
  return a.gravity == b.gravity && a.timeStep == b.timeStep && a.subStep == b.subStep &&
         a.iteration == b.iteration && a.pipeline == b.pipeline &&
         a.separateBias == b.separateBias && a.contactSlop == b.contactSlop &&
         a.contactMargin == b.contactMargin && a.restitutionThreshold == b.restitutionThreshold &&
         a.enableSleep == b.enableSleep && a.worldCenter == b.worldCenter &&
         a.worldExtent == b.worldExtent;
}

PfxInt32 loadXml(PfxWorld& world, const std::string& xml, const std::string& file,
                 const std::string& basePath, const PfxSceneLoadParam& param, PfxSceneModel& model,
                 std::string* message) {
  PfxSceneBuild build;
  build.param = world.getParam();
  PfxSceneError error;
  if (pfxReadSceneXml(xml, basePath, build, error) != PFX_OK ||
      pfxAddSceneToWorld(world, param, build, model, error) != PFX_OK) {
    return report(error.code, file, error.text, message);
  }
  if (message) message->clear();
  return PFX_OK;
}

PfxInt32 loadSdf(PfxWorld& world, const std::string& pathOrText, bool isText,
                 const PfxSceneLoadParam& param, PfxSceneModel& model, std::string* message) {
  const std::string file = isText ? "<sdf string>" : pathOrText;
  PfxSceneBuild build;
  build.param = world.getParam();
  PfxSceneError error;
  if (pfxReadSdf(pathOrText, isText, param, build, error) != PFX_OK ||
      pfxAddSceneToWorld(world, param, build, model, error) != PFX_OK) {
    return report(error.code, file, error.text, message);
  }
  if (message) message->clear();
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxSceneFail(PfxSceneError& error, PfxInt32 code, const std::string& text) {
  error.code = code;
  error.text = text;
  return code;
}

PfxInt32 pfxMakeSceneMeshShape(const std::string& path, const PfxVector3& scale, bool largeMesh,
                               PfxSceneBuild& build, PfxShape& shape, std::string& reason) {
  PfxTriangleMesh triangles;
  if (const PfxInt32 err = pfxLoadMeshFile(path, scale, triangles, &reason); err != PFX_OK) {
    return err;
  }
  shape.reset();
  if (largeMesh) {
    auto mesh = std::make_unique<PfxLargeTriMesh>();
    if (const PfxInt32 err =
            pfxCreateLargeTriMeshFromMesh(triangles, PFX_MESH_FLAG_USE_BVH, *mesh, &reason);
        err != PFX_OK) {
      return err;  // nothing was created inside the struct
    }
    build.model.largeMeshes.emplace_back(mesh.release());
    shape.setLargeTriMesh(build.model.largeMeshes.back().get());
  } else {
    auto hull = std::make_unique<PfxConvexMesh>();
    if (const PfxInt32 err = pfxCreateConvexHull(triangles, *hull, &reason); err != PFX_OK) {
      return err;
    }
    shape.setConvexMesh(hull.get());
    build.model.convexMeshes.push_back(std::move(hull));
  }
  return PFX_OK;
}

void pfxMakeScenePlaceholder(PfxSceneBuildBody& body) {
  body.shapes.push_back(pfxMakeShape(PfxSphere(kPlaceholderRadius)));
  body.state.setContactFilterSelf(0);
  body.state.setContactFilterTarget(0);
}

PfxFloat pfxSceneDampingFraction(double damping, double moved, double subStepTime) {
  if (!(damping > 0) || !(moved > 0)) return 0;
  return static_cast<PfxFloat>(1 - std::exp(-damping * subStepTime / moved));
}

PfxMatrix3 pfxSceneFrame(const PfxVector3& x, const PfxVector3& up) {
  const PfxVector3 ux = x.normalized();
  PfxVector3 uy = up - ux * ux.dot(up);
  if (uy.norm() < PfxFloat(1e-3)) {
    PfxVector3 unusedZ;
    pfxGetPlaneSpace(ux, uy, unusedZ);
  }
  uy.normalize();
  PfxMatrix3 frame;
  frame.col(0) = ux;
  frame.col(1) = uy;
  frame.col(2) = ux.cross(uy);
  return frame;
}

namespace {

template <typename Param>
Param jointParam(const PfxVector3& anchor, const PfxMatrix3& frame) {
  Param param;
  param.anchorPoint = anchor;
  param.enableJointFrame = true;
  param.jointFrame = frame;
  return param;
}

}  // namespace

PfxInt32 pfxInitSceneJoint(PfxJointType type, const PfxSceneBuild& build, PfxUInt32 bodyA,
                           PfxUInt32 bodyB, const PfxVector3& anchor, const PfxMatrix3& frame,
                           PfxJoint& joint) {
  PfxRigidState a = build.bodies[bodyA].state;
  PfxRigidState b = build.bodies[bodyB].state;
  a.setRigidBodyId(bodyA);
  b.setRigidBodyId(bodyB);
  switch (type) {
    case kPfxJointBall:
      return pfxInitializeBallJoint(joint, a, b, jointParam<PfxBallJointInitParam>(anchor, frame));
    case kPfxJointSwingTwist:
      return pfxInitializeSwingTwistJoint(joint, a, b,
                                          jointParam<PfxSwingTwistJointInitParam>(anchor, frame));
    case kPfxJointHinge:
      return pfxInitializeHingeJoint(joint, a, b,
                                     jointParam<PfxHingeJointInitParam>(anchor, frame));
    case kPfxJointSlider:
      return pfxInitializeSliderJoint(joint, a, b,
                                      jointParam<PfxSliderJointInitParam>(anchor, frame));
    case kPfxJointFixed:
      return pfxInitializeFixedJoint(joint, a, b,
                                     jointParam<PfxFixedJointInitParam>(anchor, frame));
    default:
      return pfxInitializeUniversalJoint(joint, a, b,
                                         jointParam<PfxUniversalJointInitParam>(anchor, frame));
  }
}

PfxInt32 pfxAddSceneToWorld(PfxWorld& world, const PfxSceneLoadParam& param, PfxSceneBuild& build,
                            PfxSceneModel& model, PfxSceneError& error) {
  const PfxWorldParam oldParam = world.getParam();
  const bool empty = world.getNumRigidBodies() == 0;
  bool applied = false;
  if (param.applyPhysics && build.hasPhysics && !sameParam(oldParam, build.param)) {
    if (empty) {
      if (const PfxInt32 err = world.initialize(build.param); err != PFX_OK) {
        world.initialize(oldParam);
        return pfxSceneFail(
            error, err,
            std::string("physics: the world refused the parameters (") + pfxErrorString(err) + ")");
      }
      applied = true;
    } else {
      build.model.warnings.push_back(
          "physics: not applied, as the world already holds bodies (PfxWorld::initialize "
          "would remove them); model.worldParam holds what the file asks for");
    }
  }
  const PfxUInt32 firstBody = world.getNumRigidBodies();
  const PfxUInt32 firstJoint = world.getNumJoints();
  const PfxUInt32 firstCoupling = world.getNumJointCouplings();
  PfxInt32 err = PFX_OK;
  std::string what;
  for (std::size_t i = 0; err == PFX_OK && i < build.bodies.size(); ++i) {
    const PfxSceneBuildBody& body = build.bodies[i];
    err = world.addRigidBody(body.state, body.body, body.shapes.data(),
                             static_cast<PfxUInt32>(body.shapes.size()));
    if (err != PFX_OK) what = "body '" + build.model.bodies[i].name + "'";
  }
  for (std::size_t i = 0; err == PFX_OK && i < build.joints.size(); ++i) {
    PfxJoint joint = build.joints[i];
    joint.m_rigidBodyIdA += firstBody;
    joint.m_rigidBodyIdB += firstBody;
    err = world.addJoint(joint);
    if (err != PFX_OK) what = "joint '" + build.model.joints[i].name + "'";
  }
  for (std::size_t i = 0; err == PFX_OK && i < build.couplings.size(); ++i) {
    PfxJointCoupling coupling = build.couplings[i];
    coupling.m_leaderJointId += firstJoint;
    coupling.m_followerJointId += firstJoint;
    err = world.addJointCoupling(coupling);
    if (err != PFX_OK) what = "coupling '" + build.model.couplings[i].name + "'";
  }
  for (std::size_t i = 0; err == PFX_OK && i < build.noCollision.size(); ++i) {
    err = world.excludeCollision(firstBody + build.noCollision[i].first,
                                 firstBody + build.noCollision[i].second);
    if (err != PFX_OK) what = "self collision";
  }
  if (err != PFX_OK) {
    world.truncate(firstBody, firstJoint, firstCoupling);
    if (applied) world.initialize(oldParam);
    return pfxSceneFail(error, err,
                        what + ": the world refused it (" + std::string(pfxErrorString(err)) + ")");
  }
  PfxSceneModel& built = build.model;
  for (PfxSceneBody& body : built.bodies) body.bodyId += firstBody;
  for (PfxSceneJoint& joint : built.joints) {
    if (joint.jointId != kPfxSceneNone) joint.jointId += firstJoint;
  }
  for (PfxSceneCoupling& coupling : built.couplings) coupling.couplingId += firstCoupling;
  built.worldParam = build.hasPhysics ? build.param : oldParam;
  built.physicsApplied = applied || (build.hasPhysics && sameParam(oldParam, build.param));
  built.firstBodyId = firstBody;
  built.numBodies = static_cast<PfxUInt32>(build.bodies.size());
  built.firstJointId = firstJoint;
  built.numJoints = static_cast<PfxUInt32>(build.joints.size());
  built.firstCouplingId = firstCoupling;
  built.numCouplings = static_cast<PfxUInt32>(build.couplings.size());
  model = std::move(built);
  return PFX_OK;
}

PfxInt32 pfxLoadSceneXml(PfxWorld& world, const std::string& path, const PfxSceneLoadParam& param,
                         PfxSceneModel& model, std::string* message) {
  std::string xml;
  if (!readFile(path, xml)) {
    return report(PFX_ERR_INVALID_VALUE, path, "cannot be read (no such file)", message);
  }
  return loadXml(world, xml, path, std::filesystem::path(path).parent_path().string(), param, model,
                 message);
}

PfxInt32 pfxLoadSceneXmlString(PfxWorld& world, const std::string& xml, const std::string& basePath,
                               const PfxSceneLoadParam& param, PfxSceneModel& model,
                               std::string* message) {
  return loadXml(world, xml, "<scene string>", basePath, param, model, message);
}

PfxInt32 pfxLoadSdfWorld(PfxWorld& world, const std::string& path, const PfxSceneLoadParam& param,
                         PfxSceneModel& model, std::string* message) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    return report(PFX_ERR_INVALID_VALUE, path, "cannot be read (no such file)", message);
  }
  return loadSdf(world, path, false, param, model, message);
}

PfxInt32 pfxLoadSdfString(PfxWorld& world, const std::string& sdf, const PfxSceneLoadParam& param,
                          PfxSceneModel& model, std::string* message) {
  return loadSdf(world, sdf, true, param, model, message);
}

PfxInt32 pfxLoadSceneFile(PfxWorld& world, const std::string& path, const PfxSceneLoadParam& param,
                          PfxSceneModel& model, std::string* message) {
  std::string text;
  if (!readFile(path, text)) {
    return report(PFX_ERR_INVALID_VALUE, path, "cannot be read (no such file)", message);
  }
  tinyxml2::XMLDocument document;
  if (document.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS) {
    return report(PFX_ERR_INVALID_VALUE, path,
                  std::to_string(document.ErrorLineNum()) + ": not well-formed XML (" +
                      document.ErrorStr() + ")",
                  message);
  }
  const std::string root = document.RootElement() ? document.RootElement()->Name() : "";
  if (root == "pfx_scene") {
    return loadXml(world, text, path, std::filesystem::path(path).parent_path().string(), param,
                   model, message);
  }
  if (root == "sdf") return loadSdf(world, path, false, param, model, message);
  return report(PFX_ERR_INVALID_VALUE, path,
                "root element <" + root + "> is neither <pfx_scene> nor <sdf>", message);
}

PfxInt32 pfxFindSceneBody(const PfxSceneModel& model, const std::string& name) {
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    if (model.bodies[i].name == name) return static_cast<PfxInt32>(i);
  }
  return -1;
}

PfxInt32 pfxFindSceneJoint(const PfxSceneModel& model, const std::string& name) {
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    if (model.joints[i].name == name) return static_cast<PfxInt32>(i);
  }
  return -1;
}

PfxTransform3 pfxGetSceneBodyFrame(const PfxWorld& world, const PfxSceneBody& body) {
  return world.getRigidState(body.bodyId).getTransform() * body.frameInBody;
}

PfxFloat pfxGetSceneJointPosition(const PfxWorld& world, const PfxSceneJoint& joint,
                                  PfxUInt32 which) {
  if (joint.jointId == kPfxSceneNone || which > 1 || joint.axes[which] == kPfxSceneNone) return 0;
  const PfxJoint& j = world.getJoint(joint.jointId);
  PfxFloat coordinates[6];
  pfxCalcJointCoordinates(j, world.getRigidState(j.m_rigidBodyIdA),
                          world.getRigidState(j.m_rigidBodyIdB), coordinates);
  return coordinates[joint.axes[which]];
}

}  // namespace pfx
