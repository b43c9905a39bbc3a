// What the scene readers (pfx XML, SDF) share: the scene built outside the world, its
// addition to the world, mesh shapes and the wording of errors.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "pfx/loaders/pfx_scene_loader.h"

namespace pfx {

// Why a load failed: a code and "<line>: <element> '<name>': <reason>" without the file,
// which the entry point puts in front.
struct PfxSceneError {
  PfxInt32 code = PFX_OK;
  std::string text;
};

struct PfxSceneBuildBody {
  PfxRigidState state;
  PfxRigidBody body;
  std::vector<PfxShape> shapes;
};

// Everything a load adds. Body ids in joints and model.bodies, and joint ids in couplings
// and model.joints, count from zero here; pfxAddSceneToWorld shifts them.
struct PfxSceneBuild {
  PfxWorldParam param;      // the world's parameters with the file's over them
  bool hasPhysics = false;  // the file gives physics at all
  std::vector<PfxSceneBuildBody> bodies;
  std::vector<PfxJoint> joints;
  std::vector<PfxJointCoupling> couplings;
  // Body pairs that never collide although no joint holds them (SDF links of one model
  // without self collision).
  std::vector<std::pair<PfxUInt32, PfxUInt32>> noCollision;
  PfxSceneModel model;
};

// Fails with `code` and text; returns the code.
PfxInt32 pfxSceneFail(PfxSceneError& error, PfxInt32 code, const std::string& text);

// The shape of a mesh file (pfx_mesh_loader.h): its convex hull for a body that moves, a
// large mesh for one that does not. The mesh goes into build.model, which owns it.
PfxInt32 pfxMakeSceneMeshShape(const std::string& path, const PfxVector3& scale, bool largeMesh,
                               PfxSceneBuild& build, PfxShape& shape, std::string& reason);

// A small sphere whose contact filters match nothing, for a body without geometry (SDF's
// world, a link without collision): neither bodies nor rays ever meet it.
void pfxMakeScenePlaceholder(PfxSceneBuildBody& body);

// The fraction of a free axis's velocity that viscous damping `damping` (N m s/rad or
// N s/m) removes per sub-step h from an axis that moves inertia (or mass) `moved`.
PfxFloat pfxSceneDampingFraction(double damping, double moved, double subStepTime);

// A right-handed frame (columns X, Y, Z) whose X axis is `x` and whose Y axis lies along
// `up` made perpendicular to X; any perpendicular Y when `up` is (nearly) along X.
PfxMatrix3 pfxSceneFrame(const PfxVector3& x, const PfxVector3& up);

// A joint of `type` between two built bodies, with its frame (world, columns X, Y, Z) at
// the world point `anchor`, through the pfxInitialize...Joint of the type; body ids are
// the builds' indices. Limits and drives are the type's defaults until the reader sets them.
PfxInt32 pfxInitSceneJoint(PfxJointType type, const PfxSceneBuild& build, PfxUInt32 bodyA,
                           PfxUInt32 bodyB, const PfxVector3& anchor, const PfxMatrix3& frame,
                           PfxJoint& joint);

// Applies the physics (when asked and possible), adds the bodies, joints and couplings, and
// fills `model` from build.model with world ids. On a refusal removes what it added,
// restores the world's parameters and leaves `model` alone.
PfxInt32 pfxAddSceneToWorld(PfxWorld& world, const PfxSceneLoadParam& param, PfxSceneBuild& build,
                            PfxSceneModel& model, PfxSceneError& error);

// Readers, each filling `build` from a file's text or from a file.
PfxInt32 pfxReadSceneXml(const std::string& xml, const std::string& basePath, PfxSceneBuild& build,
                         PfxSceneError& error);
PfxInt32 pfxReadSdf(const std::string& pathOrText, bool isText, const PfxSceneLoadParam& param,
                    PfxSceneBuild& build, PfxSceneError& error);

}  // namespace pfx
