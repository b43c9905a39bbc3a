// The URDF loader's stages, shared by its source files: checking the XML (so that every
// error names its element), parsing with urdfdom, resolving mesh URIs, and building bodies
// and joints into buffers outside the world.
#pragma once

#include <urdf_model/model.h>
#include <urdf_world/types.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pfx/loaders/pfx_urdf_loader.h"

namespace pfx {

// Why a load failed: an error code and a sentence naming the element ("link 'forearm':
// inertia is not positive definite"); the loader puts the file name in front.
struct PfxUrdfError {
  PfxInt32 code = PFX_OK;
  std::string text;
};

// One <collision> of a link as the file gives it. urdfdom drops every collision element of
// a link when one of them has a geometry it does not know (such as <capsule>), so the
// loader reads them itself.
struct PfxUrdfCollision {
  std::string geometry;  // the element inside <geometry>: box, sphere, ...; "" when none
  urdf::Pose origin;
  double size[3] = {0, 0, 0};  // box
  double radius = 0;           // sphere, cylinder, capsule
  double length = 0;           // cylinder, capsule (the capsule's cylinder part)
  std::string filename;        // mesh
  double scale[3] = {1, 1, 1};
  int line = 0;
};

// The URDF's links and joints in the order the file gives them, and each link's collision
// elements in file order.
struct PfxUrdfDocumentOrder {
  std::vector<std::string> links;
  std::vector<std::string> joints;
  std::map<std::string, std::vector<PfxUrdfCollision>> collisions;
};

// A name and a number as the loader's error texts print them ("link 'arm'", "mass -1").
std::string pfxUrdfQuoted(const std::string& name);
std::string pfxUrdfNumber(double value);

// Checks what urdfdom either accepts silently or rejects without naming the element:
// unexpanded xacro, XML syntax, names, joint types, dangling and duplicate references,
// cycles, mimic leaders, and the numbers of masses, inertias, limits, axes, dynamics and
// collision geometry. PFX_OK or the error.
PfxInt32 pfxCheckUrdfXml(const std::string& xml, PfxUrdfDocumentOrder& order, PfxUrdfError& error);

// urdfdom's model of the text, or null with urdfdom's own words in `error`.
urdf::ModelInterfaceSharedPtr pfxParseUrdfModel(const std::string& xml, PfxUrdfError& error);

// The file a mesh URI names: package://name/rest through ROS_PACKAGE_PATH, then
// `packageRoot`, then the URDF's folder and its parents; file:// and plain paths relative
// to the URDF's folder. False when no candidate exists; `searched` then lists the places.
bool pfxResolveUrdfMeshUri(const std::string& uri, const std::string& urdfFolder,
                           const std::string& packageRoot, std::string& path,
                           std::string& searched);

// Everything a load adds, built outside the world. Body ids in the joints, joint ids in the
// couplings and in the model, and body ids in the model's links count from zero here; the
// loader shifts them by the world's counts when it adds them.
struct PfxUrdfBuildBody {
  PfxRigidState state;
  PfxRigidBody body;
  std::vector<PfxShape> shapes;
};

struct PfxUrdfBuild {
  std::vector<PfxUrdfBuildBody> bodies;
  std::vector<PfxJoint> joints;
  std::vector<PfxJointCoupling> couplings;
  // Body pairs that never collide although no joint holds them: the bodies around a light
  // body made of a massless helper link, which the URDF joins through that link.
  std::vector<std::pair<PfxUInt32, PfxUInt32>> noCollision;
  PfxUrdfModel model;
};

// Builds the robot for a world with the given time step (damping depends on it).
PfxInt32 pfxBuildUrdf(const urdf::ModelInterface& urdfModel, const PfxUrdfDocumentOrder& order,
                      const std::string& urdfFolder, const PfxUrdfLoadParam& param,
                      PfxFloat subStepTime, PfxUrdfBuild& build, PfxUrdfError& error);

}  // namespace pfx
