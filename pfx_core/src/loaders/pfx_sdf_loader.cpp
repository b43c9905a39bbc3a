// SDFormat worlds through libsdformat 12: it parses, converts every SDF version to its own
// (1.3's <ode><solver><dt> becomes <max_step_size>, 1.5's <physics><gravity> the world's
// <gravity>, 1.6 joint axes gain their expressed-in frame), resolves <include>s and every
// pose frame; this reader turns its objects into bodies and joints (README, "SDFormat
// worlds", lists what is read and what is not). Every element of the file that pfx does not
// read is named in one warning with its count, so nothing is dropped silently.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sdf/sdf.hh>
#include <set>
#include <sstream>

#include "loaders/pfx_scene_internal.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfx {

namespace {

namespace math = ignition::math;
namespace fs = std::filesystem;

// SDF writes "no limit" as a huge number (1e16 by default).
constexpr double kNoLimit = 1e15;

// Element paths (from <world>, a nested model written as one "model") that the reader
// turns into something in pfx; anything else the file sets is listed as ignored. A path is
// honoured with everything below it only where the reader reads all of that.
const std::set<std::string> kHonoured = {
    "world",
    "world/gravity",
    "world/physics",
    "world/physics/max_step_size",
    "world/physics/gravity",
    "world/physics/ode",
    "world/physics/ode/solver",
    "world/physics/ode/solver/iters",
    "world/physics/ode/solver/dt",
    "world/model",
    "world/model/static",
    "world/model/pose",
    "world/model/self_collide",
    "world/model/link",
    "world/model/link/pose",
    "world/model/link/self_collide",
    "world/model/link/gravity",  // true is what pfx does; false gets its own warning
    "world/model/link/kinematic",
    "world/model/link/inertial",
    "world/model/link/inertial/mass",
    "world/model/link/inertial/pose",
    "world/model/link/inertial/inertia",
    "world/model/link/inertial/inertia/ixx",
    "world/model/link/inertial/inertia/iyy",
    "world/model/link/inertial/inertia/izz",
    "world/model/link/inertial/inertia/ixy",
    "world/model/link/inertial/inertia/ixz",
    "world/model/link/inertial/inertia/iyz",
    "world/model/link/collision",
    "world/model/link/collision/pose",
    "world/model/link/collision/geometry",
    "world/model/link/collision/geometry/empty",
    "world/model/link/collision/geometry/box",
    "world/model/link/collision/geometry/box/size",
    "world/model/link/collision/geometry/sphere",
    "world/model/link/collision/geometry/sphere/radius",
    "world/model/link/collision/geometry/cylinder",
    "world/model/link/collision/geometry/cylinder/radius",
    "world/model/link/collision/geometry/cylinder/length",
    "world/model/link/collision/geometry/capsule",
    "world/model/link/collision/geometry/capsule/radius",
    "world/model/link/collision/geometry/capsule/length",
    "world/model/link/collision/geometry/plane",
    "world/model/link/collision/geometry/plane/normal",
    "world/model/link/collision/geometry/plane/size",
    "world/model/link/collision/geometry/mesh",
    "world/model/link/collision/geometry/mesh/uri",
    "world/model/link/collision/geometry/mesh/scale",
    "world/model/link/collision/surface",
    "world/model/link/collision/surface/friction",
    "world/model/link/collision/surface/friction/ode",
    "world/model/link/collision/surface/friction/ode/mu",
    "world/model/link/collision/surface/bounce",
    "world/model/link/collision/surface/bounce/restitution_coefficient",
    "world/model/link/collision/surface/contact",
    "world/model/link/collision/surface/contact/collide_bitmask",
    "world/model/joint",
    "world/model/joint/parent",
    "world/model/joint/child",
    "world/model/joint/pose",
    "world/model/joint/thread_pitch",
    "world/model/joint/axis",
    "world/model/joint/axis/xyz",
    "world/model/joint/axis/use_parent_model_frame",
    "world/model/joint/axis/limit",
    "world/model/joint/axis/limit/lower",
    "world/model/joint/axis/limit/upper",
    "world/model/joint/axis/dynamics",
    "world/model/joint/axis/dynamics/damping",
    "world/model/joint/axis/dynamics/friction",
    "world/model/joint/axis2",
    "world/model/joint/axis2/xyz",
    "world/model/joint/axis2/use_parent_model_frame",
    "world/model/joint/axis2/limit",
    "world/model/joint/axis2/limit/lower",
    "world/model/joint/axis2/limit/upper",
    "world/model/joint/axis2/dynamics",
    "world/model/joint/axis2/dynamics/damping",
    "world/model/joint/axis2/dynamics/friction"};

// Attributes that name things or place frames: sdformat resolves the frames.
const std::set<std::string> kHonouredAttributes = {
    "name", "type", "version", "relative_to", "expressed_in", "frame", "canonical_link"};

std::string inQuotes(const std::string& name) { return "'" + name + "'"; }

std::string numberText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

PfxVector3 toVector(const math::Vector3d& v) {
  return PfxVector3(PfxFloat(v.X()), PfxFloat(v.Y()), PfxFloat(v.Z()));
}

PfxQuat quatFromSdf(const math::Quaterniond& q) {
  return PfxQuat(PfxFloat(q.W()), PfxFloat(q.X()), PfxFloat(q.Y()), PfxFloat(q.Z())).normalized();
}

bool finite(const math::Vector3d& v) {
  return std::isfinite(v.X()) && std::isfinite(v.Y()) && std::isfinite(v.Z());
}

bool finite(const math::Pose3d& p) {
  return finite(p.Pos()) && std::isfinite(p.Rot().W()) && std::isfinite(p.Rot().X()) &&
         std::isfinite(p.Rot().Y()) && std::isfinite(p.Rot().Z());
}

// The path of an element for kHonoured: from <world> (or <model> for a model file), with
// nested models written as one "model" and <sdf> left out.
std::string elementPath(const sdf::ElementPtr& element) {
  std::vector<std::string> names;
  for (sdf::ElementPtr e = element; e && e->GetName() != "sdf"; e = e->GetParent()) {
    if (!(e->GetName() == "model" && !names.empty() && names.back() == "model")) {
      names.push_back(e->GetName());
    }
  }
  std::string path = names.empty() || names.back() == "world" ? "" : "world/";
  for (auto it = names.rbegin(); it != names.rend(); ++it) {
    path += (it == names.rbegin() ? "" : "/") + *it;
  }
  return path;
}

// A body being built from one link, with what the joints need from it.
struct LinkInfo {
  PfxUInt32 body = 0;
  std::string model;  // scope of the link's model ("outer::inner")
  bool selfCollide = false;
};

class SdfReader {
 public:
  SdfReader(const PfxSceneLoadParam& param, PfxSceneBuild& build, PfxSceneError& error)
      : m_param(param), m_build(build), m_error(error) {}

