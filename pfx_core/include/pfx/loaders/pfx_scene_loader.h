// Scene files into a PfxWorld: pfx's own scene XML (tinyxml2; the format is documented in
// the README, "Scene files") and SDFormat worlds (Debian's libsdformat 12). Both give the
// world's physics parameters, bodies with their shapes, materials, motion types and contact
// filters, and joints; pfx XML also joint drives and couplings. One model type describes
// what either file became, so that a program (pfx_sim --world) need not know which it read.
//
// A load builds everything outside the world first, then adds it; a refusal half way is
// undone with PfxWorld::truncate, so a failed load leaves the world (parameters included)
// and the model as they were. Errors read "<file>:<line>: <element> '<name>': <reason>".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_world.h"
#include "pfx/loaders/pfx_urdf_loader.h"

namespace pfx {

constexpr PfxUInt32 kPfxSceneNone = 0xffffffffu;

struct PfxSceneLoadParam {
  // The file's physics (gravity, time step, sub-steps, iterations, ...) replace the world's
  // parameters when the world holds no body yet: PfxWorld::initialize empties a world, so on
  // a world that already holds bodies the parameters are only reported (model.worldParam)
  // and a warning says they were not applied. False: the world's parameters stay.
  bool applyPhysics = true;
  // SDF model:// URIs: the model folder NAME is looked for in these folders first, then in
  // GAZEBO_MODEL_PATH and SDF_PATH (colon-separated), then beside the world file and in its
  // models/ and ../models/ folders.
  std::vector<std::string> modelPaths;
};

// What one body of the file became. SDF names are scoped as SDFormat scopes them:
// "model::link", and "outer::inner::link" for nested models.
struct PfxSceneBody {
  std::string name;
  PfxUInt32 bodyId = 0;
  // Pose of the file's body frame (an SDF link frame) in the world body's frame: pfx bodies
  // sit at their centre of mass, so frame pose in the world = body transform * frameInBody.
  PfxTransform3 frameInBody = PfxTransform3::Identity();
};

// What one joint of the file became.
struct PfxSceneJoint {
  std::string name;
  std::string type;    // as the file names it: "revolute", "hinge", "ball", ...
  std::string parent;  // body names as in PfxSceneBody ("world" for SDF's world)
  std::string child;
  PfxUInt32 jointId = kPfxSceneNone;
  // The world joint's axes (kPfxJointAxisX ... kPfxJointAxisSwing2) that carry the file's
  // first and second joint coordinate, kPfxSceneNone where the joint has none: a hinge's
  // angle is axes[0] = twist, a slider's position axes[0] = X, a universal joint's two
  // angles are swing1 and swing2.
  PfxUInt32 axes[2] = {kPfxSceneNone, kPfxSceneNone};
};

struct PfxSceneCoupling {
  std::string name;
  PfxUInt32 couplingId = 0;
};

// A loaded scene. Owns the convex and large meshes its bodies' shapes point to: keep it
// alive as long as the world holds the scene.
struct PfxSceneModel {
  std::string name;  // the scene's or SDF world's name
  // The parameters the file asks for: the world's parameters at load with the file's
  // values over them. physicsApplied: whether the world now runs with them.
  PfxWorldParam worldParam;
  bool physicsApplied = false;
  std::vector<PfxSceneBody> bodies;  // in file order
  std::vector<PfxSceneJoint> joints;
  std::vector<PfxSceneCoupling> couplings;
  // One line per thing pfx read differently from the file or left out, e.g. every SDF
  // element pfx ignores, once, with how often it appeared.
  std::vector<std::string> warnings;
  PfxUInt32 firstBodyId = 0;  // bodies, joints and couplings the load added, contiguous
  PfxUInt32 numBodies = 0;
  PfxUInt32 firstJointId = 0;
  PfxUInt32 numJoints = 0;
  PfxUInt32 firstCouplingId = 0;
  PfxUInt32 numCouplings = 0;
  std::vector<std::unique_ptr<PfxConvexMesh>> convexMeshes;
  std::vector<std::unique_ptr<PfxLargeTriMesh, PfxLargeTriMeshRelease>> largeMeshes;
};

// pfx scene XML (root element <pfx_scene>). The string form resolves mesh files against
// `basePath` and names the file "<scene string>" in errors.
PfxInt32 pfxLoadSceneXml(PfxWorld& world, const std::string& path, const PfxSceneLoadParam& param,
                         PfxSceneModel& model, std::string* message = nullptr);
PfxInt32 pfxLoadSceneXmlString(PfxWorld& world, const std::string& xml, const std::string& basePath,
                               const PfxSceneLoadParam& param, PfxSceneModel& model,
                               std::string* message = nullptr);

// SDFormat file holding one <world> (or one <model>, loaded into the world as it is), read
// through libsdformat, which converts SDF 1.3 ... 1.8 to its own version and resolves
// <include>s. The string form names the file "<sdf string>".
PfxInt32 pfxLoadSdfWorld(PfxWorld& world, const std::string& path, const PfxSceneLoadParam& param,
                         PfxSceneModel& model, std::string* message = nullptr);
PfxInt32 pfxLoadSdfString(PfxWorld& world, const std::string& sdf, const PfxSceneLoadParam& param,
                          PfxSceneModel& model, std::string* message = nullptr);

// Either reader, chosen by the file's root element: <pfx_scene> or <sdf>.
PfxInt32 pfxLoadSceneFile(PfxWorld& world, const std::string& path, const PfxSceneLoadParam& param,
                          PfxSceneModel& model, std::string* message = nullptr);

// Index into model.bodies / model.joints by name, or -1.
PfxInt32 pfxFindSceneBody(const PfxSceneModel& model, const std::string& name);
PfxInt32 pfxFindSceneJoint(const PfxSceneModel& model, const std::string& name);
// Pose in the world of a body's file frame (an SDF link frame).
PfxTransform3 pfxGetSceneBodyFrame(const PfxWorld& world, const PfxSceneBody& body);
// The joint's file coordinate `which` (0 or 1): radians or metres; 0 where it has none.
PfxFloat pfxGetSceneJointPosition(const PfxWorld& world, const PfxSceneJoint& joint,
                                  PfxUInt32 which = 0);

}  // namespace pfx
