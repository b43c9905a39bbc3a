#include "pfx_ros/pfx_node.h"

#include <ros/callback_queue.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pfx {

namespace {

// A step this late (a slow step, a long service call) is not caught up with a burst of
// steps: the schedule starts again from now.
const ros::WallDuration kMaxLag(0.1);
// While paused, how long the loop waits for service calls before it looks around again.
const ros::WallDuration kPausedWait(0.01);

ros::WallDuration periodOf(double rate) {
  return rate > 0 ? ros::WallDuration(1.0 / rate) : ros::WallDuration(0);
}

bool positiveFinite(double x) { return std::isfinite(x) && x > 0; }
bool nonNegativeFinite(double x) { return std::isfinite(x) && x >= 0; }

// ~initial_height: a number of metres (true), or unset or "auto" (false: the robot is
// placed above the ground).
bool readInitialHeight(const ros::NodeHandle& nh, double& height) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam("initial_height", value)) return false;
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeDouble:
      height = static_cast<double>(value);
      return true;
    case XmlRpc::XmlRpcValue::TypeInt:
      height = static_cast<int>(value);
      return true;
    case XmlRpc::XmlRpcValue::TypeString:
      if (static_cast<std::string>(value) == "auto") return false;
      [[fallthrough]];
    default:
      height = std::numeric_limits<double>::quiet_NaN();  // refused below
      return true;
  }
}

}  // namespace

PfxNode::PfxNode() = default;
PfxNode::~PfxNode() = default;