  PfxInt32 read(const std::string& pathOrText, bool isText) {
    std::string paths;
    for (const std::string& p : m_param.modelPaths) paths += p + ":";
    for (const char* variable : {"GAZEBO_MODEL_PATH", "SDF_PATH"}) {
      if (const char* value = std::getenv(variable)) paths += std::string(value) + ":";
    }
    if (!isText) {
      const fs::path folder = fs::absolute(pathOrText).parent_path();
      paths += folder.string() + ":" + (folder / "models").string() + ":" +
               (folder.parent_path() / "models").string();
    }
    m_config.AddURIPath("model://", paths);
    // The loader reports sdformat's errors itself; sdformat would also print them.
    sdf::Console::Instance()->SetQuiet(true);
    sdf::Root root;
    const sdf::Errors errors =
        isText ? root.LoadSdfString(pathOrText, m_config) : root.Load(pathOrText, m_config);
    const sdf::Errors fatal = physicsErrors(errors);
    if (!fatal.empty()) {
      const sdf::Error& first = fatal.front();
      std::string text = first.LineNumber() ? std::to_string(*first.LineNumber()) + ": " : "";
      if (first.FilePath() && !isText && fs::path(*first.FilePath()) != fs::path(pathOrText)) {
        text += "in " + *first.FilePath() + ": ";
      }
      return pfxSceneFail(
          m_error, PFX_ERR_INVALID_VALUE,
          text + "sdformat: " + first.Message() +
              (fatal.size() > 1 ? " (and " + std::to_string(fatal.size() - 1) + " more errors)"
                                : ""));
    }
    PfxInt32 err = PFX_OK;
    if (root.WorldCount() == 1) {
      err = readWorld(*root.WorldByIndex(0));
    } else if (root.WorldCount() == 0 && root.Model()) {
      m_build.model.name = root.Model()->Name();
      err = readModel(*root.Model(), math::Pose3d::Zero, "");
    } else {
      return pfxSceneFail(m_error, PFX_ERR_INVALID_VALUE,
                          "sdf: the file holds " + std::to_string(root.WorldCount()) +
                              " worlds; pfx loads one world or one model");
    }
    if (err != PFX_OK) return err;
    listIgnored(root.Element());
    return PFX_OK;
  }

 private:
  PfxInt32 fail(const sdf::ElementPtr& element, const std::string& what, const std::string& reason,
                PfxInt32 code = PFX_ERR_INVALID_VALUE) {
    std::string line;
    if (element && element->LineNumber()) line = std::to_string(*element->LineNumber()) + ": ";
    return pfxSceneFail(m_error, code, line + what + ": " + reason);
  }

  // sdformat 12 refuses the older form of a visual's material, <script>Gazebo/Green</script>
  // (a name where it wants <uri> and <name> children), which Gazebo's own worlds use, and
  // then says the world failed to load although it built it whole. Colours are for
  // rendering: those errors become one warning each, and the world's summary error goes
  // with them; every other error stays.
  sdf::Errors physicsErrors(const sdf::Errors& errors) {
    static const std::string kScript = "A <script> element is missing a child";
    sdf::Errors fatal;
    std::map<std::string, int> rendering;
    for (const sdf::Error& error : errors) {
      if (error.Message().compare(0, kScript.size(), kScript) == 0) {
        ++rendering[error.Message()];
      } else {
        fatal.push_back(error);
      }
    }
    if (rendering.empty()) return fatal;
    sdf::Errors rest;
    for (const sdf::Error& error : fatal) {
      const std::string& message = error.Message();
      if (message != "Failed to load a world." && message != "Failed to load a model.") {
        rest.push_back(error);
      }
    }
    for (const auto& [message, count] : rendering) {
      m_build.model.warnings.push_back("sdformat (visual material, not read): " + message + " (" +
                                       std::to_string(count) + (count == 1 ? " time)" : " times)"));
    }
    return rest;
  }

