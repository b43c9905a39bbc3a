// The node's services, in its private namespace. Each checks the whole request before it
// touches the world: a bad request (unknown model, link or joint, NaN, a zero-length ray, a
// negative duration, too many rays, a quaternion that is not unit) gets success = false
// and a message saying what was wrong, and changes nothing. Links and joints of every model
// are reached by name (PfxNodeSimulation::findModelLink, findModelJoint). Callbacks run
// between steps.
#pragma once

#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include <functional>
#include <vector>

#include "pfx/ApplyBodyWrench.h"
#include "pfx/GetContacts.h"
#include "pfx/GetPhysics.h"
#include "pfx/Raycast.h"
#include "pfx/RaycastBatch.h"
#include "pfx/SetBodyState.h"
#include "pfx/SetJointCommand.h"
#include "pfx/SetPhysics.h"
#include "pfx/Step.h"
#include "pfx/WorldFile.h"
#include "pfx_ros/pfx_node_refusal_log.h"
#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

// ~step's bound: the node answers nothing else while it steps.
constexpr PfxInt32 kPfxNodeMaxStepsPerCall = 10000;
// ~set_physics's bounds, beyond which a robot's simulation is no longer meaningful; its
// sub-steps and iterations are bounded by the world's own PFX_MAX_SUB_STEPS and
// PFX_MAX_ITERATIONS.
constexpr double kPfxNodeMaxTimeStep = 0.1;  // s
constexpr double kPfxNodeMaxGravity = 1000;  // m/s^2

class PfxNodeServices {
 public:
  // Takes `steps` steps as the node's loop does (sensors and diagnostics included) and
  // publishes the state after them.
  using StepFunction = std::function<PfxInt32(PfxInt32 steps)>;
  // Told which joints (indices into the joints of the model in slot `model`)
  // ~set_joint_command has just commanded, so that a trajectory driving them lets them go.
  using JointCommandListener =
      std::function<void(PfxUInt32 model, const std::vector<PfxUInt32>& joints)>;

  // Advertises the services on `privateHandle`; a batch may hold at most maxBatchRays rays.
  // Refusals are logged through `refusals`.
  PfxNodeServices(ros::NodeHandle& privateHandle, PfxNodeSimulation& simulation,
                  PfxNodeRefusalLog& refusals,
                  PfxUInt32 maxBatchRays, bool startPaused, double realTimeFactor,
                  StepFunction stepFunction, JointCommandListener jointCommandListener);

  bool isPaused() const { return m_paused; }
  double getRealTimeFactor() const { return m_realTimeFactor; }

 private:
  bool raycast(Raycast::Request& req, Raycast::Response& res);
  bool raycastBatch(RaycastBatch::Request& req, RaycastBatch::Response& res);
  bool getContacts(GetContacts::Request& req, GetContacts::Response& res);
  bool applyBodyWrench(ApplyBodyWrench::Request& req, ApplyBodyWrench::Response& res);
  bool setBodyState(SetBodyState::Request& req, SetBodyState::Response& res);
  bool setJointCommand(SetJointCommand::Request& req, SetJointCommand::Response& res);
  bool reset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool saveWorld(WorldFile::Request& req, WorldFile::Response& res);
  bool loadWorld(WorldFile::Request& req, WorldFile::Response& res);
  bool pause(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool unpause(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool step(Step::Request& req, Step::Response& res);
  bool setPhysics(SetPhysics::Request& req, SetPhysics::Response& res);
  bool getPhysics(GetPhysics::Request& req, GetPhysics::Response& res);
  Physics physics() const;

  // Name of what a ray hit, empty on a miss.
  std::string hitName(const PfxRayOutput& hit) const;

  PfxNodeSimulation& m_simulation;
  PfxNodeRefusalLog& m_refusals;
  PfxUInt32 m_maxBatchRays;
  bool m_paused = false;
  double m_realTimeFactor;
  StepFunction m_stepFunction;
  JointCommandListener m_jointCommandListener;
  std::vector<ros::ServiceServer> m_servers;
  std::vector<PfxRayInput> m_batchRays;  // kept between calls: batches reuse the memory
  std::vector<PfxRayOutput> m_batchHits;
  std::vector<PfxNodeContact> m_contacts;
};

}  // namespace pfx
