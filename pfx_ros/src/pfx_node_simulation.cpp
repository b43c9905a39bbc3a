#include "pfx_ros/pfx_node_simulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx/low_level/pfx_error_detail.h"

namespace pfx {

// A model added by addModel: the loaded robot and its links' names as the node gives them.
struct PfxNodeAddedModel {
  PfxUrdfModel urdf;
  std::vector<std::string> linkNames;  // "<prefix>/<link>", in urdf.links' order
};

struct PfxNodeSimulation::Scene {
  // Declared before the world: the world's shapes point into the models' and the map's
  // meshes, so the world goes first when a scene is destroyed.
  PfxUrdfModel model;
  std::vector<std::unique_ptr<PfxNodeAddedModel>> addedModels;  // slot - 1; null: removed
  PfxSceneModel worldFile;
  std::unique_ptr<PfxOctomap> octomap;
  PfxSerializedMeshes savedMeshes;  // the meshes of a saved world loaded into `world`
  std::unique_ptr<PfxWorld> world;
  // After the world, so that it goes first: its controller holds the world.
  std::unique_ptr<PfxNodeAgentSet> agents;
  std::vector<std::string> bodyNames;
  std::unordered_map<std::string, PfxUInt32> bodyByName;
  // Cables and cloths: their particle groups in the order of the config's lists, and the
  // name of each group by id.
  std::vector<PfxUInt32> cableGroups;
  std::vector<PfxUInt32> clothGroups;
  std::vector<std::string> groupNames;
  std::vector<std::string> warnings;
};

namespace {

const char* const kGroundName = "ground";
const char* const kOctomapName = "octomap";
// A contact point this close (m) touches, whatever impulse the last sub-step gave it: a body
// at rest on several points spreads its weight over them differently from one sub-step to
// the next, and a sleeping body keeps the spread of the sub-step it fell asleep in.
const PfxFloat kTouchingDistance = PfxFloat(1e-3);
// An agent may start this deep (m) in a body: one standing on the ground touches it, and
// a foot given to the centimetre may sink a little.
const PfxFloat kAgentStartOverlap = PfxFloat(0.01);
// An added model's root may start this far (m) from the origin: beyond the world's bounds
// (1000 m each way) a body is stopped for good.
const PfxFloat kMaxModelDistance = PfxFloat(1000);
// How far from 1 the length of an added model's orientation quaternion may be.
const PfxFloat kUnitQuaternionTolerance = PfxFloat(1e-3);

// Letters, digits and _, a letter first: a ROS name without namespaces, so that it can name
// a topic, a frame and a body.
bool isPlainName(const std::string& name) {
  bool valid = !name.empty() && std::isalpha(static_cast<unsigned char>(name[0])) != 0;
  for (const char c : name) {
    valid = valid && (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_');
  }
  return valid;
}

std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Several links share a body when fixed joints lumped them; the body is named after the
// one whose parent lies on another body (or that has no parent).
void nameRobotBodies(const PfxUrdfModel& model, const std::vector<std::string>& linkNames,
                     std::vector<std::string>& bodyNames) {
  if (bodyNames.size() < model.firstBodyId + model.numBodies) {
    bodyNames.resize(model.firstBodyId + model.numBodies);
  }
  std::unordered_map<std::string, PfxUInt32> bodyOfLink;
  for (const PfxUrdfLink& link : model.links) bodyOfLink[link.name] = link.bodyId;
  std::unordered_map<std::string, std::string> parentOf;
  for (const PfxUrdfJoint& joint : model.joints) parentOf[joint.childLink] = joint.parentLink;
  for (std::size_t i = 0; i < model.links.size(); ++i) {
    const PfxUrdfLink& link = model.links[i];
    const auto parent = parentOf.find(link.name);
    const bool parentOnSameBody = parent != parentOf.end() &&
                                  bodyOfLink.count(parent->second) != 0 &&
                                  bodyOfLink[parent->second] == link.bodyId;
    if (!parentOnSameBody && bodyNames[link.bodyId].empty()) bodyNames[link.bodyId] = linkNames[i];
  }
}

// Calls query(buffer, room, found) on a buffer grown until every contact fits, and returns
// how many there are; a node's cables and cloths make few, so it rarely grows.
template <typename Contact, typename Query>
PfxUInt32 queryAllContacts(std::vector<Contact>& buffer, Query query) {
  for (std::size_t room = 256;; room *= 2) {
    buffer.resize(room);
    PfxQueryContactsResult found;
    query(buffer.data(), PfxUInt32(room), found);
    if (!found.truncated) return found.numContacts;
  }
}

}  // namespace

PfxNodeSimulation::PfxNodeSimulation() = default;
PfxNodeSimulation::~PfxNodeSimulation() = default;

PfxInt32 PfxNodeSimulation::buildScene(const PfxNodeSimulationConfig& config,
                                       std::unique_ptr<Scene>& scene, std::string* message) const {
  auto built = std::make_unique<Scene>();
  built->world = std::make_unique<PfxWorld>();
  PfxWorld& world = *built->world;

  PfxWorldParam param;
  param.gravity = config.gravity;
  param.timeStep = config.timeStep;
  param.subStep = config.subSteps;
  param.iteration = config.iterations;
  param.numThreads = config.threads;
  // Robots have few bodies: the two extra passes cost little, and the diagnostics report
  // the energy and momentum each step changed, and where the step's time goes.
  param.measureConservation = true;
  param.measureStages = true;
  if (const PfxInt32 err = world.initialize(param); err != PFX_OK) {
    if (message) {
      *message = std::string("world parameters rejected (dt, substeps, iterations): ") +
                 pfxErrorString(err);
    }
    return err;
  }

  if (config.groundPlane) {
    if (!(config.groundSize > 0) || !pfxIsFinite(config.groundSize)) {
      if (message) *message = "ground_size must be a positive number of metres";
      return PFX_ERR_INVALID_VALUE;
    }
    // A thick box rather than a thin plate, so that nothing fast tunnels through it; its
    // top face is z = 0 exactly.
    const PfxFloat halfThickness = PfxFloat(0.5);
    PfxBodyInit ground;
    ground.mass = 0;
    ground.position = PfxVector3(0, 0, -halfThickness);
    const PfxFloat half = config.groundSize / 2;
    if (const PfxInt32 err =
            pfxAddBody(world, pfxMakeShape(PfxBox(half, half, halfThickness)), ground);
        err != PFX_OK) {
      if (message) *message = std::string("ground plane: ") + pfxErrorString(err);
      return err;
    }
  }

  if (!config.octomapFile.empty()) {
    built->octomap = std::make_unique<PfxOctomap>();
    std::string why;
    if (const PfxInt32 err = pfxLoadOctomapFile(world, config.octomapFile, PfxOctomapLoadParam(),
                                                *built->octomap, &why);
        err != PFX_OK) {
      if (message) *message = why;
      return err;
    }
  }

  if (!config.worldFile.empty()) {
    PfxSceneLoadParam sceneParam;
    sceneParam.applyPhysics = false;
    std::string why;
    if (const PfxInt32 err =
            pfxLoadSceneFile(world, config.worldFile, sceneParam, built->worldFile, &why);
        err != PFX_OK) {
      if (message) *message = why;
      return err;
    }
    const PfxWorldParam& asked = built->worldFile.worldParam;
    if (asked.timeStep != param.timeStep || asked.subStep != param.subStep ||
        asked.iteration != param.iteration || asked.gravity != param.gravity) {
      built->warnings.push_back(config.worldFile +
                                ": the node runs with its own ~dt, ~substeps, ~iterations and " +
                                "gravity, not the file's");
    }
    built->warnings.insert(built->warnings.end(), built->worldFile.warnings.begin(),
                           built->worldFile.warnings.end());
  }

  // A deleted robot is not built again: its model stays empty.
  if (!config.robotRemoved) {
    PfxUrdfLoadParam urdfParam;
    urdfParam.rootPosition = PfxVector3(0, 0, config.initialHeight);
    urdfParam.fixedBase = config.fixedBase;
    urdfParam.placeAboveGround = config.placeAboveGround;
    urdfParam.disableSelfCollision = !config.selfCollision;
    urdfParam.allowMissingMeshes = config.allowMissingMeshes;
    std::string why;
    if (const PfxInt32 err = pfxLoadUrdfString(
            world, config.urdfXml, config.urdfPath.empty() ? "." : folderOf(config.urdfPath),
            urdfParam, built->model, &why);
        err != PFX_OK) {
      if (message) *message = why;
      return err;
    }
  }

  built->warnings.insert(built->warnings.end(), built->model.warnings.begin(),
                         built->model.warnings.end());
  built->bodyNames.assign(world.getNumRigidBodies(), std::string());
  if (config.groundPlane) built->bodyNames[0] = kGroundName;
  if (built->octomap) built->bodyNames[built->octomap->bodyId] = kOctomapName;
  for (const PfxSceneBody& body : built->worldFile.bodies) {
    built->bodyNames[body.bodyId] = body.name;
  }
  const std::vector<std::string> linkNames = robotLinkNames(built->model);
  nameRobotBodies(built->model, linkNames, built->bodyNames);
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    if (built->bodyNames[id].empty()) built->bodyNames[id] = "body_" + std::to_string(id);
    built->bodyByName.emplace(built->bodyNames[id], id);
  }
  for (const PfxUrdfLink& link : built->model.links) {
    built->bodyByName.emplace(link.name, link.bodyId);
  }
  built->addedModels.resize(config.models.size());
  for (std::size_t i = 0; i < config.models.size(); ++i) {
    if (!config.models[i]) continue;
    if (const PfxInt32 err = buildModel(*built, *config.models[i], PfxUInt32(i + 1), message);
        err != PFX_OK) {
      return err;
    }
  }
  built->agents = std::make_unique<PfxNodeAgentSet>(world, config.agents);
  for (const PfxNodeCableSpec& cable : config.cables) {
    if (const PfxInt32 err = buildCable(*built, cable, message); err != PFX_OK) return err;
  }
  for (const PfxNodeClothSpec& cloth : config.cloths) {
    if (const PfxInt32 err = buildCloth(*built, cloth, message); err != PFX_OK) return err;
  }
  scene = std::move(built);
  return PFX_OK;
}

std::string PfxNodeSimulation::checkGroupName(const Scene& scene, const std::string& name) const {
  if (!isPlainName(name)) return "name: '" + name + "' is not letters, digits and _ starting with a letter";
  // Rays and contacts name what they meet: a name must say which.
  if (scene.bodyByName.count(name) != 0 || name == kPfxNodeWorldLink ||
      std::find(scene.groupNames.begin(), scene.groupNames.end(), name) !=
          scene.groupNames.end()) {
    return "name: '" + name + "' names a link, body, agent, cable or cloth already";
  }
  return "";
}

bool PfxNodeSimulation::findAnchor(const Scene& scene, const std::string& link,
                                   const PfxVector3& point, PfxNodeAnchorBody& body,
                                   PfxVector3& world) const {
  const PfxWorld& w = *scene.world;
  if (link == kPfxNodeWorldLink) {
    body = PfxNodeAnchorBody();
    world = point;
    return true;
  }
  PfxTransform3 linkPose;
  // A removed robot's links are no longer among the scene's names.
  if (const PfxInt32 index = pfxFindUrdfLink(scene.model, link);
      index >= 0 && scene.bodyByName.count(link) != 0) {
    const PfxUrdfLink& urdfLink = scene.model.links[index];
    body.bodyId = urdfLink.bodyId;
    linkPose = pfxGetUrdfLinkPose(w, urdfLink);
  } else if (const auto named = scene.bodyByName.find(link); named != scene.bodyByName.end()) {
    body.bodyId = named->second;
    linkPose = w.getRigidState(named->second).getTransform();
  } else {
    return false;
  }
  body.pose = w.getRigidState(body.bodyId).getTransform();
  world = linkPose * point;
  return true;
}

PfxInt32 PfxNodeSimulation::addGroup(Scene& scene, const PfxParticleGroupBuilder& group,
                                     const std::string& name, std::vector<PfxUInt32>& ids,
                                     std::string* message) {
  PfxUInt32 id = 0;
  if (const PfxInt32 err = scene.world->addParticleGroup(group.desc(), &id); err != PFX_OK) {
    if (message) *message = std::string("the world refused it: ") + pfxGetLastErrorDetail();
    return err;
  }
  ids.push_back(id);
  if (scene.groupNames.size() <= id) scene.groupNames.resize(id + 1);
  scene.groupNames[id] = name;
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::buildCable(Scene& scene, const PfxNodeCableSpec& spec,
                                       std::string* message) const {
  PfxNodeAnchorBody startBody, endBody;
  PfxVector3 start, end = PfxVector3::Zero();
  if (!findAnchor(scene, spec.startLink, spec.startPoint, startBody, start)) {
    if (message) *message = "start_link: no link or body named '" + spec.startLink + "'";
    return PFX_ERR_INVALID_VALUE;
  }
  const bool freeEnd = spec.endLink.empty();
  if (!freeEnd && !findAnchor(scene, spec.endLink, spec.endPoint, endBody, end)) {
    if (message) *message = "end_link: no link or body named '" + spec.endLink + "'";
    return PFX_ERR_INVALID_VALUE;
  }
  PfxParticleGroupBuilder group;
  if (const PfxInt32 err = pfxBuildNodeCable(spec, start, startBody, end,
                                             freeEnd ? nullptr : &endBody, group, message);
      err != PFX_OK) {
    return err;
  }
  if (const PfxInt32 err = pfxSettleNodeCable(scene.world->getParam().gravity, group);
      err != PFX_OK) {
    if (message) *message = std::string("it did not settle: ") + pfxErrorString(err);
    return err;
  }
  return addGroup(scene, group, spec.name, scene.cableGroups, message);
}

PfxInt32 PfxNodeSimulation::buildCloth(Scene& scene, const PfxNodeClothSpec& spec,
                                       std::string* message) const {
  PfxNodeAnchorBody pinBody;
  PfxVector3 unused;
  if (!findAnchor(scene, spec.pinLink, PfxVector3::Zero(), pinBody, unused)) {
    if (message) *message = "pin_link: no link or body named '" + spec.pinLink + "'";
    return PFX_ERR_INVALID_VALUE;
  }
  PfxParticleGroupBuilder group;
  pfxBuildNodeCloth(spec, pinBody, group);
  return addGroup(scene, group, spec.name, scene.clothGroups, message);
}

PfxInt32 PfxNodeSimulation::refuse(const std::string& why, std::string* message) {
  if (message) *message = why;
  return PFX_ERR_INVALID_VALUE;
}

PfxInt32 PfxNodeSimulation::addCable(const PfxNodeCableSpec& spec, std::string* message) {
  std::string why = checkGroupName(*m_scene, spec.name);
  if (why.empty()) why = pfxCheckCableSpec(spec);
  if (!why.empty()) return refuse(why, message);
  if (const PfxInt32 err = buildCable(*m_scene, spec, message); err != PFX_OK) return err;
  m_config.cables.push_back(spec);
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::addCloth(const PfxNodeClothSpec& spec, std::string* message) {
  std::string why = checkGroupName(*m_scene, spec.name);
  if (why.empty()) why = pfxCheckClothSpec(spec);
  if (!why.empty()) return refuse(why, message);
  if (const PfxInt32 err = buildCloth(*m_scene, spec, message); err != PFX_OK) return err;
  m_config.cloths.push_back(spec);
  return PFX_OK;
}

const PfxParticleGroup& PfxNodeSimulation::getCableGroup(PfxUInt32 i) const {
  return *m_scene->world->getParticleGroup(m_scene->cableGroups[i]);
}

const PfxParticleGroup& PfxNodeSimulation::getClothGroup(PfxUInt32 i) const {
  return *m_scene->world->getParticleGroup(m_scene->clothGroups[i]);
}

const std::string& PfxNodeSimulation::getParticleGroupName(PfxUInt32 groupId) const {
  return m_scene->groupNames[groupId];
}

PfxInt64 PfxNodeSimulation::findParticleGroup(const std::string& name) const {
  const auto& names = m_scene->groupNames;
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<PfxInt64>(it - names.begin());
}

PfxInt32 PfxNodeSimulation::load(const PfxNodeSimulationConfig& config, std::string* message) {
  std::unique_ptr<Scene> scene;
  if (const PfxInt32 err = buildScene(config, scene, message); err != PFX_OK) return err;
  m_config = config;
  m_scene = std::move(scene);
  m_wrenches.clear();
  m_startTime = 0;
  m_stepCount = 0;
  ++m_generation;
  return PFX_OK;
}

void PfxNodeSimulation::nameAgentBody(Scene& scene, const std::string& name, PfxUInt32 bodyId) {
  if (scene.bodyNames.size() <= bodyId) scene.bodyNames.resize(bodyId + 1);
  scene.bodyNames[bodyId] = name;
  scene.bodyByName[name] = bodyId;
}

PfxInt32 PfxNodeSimulation::reset(std::string* message) {
  std::unique_ptr<Scene> scene;
  if (const PfxInt32 err = buildScene(m_config, scene, message); err != PFX_OK) return err;
  const PfxNodeAgentSet& agents = *m_scene->agents;
  for (PfxUInt32 i = 0; i < agents.getNumAgents(); ++i) {
    const PfxNodeAgentSpec& spec = agents.getAgentSpec(i);
    std::string why;
    if (const PfxInt32 err = scene->agents->add(spec, &why); err != PFX_OK) {
      if (message) *message = "agent '" + spec.name + "': " + why;
      return err;
    }
    nameAgentBody(*scene, spec.name, scene->agents->getAgentBody(i));
  }
  // The rebuilt world continues the clock rather than the node keeping an offset to it:
  // the world's time is what a save writes and a load resumes from, so a world saved after
  // a reset holds the node's time, and no reader of a file needs to know about resets.
  if (const PfxInt32 err = scene->world->setSimulatedTime(getTime()); err != PFX_OK) {
    if (message) *message = std::string("the clock cannot go on: ") + pfxErrorString(err);
    return err;
  }
  m_scene = std::move(scene);
  m_wrenches.clear();
  ++m_generation;
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::step() {
  PfxWorld& world = *m_scene->world;
  for (Wrench& wrench : m_wrenches) {
    const PfxUrdfLink& link = getModel(wrench.link.model).links[wrench.link.index];
    const PfxVector3 arm = getLinkPose(wrench.link.index, wrench.link.model).translation() -
                           world.getRigidState(link.bodyId).getPosition();
    world.applyForce(link.bodyId, wrench.force, wrench.torque + arm.cross(wrench.force));
    wrench.remainingSteps -= 1;
  }
  if (const PfxInt32 err = m_scene->agents->update(getTime(), m_config.timeStep); err != PFX_OK) {
    return err;
  }
  const PfxInt32 err = world.step();
  ++m_stepCount;
  std::size_t kept = 0;
  for (const Wrench& wrench : m_wrenches) {
    if (wrench.remainingSteps > 0) m_wrenches[kept++] = wrench;
  }
  m_wrenches.resize(kept);
  return err;
}

PfxInt32 PfxNodeSimulation::setPhysics(PfxFloat timeStep, PfxUInt32 subSteps,
                                       PfxUInt32 iterations, const PfxVector3& gravity,
                                       std::string* message) {
  PfxWorld& world = *m_scene->world;
  if (const PfxInt32 err = world.setStepParam(timeStep, subSteps, iterations, gravity);
      err != PFX_OK) {
    if (message) {
      *message = std::string("the world refused dt, substeps, iterations or gravity: ") +
                 pfxErrorString(err);
    }
    return err;
  }
  // getTime() counts steps of one length: the clock so far becomes the new start.
  m_startTime = getTime();
  m_stepCount = 0;
  const double stepRatio = double(m_config.timeStep) / double(timeStep);
  for (Wrench& wrench : m_wrenches) {
    wrench.remainingSteps = std::max(1.0, std::ceil(wrench.remainingSteps * stepRatio - 1e-6));
  }
  // A body asleep would otherwise float in a gravity that changed under it.
  if (gravity != m_config.gravity) {
    for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
      world.setRigidState(id, world.getRigidState(id));
    }
  }
  m_config.timeStep = timeStep;
  m_config.subSteps = subSteps;
  m_config.iterations = iterations;
  m_config.gravity = gravity;
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::saveWorld(const std::string& path, std::string* message) const {
  std::string why;
  const PfxInt32 err = pfxSaveWorld(*m_scene->world, path.c_str(), &why);
  if (err != PFX_OK && message) *message = path + ": " + why;
  return err;
}

namespace {

// Empty when `saved` holds the bodies, shapes and joints that `built` holds, under the same
// ids, else the first difference. The bodies after those were agents' when it was saved.
std::string compareWorlds(const PfxWorld& built, const PfxWorld& saved) {
  if (saved.getNumRigidBodies() < built.getNumRigidBodies()) {
    return "it holds " + std::to_string(saved.getNumRigidBodies()) + " bodies, the robot and " +
           "scene " + std::to_string(built.getNumRigidBodies());
  }
  if (saved.getNumJoints() != built.getNumJoints()) {
    return "it holds " + std::to_string(saved.getNumJoints()) + " joints, the robot " +
           std::to_string(built.getNumJoints());
  }
  for (PfxUInt32 id = 0; id < built.getNumRigidBodies(); ++id) {
    const PfxCollidable& a = built.getCollidable(id);
    const PfxCollidable& b = saved.getCollidable(id);
    // Masses match to rounding: a world saved in double precision reads rounded once.
    const PfxFloat massA = built.getRigidBody(id).getMass();
    const PfxFloat massB = saved.getRigidBody(id).getMass();
    bool same = a.getNumShapes() == b.getNumShapes() &&
                std::abs(massA - massB) <= PfxFloat(1e-5) * std::max(massA, massB);
    for (PfxUInt32 s = 0; same && s < a.getNumShapes(); ++s) {
      same = a.getShape(s).getType() == b.getShape(s).getType();
    }
    if (!same) return "its body " + std::to_string(id) + " differs from the robot's or scene's";
  }
  for (PfxUInt32 id = 0; id < built.getNumJoints(); ++id) {
    const PfxJoint& a = built.getJoint(id);
    const PfxJoint& b = saved.getJoint(id);
    if (a.m_rigidBodyIdA != b.m_rigidBodyIdA || a.m_rigidBodyIdB != b.m_rigidBodyIdB ||
        a.m_type != b.m_type) {
      return "its joint " + std::to_string(id) + " differs from the robot's";
    }
  }
  return "";
}

}  // namespace

PfxInt32 PfxNodeSimulation::loadWorld(const std::string& path, std::string* message) {
  // The robot and scene are built afresh for their names, meshes and map, and checked
  // against the saved world, which then takes the built world's place.
  if (m_scene->agents->getNumAgents() > 0) {
    if (message) {
      *message = std::to_string(m_scene->agents->getNumAgents()) +
                 " agents live, and a world file does not say who drives their bodies: "
                 "delete the agents first";
    }
    return PFX_ERR_INVALID_VALUE;
  }
  if (m_config.robotRemoved) {
    return refuse("the robot of robot_description was deleted, and a world file is checked "
                  "against it: restart the node to load one",
                  message);
  }
  const auto live = std::count_if(m_config.models.begin(), m_config.models.end(),
                                  [](const auto& model) { return model.has_value(); });
  if (live > 0) {
    if (message) {
      *message = std::to_string(live) +
                 " added models live, and a world file does not say which robots its bodies "
                 "are: delete the models first";
    }
    return PFX_ERR_INVALID_VALUE;
  }
  std::unique_ptr<Scene> scene;
  if (const PfxInt32 err = buildScene(m_config, scene, message); err != PFX_OK) return err;
  auto saved = std::make_unique<PfxWorld>();
  std::string why;
  PfxLoadWorldOptions options;
  options.keepSavedNumThreads = false;
  options.numThreads = m_config.threads;
  if (const PfxInt32 err =
          pfxLoadWorld(*saved, path.c_str(), scene->savedMeshes, &why, options);
      err != PFX_OK) {
    if (message) *message = path + ": " + why;
    return err;
  }
  if (const std::string difference = compareWorlds(*scene->world, *saved); !difference.empty()) {
    if (message) *message = path + " was not saved from this robot and scene: " + difference;
    return PFX_ERR_INVALID_VALUE;
  }
  for (PfxUInt32 id = scene->world->getNumRigidBodies(); id < saved->getNumRigidBodies(); ++id) {
    if (saved->hasRigidBody(id)) saved->removeRigidBody(id);  // a saved agent's capsule
  }
  scene->agents.reset();  // it holds the built world
  scene->world = std::move(saved);
  scene->agents = std::make_unique<PfxNodeAgentSet>(*scene->world, m_config.agents);
  const PfxWorldParam& param = scene->world->getParam();
  m_config.timeStep = param.timeStep;
  m_config.subSteps = param.subStep;
  m_config.iterations = param.iteration;
  m_config.gravity = param.gravity;
  m_startTime = scene->world->getSimulatedTime();
  m_stepCount = 0;
  m_scene = std::move(scene);
  m_wrenches.clear();
  ++m_generation;
  return PFX_OK;
}

const std::string& PfxNodeSimulation::getShapeName(PfxUInt32 bodyId, PfxUInt32 shapeIndex) const {
  // A removed robot's body ids may have gone to bodies added since.
  if (const PfxInt32 link = pfxFindUrdfShapeLink(m_scene->model, bodyId, shapeIndex);
      link >= 0 && hasModel(0)) {
    return m_scene->model.links[link].name;
  }
  for (const auto& added : m_scene->addedModels) {
    if (!added) continue;
    if (const PfxInt32 link = pfxFindUrdfShapeLink(added->urdf, bodyId, shapeIndex); link >= 0) {
      return added->linkNames[link];
    }
  }
  return getBodyName(bodyId);
}

const PfxWorld& PfxNodeSimulation::getWorld() const { return *m_scene->world; }

const std::vector<std::string>& PfxNodeSimulation::getWarnings() const { return m_scene->warnings; }

const PfxUrdfModel& PfxNodeSimulation::getModel(PfxUInt32 model) const {
  return model == 0 ? m_scene->model : m_scene->addedModels[model - 1]->urdf;
}

bool PfxNodeSimulation::hasModel(PfxUInt32 slot) const {
  if (slot == 0) return !m_config.robotRemoved;
  return (slot <= m_config.models.size() && m_config.models[slot - 1].has_value());
}

const std::string& PfxNodeSimulation::getModelName(PfxUInt32 slot) const {
  return slot == 0 ? m_scene->model.name : m_config.models[slot - 1]->name;
}

PfxInt64 PfxNodeSimulation::findModel(const std::string& name) const {
  for (PfxUInt32 slot = 0; slot < getNumModelSlots(); ++slot) {
    if (hasModel(slot) && getModelName(slot) == name) return slot;
  }
  return -1;
}

const std::string& PfxNodeSimulation::getLinkName(PfxUInt32 linkIndex, PfxUInt32 model) const {
  return model == 0 ? m_scene->model.links[linkIndex].name
                    : m_scene->addedModels[model - 1]->linkNames[linkIndex];
}

PfxInt32 PfxNodeSimulation::buildModel(Scene& scene, const PfxNodeModelSpec& spec,
                                       PfxUInt32 slot, std::string* message) {
  PfxWorld& world = *scene.world;
  auto added = std::make_unique<PfxNodeAddedModel>();
  PfxUrdfLoadParam param;
  param.rootPosition = spec.position;
  param.rootOrientation = spec.orientation.normalized();
  param.fixedBase = spec.fixedBase;
  param.allowMissingMeshes = spec.allowMissingMeshes;
  const std::string basePath = spec.urdfPath.empty() ? "." : folderOf(spec.urdfPath);
  if (const PfxInt32 err =
          pfxLoadUrdfString(world, spec.urdfXml, basePath, param, added->urdf, message);
      err != PFX_OK) {
    return err;
  }
  PfxUrdfModel& urdf = added->urdf;
  for (const PfxUrdfLink& link : urdf.links) {
    added->linkNames.push_back(spec.framePrefix + "/" + link.name);
    const std::string& name = added->linkNames.back();
    if (scene.bodyByName.count(name) != 0 || name == kPfxNodeWorldLink ||
        std::find(scene.groupNames.begin(), scene.groupNames.end(), name) !=
            scene.groupNames.end()) {
      world.truncate(urdf.firstBodyId, urdf.firstJointId, urdf.firstCouplingId);
      if (message) {
        *message = "its link frame '" + name +
                   "' names a link, body, agent, cable or cloth already: give another tf_prefix";
      }
      return PFX_ERR_INVALID_VALUE;
    }
  }
  nameRobotBodies(urdf, added->linkNames, scene.bodyNames);
  for (std::size_t i = 0; i < urdf.links.size(); ++i) {
    scene.bodyByName.emplace(added->linkNames[i], urdf.links[i].bodyId);
  }
  scene.warnings.insert(scene.warnings.end(), urdf.warnings.begin(), urdf.warnings.end());
  if (scene.addedModels.size() < slot) scene.addedModels.resize(slot);
  scene.addedModels[slot - 1] = std::move(added);
  return PFX_OK;
}

std::string PfxNodeSimulation::checkModelSpec(const PfxNodeModelSpec& spec) const {
  if (!isPlainName(spec.name)) {
    return "name: '" + spec.name + "' is not letters, digits and _ starting with a letter";
  }
  if (findModel(spec.name) >= 0) {
    return "name: a model named '" + spec.name + "' is in the world already";
  }
  bool prefixValid = !spec.framePrefix.empty();
  for (std::size_t start = 0; prefixValid && start <= spec.framePrefix.size();) {
    const std::size_t slash = std::min(spec.framePrefix.find('/', start), spec.framePrefix.size());
    prefixValid = isPlainName(spec.framePrefix.substr(start, slash - start));
    start = slash + 1;
  }
  if (!prefixValid) {
    return "tf_prefix: '" + spec.framePrefix +
           "' is not names of letters, digits and _ (a letter first) joined by /";
  }
  if (!pfxIsFinite(spec.position) || spec.position.cwiseAbs().maxCoeff() > kMaxModelDistance) {
    return "pose: the position must be finite and within 1000 m of the origin";
  }
  const PfxFloat norm = spec.orientation.coeffs().norm();
  if (!pfxIsFinite(spec.orientation) ||
      !(std::abs(norm - 1) <= kUnitQuaternionTolerance)) {
    return "pose: the orientation is not a unit quaternion (its length is " +
           std::to_string(norm) + ")";
  }
  return "";
}

PfxInt32 PfxNodeSimulation::addModel(const PfxNodeModelSpec& spec, PfxUInt32* slot,
                                     std::string* message) {
  if (const std::string why = checkModelSpec(spec); !why.empty()) return refuse(why, message);
  const PfxUInt32 newSlot = getNumModelSlots();
  if (const PfxInt32 err = buildModel(*m_scene, spec, newSlot, message); err != PFX_OK) {
    return err;
  }
  m_config.models.push_back(spec);
  ++m_modelChanges;
  if (slot) *slot = newSlot;
  return PFX_OK;
}

std::vector<std::string> PfxNodeSimulation::robotLinkNames(const PfxUrdfModel& robot) {
  std::vector<std::string> names;
  for (const PfxUrdfLink& link : robot.links) names.push_back(link.name);
  return names;
}

void PfxNodeSimulation::removeModelBodies(Scene& scene, const PfxUrdfModel& urdf,
                                          const std::vector<std::string>& linkNames) {
  PfxWorld& world = *scene.world;
  const bool addedLast = urdf.firstBodyId + urdf.numBodies == world.getNumRigidBodies() &&
                         urdf.firstJointId + urdf.numJoints == world.getNumJoints() &&
                         urdf.firstCouplingId + urdf.numCouplings == world.getNumJointCouplings();
  if (addedLast) {
    // Nothing came after it: its slots go too, as if it had never been added.
    world.truncate(urdf.firstBodyId, urdf.firstJointId, urdf.firstCouplingId);
    scene.bodyNames.resize(std::min<std::size_t>(scene.bodyNames.size(), urdf.firstBodyId));
  } else {
    for (PfxUInt32 id = urdf.firstBodyId; id < urdf.firstBodyId + urdf.numBodies; ++id) {
      if (world.hasRigidBody(id)) world.removeRigidBody(id);
    }
  }
  for (const std::string& name : linkNames) scene.bodyByName.erase(name);
}

PfxInt32 PfxNodeSimulation::removeModel(PfxUInt32 slot, std::string* message) {
  if (!hasModel(slot)) return refuse("no model in slot " + std::to_string(slot), message);
  if (slot == 0) {
    // Its bodies would leave the particles tied to nothing.
    const std::vector<std::string> links = robotLinkNames(m_scene->model);
    auto holds = [&](const std::string& link) {
      return std::find(links.begin(), links.end(), link) != links.end();
    };
    for (const PfxNodeCableSpec& cable : m_config.cables) {
      if (holds(cable.startLink) || holds(cable.endLink)) {
        return refuse("cable '" + cable.name + "' holds on to it", message);
      }
    }
    for (const PfxNodeClothSpec& cloth : m_config.cloths) {
      if (holds(cloth.pinLink)) return refuse("cloth '" + cloth.name + "' holds on to it", message);
    }
    removeModelBodies(*m_scene, m_scene->model, links);
    m_config.robotRemoved = true;
  } else {
    std::unique_ptr<PfxNodeAddedModel>& added = m_scene->addedModels[slot - 1];
    removeModelBodies(*m_scene, added->urdf, added->linkNames);
    // The world's shapes pointed into the model's meshes; its bodies are gone now.
    added.reset();
    m_config.models[slot - 1].reset();
  }
  m_wrenches.erase(std::remove_if(m_wrenches.begin(), m_wrenches.end(),
                                  [slot](const Wrench& w) { return w.link.model == slot; }),
                   m_wrenches.end());
  ++m_modelChanges;
  return PFX_OK;
}

const std::string& PfxNodeSimulation::getBodyName(PfxUInt32 bodyId) const {
  return m_scene->bodyNames[bodyId];
}

PfxInt32 PfxNodeSimulation::findLink(const std::string& name, PfxUInt32 model) const {
  return pfxFindUrdfLink(getModel(model), name);
}

PfxInt32 PfxNodeSimulation::findJoint(const std::string& name, PfxUInt32 model) const {
  return pfxFindUrdfJoint(getModel(model), name);
}

std::string PfxNodeSimulation::findQualifiedPart(const std::string& name, bool isLink,
                                                 PfxNodeModelPart& part) const {
  const std::string kind = isLink ? "link" : "joint";
  if (name.empty()) return "no " + kind + " named";
  std::string modelAsked;
  for (const std::string separator : {"::", "/"}) {
    const std::size_t at = name.find(separator);
    if (at == std::string::npos) continue;
    if (modelAsked.empty()) modelAsked = name.substr(0, at);
    const PfxInt64 slot = findModel(name.substr(0, at));
    if (slot < 0) continue;
    const std::string partName = name.substr(at + separator.size());
    const PfxInt32 index =
        isLink ? findLink(partName, PfxUInt32(slot)) : findJoint(partName, PfxUInt32(slot));
    if (index < 0) {
      return "unknown " + kind + " '" + name + "': model '" + getModelName(PfxUInt32(slot)) +
             "' has no " + kind + " '" + partName + "'";
    }
    part = {PfxUInt32(slot), PfxUInt32(index)};
    return "";
  }
  if (modelAsked.empty()) return "unknown " + kind + " '" + name + "'";
  return "unknown " + kind + " '" + name + "': " +
         (isLink ? "no link has that frame, and " : "") + "no model is named '" + modelAsked +
         "'";
}

std::string PfxNodeSimulation::findModelLink(const std::string& name,
                                             PfxNodeModelPart& link) const {
  for (PfxUInt32 slot = 0; slot < getNumModelSlots(); ++slot) {
    if (!hasModel(slot)) continue;
    for (std::size_t i = 0; i < getModel(slot).links.size(); ++i) {
      if (getLinkName(PfxUInt32(i), slot) == name) {
        link = {slot, PfxUInt32(i)};
        return "";
      }
    }
  }
  return findQualifiedPart(name, true, link);
}

std::string PfxNodeSimulation::findModelJoint(const std::string& name,
                                              PfxNodeModelPart& joint) const {
  if (hasModel(0)) {
    if (const PfxInt32 index = findJoint(name, 0); index >= 0) {
      joint = {0, PfxUInt32(index)};
      return "";
    }
  }
  return findQualifiedPart(name, false, joint);
}

PfxInt64 PfxNodeSimulation::findBody(const std::string& name) const {
  const auto it = m_scene->bodyByName.find(name);
  return it == m_scene->bodyByName.end() ? -1 : static_cast<PfxInt64>(it->second);
}

PfxTransform3 PfxNodeSimulation::getLinkPose(PfxUInt32 linkIndex, PfxUInt32 model) const {
  return pfxGetUrdfLinkPose(*m_scene->world, getModel(model).links[linkIndex]);
}

PfxInt32 PfxNodeSimulation::addAgent(const PfxNodeAgentSpec& spec, std::string* message) {
  PfxNodeAgentSet& agents = *m_scene->agents;
  if (m_scene->bodyByName.count(spec.name) != 0 && agents.find(spec.name) < 0) {
    if (message) *message = "'" + spec.name + "' names a body of the robot or scene already";
    return PFX_ERR_INVALID_VALUE;
  }
  if (findParticleGroup(spec.name) >= 0) {
    if (message) *message = "'" + spec.name + "' names a cable or cloth already";
    return PFX_ERR_INVALID_VALUE;
  }
  if (const std::string why = agents.check(spec); !why.empty()) {
    if (message) *message = why;
    return PFX_ERR_INVALID_VALUE;
  }
  PfxInt64 body = -1;
  PfxFloat depth = 0;
  if (const PfxInt32 err = agents.findOverlap(spec, kAgentStartOverlap, body, depth);
      err != PFX_OK) {
    if (message)
      *message = std::string("cannot look for room at its start: ") + pfxErrorString(err);
    return err;
  }
  if (body >= 0) {
    if (message) {
      *message = "at its start it would be " + std::to_string(int(std::lround(depth * 1000))) +
                 " mm deep inside '" + getBodyName(PfxUInt32(body)) + "'";
    }
    return PFX_ERR_INVALID_VALUE;
  }
  if (const PfxInt32 err = agents.add(spec, message); err != PFX_OK) return err;
  nameAgentBody(*m_scene, spec.name, agents.getAgentBody(agents.getNumAgents() - 1));
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::removeAgent(const std::string& name, std::string* message) {
  if (const PfxInt32 err = m_scene->agents->remove(name); err != PFX_OK) {
    if (message) {
      *message = err == PFX_ERR_OUT_OF_RANGE ? "no agent named '" + name + "'"
                                             : std::string(pfxErrorString(err));
    }
    return err;
  }
  m_scene->bodyByName.erase(name);
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::commandAgent(const std::string& name, PfxFloat vx, PfxFloat vy,
                                         PfxFloat turnRate) {
  return m_scene->agents->command(name, vx, vy, turnRate, getTime());
}

const PfxNodeAgentSet& PfxNodeSimulation::getAgents() const { return *m_scene->agents; }

PfxInt32 PfxNodeSimulation::castRay(const PfxRayInput& ray, PfxRayOutput& hit) {
  return m_scene->world->castRay(ray, hit);
}

PfxInt32 PfxNodeSimulation::castRays(const PfxRayInput* rays, PfxRayOutput* hits,
                                     PfxUInt32 numRays) {
  return m_scene->world->castRays(rays, hits, numRays);
}

void PfxNodeSimulation::getContacts(std::vector<PfxNodeContact>& contacts) const {
  contacts.clear();
  const PfxWorld& world = *m_scene->world;
  for (PfxUInt32 p = 0; p < world.getNumContactPairs(); ++p) {
    const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(p));
    if (manifold.getNumContacts() == 0) continue;
    const PfxUInt32 idA = manifold.getRigidBodyIdA();
    const PfxUInt32 idB = manifold.getRigidBodyIdB();
    const PfxTransform3 transformA = world.getRigidState(idA).getTransform();
    const PfxTransform3 transformB = world.getRigidState(idB).getTransform();
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      const PfxContactPoint& point = manifold.getContactPoint(i);
      const PfxFloat impulse = point.m_constraintRow[0].m_accumImpulse;
      if (point.m_distance > kTouchingDistance && impulse <= 0) continue;
      PfxNodeContact contact;
      contact.bodyA = idA;
      contact.bodyB = idB;
      contact.shapeA = point.m_shapeIdA;
      contact.shapeB = point.m_shapeIdB;
      contact.position = (transformA * point.m_localPointA + transformB * point.m_localPointB) / 2;
      contact.normal = point.getNormal();
      contact.depth = -point.m_distance;
      contact.impulse = impulse;
      contacts.push_back(contact);
    }
  }
  const PfxUInt32 numBodyContacts =
      queryAllContacts(m_particleContacts, [&](auto* out, PfxUInt32 room, auto& found) {
        world.getParticleBodyContacts(out, room, found);
      });
  for (PfxUInt32 i = 0; i < numBodyContacts; ++i) {
    const PfxParticleBodyContact& c = m_particleContacts[i];
    if (c.m_depth < -kTouchingDistance && c.m_impulse <= 0) continue;
    PfxNodeContact contact;
    contact.bodyA = c.m_rigidBodyId;
    contact.shapeA = c.m_shapeId;
    contact.particleGroupB = c.m_particleGroupId;
    contact.position = c.m_point;
    contact.normal = c.m_normal;
    contact.depth = c.m_depth;
    contact.impulse = c.m_impulse;
    contacts.push_back(contact);
  }
  const PfxUInt32 numGroupContacts =
      queryAllContacts(m_particleGroupContacts, [&](auto* out, PfxUInt32 room, auto& found) {
        world.getParticleGroupContacts(out, room, found);
      });
  for (PfxUInt32 i = 0; i < numGroupContacts; ++i) {
    const PfxParticleGroupContact& c = m_particleGroupContacts[i];
    if (c.m_depth < -kTouchingDistance && c.m_impulse <= 0) continue;
    PfxNodeContact contact;
    contact.particleGroupA = c.m_particleGroupIdA;
    contact.particleGroupB = c.m_particleGroupIdB;
    contact.position = c.m_point;
    // From A to B, as between bodies; the core's points from B's particle to A's.
    contact.normal = -c.m_normal;
    contact.depth = c.m_depth;
    contact.impulse = c.m_impulse;
    contacts.push_back(contact);
  }
}

const std::string& PfxNodeSimulation::getContactNameA(const PfxNodeContact& contact) const {
  return contact.particleGroupA != PFX_RAY_NO_OBJECT ? getParticleGroupName(contact.particleGroupA)
                                                     : getShapeName(contact.bodyA, contact.shapeA);
}

const std::string& PfxNodeSimulation::getContactNameB(const PfxNodeContact& contact) const {
  return contact.particleGroupB != PFX_RAY_NO_OBJECT ? getParticleGroupName(contact.particleGroupB)
                                                     : getShapeName(contact.bodyB, contact.shapeB);
}

PfxInt32 PfxNodeSimulation::applyLinkWrench(const PfxNodeModelPart& link, const PfxVector3& force,
                                            const PfxVector3& torque, double duration) {
  if (!hasModel(link.model) || link.index >= getModel(link.model).links.size()) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  if (!pfxIsFinite(force) || !pfxIsFinite(torque) || !std::isfinite(duration) || duration < 0) {
    return PFX_ERR_INVALID_VALUE;
  }
  // Steps whose start lies within the duration; a tolerance keeps 0.1 s at dt 0.004 from
  // rounding to 26 steps.
  const double steps = std::ceil(duration / m_config.timeStep - 1e-6);
  m_wrenches.push_back({link, force, torque, std::max(1.0, steps)});
  return PFX_OK;
}

PfxInt32 PfxNodeSimulation::setLinkState(const PfxNodeModelPart& part, const PfxTransform3& pose,
                                         const PfxVector3& linearVelocity,
                                         const PfxVector3& angularVelocity) {
  if (!hasModel(part.model) || part.index >= getModel(part.model).links.size()) {
    return PFX_ERR_OUT_OF_RANGE;
  }
  const PfxUrdfLink& link = getModel(part.model).links[part.index];
  const PfxTransform3 bodyPose = pose * link.linkInBody.inverse();
  PfxRigidState state = m_scene->world->getRigidState(link.bodyId);
  state.setPosition(bodyPose.translation());
  state.setOrientation(PfxQuat(bodyPose.linear()).normalized());
  // The link's origin and the body's centre of mass move alike only without rotation.
  state.setLinearVelocity(linearVelocity +
                          angularVelocity.cross(bodyPose.translation() - pose.translation()));
  state.setAngularVelocity(angularVelocity);
  state.wakeup();
  return m_scene->world->setRigidState(link.bodyId, state);
}

PfxInt32 PfxNodeSimulation::setJointCommands(const std::vector<PfxUInt32>& jointIndices,
                                             PfxJointDrive drive,
                                             const std::vector<PfxFloat>& targets,
                                             const std::vector<PfxFloat>& maxForces,
                                             PfxUInt32 modelSlot) {
  if (targets.size() != jointIndices.size() || maxForces.size() != jointIndices.size()) {
    return PFX_ERR_INVALID_VALUE;
  }
  PfxWorld& world = *m_scene->world;
  const PfxUrdfModel& model = getModel(modelSlot);
  for (const PfxUInt32 index : jointIndices) {
    if (index >= model.joints.size()) return PFX_ERR_OUT_OF_RANGE;
  }
  std::vector<PfxJoint> before;
  for (const PfxUInt32 index : jointIndices) {
    const PfxUInt32 jointId = model.joints[index].jointId;
    if (jointId == kPfxUrdfNoJoint) return PFX_ERR_INVALID_VALUE;
    before.push_back(world.getJoint(jointId));
  }
  for (std::size_t i = 0; i < jointIndices.size(); ++i) {
    const PfxInt32 err =
        pfxSetUrdfJointCommand(world, model, jointIndices[i], drive, targets[i], maxForces[i]);
    if (err != PFX_OK) {
      for (std::size_t j = i; j-- > 0;) {
        world.setJoint(model.joints[jointIndices[j]].jointId, before[j]);
      }
      return err;
    }
  }
  return PFX_OK;
}

}  // namespace pfx
