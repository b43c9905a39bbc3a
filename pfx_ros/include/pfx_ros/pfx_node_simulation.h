// The world behind pfx_node: the robot of robot_description, a ground and an optional
// OctoMap in one PfxWorld stepped at a fixed dt, and what the node's services ask of it
// (rays, contacts, wrenches held for a duration, body states, motor commands, reset). No
// ROS types here: this is plain use of pfx's API, and the services only translate.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_world.h"
#include "pfx/loaders/pfx_octomap_loader.h"
#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx/loaders/pfx_urdf_loader.h"
#include "pfx_ros/pfx_node_agent_set.h"
#include "pfx_ros/pfx_node_cables.h"

namespace pfx {

// A robot added while the node runs (README, "Models"), beside the robot of
// robot_description, into the same world.
struct PfxNodeModelSpec {
  std::string name;  // letters, digits and _, a letter first; link_states' "<name>::<link>"
  std::string urdfXml;
  std::string urdfPath;  // the file the text came from, for relative mesh paths; may be empty
  // Its links' TF frames, and their names in rays and contacts: "<framePrefix>/<link>".
  std::string framePrefix;
  PfxVector3 position = PfxVector3::Zero();  // of its root link, in the world
  PfxQuat orientation = PfxQuat::Identity();
  bool fixedBase = false;
  bool allowMissingMeshes = false;
};

struct PfxNodeSimulationConfig {
  std::string urdfXml;
  // The file the URDF text came from: relative mesh paths resolve against its folder.
  // Empty: against the working directory.
  std::string urdfPath;
  std::string octomapFile;  // empty: no map
  // A scene file (pfx scene XML or an SDFormat world) loaded with the robot, before it;
  // empty: none. The node's time step, sub-steps and iterations stay; the file's physics
  // are reported in a warning where they differ.
  std::string worldFile;
  bool groundPlane = true;   // a fixed box whose top face is the plane z = 0
  PfxFloat groundSize = 20;  // edge of the square ground (m)
  PfxFloat timeStep = PfxFloat(0.004);
  PfxUInt32 subSteps = 1;
  PfxUInt32 iterations = 10;
  // Threads the world steps on (0: every core the process may use); the states are the same
  // bits whatever the count.
  PfxUInt32 threads = 1;
  PfxVector3 gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  bool fixedBase = false;
  PfxFloat initialHeight = 0;  // z of the root link's frame at the start (m)
  // Instead of initialHeight: the lowest point of the robot's collision shapes starts
  // 5 cm above z = 0 (PfxUrdfLoadParam::placeAboveGround).
  bool placeAboveGround = false;
  // false: no two links of the robot collide (by default only links joined by a joint or
  // overlapping at the start do not).
  bool selfCollision = true;
  // A collision mesh whose file is missing is left out (with a warning) instead of failing
  // the load.
  bool allowMissingMeshes = false;
  PfxNodeAgentSetParam agents;
  // Accepted by addCable and addCloth, and built again with the world by reset().
  std::vector<PfxNodeCableSpec> cables;
  std::vector<PfxNodeClothSpec> cloths;
  // The robot of urdfXml (model slot 0) was removed by removeModel: reset() leaves it out.
  bool robotRemoved = false;
  // Models added by addModel, slot 1 on (slot 0 is the robot of urdfXml); a removed one
  // leaves its slot empty, so that the others keep their slots. Built again by reset().
  std::vector<std::optional<PfxNodeModelSpec>> models;
};

// A link or joint of one of the world's robots: its model slot and its index into that
// model's links or joints.
struct PfxNodeModelPart {
  PfxUInt32 model = 0;
  PfxUInt32 index = 0;
};

// One point where two bodies touch (or pushed on each other during the last step), or a
// body (A) and a particle of a cable or cloth (B: particleGroup names it, bodyB is unused).
struct PfxNodeContact {
  PfxUInt32 bodyA = 0;
  PfxUInt32 bodyB = 0;
  // A side that is a cable or cloth (a particle group's id) rather than its body.
  PfxUInt32 particleGroupA = PFX_RAY_NO_OBJECT;
  PfxUInt32 particleGroupB = PFX_RAY_NO_OBJECT;
  PfxUInt32 shapeA = 0;  // which shape of each body's compound (getShapeName)
  PfxUInt32 shapeB = 0;
  PfxVector3 position = PfxVector3::Zero();  // midway between the two surfaces
  PfxVector3 normal = PfxVector3::Zero();    // from A to B
  PfxFloat depth = 0;                        // overlap, > 0 when interpenetrating
  PfxFloat impulse = 0;                      // normal impulse of the last sub-step (N s)
};

class PfxNodeSimulation {
 public:
  PfxNodeSimulation();
  ~PfxNodeSimulation();