bool PfxNode::readParam(PfxNodeParam& p) const {
  const ros::NodeHandle& nh = m_privateHandle;
  if (!m_handle.getParam("robot_description", p.simulation.urdfXml)) {
    ROS_FATAL("pfx_node: parameter robot_description (the robot's URDF text) is not set");
    return false;
  }
  nh.param<std::string>("urdf_path", p.simulation.urdfPath, "");
  nh.param<std::string>("octomap_file", p.simulation.octomapFile, "");
  nh.param<std::string>("world_file", p.simulation.worldFile, "");
  nh.param("ground_plane", p.simulation.groundPlane, true);
  nh.param("fixed_base", p.simulation.fixedBase, false);
  nh.param("allow_missing_meshes", p.simulation.allowMissingMeshes, false);
  nh.param("self_collision", p.simulation.selfCollision, true);
  nh.param<std::string>("fixed_frame", p.fixedFrame, "world");
  nh.param("paused", p.paused, false);
  double groundSize, dt, initialHeight = 0;
  int subSteps, iterations, threads;
  nh.param("ground_size", groundSize, 20.0);
  nh.param("dt", dt, 0.004);
  nh.param("substeps", subSteps, 1);
  nh.param("iterations", iterations, 10);
  nh.param("threads", threads, 1);
  const bool heightGiven = readInitialHeight(nh, initialHeight);
  nh.param("real_time_factor", p.realTimeFactor, 1.0);
  nh.param("publish_rate", p.publishRate, 100.0);
  nh.param("marker_rate", p.markerRate, 10.0);
  nh.param("diagnostics_rate", p.diagnosticsRate, 1.0);
  nh.param("link_states_rate", p.linkStatesRate, 10.0);
  nh.param("max_batch_rays", p.maxBatchRays, 100000);
  nh.param<std::string>("agent_frame_prefix", p.agentFramePrefix, "agents");
  double commandTimeout, maxTurnRate, waypointTolerance;
  nh.param("agent_cmd_vel_timeout", commandTimeout, 0.5);
  nh.param("agent_max_turn_rate", maxTurnRate, 3.0);
  nh.param("agent_waypoint_tolerance", waypointTolerance, 0.1);

  const char* invalid = nullptr;
  // The world's bounds, which it would otherwise refuse without naming the parameter.
  const std::string subStepsRange = "~substeps must be 1 .. " + std::to_string(PFX_MAX_SUB_STEPS);
  const std::string iterationsRange =
      "~iterations must be 1 .. " + std::to_string(PFX_MAX_ITERATIONS);
  const std::string dtRange =
      "~dt must be a positive number of seconds, at most " + std::to_string(int(PFX_MAX_TIME_STEP));
  if (!positiveFinite(dt) || dt > PFX_MAX_TIME_STEP) invalid = dtRange.c_str();
  if (subSteps < 1 || PfxUInt32(subSteps) > PFX_MAX_SUB_STEPS) invalid = subStepsRange.c_str();
  if (iterations < 1 || PfxUInt32(iterations) > PFX_MAX_ITERATIONS) {
    invalid = iterationsRange.c_str();
  }
  const std::string threadsRange = "~threads must be a whole number from 0 (every core) to " +
                                   std::to_string(PFX_MAX_THREADS);
  if (threads < 0 || PfxUInt32(threads) > PFX_MAX_THREADS) invalid = threadsRange.c_str();
  if (!positiveFinite(groundSize)) invalid = "~ground_size must be a positive number of metres";
  if (!std::isfinite(initialHeight)) {
    invalid = "~initial_height must be a finite number of metres, or auto";
  }
  if (!nonNegativeFinite(p.realTimeFactor)) invalid = "~real_time_factor must be >= 0";
  if (!nonNegativeFinite(p.publishRate) || !nonNegativeFinite(p.markerRate) ||
      !nonNegativeFinite(p.diagnosticsRate) || !nonNegativeFinite(p.linkStatesRate)) {
    invalid = "~publish_rate, ~marker_rate, ~diagnostics_rate and ~link_states_rate must be >= 0";
  }
  if (p.maxBatchRays < 1) invalid = "~max_batch_rays must be at least 1";
  if (p.fixedFrame.empty()) invalid = "~fixed_frame must not be empty";
  if (!positiveFinite(commandTimeout)) {
    invalid = "~agent_cmd_vel_timeout must be a positive number of seconds";
  }
  if (!positiveFinite(maxTurnRate)) invalid = "~agent_max_turn_rate must be > 0 (rad/s)";
  if (!positiveFinite(waypointTolerance)) {
    invalid = "~agent_waypoint_tolerance must be a positive number of metres";
  }
  if (!p.agentFramePrefix.empty() &&
      (p.agentFramePrefix.front() == '/' || p.agentFramePrefix.back() == '/' ||
       p.agentFramePrefix.find_first_of(" \t") != std::string::npos)) {
    invalid = "~agent_frame_prefix must not start or end with / nor hold spaces";
  }
  if (invalid) {
    ROS_FATAL("pfx_node: %s", invalid);
    return false;
  }
  p.simulation.groundSize = PfxFloat(groundSize);
  p.simulation.timeStep = PfxFloat(dt);
  p.simulation.subSteps = PfxUInt32(subSteps);
  p.simulation.iterations = PfxUInt32(iterations);
  p.simulation.threads = PfxUInt32(threads);
  p.simulation.initialHeight = PfxFloat(initialHeight);
  p.simulation.placeAboveGround = !heightGiven;
  p.simulation.agents.commandTimeout = commandTimeout;
  p.simulation.agents.maxTurnRate = PfxFloat(maxTurnRate);
  p.simulation.agents.waypointTolerance = PfxFloat(waypointTolerance);
  return true;
}

