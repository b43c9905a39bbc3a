#include "pfx_ros/pfx_node_services.h"

#include <cmath>
#include <set>
#include <sstream>

#include "pfx_ros/pfx_ros_conversions.h"

namespace pfx {

namespace {

template <typename Response>
bool accept(Response& res, const std::string& message = "") {
  res.success = true;
  res.message = message;
  return true;
}

// Empty when the ray can be cast, otherwise why not.
std::string makeRay(const geometry_msgs::Point& origin, const geometry_msgs::Vector3& direction,
                    PfxRayInput& ray) {
  ray.reset();
  ray.m_startPosition = pfxFromMsg(origin);
  ray.m_direction = pfxFromMsg(direction);
  if (!pfxIsFinite(ray.m_startPosition)) return "origin is not finite (NaN, infinite or too large)";
  if (!pfxIsFinite(ray.m_direction)) return "direction is not finite (NaN, infinite or too large)";
  switch (pfxCheckRayInput(ray)) {
    case PFX_OK:
      return "";
    case PFX_ERR_DEGENERATE:
      return "direction has zero length (its length is the ray's length)";
    default:
      return "direction is too long to cast";
  }
}

bool isFinite(const geometry_msgs::Vector3& v) { return pfxIsFinite(pfxFromMsg(v)); }

}  // namespace

PfxNodeServices::PfxNodeServices(ros::NodeHandle& privateHandle, PfxNodeSimulation& simulation,
                                 PfxNodeRefusalLog& refusals, PfxUInt32 maxBatchRays,
                                 bool startPaused, double realTimeFactor, StepFunction stepFunction,
                                 JointCommandListener jointCommandListener)
    : m_simulation(simulation),
      m_refusals(refusals),
      m_maxBatchRays(maxBatchRays),
      m_paused(startPaused),
      m_realTimeFactor(realTimeFactor),
      m_stepFunction(std::move(stepFunction)),
      m_jointCommandListener(std::move(jointCommandListener)) {
  ros::NodeHandle& nh = privateHandle;
  m_servers.push_back(nh.advertiseService("raycast", &PfxNodeServices::raycast, this));
  m_servers.push_back(nh.advertiseService("raycast_batch", &PfxNodeServices::raycastBatch, this));
  m_servers.push_back(nh.advertiseService("get_contacts", &PfxNodeServices::getContacts, this));
  m_servers.push_back(
      nh.advertiseService("apply_body_wrench", &PfxNodeServices::applyBodyWrench, this));
  m_servers.push_back(nh.advertiseService("set_body_state", &PfxNodeServices::setBodyState, this));
  m_servers.push_back(
      nh.advertiseService("set_joint_command", &PfxNodeServices::setJointCommand, this));
  m_servers.push_back(nh.advertiseService("reset", &PfxNodeServices::reset, this));
  m_servers.push_back(nh.advertiseService("save_world", &PfxNodeServices::saveWorld, this));
  m_servers.push_back(nh.advertiseService("load_world", &PfxNodeServices::loadWorld, this));
  m_servers.push_back(nh.advertiseService("pause", &PfxNodeServices::pause, this));
  m_servers.push_back(nh.advertiseService("unpause", &PfxNodeServices::unpause, this));
  m_servers.push_back(nh.advertiseService("step", &PfxNodeServices::step, this));
  m_servers.push_back(nh.advertiseService("set_physics", &PfxNodeServices::setPhysics, this));
  m_servers.push_back(nh.advertiseService("get_physics", &PfxNodeServices::getPhysics, this));
}

std::string PfxNodeServices::hitName(const PfxRayOutput& hit) const {
  if (!hit.m_contactFlag) return "";
  if (hit.m_particleGroupId != PFX_RAY_NO_OBJECT) {
    return m_simulation.getParticleGroupName(hit.m_particleGroupId);
  }
  if (hit.m_objectId == PFX_RAY_NO_OBJECT) return "";
  return m_simulation.getShapeName(hit.m_objectId, hit.m_shapeId);
}

bool PfxNodeServices::raycast(Raycast::Request& req, Raycast::Response& res) {
  PfxRayInput ray;
  if (const std::string why = makeRay(req.origin, req.direction, ray); !why.empty()) {
    return pfxRejectRequest(m_refusals, res, "raycast", why);
  }
  PfxRayOutput hit;
  if (const PfxInt32 err = m_simulation.castRay(ray, hit); err != PFX_OK) {
    return pfxRejectRequest(m_refusals, res, "raycast",
                            std::string("cast failed: ") + pfxErrorString(err));
  }
  res.hit = hit.m_contactFlag;
  res.point = pfxToPointMsg(hit.m_contactPoint);
  res.normal = pfxToVector3Msg(hit.m_contactNormal);
  res.fraction = hit.m_variable;
  res.distance = double(hit.m_variable) * double(ray.m_direction.norm());
  res.link = hitName(hit);
  return accept(res);
}

bool PfxNodeServices::raycastBatch(RaycastBatch::Request& req, RaycastBatch::Response& res) {
  const std::size_t numRays = req.origins.size();
  if (req.directions.size() != numRays) {
    std::ostringstream why;
    why << req.origins.size() << " origins but " << req.directions.size()
        << " directions: one of each per ray";
    return pfxRejectRequest(m_refusals, res, "raycast_batch", why.str());
  }
  if (numRays > m_maxBatchRays) {
    std::ostringstream why;
    why << numRays << " rays in one batch, at most " << m_maxBatchRays << " allowed";
    return pfxRejectRequest(m_refusals, res, "raycast_batch", why.str());
  }
  m_batchRays.resize(numRays);
  m_batchHits.resize(numRays);
  for (std::size_t i = 0; i < numRays; ++i) {
    if (const std::string why = makeRay(req.origins[i], req.directions[i], m_batchRays[i]);
        !why.empty()) {
      return pfxRejectRequest(m_refusals, res, "raycast_batch",
                              "ray " + std::to_string(i) + ": " + why);
    }
  }
  if (numRays > 0) {
    const PfxInt32 err =
        m_simulation.castRays(m_batchRays.data(), m_batchHits.data(), PfxUInt32(numRays));
    if (err != PFX_OK) {
      return pfxRejectRequest(m_refusals, res, "raycast_batch",
                              std::string("cast failed: ") + pfxErrorString(err));
    }
  }
  res.hit.resize(numRays);
  res.points.resize(numRays);
  res.normals.resize(numRays);
  res.fractions.resize(numRays);
  res.links.resize(numRays);
  for (std::size_t i = 0; i < numRays; ++i) {
    const PfxRayOutput& hit = m_batchHits[i];
    res.hit[i] = hit.m_contactFlag;
    res.points[i] = pfxToPointMsg(hit.m_contactPoint);
    res.normals[i] = pfxToVector3Msg(hit.m_contactNormal);
    res.fractions[i] = hit.m_variable;
    res.links[i] = hitName(hit);
  }
  return accept(res);
}

bool PfxNodeServices::getContacts(GetContacts::Request& req, GetContacts::Response& res) {
  // Contacts name links by their frames: a model-qualified name becomes its link's frame.
  std::string asked = req.link;
  if (!asked.empty() && m_simulation.findBody(asked) < 0 &&
      m_simulation.findParticleGroup(asked) < 0) {
    PfxNodeModelPart link;
    if (const std::string why = m_simulation.findModelLink(asked, link); !why.empty()) {
      return pfxRejectRequest(m_refusals, res, "get_contacts", why);
    }
    asked = m_simulation.getLinkName(link.index, link.model);
  }
  m_simulation.getContacts(m_contacts);
  for (const PfxNodeContact& c : m_contacts) {
    const std::string& nameA = m_simulation.getContactNameA(c);
    const std::string& nameB = m_simulation.getContactNameB(c);
    if (!asked.empty() && nameA != asked && nameB != asked) continue;
    // The link asked about comes first, the normal pointing away from it.
    const bool swap = !asked.empty() && nameA != asked;
    Contact msg;
    msg.link_a = swap ? nameB : nameA;
    msg.link_b = swap ? nameA : nameB;
    msg.position = pfxToPointMsg(c.position);
    msg.normal = pfxToVector3Msg(swap ? PfxVector3(-c.normal) : c.normal);
    msg.depth = c.depth;
    msg.impulse = c.impulse;
    res.contacts.push_back(msg);
  }
  return accept(res);
}

bool PfxNodeServices::applyBodyWrench(ApplyBodyWrench::Request& req,
                                      ApplyBodyWrench::Response& res) {
  PfxNodeModelPart link;
  if (const std::string why = m_simulation.findModelLink(req.link, link); !why.empty()) {
    return pfxRejectRequest(m_refusals, res, "apply_body_wrench", why);
  }
  if (!isFinite(req.force))
    return pfxRejectRequest(m_refusals, res, "apply_body_wrench", "force is not finite");
  if (!isFinite(req.torque))
    return pfxRejectRequest(m_refusals, res, "apply_body_wrench", "torque is not finite");
  if (!std::isfinite(req.duration) || req.duration < 0) {
    std::ostringstream why;
    why << "duration " << req.duration << " s: must be finite and >= 0 (0: one step)";
    return pfxRejectRequest(m_refusals, res, "apply_body_wrench", why.str());
  }
  if (const PfxInt32 err = m_simulation.applyLinkWrench(link, pfxFromMsg(req.force),
                                                        pfxFromMsg(req.torque), req.duration);
      err != PFX_OK) {
    return pfxRejectRequest(m_refusals, res, "apply_body_wrench", pfxErrorString(err));
  }
  return accept(res);
}

bool PfxNodeServices::setBodyState(SetBodyState::Request& req, SetBodyState::Response& res) {
  PfxNodeModelPart link;
  if (const std::string why = m_simulation.findModelLink(req.link, link); !why.empty()) {
    return pfxRejectRequest(m_refusals, res, "set_body_state", why);
  }
  const PfxVector3 position = pfxFromMsg(req.pose.position);
  if (!pfxIsFinite(position))
    return pfxRejectRequest(m_refusals, res, "set_body_state", "position is not finite");
  const PfxQuat orientation = pfxFromMsg(req.pose.orientation);
  const double norm = std::sqrt(req.pose.orientation.x * req.pose.orientation.x +
                                req.pose.orientation.y * req.pose.orientation.y +
                                req.pose.orientation.z * req.pose.orientation.z +
                                req.pose.orientation.w * req.pose.orientation.w);
  if (!pfxIsFinite(orientation) || !(std::abs(norm - 1) <= 1e-3)) {
    std::ostringstream why;
    why << "orientation is not a unit quaternion (norm " << norm << ")";
    return pfxRejectRequest(m_refusals, res, "set_body_state", why.str());
  }
  if (!isFinite(req.twist.linear) || !isFinite(req.twist.angular)) {
    return pfxRejectRequest(m_refusals, res, "set_body_state", "twist is not finite");
  }
  const PfxTransform3 pose = pfxMakeTransform(orientation.normalized(), position);
  if (const PfxInt32 err = m_simulation.setLinkState(link, pose, pfxFromMsg(req.twist.linear),
                                                     pfxFromMsg(req.twist.angular));
      err != PFX_OK) {
    return pfxRejectRequest(m_refusals, res, "set_body_state", pfxErrorString(err));
  }
  return accept(res);
}

bool PfxNodeServices::setJointCommand(SetJointCommand::Request& req,
                                      SetJointCommand::Response& res) {
  const char* service = "set_joint_command";
  const std::size_t n = req.names.size();
  if (n == 0) return pfxRejectRequest(m_refusals, res, service, "no joints named");
  PfxJointDrive drive;
  switch (req.mode) {
    case SetJointCommand::Request::OFF:
      drive = kPfxJointDriveNone;
      break;
    case SetJointCommand::Request::POSITION:
      drive = kPfxJointDrivePosition;
      break;
    case SetJointCommand::Request::VELOCITY:
      drive = kPfxJointDriveVelocity;
      break;
    case SetJointCommand::Request::EFFORT:
      drive = kPfxJointDriveEffort;
      break;
    default:
      return pfxRejectRequest(m_refusals, res, service,
                              "mode " + std::to_string(req.mode) +
                                  ": OFF (0), POSITION (1), VELOCITY (2) or EFFORT (3)");
  }
  const bool needTargets = drive != kPfxJointDriveNone;
  if (req.targets.size() != n && (needTargets || !req.targets.empty())) {
    return pfxRejectRequest(
        m_refusals, res, service,
        std::to_string(n) + " joints but " + std::to_string(req.targets.size()) + " targets");
  }
  if (!req.max_forces.empty() && req.max_forces.size() != n) {
    return pfxRejectRequest(m_refusals, res, service,
                            std::to_string(n) + " joints but " +
                                std::to_string(req.max_forces.size()) +
                                " max_forces (empty, or one per joint)");
  }
  // One model per request: its joints are set all or none.
  std::vector<PfxNodeModelPart> found(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (const std::string why = m_simulation.findModelJoint(req.names[i], found[i]); !why.empty()) {
      return pfxRejectRequest(m_refusals, res, service, why);
    }
    if (found[i].model != found[0].model) {
      return pfxRejectRequest(m_refusals, res, service,
                              "joints of models '" + m_simulation.getModelName(found[0].model) +
                                  "' and '" + m_simulation.getModelName(found[i].model) +
                                  "' in one request: command one model per request");
    }
  }
  const PfxUInt32 modelSlot = found[0].model;
  const PfxUrdfModel& model = m_simulation.getModel(modelSlot);
  std::vector<PfxUInt32> joints(n);
  std::vector<PfxFloat> targets(n, 0);
  std::vector<PfxFloat> maxForces(n, 0);
  std::set<PfxUInt32> seen;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& name = req.names[i];
    const PfxUInt32 index = found[i].index;
    if (!seen.insert(index).second)
      return pfxRejectRequest(m_refusals, res, service, "joint '" + name + "' named twice");
    const PfxUrdfJoint& joint = model.joints[index];
    if (joint.jointId == kPfxUrdfNoJoint) {
      return pfxRejectRequest(m_refusals, res, service,
                              "joint '" + name + "' has no coordinate to drive");
    }
    if (joint.mimicLeader >= 0) {
      return pfxRejectRequest(m_refusals, res, service,
                              "joint '" + name + "' mimics '" +
                                  model.joints[joint.mimicLeader].name + "': command the leader");
    }
    if (needTargets) {
      targets[i] = PfxFloat(req.targets[i]);
      if (!pfxIsFinite(targets[i])) {
        return pfxRejectRequest(m_refusals, res, service,
                                "target of joint '" + name + "' is not finite");
      }
    }
    if (!req.max_forces.empty()) {
      maxForces[i] = PfxFloat(req.max_forces[i]);
      if (!pfxIsFinite(maxForces[i]) || maxForces[i] < 0) {
        return pfxRejectRequest(m_refusals, res, service,
                                "max_force of joint '" + name + "' must be finite and >= 0");
      }
    }
    joints[i] = index;
  }
  if (const PfxInt32 err =
          m_simulation.setJointCommands(joints, drive, targets, maxForces, modelSlot);
      err != PFX_OK) {
    return pfxRejectRequest(m_refusals, res, service, pfxErrorString(err));
  }
  m_jointCommandListener(modelSlot, joints);
  // The targets were cut to the joints' limits where they lay beyond; say which.
  std::string cut;
  for (std::size_t i = 0; needTargets && i < n; ++i) {
    std::string note;
    pfxClampUrdfJointTarget(model.joints[joints[i]], drive, targets[i], &note);
    if (!note.empty()) cut += (cut.empty() ? "" : "; ") + note;
  }
  return accept(res, cut);
}