  PfxInt32 readWorld(const sdf::World& world) {
    m_build.model.name = world.Name();
    PfxWorldParam& p = m_build.param;
    m_build.hasPhysics = true;
    p.gravity = toVector(world.Gravity());  // sdformat has refused one that is not finite
    if (const sdf::Physics* physics = world.PhysicsDefault()) {
      if (!(physics->MaxStepSize() > 0) || !std::isfinite(physics->MaxStepSize())) {
        return fail(physics->Element(), "physics " + inQuotes(physics->Name()),
                    "max_step_size must be positive and finite (got " +
                        numberText(physics->MaxStepSize()) + ")");
      }
      p.timeStep = static_cast<PfxFloat>(physics->MaxStepSize());
      // ODE's iterations where the file gives them: pfx's solver iterations play that part.
      const sdf::ElementPtr e = physics->Element();
      if (e && e->HasElement("ode") && e->GetElement("ode")->HasElement("solver")) {
        const sdf::ElementPtr solver = e->GetElement("ode")->GetElement("solver");
        if (solver->HasElement("iters") && solver->GetElement("iters")->GetExplicitlySetInFile()) {
          const int iters = solver->Get<int>("iters");
          if (iters < 1) {
            return fail(solver, "physics " + inQuotes(physics->Name()),
                        "ode solver iters must be at least 1");
          }
          p.iteration = static_cast<PfxUInt32>(iters);
        }
      }
    }
    for (uint64_t i = 0; i < world.ModelCount(); ++i) {
      const sdf::Model& model = *world.ModelByIndex(i);
      math::Pose3d pose;
      if (!model.SemanticPose().Resolve(pose).empty() || !finite(pose)) {
        return fail(model.Element(), "model " + inQuotes(model.Name()),
                    "its pose cannot be resolved or is not finite");
      }
      if (const PfxInt32 err = readModel(model, pose, ""); err != PFX_OK) return err;
    }
    return PFX_OK;
  }

  // A model (nested ones too) whose frame lies at `pose` in the world.
  PfxInt32 readModel(const sdf::Model& model, const math::Pose3d& pose, const std::string& scope,
                     bool parentStatic = false) {
    const std::string name = scope + model.Name();
    const bool isStatic = parentStatic || model.Static();
    for (uint64_t i = 0; i < model.LinkCount(); ++i) {
      if (const PfxInt32 err =
              readLink(*model.LinkByIndex(i), pose, name, isStatic, model.SelfCollide());
          err != PFX_OK) {
        return err;
      }
    }
    for (uint64_t i = 0; i < model.ModelCount(); ++i) {
      const sdf::Model& nested = *model.ModelByIndex(i);
      math::Pose3d inParent;
      if (!nested.SemanticPose().Resolve(inParent).empty() || !finite(inParent)) {
        return fail(nested.Element(), "model " + inQuotes(name + "::" + nested.Name()),
                    "its pose cannot be resolved or is not finite");
      }
      if (const PfxInt32 err = readModel(nested, pose * inParent, name + "::", isStatic);
          err != PFX_OK) {
        return err;
      }
    }
    for (uint64_t i = 0; i < model.JointCount(); ++i) {
      if (const PfxInt32 err = readJoint(*model.JointByIndex(i), pose, name); err != PFX_OK) {
        return err;
      }
    }
    excludeSelfCollision(name, model.SelfCollide());
    return PFX_OK;
  }

  // Gazebo collides two links of one model only when the model, or both links, ask for
  // self collision; pfx collides every pair that no joint holds, so the others are excluded.
  void excludeSelfCollision(const std::string& model, bool modelSelfCollide) {
    if (modelSelfCollide) return;
    std::vector<const LinkInfo*> links;
    for (const auto& [name, link] : m_links) {
      if (link.model == model) links.push_back(&link);
    }
    for (std::size_t a = 0; a < links.size(); ++a) {
      for (std::size_t b = a + 1; b < links.size(); ++b) {
        if (links[a]->selfCollide && links[b]->selfCollide) continue;
        m_build.noCollision.emplace_back(links[a]->body, links[b]->body);
      }
    }
  }