  // Builds the world. On error returns the code, writes why into *message and keeps the
  // world it had.
  PfxInt32 load(const PfxNodeSimulationConfig& config, std::string* message);
  // Builds the world again as load() built it: every body and joint back at its start and
  // motor commands and pending wrenches dropped; the agents of the moment stand at their
  // starts again (without the overlap check of addAgent), and bodies of removed agents are
  // gone. Simulated time keeps running, the world's clock with the node's, so that time
  // stamps never go back and a world saved after a reset holds the time since load().
  PfxInt32 reset(std::string* message);
  // One step of the time step; the wrenches that are due act during it.
  PfxInt32 step();
  // A new time step, sub-steps, iterations and gravity from the next step on, kept by
  // reset(). Bodies, joints, contacts and the clock stay; a wrench still acting keeps its
  // duration in seconds; a new gravity wakes every body. On error *message says why and
  // nothing changes.
  PfxInt32 setPhysics(PfxFloat timeStep, PfxUInt32 subSteps, PfxUInt32 iterations,
                      const PfxVector3& gravity, std::string* message);

  // Writes the whole world to `path` (pfxSaveWorld: bodies, joints, motor commands,
  // contacts with their impulses, sleep and the simulated time), so that loadWorld can
  // resume it exactly. Wrenches still to act are not saved. Agents are the node's, not the
  // file's: their capsules are saved as the bodies they are, but not their names, headings,
  // commands or waypoints.
  PfxInt32 saveWorld(const std::string& path, std::string* message) const;
  // Replaces the world with one that saveWorld wrote for the same robot and scene (the
  // same bodies with the same shapes, the same joints), which then continues exactly where
  // it was saved: its clock, time step, sub-steps and iterations included. Pending
  // wrenches are dropped. On error the world, the clock and the settings stay as they
  // were, and *message says why (a file that does not read, or one saved from another
  // robot or scene).
  // Refused while agents or added models live (delete them first): the file cannot say
  // who drives the agents' bodies nor which robot a body belongs to. The saved agents' capsules are removed from the loaded world, which keeps the
  // robot's and scene's bodies under their ids.
  PfxInt32 loadWorld(const std::string& path, std::string* message);

  double getTime() const {
    return m_startTime + static_cast<double>(m_stepCount) * m_config.timeStep;
  }
  double getTimeStep() const { return m_config.timeStep; }
  PfxUInt32 getSubSteps() const { return m_config.subSteps; }
  PfxUInt32 getIterations() const { return m_config.iterations; }
  const PfxVector3& getGravity() const { return m_config.gravity; }
  // Counts load(), reset() and loadWorld() calls: whoever draws the static bodies draws them again.
  PfxUInt32 getGeneration() const { return m_generation; }
  const PfxWorld& getWorld() const;
  // The robot in model slot `model`: 0 the robot of robot_description, from 1 on the models
  // addModel added (hasModel says whether the slot still holds one).
  const PfxUrdfModel& getModel(PfxUInt32 model = 0) const;
  // Warnings of the robot's and the scene file's loads.
  const std::vector<std::string>& getWarnings() const;
  // The link a body carries (the one nearest the URDF root when fixed joints lumped
  // several into it), "ground", "octomap", or the scene file's name for its body.
  const std::string& getBodyName(PfxUInt32 bodyId) const;
  // The link whose <collision> element became shape `shapeIndex` of the body (a contact
  // point's or a ray hit's shape), so that a body lumping a massless helper with the link
  // that carries the geometry is named after the latter; getBodyName for the ground, the
  // OctoMap and a body's placeholder shape.
  const std::string& getShapeName(PfxUInt32 bodyId, PfxUInt32 shapeIndex) const;
  // Index into getModel(model).links or .joints by the URDF's name, or -1.
  PfxInt32 findLink(const std::string& name, PfxUInt32 model = 0) const;
  PfxInt32 findJoint(const std::string& name, PfxUInt32 model = 0) const;
  // A link of any model by the name a service is given, tried in this order, the first
  // match winning (README, "Models"): its TF frame (a link of the robot of
  // robot_description by its URDF name, an added model's as "<tf_prefix>/<link>"; frames
  // are unique in the world), then "<model>::<link>" (Gazebo's and ~link_states' form),
  // then "<model>/<link>". Empty, or why the name names no link: no model so named, or
  // no such link in the model named.
  std::string findModelLink(const std::string& name, PfxNodeModelPart& link) const;
  // A joint by name: the robot of robot_description's by its URDF name, then
  // "<model>::<joint>", then "<model>/<joint>". Empty, or why not, as findModelLink.
  std::string findModelJoint(const std::string& name, PfxNodeModelPart& joint) const;
  // Body id of a link, of "ground" or of "octomap", or -1.
  PfxInt64 findBody(const std::string& name) const;
  PfxTransform3 getLinkPose(PfxUInt32 linkIndex, PfxUInt32 model = 0) const;
  // A link's TF frame, and its name in rays and contacts: the URDF's name for model 0,
  // "<framePrefix>/<link>" for an added model.
  const std::string& getLinkName(PfxUInt32 linkIndex, PfxUInt32 model = 0) const;