bool PfxNodeServices::reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  std::string why;
  if (m_simulation.reset(&why) != PFX_OK) return pfxRejectRequest(m_refusals, res, "reset", why);
  return accept(res, "initial state restored");
}

bool PfxNodeServices::saveWorld(WorldFile::Request& req, WorldFile::Response& res) {
  if (req.path.empty()) return pfxRejectRequest(m_refusals, res, "save_world", "no path given");
  std::string why;
  if (m_simulation.saveWorld(req.path, &why) != PFX_OK)
    return pfxRejectRequest(m_refusals, res, "save_world", why);
  std::ostringstream msg;
  msg << "world at t = " << m_simulation.getTime() << " s saved to " << req.path;
  return accept(res, msg.str());
}

bool PfxNodeServices::loadWorld(WorldFile::Request& req, WorldFile::Response& res) {
  if (req.path.empty()) return pfxRejectRequest(m_refusals, res, "load_world", "no path given");
  std::string why;
  if (m_simulation.loadWorld(req.path, &why) != PFX_OK)
    return pfxRejectRequest(m_refusals, res, "load_world", why);
  std::ostringstream msg;
  msg << "world loaded from " << req.path << ", continuing from t = " << m_simulation.getTime()
      << " s";
  return accept(res, msg.str());
}