bool PfxNode::initialize() {
  if (!readParam(m_param)) return false;
  std::string why;
  if (m_simulation.load(m_param.simulation, &why) != PFX_OK) {
    ROS_FATAL_STREAM("pfx_node: " << why);
    return false;
  }
  for (const std::string& warning : m_simulation.getWarnings()) {
    ROS_WARN_STREAM("pfx_node: " << warning);
  }
  // Before the agents, cables and sensors: a saved world takes the built one's place.
  std::string notice;
  if (!m_autosave.configure(m_privateHandle, &why) ||
      !m_autosave.resume(m_simulation, &why, &notice)) {
    ROS_FATAL_STREAM("pfx_node: " << why);
    return false;
  }
  if (!notice.empty()) ROS_INFO_STREAM("pfx_node: " << notice);
  ros::param::param("/use_sim_time", m_useSimTime, false);

  m_agents = std::make_unique<PfxNodeAgents>(m_handle, m_privateHandle, m_simulation, m_refusals);
  if (!m_agents->addDeclared(&why)) {
    ROS_FATAL_STREAM("pfx_node: " << why);
    return false;
  }
  // Before the sensors: the first scan sees them.
  pfxAddDeclaredCablesAndCloths(m_privateHandle, m_simulation);
  m_sensors = std::make_unique<PfxNodeSensors>(m_handle, m_param.fixedFrame);
  const std::string urdfName =
      m_param.simulation.urdfPath.empty() ? "robot_description" : m_param.simulation.urdfPath;
  if (!m_sensors->configure(m_param.simulation.urdfXml, urdfName, m_privateHandle, m_simulation,
                            &why)) {
    ROS_FATAL_STREAM("pfx_node: " << why);
    return false;
  }
  m_jointCommands =
      std::make_unique<PfxNodeJointCommands>(m_handle, m_privateHandle, m_simulation,
                                             m_refusals, m_useSimTime);
  if (!m_jointCommands->configure(&why)) {
    ROS_FATAL_STREAM("pfx_node: " << why);
    return false;
  }
  // After the robot's own sensors and topics: a model's namespace is checked against them.
  m_models = std::make_unique<PfxNodeModels>(m_handle, m_privateHandle, m_simulation,
                                             m_refusals, m_param.fixedFrame, m_useSimTime,
                                             [this] { return removeRobot(); });
  if (!m_models->addDeclared(&why)) {
    ROS_FATAL_STREAM("pfx_node: " << why);
    return false;
  }
  m_linkStates = std::make_unique<PfxNodeLinkStates>(m_privateHandle, m_param.fixedFrame);
  m_statePublisher = std::make_unique<PfxNodeStatePublisher>(
      m_handle, m_param.fixedFrame, m_param.agentFramePrefix, m_useSimTime);
  m_statePublisher->bind(m_simulation);
  m_boundGeneration = m_simulation.getGeneration();
  m_diagnostics = std::make_unique<PfxNodeDiagnostics>(m_handle, m_param.realTimeFactor);
  m_markers = std::make_unique<PfxNodeMarkers>(m_privateHandle, m_param.fixedFrame);
  m_services = std::make_unique<PfxNodeServices>(
      m_privateHandle, m_simulation, m_refusals, PfxUInt32(m_param.maxBatchRays), m_param.paused,
      m_param.realTimeFactor, [this](PfxInt32 steps) { return stepPaused(steps); },
      [this](PfxUInt32 model, const std::vector<PfxUInt32>& joints) {
        if (model != 0) {
          m_models->releaseFromTrajectories(model, joints);
        } else if (m_jointCommands) {
          m_jointCommands->releaseFromTrajectories(joints);
        }
      });

  const PfxUrdfModel& model = m_simulation.getModel();
  ROS_INFO(
      "pfx_node: robot '%s': %zu links, %zu joints, %u bodies in the world; dt %g s, "
      "%u sub-steps, %u iterations, real-time factor %g, %u agents, %zu cables, %zu cloths, "
      "%zu sensors, %zu added models%s",
      model.name.c_str(), model.links.size(), model.joints.size(),
      m_simulation.getWorld().getNumRigidBodies(), double(m_param.simulation.timeStep),
      m_param.simulation.subSteps, m_param.simulation.iterations, m_param.realTimeFactor,
      m_simulation.getAgents().getNumAgents(), m_simulation.getCables().size(),
      m_simulation.getCloths().size(), m_sensors->getNumSensors(), m_models->getNumModels(),
      m_param.paused ? " (paused)" : "");
  return true;
}

ros::Time PfxNode::stamp() const {
  return m_useSimTime ? ros::Time(m_simulation.getTime()) : ros::Time::now();
}

PfxInt32 PfxNode::stepOnce() {
  if (m_jointCommands) m_jointCommands->update();
  m_models->beforeStep();
  const PfxInt32 err = m_simulation.step();
  if (err != PFX_OK) {
    ROS_ERROR_THROTTLE(1.0, "pfx_node: step at t = %.3f s failed: %s", m_simulation.getTime(),
                       pfxErrorString(err));
  }
  m_diagnostics->addStep(m_simulation.getWorld().getStats());
  if (m_sensors) m_sensors->update(m_simulation, stamp());
  m_models->afterStep(stamp());
  m_autosave.afterStep(m_simulation);
  return err;
}