  // Loads a robot into the world as it is now, its root link at spec's pose (nothing moves
  // out of its way), in a new model slot (*slot). Rejects, with *message saying why and
  // nothing changed: a name that is not letters, digits and _ starting with a letter or
  // that names a model already (the robot of robot_description is named after its URDF),
  // a frame prefix that is not such names joined by /, a link frame that names a body,
  // agent, cable or cloth already, a position that is not finite or beyond 1000 m, an
  // orientation that is not a unit quaternion (within 1e-3), and what the URDF loader
  // rejects (its message).
  PfxInt32 addModel(const PfxNodeModelSpec& spec, PfxUInt32* slot, std::string* message);
  // What addModel would refuse before loading the URDF (the name, the frame prefix, the
  // pose), or empty.
  std::string checkModelSpec(const PfxNodeModelSpec& spec) const;
  // Removes a model's bodies and joints from the world (PfxWorld::removeRigidBody); reset()
  // does not bring it back, and its name is free for addModel. Slot 0, the robot of
  // robot_description, too, its body ids left unused. Refused, with nothing changed: an
  // empty slot, and a model a cable or cloth holds on to.
  PfxInt32 removeModel(PfxUInt32 slot, std::string* message);
  // Counts addModel and removeModel calls that changed the world: whoever draws the fixed
  // bodies draws them again.
  PfxUInt32 getModelChanges() const { return m_modelChanges; }
  // Slot of the model named `name`, or -1.
  PfxInt64 findModel(const std::string& name) const;
  PfxUInt32 getNumModelSlots() const { return PfxUInt32(m_config.models.size()) + 1; }
  bool hasModel(PfxUInt32 slot) const;
  const std::string& getModelName(PfxUInt32 slot) const;
  // The spec an added model was made from (slot >= 1 and hasModel).
  const PfxNodeModelSpec& getModelSpec(PfxUInt32 slot) const { return *m_config.models[slot - 1]; }

  // Adds an agent (PfxNodeAgentSet::add) after checking that its name is no body's name
  // (rays and contacts name it) and that at its start it overlaps no body by more than 1 cm
  // (standing on the ground, it touches it). On error *message says why and nothing changes.
  PfxInt32 addAgent(const PfxNodeAgentSpec& spec, std::string* message);
  PfxInt32 removeAgent(const std::string& name, std::string* message);
  // PfxNodeAgentSet::command at the current simulated time.
  PfxInt32 commandAgent(const std::string& name, PfxFloat vx, PfxFloat vy, PfxFloat turnRate);
  const PfxNodeAgentSet& getAgents() const;

  // Adds a cable or cloth (pfx_node_cables.h) to the world as it is now, its ends or pins
  // tied to the links' poses of the moment; reset() builds it again at the robot's start.
  // Rejects, with *message naming the field and nothing changed: what pfxCheckCableSpec or
  // pfxCheckClothSpec rejects, a name that is not letters, digits and _ starting with a
  // letter or that a body, agent, cable or cloth has already, an unknown link, and a cable
  // shorter than the distance between its ends.
  PfxInt32 addCable(const PfxNodeCableSpec& spec, std::string* message);
  PfxInt32 addCloth(const PfxNodeClothSpec& spec, std::string* message);
  const std::vector<PfxNodeCableSpec>& getCables() const { return m_config.cables; }
  const std::vector<PfxNodeClothSpec>& getCloths() const { return m_config.cloths; }
  // The particle group of the i-th cable or cloth.
  const PfxParticleGroup& getCableGroup(PfxUInt32 i) const;
  const PfxParticleGroup& getClothGroup(PfxUInt32 i) const;
  // The cable or cloth a particle group is, by group id; -1 for a name that is none.
  const std::string& getParticleGroupName(PfxUInt32 groupId) const;
  PfxInt64 findParticleGroup(const std::string& name) const;