bool PfxNodeServices::pause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  const bool was = m_paused;
  m_paused = true;
  std::ostringstream msg;
  msg << (was ? "already paused" : "paused") << " at t = " << m_simulation.getTime() << " s";
  return accept(res, msg.str());
}

bool PfxNodeServices::unpause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  const bool was = m_paused;
  m_paused = false;
  std::ostringstream msg;
  msg << (was ? "running" : "already running") << " from t = " << m_simulation.getTime() << " s";
  return accept(res, msg.str());
}

bool PfxNodeServices::step(Step::Request& req, Step::Response& res) {
  res.steps_done = 0;
  res.time = m_simulation.getTime();
  if (!m_paused)
    return pfxRejectRequest(m_refusals, res, "step", "the simulation is running: pause it first");
  if (req.steps < 1 || req.steps > kPfxNodeMaxStepsPerCall) {
    return pfxRejectRequest(m_refusals, res, "step",
                            "steps " + std::to_string(req.steps) + ": must be 1 .. " +
                                std::to_string(kPfxNodeMaxStepsPerCall));
  }
  const PfxInt32 err = m_stepFunction(req.steps);
  res.steps_done = req.steps;
  res.time = m_simulation.getTime();
  std::ostringstream msg;
  msg << req.steps << " steps to t = " << res.time << " s";
  // The steps were taken either way; a failed one is reported as the loop reports it.
  if (err != PFX_OK)
    return pfxRejectRequest(m_refusals, res, "step",
                            msg.str() + ", a step failed: " + pfxErrorString(err));
  return accept(res, msg.str());
}