  PfxInt32 readLink(const sdf::Link& link, const math::Pose3d& modelPose, const std::string& model,
                    bool isStatic, bool modelSelfCollide) {
    const std::string name = model + "::" + link.Name();
    const std::string what = "link " + inQuotes(name);
    const sdf::ElementPtr element = link.Element();
    math::Pose3d inModel;
    if (!link.SemanticPose().Resolve(inModel).empty() || !finite(inModel)) {
      return fail(element, what, "its pose cannot be resolved or is not finite");
    }
    const math::Pose3d linkPose = modelPose * inModel;
    const bool kinematic =
        element && element->HasElement("kinematic") && element->Get<bool>("kinematic");
    const PfxMotionType motion = isStatic
                                     ? kPfxMotionTypeFixed
                                     : (kinematic ? kPfxMotionTypeKeyframe : kPfxMotionTypeActive);
    const bool moves = pfxMotionTypeIsDynamic(motion);
    if (element && element->HasElement("gravity") && !element->Get<bool>("gravity") && moves) {
      m_build.model.warnings.push_back(what +
                                       ": <gravity>false</gravity> not honoured (pfx applies the "
                                       "world's gravity to every body)");
    }

    // The body sits at the centre of mass, turned as the link.
    const math::Inertiald& inertial = link.Inertial();
    const math::Vector3d com = inertial.Pose().Pos();
    PfxSceneBuildBody body;
    body.state.reset();
    body.body.reset();
    body.state.setMotionType(motion);
    body.state.setPosition(toVector(linkPose.Pos() + linkPose.Rot().RotateVector(com)));
    body.state.setOrientation(quatFromSdf(linkPose.Rot()));
    if (moves) {
      const double mass = inertial.MassMatrix().Mass();
      const math::Matrix3d moi = inertial.Moi();
      PfxMatrix3 inertia;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) inertia(r, c) = static_cast<PfxFloat>(moi(r, c));
      }
      // sdformat has refused a mass or inertia that is not positive definite already.
      body.body.setMass(static_cast<PfxFloat>(mass));
      body.body.setInertia(inertia);
    }
    const math::Pose3d comFrame(com, math::Quaterniond::Identity);
    bool haveSurface = false;
    for (uint64_t i = 0; i < link.CollisionCount(); ++i) {
      const sdf::Collision& collision = *link.CollisionByIndex(i);
      math::Pose3d inLink;
      if (!collision.SemanticPose().Resolve(inLink).empty() || !finite(inLink)) {
        return fail(collision.Element(), "collision " + inQuotes(name + "::" + collision.Name()),
                    "its pose cannot be resolved or is not finite");
      }
      const PfxInt32 err =
          readCollision(collision, name, comFrame.Inverse() * inLink, moves, body, haveSurface);
      if (err != PFX_OK) return err;
    }
    if (body.shapes.empty()) pfxMakeScenePlaceholder(body);
    const bool selfCollide =
        element && element->HasElement("self_collide") && element->Get<bool>("self_collide");
    LinkInfo info;
    info.body = static_cast<PfxUInt32>(m_build.bodies.size());
    info.model = model;
    info.selfCollide = selfCollide || modelSelfCollide;
    m_links[name] = info;
    PfxSceneBody out;
    out.name = name;
    out.bodyId = info.body;
    out.frameInBody = pfxMakeTransform(PfxQuat::Identity(), -toVector(com));
    m_build.model.bodies.push_back(out);
    m_build.bodies.push_back(std::move(body));
    return PFX_OK;
  }

  // One collision: its shape at `inBody` (the collision's pose in the body frame), and the
  // body's friction, restitution and contact filters from its <surface>. pfx has one
  // material and one filter per body: the first collision that gives them sets them.
  PfxInt32 readCollision(const sdf::Collision& collision, const std::string& link,
                         const math::Pose3d& inBody, bool moves, PfxSceneBuildBody& body,
                         bool& haveSurface) {
    const std::string what = "collision " + inQuotes(link + "::" + collision.Name());
    const sdf::ElementPtr element = collision.Element();
    const sdf::Geometry* geometry = collision.Geom();
    PfxShape shape;
    // pfx's cylinders and capsules lie along X, SDF's along Z.
    const math::Quaterniond xToZ(0, -PFX_PI / 2, 0);
    math::Quaterniond turn = math::Quaterniond::Identity;
    math::Vector3d shift = math::Vector3d::Zero;
    switch (geometry->Type()) {
      case sdf::GeometryType::EMPTY:
        return PFX_OK;
      case sdf::GeometryType::BOX: {
        const math::Vector3d size = geometry->BoxShape()->Size();
        if (!finite(size) || !(size.Min() > 0)) {
          return fail(element, what, "box size must be positive and finite");
        }
        shape = pfxMakeShape(PfxBox(toVector(size) / 2));
        break;
      }
      case sdf::GeometryType::SPHERE: {
        const double r = geometry->SphereShape()->Radius();
        if (!(r > 0) || !std::isfinite(r)) {
          return fail(element, what, "sphere radius must be positive and finite");
        }
        shape = pfxMakeShape(PfxSphere(PfxFloat(r)));
        break;
      }
      case sdf::GeometryType::CYLINDER:
      case sdf::GeometryType::CAPSULE: {
        const bool cylinder = geometry->Type() == sdf::GeometryType::CYLINDER;
        const double r =
            cylinder ? geometry->CylinderShape()->Radius() : geometry->CapsuleShape()->Radius();
        const double l =
            cylinder ? geometry->CylinderShape()->Length() : geometry->CapsuleShape()->Length();
        if (!(r > 0) || !(l > 0) || !std::isfinite(r) || !std::isfinite(l)) {
          return fail(element, what, "radius and length must be positive and finite");
        }
        shape = cylinder ? pfxMakeShape(PfxCylinder(PfxFloat(l / 2), PfxFloat(r)))
                         : pfxMakeShape(PfxCapsule(PfxFloat(l / 2), PfxFloat(r)));
        turn = xToZ;
        break;
      }
      case sdf::GeometryType::PLANE: {
        // pfx has no plane: a box 1 m deep below it, as wide as the plane's <size>, whose
        // top face is the plane. Only a body that does not move may hold one.
        if (moves) return fail(element, what, "a plane can only belong to a static model");
        const sdf::Plane* plane = geometry->PlaneShape();
        const math::Vector3d normal = plane->Normal();
        const math::Vector2d size = plane->Size();
        if (!finite(normal) || normal.Length() < 1e-9 || !(size.X() > 0) || !(size.Y() > 0) ||
            !std::isfinite(size.X()) || !std::isfinite(size.Y())) {
          return fail(element, what, "plane normal and size must be finite, size positive");
        }
        shape = pfxMakeShape(
            PfxBox(PfxVector3(PfxFloat(size.X() / 2), PfxFloat(size.Y() / 2), PfxFloat(0.5))));
        turn.From2Axes(math::Vector3d::UnitZ, normal.Normalized());
        shift = normal.Normalized() * -0.5;
        break;
      }
      case sdf::GeometryType::MESH: {
        const sdf::Mesh* mesh = geometry->MeshShape();
        if (!finite(mesh->Scale()) || !(mesh->Scale().Min() > 0)) {
          return fail(element, what, "mesh scale must be positive and finite");
        }
        std::string path = sdf::findFile(mesh->Uri(), true, true, m_config);
        if (!path.empty() && !fs::path(path).is_absolute() && !mesh->FilePath().empty()) {
          path = (fs::path(mesh->FilePath()).parent_path() / path).string();
        }
        if (path.empty()) {
          return fail(element, what, "mesh " + inQuotes(mesh->Uri()) + " not found");
        }
        std::string reason;
        if (const PfxInt32 err = pfxMakeSceneMeshShape(path, toVector(mesh->Scale()), !moves,
                                                       m_build, shape, reason);
            err != PFX_OK) {
          return fail(element, what, "mesh " + inQuotes(mesh->Uri()) + ": " + reason, err);
        }
        break;
      }
      default:
        return fail(element, what,
                    "pfx has no shape for this geometry (it reads box, sphere, cylinder, "
                    "capsule, plane and mesh)");
    }
    const math::Pose3d placed = inBody * math::Pose3d(shift, turn);
    shape.setOffsetPosition(toVector(placed.Pos()));
    shape.setOffsetOrientation(quatFromSdf(placed.Rot()));
    body.shapes.push_back(shape);
    if (body.shapes.size() > PFX_MAX_SHAPES_PER_COLLIDABLE) {
      return fail(
          element, what,
          "the link has more than " + std::to_string(PFX_MAX_SHAPES_PER_COLLIDABLE) + " collisions",
          PFX_ERR_OUT_OF_RANGE);
    }
    return readSurface(element, what, body, haveSurface);
  }

  // <surface>: friction/ode/mu, bounce/restitution_coefficient, contact/collide_bitmask.
  PfxInt32 readSurface(const sdf::ElementPtr& collision, const std::string& what,
                       PfxSceneBuildBody& body, bool& haveSurface) {
    // SDF's defaults: mu 1, restitution 0, every bit of the mask.
    double mu = 1, restitution = 0;
    PfxUInt32 mask = 0xffff;
    bool explicitMask = false;
    if (collision && collision->HasElement("surface")) {
      const sdf::ElementPtr surface = collision->GetElement("surface");
      if (surface->HasElement("friction")) {
        const sdf::ElementPtr friction = surface->GetElement("friction");
        if (friction->HasElement("ode")) {
          const sdf::ElementPtr ode = friction->GetElement("ode");
          mu = ode->Get<double>("mu");
          const double mu2 = ode->Get<double>("mu2");
          if (ode->HasElement("mu2") && ode->GetElement("mu2")->GetExplicitlySetInFile() &&
              mu2 != mu) {
            m_build.model.warnings.push_back(what + ": friction is isotropic in pfx: mu " +
                                             numberText(mu) + " is used, mu2 " + numberText(mu2) +
                                             " is not");
          }
        }
      }
      if (surface->HasElement("bounce")) {
        restitution = surface->GetElement("bounce")->Get<double>("restitution_coefficient");
      }
      if (surface->HasElement("contact") &&
          surface->GetElement("contact")->HasElement("collide_bitmask")) {
        const sdf::ElementPtr bits = surface->GetElement("contact")->GetElement("collide_bitmask");
        explicitMask = bits->GetExplicitlySetInFile();
        mask = bits->Get<unsigned int>();
      }
    }
    // sdformat has refused a negative mu and a restitution outside [0, 1]. ODE reads a mu
    // above its own infinity as infinite friction; pfx needs a finite value.
    mu = std::min(mu, 1e6);
    if (!haveSurface) {
      haveSurface = true;
      body.body.setFriction(static_cast<PfxFloat>(mu));
      body.body.setRestitution(static_cast<PfxFloat>(restitution));
      if (explicitMask) {
        // Gazebo lets two collisions meet when their masks share a bit: pfx's filters do
        // that with self = target = mask.
        body.state.setContactFilterSelf(mask);
        body.state.setContactFilterTarget(mask);
      }
    } else if (body.body.getFriction() != PfxFloat(mu) ||
               body.body.getRestitution() != PfxFloat(restitution)) {
      m_build.model.warnings.push_back(what +
                                       ": pfx has one friction and restitution per body; the "
                                       "link's first collision's are used");
    }
    return PFX_OK;
  }

  // The world body that SDF joints name as "world": fixed, without geometry, made once.
  PfxUInt32 worldBody() {
    if (m_worldBody == kPfxSceneNone) {
      PfxSceneBuildBody body;
      body.state.reset();
      body.body.reset();
      body.state.setMotionType(kPfxMotionTypeFixed);
      pfxMakeScenePlaceholder(body);
      m_worldBody = static_cast<PfxUInt32>(m_build.bodies.size());
      m_build.bodies.push_back(body);
      PfxSceneBody out;
      out.name = "world";
      out.bodyId = m_worldBody;
      m_build.model.bodies.push_back(out);
    }
    return m_worldBody;
  }

  // The body of a link a joint names, scoped in `model`; null when there is none.
  const LinkInfo* findLink(const std::string& name, const std::string& model) {
    auto it = m_links.find(model + "::" + name);
    if (it == m_links.end()) it = m_links.find(name);
    return it == m_links.end() ? nullptr : &it->second;
  }

  // What a joint axis moves when it alone moves: the child's inertia about the axis (or
  // its mass along it) in series with the parent's when the parent moves too.
  double movedInertia(PfxUInt32 a, PfxUInt32 b, bool rotation, const PfxVector3& axis,
                      const PfxVector3& anchor) const {
    double inverse = 0;
    for (const PfxUInt32 id : {a, b}) {
      const PfxSceneBuildBody& body = m_build.bodies[id];
      if (!pfxMotionTypeIsDynamic(body.state.getMotionType())) continue;
      double moved = body.body.getMass();
      if (rotation) {
        const PfxMatrix3 r = body.state.getOrientation().toRotationMatrix();
        const PfxVector3 arm = (body.state.getPosition() - anchor).cross(axis);
        moved = axis.dot(pfxRotateInertia(r, body.body.getInertia()) * axis) +
                body.body.getMass() * arm.squaredNorm();
      }
      if (moved > 0) inverse += 1 / moved;
    }
    return inverse > 0 ? 1 / inverse : 0;
  }

  // Limits of axis `c` from the SDF limits: none when both are SDF's "no limit"; rotations
  // beyond +-pi are cut to +-pi (the hinge's angle wraps there) with a warning.
  void setLimits(PfxJointConstraint& c, double lower, double upper, bool rotation,
                 const std::string& what) {
    if (lower <= -kNoLimit && upper >= kNoLimit) {
      c.m_lock = kPfxJointLockFree;
      return;
    }
    if (rotation && (lower < -PFX_PI || upper > PFX_PI)) {
      m_build.model.warnings.push_back(what + ": limits [" + numberText(lower) + ", " +
                                       numberText(upper) +
                                       "] cut to [-pi, pi], where the joint's angle wraps");
      lower = std::max(lower, double(-PFX_PI));
      upper = std::min(upper, double(PFX_PI));
    }
    c.m_lock = kPfxJointLockLimit;
    c.m_movableLowerLimit = static_cast<PfxFloat>(lower);
    c.m_movableUpperLimit = static_cast<PfxFloat>(upper);
  }

  PfxInt32 readAxis(const sdf::JointAxis& axis, const std::string& what, PfxJointConstraint& c,
                    bool rotation, PfxUInt32 a, PfxUInt32 b, const PfxVector3& worldAxis,
                    const PfxVector3& anchor) {
    const double lower = axis.Lower(), upper = axis.Upper();
    if (std::isnan(lower) || std::isnan(upper) || !(lower <= upper)) {
      return fail(axis.Element(), what,
                  "limits must be numbers with lower <= upper (got [" + numberText(lower) + ", " +
                      numberText(upper) + "])");
    }
    if (!(axis.Damping() >= 0) || !(axis.Friction() >= 0) || !std::isfinite(axis.Damping()) ||
        !std::isfinite(axis.Friction())) {
      return fail(axis.Element(), what, "dynamics damping and friction must be finite and >= 0");
    }
    setLimits(c, lower, upper, rotation, what);
    const double subStep = m_build.param.timeStep / m_build.param.subStep;
    c.m_damping = pfxSceneDampingFraction(axis.Damping(),
                                          movedInertia(a, b, rotation, worldAxis, anchor), subStep);
    c.m_friction = static_cast<PfxFloat>(axis.Friction());
    return PFX_OK;
  }

  // The joint axis `index` in the world, unit length.
  PfxInt32 worldAxis(const sdf::Joint& joint, unsigned index, const math::Pose3d& modelPose,
                     const std::string& what, PfxVector3& out) {
    const sdf::JointAxis* axis = joint.Axis(index);
    math::Vector3d xyz;
    if (!axis || !axis->ResolveXyz(xyz, "__model__").empty() || !finite(xyz) ||
        xyz.Length() < 1e-9) {
      return fail(joint.Element(), what,
                  std::string(index == 0 ? "axis" : "axis2") +
                      " is missing, cannot be resolved, or has no direction");
    }
    out = toVector(modelPose.Rot().RotateVector(xyz.Normalized()));
    return PFX_OK;
  }

  PfxInt32 readJoint(const sdf::Joint& joint, const math::Pose3d& modelPose,
                     const std::string& scope) {
    const std::string name = scope + "::" + joint.Name();
    const std::string what = "joint " + inQuotes(name);
    const sdf::ElementPtr element = joint.Element();
    std::string parentName, childName;
    if (!joint.ResolveParentLink(parentName).empty() ||
        !joint.ResolveChildLink(childName).empty()) {
      parentName = joint.ParentLinkName();
      childName = joint.ChildLinkName();
    }
    const bool parentIsWorld = parentName == "world";
    const LinkInfo* parent = parentIsWorld ? nullptr : findLink(parentName, scope);
    const LinkInfo* child = findLink(childName, scope);
    if ((!parentIsWorld && !parent) || !child) {
      return fail(element, what,
                  "names a link that is not in the model (parent " + inQuotes(parentName) +
                      ", child " + inQuotes(childName) + ")");
    }
    const PfxUInt32 childBody = child->body;
    const PfxUInt32 parentBody = parentIsWorld ? worldBody() : parent->body;
    if (parentBody == childBody) return fail(element, what, "parent and child are the same link");
    math::Pose3d inModel;
    if (!joint.SemanticPose().Resolve(inModel, "__model__").empty() || !finite(inModel)) {
      return fail(element, what, "its pose cannot be resolved or is not finite");
    }
    const math::Pose3d jointPose = modelPose * inModel;
    const PfxVector3 anchor = toVector(jointPose.Pos());
    PfxSceneJoint out;
    out.name = name;
    out.parent = parentIsWorld ? "world" : scope + "::" + parentName;
    out.child = scope + "::" + childName;
    PfxJoint built;
    PfxVector3 axis1 = PfxVector3::UnitX(), axis2 = PfxVector3::UnitY();
    PfxJointType type = kPfxJointFixed;
    bool screw = false;
    switch (joint.Type()) {
      case sdf::JointType::REVOLUTE:
      case sdf::JointType::CONTINUOUS:
        type = kPfxJointHinge;
        out.type = joint.Type() == sdf::JointType::REVOLUTE ? "revolute" : "continuous";
        out.axes[0] = kPfxJointAxisTwist;
        break;
      case sdf::JointType::PRISMATIC:
        type = kPfxJointSlider;
        out.type = "prismatic";
        out.axes[0] = kPfxJointAxisX;
        break;
      case sdf::JointType::SCREW:
        type = kPfxJointHinge;
        screw = true;
        out.type = "screw";
        out.axes[0] = kPfxJointAxisTwist;
        out.axes[1] = kPfxJointAxisX;
        break;
      case sdf::JointType::BALL:
        type = kPfxJointBall;
        out.type = "ball";
        break;
      case sdf::JointType::FIXED:
        type = kPfxJointFixed;
        out.type = "fixed";
        break;
      case sdf::JointType::UNIVERSAL:
      case sdf::JointType::REVOLUTE2:
        type = kPfxJointUniversal;
        out.type = joint.Type() == sdf::JointType::UNIVERSAL ? "universal" : "revolute2";
        out.axes[0] = kPfxJointAxisSwing1;
        out.axes[1] = kPfxJointAxisSwing2;
        break;
      default:
        return fail(element, what,
                    "pfx cannot honour this joint type (it reads revolute, continuous, "
                    "prismatic, screw, ball, fixed, universal and revolute2; a gearbox needs a "
                    "reference body pfx joints do not have)");
    }
    PfxMatrix3 frame = PfxMatrix3::Identity();
    if (type == kPfxJointHinge || type == kPfxJointSlider) {
      if (worldAxis(joint, 0, modelPose, what, axis1) != PFX_OK) return m_error.code;
      frame = pfxSceneFrame(axis1, PfxVector3::UnitZ());
    } else if (type == kPfxJointUniversal) {
      // Two rotations: the first about axis (fixed in the parent), the second about axis2
      // (carried by the child): Euler angles about the frame's Y, then the turned Z, with
      // the twist about X = Y x Z locked.
      if (worldAxis(joint, 0, modelPose, what, axis1) != PFX_OK ||
          worldAxis(joint, 1, modelPose, what, axis2) != PFX_OK) {
        return m_error.code;
      }
      if (std::abs(axis1.dot(axis2)) > PfxFloat(1e-3)) {
        return fail(element, what,
                    "pfx holds the two axes of a universal or revolute2 joint only when they "
                    "are perpendicular");
      }
      frame.col(1) = axis1;
      frame.col(2) = axis2;
      frame.col(0) = axis1.cross(axis2);
    } else {
      frame = quatFromSdf(jointPose.Rot()).toRotationMatrix();
    }
    if (pfxInitSceneJoint(type, m_build, parentBody, childBody, anchor, frame, built) != PFX_OK) {
      return fail(element, what, "the joint cannot be set up between these links");
    }
    if (type == kPfxJointHinge || type == kPfxJointSlider) {
      const PfxUInt32 axis = type == kPfxJointHinge ? kPfxJointAxisTwist : kPfxJointAxisX;
      if (readAxis(*joint.Axis(0), what, built.m_constraints[axis], type == kPfxJointHinge,
                   parentBody, childBody, axis1, anchor) != PFX_OK) {
        return m_error.code;
      }
      if (joint.Type() == sdf::JointType::CONTINUOUS) {
        built.m_constraints[axis].m_lock = kPfxJointLockFree;
      }
    } else if (type == kPfxJointUniversal) {
      built.m_rotation = kPfxJointRotationEulerYZX;
      if (readAxis(*joint.Axis(0), what, built.m_constraints[kPfxJointAxisSwing1], true, parentBody,
                   childBody, axis1, anchor) != PFX_OK ||
          readAxis(*joint.Axis(1), what, built.m_constraints[kPfxJointAxisSwing2], true, parentBody,
                   childBody, axis2, anchor) != PFX_OK) {
        return m_error.code;
      }
    }
    if (screw && makeScrew(joint, what, built) != PFX_OK) return m_error.code;
    if (pfxCheckJoint(built) != PFX_OK) {
      return fail(element, what, "the joint's values are not valid together (pfxCheckJoint)");
    }
    out.jointId = static_cast<PfxUInt32>(m_build.joints.size());
    m_build.joints.push_back(built);
    m_build.model.joints.push_back(out);
    if (screw) {
      PfxJointCoupling coupling;
      coupling.reset();
      coupling.m_leaderJointId = out.jointId;
      coupling.m_followerJointId = out.jointId;
      coupling.m_leaderAxis = kPfxJointAxisTwist;
      coupling.m_followerAxis = kPfxJointAxisX;
      coupling.m_multiplier = static_cast<PfxFloat>(-1 / joint.ThreadPitch());
      PfxSceneCoupling c;
      c.name = name;
      c.couplingId = static_cast<PfxUInt32>(m_build.couplings.size());
      m_build.couplings.push_back(coupling);
      m_build.model.couplings.push_back(c);
    }
    return PFX_OK;
  }

  // A screw: the hinge's rotation free and its translation along the axis free too, the
  // translation coupled to the rotation. SDF's thread_pitch is Gazebo's (ODE's) reading,
  // radians per metre with the sign of a left-hand thread: the slide is -angle /
  // thread_pitch (SDF 1.10 writes the same as screw_thread_pitch = -2 pi / thread_pitch).
  PfxInt32 makeScrew(const sdf::Joint& joint, const std::string& what, PfxJoint& built) {
    const double pitch = joint.ThreadPitch();
    if (!std::isfinite(pitch) || pitch == 0) {
      return fail(joint.Element(), what, "a screw needs a finite, non-zero thread_pitch");
    }
    built.m_type = kPfxJointCustom;
    built.m_constraints[kPfxJointAxisX].m_lock = kPfxJointLockFree;
    return PFX_OK;
  }

  // One warning per element path that the file sets and pfx does not read, with how often
  // it appears; below an ignored element nothing more is listed.
  void listIgnored(const sdf::ElementPtr& root) {
    std::map<std::string, int> counts;
    std::vector<std::string> order;
    const auto note = [&](const std::string& key) {
      if (counts[key]++ == 0) order.push_back(key);
    };
    std::vector<sdf::ElementPtr> stack;
    for (sdf::ElementPtr e = root->GetFirstElement(); e; e = e->GetNextElement())
      stack.push_back(e);
    while (!stack.empty()) {
      const sdf::ElementPtr e = stack.back();
      stack.pop_back();
      const std::string path = elementPath(e);
      if (!e->GetExplicitlySetInFile()) continue;
      if (!kHonoured.count(path)) {
        note(path);
        continue;
      }
      for (const sdf::ParamPtr& attribute : e->GetAttributes()) {
        if (attribute->GetSet() && !kHonouredAttributes.count(attribute->GetKey())) {
          note(path + "@" + attribute->GetKey());
        }
      }
      for (sdf::ElementPtr c = e->GetFirstElement(); c; c = c->GetNextElement()) {
        stack.push_back(c);
      }
    }
    for (const std::string& key : order) {
      m_build.model.warnings.push_back("ignored <" + key + "> (" + std::to_string(counts[key]) +
                                       (counts[key] == 1 ? " time)" : " times)"));
    }
  }

  const PfxSceneLoadParam& m_param;
  PfxSceneBuild& m_build;
  PfxSceneError& m_error;
  sdf::ParserConfig m_config;  // model:// folders, for <include>s and mesh URIs
  std::map<std::string, LinkInfo> m_links;
  PfxUInt32 m_worldBody = kPfxSceneNone;
};

}  // namespace

PfxInt32 pfxReadSdf(const std::string& pathOrText, bool isText, const PfxSceneLoadParam& param,
                    PfxSceneBuild& build, PfxSceneError& error) {
  return SdfReader(param, build, error).read(pathOrText, isText);
}

}  // namespace pfx