  PfxInt32 castRay(const PfxRayInput& ray, PfxRayOutput& hit);
  PfxInt32 castRays(const PfxRayInput* rays, PfxRayOutput* hits, PfxUInt32 numRays);
  // The points of the last step where bodies touch (closer than 1 mm) or pushed on each
  // other, those of sleeping bodies included (they keep the points they had when they fell
  // asleep); speculative points farther apart that did nothing are left out. Then, by the
  // same rule, the points where cables and cloths touch bodies, and where they touch each
  // other.
  void getContacts(std::vector<PfxNodeContact>& contacts) const;
  // What a contact's side A or B is called: a link (getShapeName), a body, a cable or a cloth.
  const std::string& getContactNameA(const PfxNodeContact& contact) const;
  const std::string& getContactNameB(const PfxNodeContact& contact) const;

  // A force at the link's origin plus a torque (world frame), on the link's body for
  // `duration` seconds of simulated time (at least one step). Deleting its model ends it.
  PfxInt32 applyLinkWrench(const PfxNodeModelPart& link, const PfxVector3& force,
                           const PfxVector3& torque, double duration);
  // Moves the link's body so that the link's frame is at `pose`, with the link origin's
  // velocity and the angular velocity given (world frame).
  PfxInt32 setLinkState(const PfxNodeModelPart& link, const PfxTransform3& pose,
                        const PfxVector3& linearVelocity, const PfxVector3& angularVelocity);
  // One drive for several joints of a model, all or none: when one is rejected the joints
  // set before it are put back.
  PfxInt32 setJointCommands(const std::vector<PfxUInt32>& jointIndices, PfxJointDrive drive,
                            const std::vector<PfxFloat>& targets,
                            const std::vector<PfxFloat>& maxForces, PfxUInt32 model = 0);

 private:
  struct Scene;
  struct Wrench {
    PfxNodeModelPart link;
    PfxVector3 force;
    PfxVector3 torque;
    double remainingSteps;
  };
  PfxInt32 buildScene(const PfxNodeSimulationConfig& config, std::unique_ptr<Scene>& scene,
                      std::string* message) const;
  static void nameAgentBody(Scene& scene, const std::string& name, PfxUInt32 bodyId);
  // Loads an added model into the scene's world in slot `slot`; on error nothing changes.
  static PfxInt32 buildModel(Scene& scene, const PfxNodeModelSpec& spec, PfxUInt32 slot,
                             std::string* message);
  // Takes a model's bodies out of the scene's world and its links' names out of the
  // scene's; the newest bodies' slots are truncated away.
  static void removeModelBodies(Scene& scene, const PfxUrdfModel& urdf,
                                const std::vector<std::string>& linkNames);
  // The frames of slot 0's links: the URDF's names.
  static std::vector<std::string> robotLinkNames(const PfxUrdfModel& robot);
  // Empty when `name` may name a new cable or cloth, else why not.
  std::string checkGroupName(const Scene& scene, const std::string& name) const;
  // The body a cable end or cloth pin named `link` holds on to, and where `point` (in the
  // link's frame) lies in the world; false for an unknown link.
  bool findAnchor(const Scene& scene, const std::string& link, const PfxVector3& point,
                  PfxNodeAnchorBody& body, PfxVector3& world) const;
  PfxInt32 buildCable(Scene& scene, const PfxNodeCableSpec& spec, std::string* message) const;
  // Adds a built cable or cloth to the scene's world under `name`, its group id to `ids`.
  static PfxInt32 addGroup(Scene& scene, const PfxParticleGroupBuilder& group,
                           const std::string& name, std::vector<PfxUInt32>& ids,
                           std::string* message);
  // PFX_ERR_INVALID_VALUE with `why` in *message.
  // A link (isLink) or joint named "<model>::<part>" or "<model>/<part>"; empty, or why not.
  std::string findQualifiedPart(const std::string& name, bool isLink,
                                PfxNodeModelPart& part) const;
  static PfxInt32 refuse(const std::string& why, std::string* message);
  PfxInt32 buildCloth(Scene& scene, const PfxNodeClothSpec& spec, std::string* message) const;

  PfxNodeSimulationConfig m_config;
  std::unique_ptr<Scene> m_scene;
  std::vector<Wrench> m_wrenches;
  // getContacts' scratch.
  mutable std::vector<PfxParticleBodyContact> m_particleContacts;
  mutable std::vector<PfxParticleGroupContact> m_particleGroupContacts;
  // Simulated time at the last load (of a saved world) or change of the time step, and
  // steps since.
  double m_startTime = 0;
  PfxUInt64 m_stepCount = 0;
  PfxUInt32 m_generation = 0;
  PfxUInt32 m_modelChanges = 0;
};

}  // namespace pfx