Physics PfxNodeServices::physics() const {
  Physics p;
  p.dt = m_simulation.getTimeStep();
  p.substeps = PfxInt32(m_simulation.getSubSteps());
  p.iterations = PfxInt32(m_simulation.getIterations());
  p.gravity = pfxToVector3Msg(m_simulation.getGravity());
  p.real_time_factor = m_realTimeFactor;
  return p;
}

bool PfxNodeServices::setPhysics(SetPhysics::Request& req, SetPhysics::Response& res) {
  const char* service = "set_physics";
  const Physics& p = req.physics;
  res.physics = physics();
  std::ostringstream why;
  if (!std::isfinite(p.dt) || !(p.dt > 0) || p.dt > kPfxNodeMaxTimeStep) {
    why << "dt " << p.dt << " s: must be in (0, " << kPfxNodeMaxTimeStep << "]";
  } else if (p.substeps < 1 || PfxUInt32(p.substeps) > PFX_MAX_SUB_STEPS) {
    why << "substeps " << p.substeps << ": must be 1 .. " << PFX_MAX_SUB_STEPS;
  } else if (p.iterations < 1 || PfxUInt32(p.iterations) > PFX_MAX_ITERATIONS) {
    why << "iterations " << p.iterations << ": must be 1 .. " << PFX_MAX_ITERATIONS;
  } else if (!isFinite(p.gravity) || pfxFromMsg(p.gravity).norm() > kPfxNodeMaxGravity) {
    why << "gravity (" << p.gravity.x << ", " << p.gravity.y << ", " << p.gravity.z
        << "): must be finite and at most " << kPfxNodeMaxGravity << " m/s^2 long";
  } else if (!std::isfinite(p.real_time_factor) || p.real_time_factor < 0) {
    why << "real_time_factor " << p.real_time_factor << ": must be finite and >= 0";
  }
  if (!why.str().empty()) return pfxRejectRequest(m_refusals, res, service, why.str());
  std::string refused;
  if (m_simulation.setPhysics(PfxFloat(p.dt), PfxUInt32(p.substeps), PfxUInt32(p.iterations),
                              pfxFromMsg(p.gravity), &refused) != PFX_OK) {
    return pfxRejectRequest(m_refusals, res, service, refused);
  }
  m_realTimeFactor = p.real_time_factor;
  res.physics = physics();
  std::ostringstream msg;
  msg << "from t = " << m_simulation.getTime() << " s on";
  return accept(res, msg.str());
}

bool PfxNodeServices::getPhysics(GetPhysics::Request&, GetPhysics::Response& res) {
  res.physics = physics();
  return true;
}

}  // namespace pfx