bool PfxNode::rebindIfRebuilt() {
  if (m_simulation.getGeneration() == m_boundGeneration) return false;
  m_statePublisher->bind(m_simulation);
  m_boundGeneration = m_simulation.getGeneration();
  if (m_sensors) m_sensors->restart();
  m_models->rebind();
  return true;
}

std::string PfxNode::removeRobot() {
  std::string why;
  if (m_simulation.removeModel(0, &why) != PFX_OK) return why;
  m_jointCommands.reset();
  m_sensors.reset();
  m_statePublisher->bind(m_simulation);
  return "";
}

PfxInt32 PfxNode::stepPaused(PfxInt32 steps) {
  // A ~reset or ~load_world answered just before, in the same turn of the loop.
  rebindIfRebuilt();
  PfxInt32 firstError = PFX_OK;
  for (PfxInt32 i = 0; i < steps; ++i) {
    const PfxInt32 err = stepOnce();
    if (firstError == PFX_OK) firstError = err;
  }
  // Whoever asked for the steps looks at the state right after the answer.
  publishState();
  return firstError;
}

void PfxNode::publishState() {
  const ros::Time now = stamp();
  // A reset leaves the simulated clock where it was: its state under the stamp already sent
  // would be dropped by every TF listener as repeated data (TF_REPEATED_DATA), so it goes
  // out with the next step.
  if (now == m_lastStateStamp) return;
  m_lastStateStamp = now;
  m_statePublisher->publish(m_simulation, now);
  m_models->publishState(now);
}

void PfxNode::run() {
  ros::CallbackQueue& queue = *ros::getGlobalCallbackQueue();
  // A world loaded through ~load_world brings its own time step; ~set_physics changes it
  // and the real-time factor.
  auto stepPeriod = [&] {
    const double dt = m_simulation.getTimeStep();
    const double factor = m_services->getRealTimeFactor();
    return ros::WallDuration(factor > 0 ? dt / factor : 0);
  };
  const ros::WallDuration statePeriod = periodOf(m_param.publishRate);
  const ros::WallDuration markerPeriod = periodOf(m_param.markerRate);
  const ros::WallDuration diagnosticsPeriod = periodOf(m_param.diagnosticsRate);
  const ros::WallDuration linkStatesPeriod = periodOf(m_param.linkStatesRate);

  ros::WallTime now = ros::WallTime::now();
  ros::WallTime nextStep = now, nextState = now, nextMarkers = now, nextLinkStates = now;
  ros::WallTime nextDiagnostics = now + diagnosticsPeriod;
  bool stepsUnpublished = false;
  while (ros::ok()) {
    now = ros::WallTime::now();
    const bool paused = m_services->isPaused();
    if (paused) {
      nextStep = now;  // no burst of steps on unpause
    } else if (now >= nextStep) {
      stepOnce();
      stepsUnpublished = true;
      nextStep += stepPeriod();
      if (now - nextStep > kMaxLag) nextStep = now;
    }
    // A reset or a loaded world is a new state, paused or not.
    if (rebindIfRebuilt()) stepsUnpublished = true;
    // Stamps are simulated time under use_sim_time: only a step makes a new state.
    if (stepsUnpublished && now >= nextState) {
      publishState();
      stepsUnpublished = false;
      nextState = now + statePeriod;
    }
    if (m_param.markerRate > 0 && now >= nextMarkers) {
      m_markers->publish(m_simulation, stamp());
      nextMarkers = now + markerPeriod;
    }
    // Paused too, like the markers: a client stepping the world reads the state after it.
    if (m_param.linkStatesRate > 0 && now >= nextLinkStates) {
      m_linkStates->publish(m_simulation, stamp());
      nextLinkStates = now + linkStatesPeriod;
    }
    if (m_param.diagnosticsRate > 0 && now >= nextDiagnostics) {
      m_diagnostics->setTargetRealTimeFactor(m_services->getRealTimeFactor());
      m_diagnostics->publish(m_simulation, paused, stamp());
      nextDiagnostics = now + diagnosticsPeriod;
    }
    m_refusals.flush();
    // Answer service calls until the next step is due.
    const ros::WallTime wake = paused ? now + kPausedWait : nextStep;
    const ros::WallDuration wait = wake - ros::WallTime::now();
    queue.callAvailable(wait > ros::WallDuration(0) ? wait : ros::WallDuration(0));
  }
}

}  // namespace pfx
