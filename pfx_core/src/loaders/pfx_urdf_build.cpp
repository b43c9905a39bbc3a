// From urdfdom's model to bodies, shapes and joints, all outside the world: which links make
// one body, which massless links collapse into a universal or ball joint, the bodies' mass
// properties and shapes, the joints, their damping and the mimic couplings.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "loaders/pfx_urdf_internal.h"
#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_mesh_loader.h"

namespace pfx {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Pose = Eigen::Isometry3d;

// Joint origins closer than this meet at one point; axes whose cosine is below this are
// perpendicular. Both are far above the rounding of the usual "1.5708" in URDF files and far
// below anything a designer means.
constexpr double kCoincidentDistance = 1e-5;
constexpr double kPerpendicularCosine = 1e-3;
// A massless link between joints that cannot become one joint is a light body: this share
// of its lighter neighbour's mass, or, with no neighbour of mass, this mass and radius of
// gyration.
constexpr double kLightBodyMassFraction = 0.1;
constexpr double kLightBodyFallbackMass = 0.01;
constexpr double kLightBodyFallbackGyration = 0.01;
// Radius of the sphere a body without collision geometry carries (its filters match nothing).
constexpr PfxFloat kUrdfPlaceholderRadius = PfxFloat(0.01);

Pose toPose(const urdf::Pose& p) {
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                      .normalized()
                      .toRotationMatrix();
  pose.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  return pose;
}

PfxTransform3 toTransform(const Pose& pose) {
  PfxTransform3 transform = PfxTransform3::Identity();
  transform.linear() = pose.linear().cast<PfxFloat>();
  transform.translation() = pose.translation().cast<PfxFloat>();
  return transform;
}

PfxQuat toQuat(const Mat3& rotation) {
  return PfxQuat(Eigen::Quaterniond(rotation).normalized().cast<PfxFloat>());
}

bool isRotational(PfxUrdfJointType type) {
  return type == kPfxUrdfRevolute || type == kPfxUrdfContinuous;
}

bool hasCoordinate(PfxUrdfJointType type) {
  return isRotational(type) || type == kPfxUrdfPrismatic;
}

PfxUrdfJointType jointType(int urdfType) {
  switch (urdfType) {
    case urdf::Joint::REVOLUTE:
      return kPfxUrdfRevolute;
    case urdf::Joint::CONTINUOUS:
      return kPfxUrdfContinuous;
    case urdf::Joint::PRISMATIC:
      return kPfxUrdfPrismatic;
    case urdf::Joint::FLOATING:
      return kPfxUrdfFloating;
    case urdf::Joint::PLANAR:
      return kPfxUrdfPlanar;
    default:
      return kPfxUrdfFixed;
  }
}

// A right-handed frame whose X axis is `x` (unit).
Mat3 frameFromAxis(const Vec3& x) {
  Vec3 other = Vec3::UnitX();
  if (std::abs(x.y()) < std::abs(x[0]) && std::abs(x.y()) <= std::abs(x.z())) {
    other = Vec3::UnitY();
  } else if (std::abs(x.z()) < std::abs(x[0])) {
    other = Vec3::UnitZ();
  }
  const Vec3 y = (other - x * x.dot(other)).normalized();
  Mat3 frame;
  frame << x, y, x.cross(y);
  return frame;
}

// Init parameters of a joint whose frame (world, columns X, Y, Z) is given at `anchor`.
template <typename Param>
Param atJointFrame(const Vec3& anchor, const Mat3& frame) {
  Param param;
  param.anchorPoint = anchor.cast<PfxFloat>();
  param.enableJointFrame = true;
  param.jointFrame = frame.cast<PfxFloat>();
  return param;
}

enum class Role { kBody, kFrame, kHelper };

struct LinkNode {
  urdf::LinkConstSharedPtr link;
  int parentJoint = -1;
  std::vector<int> childJoints;  // in file order
  Pose pose = Pose::Identity();  // in the world, every joint at zero
  bool massless = true;
  double mass = 0;
  Vec3 centerOfMass = Vec3::Zero();  // link frame
  Mat3 inertia = Mat3::Zero();       // link frame, about the centre of mass
  int group = -1;
};

struct JointNode {
  urdf::JointConstSharedPtr joint;
  PfxUrdfJointType type = kPfxUrdfFixed;
  int parent = -1;
  int child = -1;
  Vec3 axis = Vec3::UnitX();   // world, unit
  Vec3 origin = Vec3::Zero();  // world
  // What it became.
  int worldJoint = -1;
  PfxUInt32 worldAxis = 0;
  double sign = 1;
  bool collapsed = false;
};

// Links that move as one: one body, or a frame or helper without a body.
struct Group {
  std::vector<int> links;  // the top link first
  int parentJoint = -1;    // the joint into the top link
  int parentGroup = -1;
  std::vector<int> childJoints;  // joints to other groups
  double mass = 0;
  Role role = Role::kBody;
  int body = -1;   // the body carrying the group's links
  int chain = -1;  // a helper: its chain, and how many of the chain's joints turn it
  int chainDepth = 0;
  bool light = false;  // a massless link given a light body (makeLightBody)
};

// Revolute joints through massless helper links, meeting at one point.
struct Chain {
  std::vector<int> joints;  // parent side first
  int parentGroup = -1;
  int childGroup = -1;
  Mat3 frame = Mat3::Identity();  // world joint frame
  int worldJoint = -1;
};

struct BodyNode {
  int group = -1;
  int parentBody = -1;  // across a joint; -1 for a root or a floating body
  bool fixed = false;
  double mass = 0;
  Vec3 centerOfMass = Vec3::Zero();  // world
  Mat3 inertia = Mat3::Zero();       // world, about the centre of mass
  Pose pose = Pose::Identity();      // top link's orientation, at the centre of mass
};

class UrdfBuilder {
 public:
  UrdfBuilder(const urdf::ModelInterface& model, const PfxUrdfDocumentOrder& order,
              const std::string& urdfFolder, const PfxUrdfLoadParam& param, PfxFloat subStepTime,
              PfxUrdfBuild& build, PfxUrdfError& error)
      : m_model(model),
        m_order(order),
        m_folder(urdfFolder),
        m_param(param),
        m_subStepTime(subStepTime),
        m_build(build),
        m_error(error) {}

  PfxInt32 run() {
    if (collect() != PFX_OK) return m_error.code;
    place();
    group();
    if (assignRoles() != PFX_OK || makeBodies() != PFX_OK || makeShapes() != PFX_OK ||
        makeJoints() != PFX_OK || makeCouplings() != PFX_OK) {
      return m_error.code;
    }
    keepLightBodiesNeighboursApart();
    describeModel();
    return PFX_OK;
  }

 private:
  PfxInt32 fail(PfxInt32 code, const std::string& text) {
    m_error.code = code;
    m_error.text = text;
    return code;
  }
  void warn(const std::string& text) { m_build.model.warnings.push_back(text); }
  const std::string& linkName(int link) const { return m_links[link].link->name; }
  const std::string& jointName(int joint) const { return m_joints[joint].joint->name; }

  PfxInt32 collect() {
    std::map<std::string, int> linkIndex;
    for (const std::string& name : m_order.links) {
      LinkNode node;
      node.link = m_model.getLink(name);
      if (!node.link)
        return fail(PFX_ERR_INVALID_VALUE, "link " + pfxUrdfQuoted(name) + ": not parsed");
      linkIndex[name] = static_cast<int>(m_links.size());
      m_links.push_back(node);
    }
    for (const std::string& name : m_order.joints) {
      JointNode node;
      node.joint = m_model.getJoint(name);
      if (!node.joint)
        return fail(PFX_ERR_INVALID_VALUE, "joint " + pfxUrdfQuoted(name) + ": not parsed");
      node.type = jointType(node.joint->type);
      node.parent = linkIndex.at(node.joint->parent_link_name);
      node.child = linkIndex.at(node.joint->child_link_name);
      const int index = static_cast<int>(m_joints.size());
      m_links[node.child].parentJoint = index;
      m_links[node.parent].childJoints.push_back(index);
      m_joints.push_back(node);
    }
    for (int i = 0; i < static_cast<int>(m_links.size()); ++i) {
      if (m_links[i].parentJoint < 0) m_root = i;
    }
    for (LinkNode& node : m_links) {
      const urdf::InertialSharedPtr& inertial = node.link->inertial;
      if (!inertial || !(inertial->mass > 0)) continue;
      node.massless = false;
      node.mass = inertial->mass;
      const Pose frame = toPose(inertial->origin);
      Mat3 tensor;
      tensor << inertial->ixx, inertial->ixy, inertial->ixz, inertial->ixy, inertial->iyy,
          inertial->iyz, inertial->ixz, inertial->iyz, inertial->izz;
      node.centerOfMass = frame.translation();
      node.inertia = frame.linear() * tensor * frame.linear().transpose();
      const Eigen::SelfAdjointEigenSolver<Mat3> eigen(tensor, Eigen::EigenvaluesOnly);
      const Vec3 moments = eigen.eigenvalues();  // ascending
      if (moments[0] + moments[1] < moments[2] * (1 - 1e-6)) {
        warn("link " + pfxUrdfQuoted(node.link->name) + ": principal moments of inertia " +
             pfxUrdfNumber(moments[0]) + ", " + pfxUrdfNumber(moments[1]) + ", " +
             pfxUrdfNumber(moments[2]) +
             " break the triangle inequality (no solid body has them); kept as given");
      }
    }
    return PFX_OK;
  }

  // Link poses and joint axes in the world with every joint at zero, parents before
  // children (m_treeOrder).
  void place() {
    Pose root = Pose::Identity();
    root.linear() = m_param.rootOrientation.cast<double>().normalized().toRotationMatrix();
    root.translation() = m_param.rootPosition.cast<double>();
    m_links[m_root].pose = root;
    std::vector<int> stack{m_root};
    while (!stack.empty()) {
      const int link = stack.back();
      stack.pop_back();
      m_treeOrder.push_back(link);
      const std::vector<int>& children = m_links[link].childJoints;
      for (auto it = children.rbegin(); it != children.rend(); ++it) {
        JointNode& joint = m_joints[*it];
        m_links[joint.child].pose =
            m_links[link].pose * toPose(joint.joint->parent_to_joint_origin_transform);
        const Pose& frame = m_links[joint.child].pose;
        const urdf::Vector3& axis = joint.joint->axis;
        joint.origin = frame.translation();
        // Fixed and floating joints have no axis; their frame follows the child link's.
        const Vec3 local(axis.x, axis.y, axis.z);
        joint.axis = frame.linear() * (local.norm() > 0 ? Vec3(local.normalized()) : Vec3::UnitX());
        stack.push_back(joint.child);
      }
    }
  }

  // Fixed joints join links into groups; a link without mass always joins its neighbour.
  void group() {
    for (const int link : m_treeOrder) {
      LinkNode& node = m_links[link];
      if (node.parentJoint < 0) {
        node.group = newGroup(link, -1, -1);
        m_groups[node.group].mass += node.mass;
        continue;
      }
      const JointNode& joint = m_joints[node.parentJoint];
      const LinkNode& parent = m_links[joint.parent];
      const bool lump = joint.type == kPfxUrdfFixed &&
                        (m_param.lumpFixedJoints || node.massless || parent.massless);
      if (lump) {
        node.group = parent.group;
        m_groups[node.group].links.push_back(link);
        if (!m_param.lumpFixedJoints) {
          warn("joint " + pfxUrdfQuoted(joint.joint->name) +
               ": lumped although lumpFixedJoints is off, " + "since link " +
               pfxUrdfQuoted(node.massless ? node.link->name : parent.link->name) +
               " has no mass to be a body of its own");
        }
      } else {
        node.group = newGroup(link, node.parentJoint, parent.group);
        m_groups[parent.group].childJoints.push_back(node.parentJoint);
      }
      m_groups[node.group].mass += node.mass;
    }
  }

  int newGroup(int link, int parentJoint, int parentGroup) {
    Group g;
    g.links.push_back(link);
    g.parentJoint = parentJoint;
    g.parentGroup = parentGroup;
    m_groups.push_back(g);
    return static_cast<int>(m_groups.size()) - 1;
  }

  PfxInt32 assignRoles() {
    m_fixedRoot = m_param.fixedBase || linkName(m_root) == "world";
    for (int g = 0; g < static_cast<int>(m_groups.size()); ++g) {
      Group& group = m_groups[g];
      if (group.parentJoint < 0) {
        if (group.mass == 0 && !m_fixedRoot) {
          m_fixedRoot = true;
          warn("link " + pfxUrdfQuoted(linkName(m_root)) +
               ": the root link has no mass, so it cannot float; the robot is loaded with a "
               "fixed base (give the root an <inertial> to let it float)");
        }
        group.role = Role::kBody;
        continue;
      }
      if (group.mass > 0) {
        group.role = Role::kBody;
        continue;
      }
      if (group.chain >= 0) continue;  // a helper of a chain found above it
      const JointNode& joint = m_joints[group.parentJoint];
      if (group.childJoints.empty()) {
        group.role = Role::kFrame;
        for (const int link : group.links) {
          warn("link " + pfxUrdfQuoted(linkName(link)) +
               ": no mass and no child joint; carried as a frame by the body of link " +
               pfxUrdfQuoted(linkName(joint.parent)) + ", with joint " +
               pfxUrdfQuoted(joint.joint->name) + " held at zero");
        }
        continue;
      }
      if (!m_param.collapseMasslessChains) {
        return fail(PFX_ERR_INVALID_VALUE,
                    "link " + pfxUrdfQuoted(linkName(group.links[0])) +
                        ": no mass (no <inertial>, or mass 0) and joints below it, "
                        "and collapseMasslessChains is off");
      }
      std::string whyNotCollapsed;
      if (!makeChain(g, whyNotCollapsed)) makeLightBody(g, whyNotCollapsed);
    }
    for (Group& group : m_groups) {
      for (const int link : group.links) {
        if (group.role == Role::kBody && m_links[link].massless &&
            m_links[link].childJoints.empty()) {
          warn("link " + pfxUrdfQuoted(linkName(link)) +
               ": no mass and no child joint; a frame of the body of link " +
               pfxUrdfQuoted(linkName(group.links[0])));
        }
      }
      if (group.role == Role::kHelper) {
        for (const int link : group.links) {
          if (!collisionsOf(link).empty()) {
            warn("link " + pfxUrdfQuoted(linkName(link)) +
                 ": collision geometry left out, since the link has no mass and no body (it "
                 "is a helper of a collapsed joint)");
          }
        }
      }
    }
    return PFX_OK;
  }

  // Group `g` has no mass and joints below it. When it is the first helper of a chain of two
  // or three revolute joints meeting at one point with perpendicular axes, makes the chain
  // and returns true; else says why not.
  bool makeChain(int g, std::string& whyNot) {
    Chain chain;
    chain.parentGroup = m_groups[g].parentGroup;
    chain.joints.push_back(m_groups[g].parentJoint);
    std::vector<int> helpers{g};
    int current = g;
    for (;;) {
      const Group& group = m_groups[current];
      if (!isRotational(m_joints[chain.joints.back()].type) || group.childJoints.size() != 1 ||
          !isRotational(m_joints[group.childJoints[0]].type) || chain.joints.size() == 3) {
        whyNot = "it is not a helper between two or three revolute joints meeting at one point";
        return false;
      }
      chain.joints.push_back(group.childJoints[0]);
      const int next = m_links[m_joints[group.childJoints[0]].child].group;
      if (m_groups[next].mass > 0) {
        chain.childGroup = next;
        break;
      }
      helpers.push_back(next);
      current = next;
    }
    const JointNode& first = m_joints[chain.joints[0]];
    for (std::size_t i = 1; i < chain.joints.size(); ++i) {
      const JointNode& joint = m_joints[chain.joints[i]];
      const double distance = (joint.origin - first.origin).norm();
      if (distance > kCoincidentDistance) {
        whyNot = "joints " + pfxUrdfQuoted(first.joint->name) + " and " +
                 pfxUrdfQuoted(joint.joint->name) + " do not meet at one point (" +
                 pfxUrdfNumber(distance) + " m apart)";
        return false;
      }
      for (std::size_t k = 0; k < i; ++k) {
        const JointNode& other = m_joints[chain.joints[k]];
        if (std::abs(joint.axis.dot(other.axis)) > kPerpendicularCosine) {
          whyNot = "the axes of joints " + pfxUrdfQuoted(other.joint->name) + " and " +
                   pfxUrdfQuoted(joint.joint->name) + " are not perpendicular";
          return false;
        }
      }
    }
    // The frame: the first axis on Y, the second on +-Z, the third (or the cross product of
    // the two) on X.
    const Vec3& w0 = m_joints[chain.joints[0]].axis;
    const Vec3& w1 = m_joints[chain.joints[1]].axis;
    const Vec3 x =
        chain.joints.size() == 3 ? m_joints[chain.joints[2]].axis : Vec3(w0.cross(w1).normalized());
    const Vec3 y = (w0 - x * x.dot(w0)).normalized();
    chain.frame << x, y, x.cross(y);
    const int index = static_cast<int>(m_chains.size());
    m_chains.push_back(chain);
    for (std::size_t depth = 0; depth < helpers.size(); ++depth) {
      Group& helper = m_groups[helpers[depth]];
      helper.role = Role::kHelper;
      helper.chain = index;
      helper.chainDepth = static_cast<int>(depth) + 1;
    }
    return true;
  }

  // Makes massless group g, which cannot collapse, a light body that carries its joints as
  // the URDF places them: a tenth of the mass of its lighter massive neighbour (the body
  // above it or a body right below it), with that neighbour's smallest radius of gyration
  // as an even inertia, at the centre of its joints' origins.
  void makeLightBody(int g, const std::string& whyNotCollapsed) {
    Group& group = m_groups[g];
    std::vector<int> neighbours{group.parentGroup};
    for (const int j : group.childJoints) neighbours.push_back(m_links[m_joints[j].child].group);
    int lighter = -1;
    for (const int n : neighbours) {
      if (m_groups[n].mass > 0 && (lighter < 0 || m_groups[n].mass < m_groups[lighter].mass)) {
        lighter = n;
      }
    }
    double mass = kLightBodyFallbackMass;
    double gyration = kLightBodyFallbackGyration;
    if (lighter >= 0) {
      mass = kLightBodyMassFraction * m_groups[lighter].mass;
      double squared = std::numeric_limits<double>::max();
      for (const int link : m_groups[lighter].links) {
        const LinkNode& node = m_links[link];
        if (node.mass <= 0) continue;
        const Eigen::SelfAdjointEigenSolver<Mat3> eigen(node.inertia, Eigen::EigenvaluesOnly);
        squared = std::min(squared, std::max(eigen.eigenvalues()[0], 0.0) / node.mass);
      }
      gyration = std::sqrt(squared);
    }
    const int top = group.links[0];
    LinkNode& node = m_links[top];
    const Pose toLink = node.pose.inverse();
    Vec3 center = Vec3::Zero();  // the joint into the link is at its frame's origin
    for (const int j : group.childJoints) center += toLink * m_joints[j].origin;
    center /= double(group.childJoints.size() + 1);
    node.massless = false;
    node.mass = mass;
    node.centerOfMass = center;
    node.inertia = mass * gyration * gyration * Mat3::Identity();
    group.mass = mass;
    group.role = Role::kBody;
    group.light = true;
    warn("link " + pfxUrdfQuoted(linkName(top)) + ": no mass, and " + whyNotCollapsed +
         ", so its joints cannot become one; loaded as a light body of " + pfxUrdfNumber(mass) +
         " kg" +
         (lighter >= 0 ? " (a tenth of the mass of link " +
                             pfxUrdfQuoted(linkName(m_groups[lighter].links[0])) + ")"
                       : std::string()) +
         " so that each of its joints turns where the URDF puts it");
  }

  PfxInt32 makeBodies() {
    for (int g = 0; g < static_cast<int>(m_groups.size()); ++g) {
      Group& group = m_groups[g];
      if (group.role == Role::kFrame) {
        group.body = m_groups[group.parentGroup].body;
        continue;
      }
      if (group.role == Role::kHelper) {
        group.body = m_groups[m_chains[group.chain].parentGroup].body;
        continue;
      }
      BodyNode body;
      body.group = g;
      body.fixed = group.parentJoint < 0 && m_fixedRoot;
      const Pose& top = m_links[group.links[0]].pose;
      Vec3 weighted = Vec3::Zero();
      for (const int link : group.links) {
        const LinkNode& node = m_links[link];
        body.mass += node.mass;
        weighted += node.mass * (node.pose * node.centerOfMass);
      }
      body.centerOfMass = body.mass > 0 ? Vec3(weighted / body.mass) : top.translation();
      for (const int link : group.links) {
        const LinkNode& node = m_links[link];
        const Vec3 d = node.pose * node.centerOfMass - body.centerOfMass;
        body.inertia += node.pose.linear() * node.inertia * node.pose.linear().transpose() +
                        node.mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
      }
      body.pose.linear() = top.linear();
      body.pose.translation() = body.centerOfMass;
      if (group.parentJoint >= 0 && m_joints[group.parentJoint].type != kPfxUrdfFloating) {
        body.parentBody = carrierOfParent(g);
      }
      group.body = static_cast<int>(m_bodies.size());
      m_bodies.push_back(body);

      PfxUrdfBuildBody out;
      out.state.reset();
      out.state.setPosition(body.pose.translation().cast<PfxFloat>());
      out.state.setOrientation(toQuat(body.pose.linear()));
      out.state.setMotionType(body.fixed ? kPfxMotionTypeFixed : kPfxMotionTypeActive);
      out.state.setRigidBodyId(static_cast<PfxUInt32>(group.body));
      out.body.reset();
      out.body.setFriction(m_param.friction);
      out.body.setRestitution(m_param.restitution);
      if (!body.fixed) {
        Mat3 local = top.linear().transpose() * body.inertia * top.linear();
        local = 0.5 * (local + local.transpose());
        out.body.setMass(static_cast<PfxFloat>(body.mass));
        out.body.setInertia(local.cast<PfxFloat>());
        if (const char* problem = out.body.problem()) {
          const Eigen::SelfAdjointEigenSolver<Mat3> moments(local, Eigen::EigenvaluesOnly);
          return fail(PFX_ERR_INVALID_VALUE,
                      "link " + pfxUrdfQuoted(linkName(group.links[0])) + ": " + problem +
                          " (mass " + pfxUrdfNumber(body.mass) + " kg, principal moments " +
                          pfxUrdfNumber(moments.eigenvalues()[0]) + ", " +
                          pfxUrdfNumber(moments.eigenvalues()[1]) + ", " +
                          pfxUrdfNumber(moments.eigenvalues()[2]) + " kg m^2)");
        }
      }
      m_build.bodies.push_back(out);
    }
    return PFX_OK;
  }

  // The URDF joins the bodies around a light body through one link, as a joint joins two:
  // none of them collide with each other.
  void keepLightBodiesNeighboursApart() {
    for (const Group& group : m_groups) {
      if (!group.light) continue;
      std::vector<int> around{m_groups[group.parentGroup].body};
      for (const int j : group.childJoints) {
        around.push_back(m_groups[m_links[m_joints[j].child].group].body);
      }
      for (std::size_t a = 0; a < around.size(); ++a) {
        for (std::size_t b = a + 1; b < around.size(); ++b) {
          if (around[a] != around[b]) {
            m_build.noCollision.emplace_back(PfxUInt32(around[a]), PfxUInt32(around[b]));
          }
        }
      }
    }
  }

  // The body on the parent side of group g's joint (a chain's parent for its child).
  int carrierOfParent(int g) const {
    for (const Chain& chain : m_chains) {
      if (chain.childGroup == g) return m_groups[chain.parentGroup].body;
    }
    return m_groups[m_groups[g].parentGroup].body;
  }

  PfxInt32 makeShapes() {
    std::vector<std::vector<PfxInt32>>& shapeLinks = m_build.model.shapeLinks;
    shapeLinks.assign(m_build.bodies.size(), std::vector<PfxInt32>());
    for (const int link : m_treeOrder) {
      const Group& group = m_groups[m_links[link].group];
      if (group.role == Role::kHelper) continue;
      const BodyNode& body = m_bodies[group.body];
      const Pose linkInBody = body.pose.inverse() * m_links[link].pose;
      for (const PfxUrdfCollision& collision : collisionsOf(link)) {
        const Pose shapePose = linkInBody * toPose(collision.origin);
        if (const PfxInt32 err =
                addShape(link, collision, shapePose, body.fixed, m_build.bodies[group.body].shapes);
            err != PFX_OK) {
          return err;
        }
        shapeLinks[group.body].resize(m_build.bodies[group.body].shapes.size(), link);
      }
    }
    for (std::size_t b = 0; b < m_build.bodies.size(); ++b) {
      PfxUrdfBuildBody& out = m_build.bodies[b];
      const std::string& top = linkName(m_groups[m_bodies[b].group].links[0]);
      if (out.shapes.size() > PFX_MAX_SHAPES_PER_COLLIDABLE) {
        return fail(PFX_ERR_OUT_OF_RANGE,
                    "link " + pfxUrdfQuoted(top) + ": its body has " +
                        std::to_string(out.shapes.size()) + " collision shapes, more than the " +
                        std::to_string(PFX_MAX_SHAPES_PER_COLLIDABLE) + " a body holds");
      }
      if (out.shapes.empty()) {
        out.shapes.push_back(pfxMakeShape(PfxSphere(kUrdfPlaceholderRadius)));
        shapeLinks[b].push_back(-1);
        out.state.setContactFilterSelf(0);
        out.state.setContactFilterTarget(0);
      } else if (m_param.disableSelfCollision) {
        out.state.setContactFilterSelf(m_param.selfCollisionGroup);
        out.state.setContactFilterTarget(~m_param.selfCollisionGroup);
      }
      for (const PfxShape& shape : out.shapes) {
        if (shape.validate() != PFX_OK) {
          return fail(PFX_ERR_INVALID_VALUE,
                      "link " + pfxUrdfQuoted(top) + ": a collision shape is invalid");
        }
      }
    }
    return PFX_OK;
  }

  const std::vector<PfxUrdfCollision>& collisionsOf(int link) const {
    static const std::vector<PfxUrdfCollision> kNone;
    const auto found = m_order.collisions.find(linkName(link));
    return found == m_order.collisions.end() ? kNone : found->second;
  }

  PfxInt32 addShape(int link, const PfxUrdfCollision& collision, const Pose& pose, bool fixedBody,
                    std::vector<PfxShape>& shapes) {
    const std::string subject = "link " + pfxUrdfQuoted(linkName(link)) + ": ";
    const std::string& geometry = collision.geometry;
    Pose placed = pose;
    PfxShape shape;
    // URDF's cylinders and capsules lie along Z, the shapes' along X.
    const Mat3 zToX = Eigen::AngleAxisd(-PFX_PI / 2, Vec3::UnitY()).toRotationMatrix();
    if (geometry == "sphere") {
      if (!(collision.radius > 0)) {
        return fail(PFX_ERR_DEGENERATE, subject + "sphere radius is not positive");
      }
      shape = pfxMakeShape(PfxSphere(static_cast<PfxFloat>(collision.radius)));
    } else if (geometry == "box") {
      const Vec3 size(collision.size[0], collision.size[1], collision.size[2]);
      if (!(size.minCoeff() > 0)) {
        return fail(PFX_ERR_DEGENERATE, subject + "box size is not positive");
      }
      shape = pfxMakeShape(PfxBox(PfxVector3(size.cast<PfxFloat>() / 2)));
    } else if (geometry == "cylinder") {
      if (!(collision.radius > 0 && collision.length > 0)) {
        return fail(PFX_ERR_DEGENERATE, subject + "cylinder radius or length is not positive");
      }
      shape = pfxMakeShape(PfxCylinder(static_cast<PfxFloat>(collision.length / 2),
                                       static_cast<PfxFloat>(collision.radius)));
      placed.linear() = pose.linear() * zToX;
    } else if (geometry == "capsule") {
      // `length` is the cylinder part between the centres of the two hemispheres, as Bullet's
      // URDF importer reads it: the capsule is length + 2 radius long; length 0 is a sphere.
      if (!(collision.radius > 0 && collision.length >= 0)) {
        return fail(PFX_ERR_DEGENERATE,
                    subject + "capsule radius is not positive or its length is negative");
      }
      shape = pfxMakeShape(PfxCapsule(static_cast<PfxFloat>(collision.length / 2),
                                      static_cast<PfxFloat>(collision.radius)));
      placed.linear() = pose.linear() * zToX;
    } else if (geometry == "mesh") {
      bool missing = false;
      if (const PfxInt32 err = makeMeshShape(subject, collision, fixedBody, shape, missing);
          err != PFX_OK) {
        return err;
      }
      if (missing) return PFX_OK;
    } else {
      warn(subject + "<collision> on line " + std::to_string(collision.line) + " left out: " +
           (geometry.empty() ? std::string("it has no geometry")
                             : "unknown geometry <" + geometry + ">") +
           " (pfx knows box, sphere, cylinder, capsule and mesh)");
      return PFX_OK;
    }
    shape.setOffsetPosition(placed.translation().cast<PfxFloat>());
    shape.setOffsetOrientation(toQuat(placed.linear()));
    shapes.push_back(shape);
    return PFX_OK;
  }

  PfxInt32 makeMeshShape(const std::string& subject, const PfxUrdfCollision& mesh, bool fixedBody,
                         PfxShape& shape, bool& missing) {
    const Vec3 scale(mesh.scale[0], mesh.scale[1], mesh.scale[2]);
    if (!scale.allFinite() || !(scale.minCoeff() > 0)) {
      return fail(PFX_ERR_INVALID_VALUE, subject + "mesh " + pfxUrdfQuoted(mesh.filename) +
                                             ": scale must be positive and finite");
    }
    std::string path, searched;
    if (mesh.filename.empty() ||
        !pfxResolveUrdfMeshUri(mesh.filename, m_folder, m_param.packageRoot, path, searched)) {
      const std::string text =
          subject +
          (mesh.filename.empty()
               ? "<mesh> on line " + std::to_string(mesh.line) + " has no filename"
               : "mesh " + pfxUrdfQuoted(mesh.filename) + " not found (" + searched + ")");
      if (!m_param.allowMissingMeshes) return fail(PFX_ERR_INVALID_VALUE, text);
      warn(text + "; left out");
      missing = true;
      return PFX_OK;
    }
    std::ostringstream key;
    key << path << ' ' << scale.transpose() << ' ' << fixedBody;
    if (const auto cached = m_meshShapes.find(key.str()); cached != m_meshShapes.end()) {
      shape = cached->second;
      return PFX_OK;
    }
    PfxTriangleMesh triangles;
    std::string reason;
    if (const PfxInt32 err = pfxLoadMeshFile(path, scale.cast<PfxFloat>(), triangles, &reason);
        err != PFX_OK) {
      return fail(err, subject + "mesh " + pfxUrdfQuoted(mesh.filename) + ": " + reason);
    }
    shape.reset();
    if (fixedBody) {
      std::unique_ptr<PfxLargeTriMesh, PfxLargeTriMeshRelease> large(pfxNewLargeTriMesh());
      if (!large) return fail(PFX_ERR_OUT_OF_BUFFER, subject + "out of memory");
      if (const PfxInt32 err =
              pfxCreateLargeTriMeshFromMesh(triangles, PFX_MESH_FLAG_USE_BVH, *large, &reason);
          err != PFX_OK) {
        return fail(err, subject + "mesh " + pfxUrdfQuoted(mesh.filename) + ": " + reason);
      }
      shape.setLargeTriMesh(large.get());
      m_build.model.largeMeshes.push_back(std::move(large));
    } else {
      std::unique_ptr<PfxConvexMesh, PfxConvexMeshRelease> hull(pfxNewConvexMesh());
      if (!hull) return fail(PFX_ERR_OUT_OF_BUFFER, subject + "out of memory");
      if (const PfxInt32 err = pfxCreateConvexHull(triangles, *hull, &reason); err != PFX_OK) {
        return fail(err, subject + "mesh " + pfxUrdfQuoted(mesh.filename) + ": " + reason);
      }
      shape.setConvexMesh(hull.get());
      m_build.model.convexMeshes.push_back(std::move(hull));
    }
    m_meshShapes[key.str()] = shape;
    return PFX_OK;
  }

  // Limits of a rotation axis as the hinge can hold them: its angle wraps at +-pi.
  void rotationLimits(int j, double& lower, double& upper) {
    lower = m_joints[j].joint->limits->lower;
    upper = m_joints[j].joint->limits->upper;
    if (lower < -PFX_PI || upper > PFX_PI) {
      warn("joint " + pfxUrdfQuoted(jointName(j)) + ": limits [" + pfxUrdfNumber(lower) + ", " +
           pfxUrdfNumber(upper) + "] cut to [-pi, pi], where the joint's angle wraps");
      lower = std::max(lower, double(-PFX_PI));
      upper = std::min(upper, double(PFX_PI));
    }
  }

  // Sets axis `axis` of `joint` from URDF joint j: its limits (through `sign`), damping and
  // friction.
  void setAxis(PfxJoint& joint, PfxUInt32 axis, int j, double sign) {
    JointNode& node = m_joints[j];
    PfxJointConstraint& c = joint.m_constraints[axis];
    if (node.type == kPfxUrdfContinuous) {
      c.m_lock = kPfxJointLockFree;
    } else {
      double lower = node.joint->limits->lower, upper = node.joint->limits->upper;
      if (node.type == kPfxUrdfRevolute) rotationLimits(j, lower, upper);
      c.m_lock = kPfxJointLockLimit;
      c.m_movableLowerLimit = static_cast<PfxFloat>(sign > 0 ? lower : -upper);
      c.m_movableUpperLimit = static_cast<PfxFloat>(sign > 0 ? upper : -lower);
    }
    c.m_damping = 0;
    c.m_friction = 0;
    if (const urdf::JointDynamicsSharedPtr& dynamics = node.joint->dynamics) {
      c.m_friction = static_cast<PfxFloat>(dynamics->friction);
      if (dynamics->damping > 0) {
        const double moved = movedInertia(j);
        c.m_damping = static_cast<PfxFloat>(
            moved > 0 ? 1 - std::exp(-dynamics->damping * m_subStepTime / moved) : 0);
      }
    }
    node.worldAxis = axis;
    node.sign = sign;
  }

  // What joint j moves when it alone moves: the inertia about its axis (or the mass along
  // it) of the child's subtree against that of the rest of the robot, in series.
  double movedInertia(int j) const {
    const JointNode& node = m_joints[j];
    const int childBody = m_groups[childGroupOf(j)].body;
    std::vector<char> inSubtree(m_bodies.size(), 0);
    for (std::size_t b = 0; b < m_bodies.size(); ++b) {
      for (int up = static_cast<int>(b); up >= 0; up = m_bodies[up].parentBody) {
        if (up == childBody) {
          inSubtree[b] = 1;
          break;
        }
      }
    }
    int top = childBody;
    while (m_bodies[top].parentBody >= 0) top = m_bodies[top].parentBody;
    const bool groundedRest = m_bodies[top].fixed;
    double child = 0, rest = 0;
    for (std::size_t b = 0; b < m_bodies.size(); ++b) {
      int root = static_cast<int>(b);
      while (m_bodies[root].parentBody >= 0) root = m_bodies[root].parentBody;
      if (root != top) continue;
      const BodyNode& body = m_bodies[b];
      double share = body.mass;
      if (isRotational(node.type)) {
        share = node.axis.dot(body.inertia * node.axis) +
                body.mass * node.axis.cross(body.centerOfMass - node.origin).squaredNorm();
      }
      (inSubtree[b] ? child : rest) += body.fixed ? 0 : share;
    }
    if (groundedRest || rest <= 0) return child;
    return child > 0 ? 1 / (1 / child + 1 / rest) : 0;
  }

  // The group below joint j: its child's, or for a chain joint the chain's massive end.
  int childGroupOf(int j) const {
    for (const Chain& chain : m_chains) {
      if (std::find(chain.joints.begin(), chain.joints.end(), j) != chain.joints.end()) {
        return chain.childGroup;
      }
    }
    return m_links[m_joints[j].child].group;
  }

  PfxInt32 addJoint(const PfxJoint& joint, int j) {
    if (const PfxInt32 err = pfxCheckJoint(joint); err != PFX_OK) {
      return fail(err, "joint " + pfxUrdfQuoted(jointName(j)) + ": cannot be built (" +
                           pfxErrorString(err) + ")");
    }
    m_build.joints.push_back(joint);
    return PFX_OK;
  }

  PfxInt32 makeJoints() {
    for (int c = 0; c < static_cast<int>(m_chains.size()); ++c) {
      if (const PfxInt32 err = makeChainJoint(m_chains[c]); err != PFX_OK) return err;
    }
    for (int j = 0; j < static_cast<int>(m_joints.size()); ++j) {
      JointNode& node = m_joints[j];
      const Group& childGroup = m_groups[m_links[node.child].group];
      const Group& parentGroup = m_groups[m_links[node.parent].group];
      if (node.collapsed || childGroup.parentJoint != j || childGroup.role != Role::kBody ||
          node.type == kPfxUrdfFloating) {
        continue;  // collapsed, lumped, held at zero as a frame, or free
      }
      const PfxRigidState& a = m_build.bodies[parentGroup.body].state;
      const PfxRigidState& b = m_build.bodies[childGroup.body].state;
      const Mat3 frame = frameFromAxis(node.axis);
      PfxJoint joint;
      PfxInt32 err = PFX_OK;
      if (node.type == kPfxUrdfFixed || node.type == kPfxUrdfPlanar) {
        err = pfxInitializeFixedJoint(joint, a, b,
                                      atJointFrame<PfxFixedJointInitParam>(node.origin, frame));
        if (err == PFX_OK && node.type == kPfxUrdfPlanar) {
          // Normal on X: slides along Y and Z, turns about X.
          joint.m_type = kPfxJointCustom;
          for (const PfxUInt32 axis : {kPfxJointAxisY, kPfxJointAxisZ, kPfxJointAxisTwist}) {
            joint.m_constraints[axis].m_lock = kPfxJointLockFree;
          }
        }
      } else if (isRotational(node.type)) {
        err = pfxInitializeHingeJoint(joint, a, b,
                                      atJointFrame<PfxHingeJointInitParam>(node.origin, frame));
        if (err == PFX_OK) setAxis(joint, kPfxJointAxisTwist, j, 1);
      } else {
        err = pfxInitializeSliderJoint(joint, a, b,
                                       atJointFrame<PfxSliderJointInitParam>(node.origin, frame));
        if (err == PFX_OK) setAxis(joint, kPfxJointAxisX, j, 1);
      }
      if (err != PFX_OK) {
        return fail(err, "joint " + pfxUrdfQuoted(jointName(j)) + ": cannot be built (" +
                             pfxErrorString(err) + ")");
      }
      if (hasCoordinate(node.type)) node.worldJoint = static_cast<int>(m_build.joints.size());
      if (const PfxInt32 e = addJoint(joint, j); e != PFX_OK) return e;
    }
    return PFX_OK;
  }

  PfxInt32 makeChainJoint(Chain& chain) {
    const int first = chain.joints[0];
    const PfxRigidState& a = m_build.bodies[m_groups[chain.parentGroup].body].state;
    const PfxRigidState& b = m_build.bodies[m_groups[chain.childGroup].body].state;
    PfxJoint joint;
    const Vec3& anchor = m_joints[first].origin;
    const PfxInt32 err =
        chain.joints.size() == 2
            ? pfxInitializeUniversalJoint(
                  joint, a, b, atJointFrame<PfxUniversalJointInitParam>(anchor, chain.frame))
            : pfxInitializeBallJoint(joint, a, b,
                                     atJointFrame<PfxBallJointInitParam>(anchor, chain.frame));
    if (err != PFX_OK) {
      return fail(err, "joint " + pfxUrdfQuoted(jointName(first)) + ": cannot be built (" +
                           pfxErrorString(err) + ")");
    }
    // Euler angles along the chain's axes: each URDF joint's limits bound its own turn.
    joint.m_rotation = kPfxJointRotationEulerYZX;
    const PfxUInt32 axes[3] = {kPfxJointAxisSwing1, kPfxJointAxisSwing2, kPfxJointAxisTwist};
    for (std::size_t i = 0; i < chain.joints.size(); ++i) {
      const int j = chain.joints[i];
      const double sign = i == 1 && m_joints[j].axis.dot(chain.frame.col(2)) < 0 ? -1 : 1;
      setAxis(joint, axes[i], j, sign);
      m_joints[j].collapsed = true;
      m_joints[j].worldJoint = static_cast<int>(m_build.joints.size());
    }
    chain.worldJoint = static_cast<int>(m_build.joints.size());
    return addJoint(joint, first);
  }

  PfxInt32 makeCouplings() {
    std::map<std::string, int> byName;
    for (int j = 0; j < static_cast<int>(m_joints.size()); ++j) byName[jointName(j)] = j;
    for (int j = 0; j < static_cast<int>(m_joints.size()); ++j) {
      const urdf::JointMimicSharedPtr& mimic = m_joints[j].joint->mimic;
      if (!mimic) continue;
      const int leader = byName.at(mimic->joint_name);
      const JointNode& f = m_joints[j];
      const JointNode& l = m_joints[leader];
      if (f.worldJoint < 0 || l.worldJoint < 0) {
        warn("joint " + pfxUrdfQuoted(jointName(j)) + ": <mimic> of " +
             pfxUrdfQuoted(jointName(leader)) + " left out, since " +
             pfxUrdfQuoted(jointName(f.worldJoint < 0 ? j : leader)) + " is held at zero");
        continue;
      }
      // URDF: qf = m ql + o, with q = sign c for both; so cf = (m sl / sf) cl + o / sf.
      PfxJointCoupling coupling;
      coupling.reset();
      coupling.m_leaderJointId = static_cast<PfxUInt32>(l.worldJoint);
      coupling.m_followerJointId = static_cast<PfxUInt32>(f.worldJoint);
      coupling.m_leaderAxis = static_cast<PfxUInt8>(l.worldAxis);
      coupling.m_followerAxis = static_cast<PfxUInt8>(f.worldAxis);
      coupling.m_multiplier = static_cast<PfxFloat>(mimic->multiplier * l.sign / f.sign);
      coupling.m_offset = static_cast<PfxFloat>(mimic->offset / f.sign);
      if (const PfxInt32 err = pfxCheckJointCoupling(coupling, m_build.joints.data(),
                                                     static_cast<PfxUInt32>(m_build.joints.size()));
          err != PFX_OK) {
        return fail(err, "joint " + pfxUrdfQuoted(jointName(j)) + ": <mimic> cannot be built (" +
                             pfxErrorString(err) + ")");
      }
      m_couplingOf[j] = static_cast<int>(m_build.couplings.size());
      m_build.couplings.push_back(coupling);
    }
    return PFX_OK;
  }

  void describeModel() {
    PfxUrdfModel& model = m_build.model;
    model.name = m_model.getName();
    model.fixedBase = m_fixedRoot;
    std::map<std::string, int> jointIndex;
    for (int j = 0; j < static_cast<int>(m_joints.size()); ++j) jointIndex[jointName(j)] = j;
    for (std::size_t l = 0; l < m_links.size(); ++l) {
      const LinkNode& node = m_links[l];
      const Group& group = m_groups[node.group];
      PfxUrdfLink link;
      link.name = node.link->name;
      link.bodyId = static_cast<PfxUInt32>(group.body);
      link.linkInBody = toTransform(m_bodies[group.body].pose.inverse() * node.pose);
      if (group.role == Role::kHelper) {
        link.collapsedJointId = static_cast<PfxUInt32>(m_chains[group.chain].worldJoint);
        link.collapsedAxes = static_cast<PfxUInt32>(group.chainDepth);
      }
      model.links.push_back(link);
    }
    const PfxFloat infinity = std::numeric_limits<PfxFloat>::infinity();
    for (int j = 0; j < static_cast<int>(m_joints.size()); ++j) {
      const JointNode& node = m_joints[j];
      PfxUrdfJoint joint;
      joint.name = node.joint->name;
      joint.parentLink = node.joint->parent_link_name;
      joint.childLink = node.joint->child_link_name;
      joint.type = node.type;
      if (node.worldJoint >= 0 && hasCoordinate(node.type)) {
        joint.jointId = static_cast<PfxUInt32>(node.worldJoint);
        joint.axis = node.worldAxis;
        joint.sign = static_cast<PfxFloat>(node.sign);
        joint.collapsed = node.collapsed;
      }
      if (const urdf::JointLimitsSharedPtr& limits = node.joint->limits) {
        joint.effortLimit = static_cast<PfxFloat>(limits->effort);
        joint.velocityLimit = static_cast<PfxFloat>(limits->velocity);
        if (node.type == kPfxUrdfRevolute || node.type == kPfxUrdfPrismatic) {
          joint.lowerLimit = static_cast<PfxFloat>(limits->lower);
          joint.upperLimit = static_cast<PfxFloat>(limits->upper);
        }
      }
      if (node.type == kPfxUrdfContinuous) {
        joint.lowerLimit = -infinity;
        joint.upperLimit = infinity;
      }
      if (const urdf::JointMimicSharedPtr& mimic = node.joint->mimic) {
        joint.mimicLeader = jointIndex.at(mimic->joint_name);
        joint.mimicMultiplier = static_cast<PfxFloat>(mimic->multiplier);
        joint.mimicOffset = static_cast<PfxFloat>(mimic->offset);
        if (const auto it = m_couplingOf.find(j); it != m_couplingOf.end()) {
          joint.couplingId = static_cast<PfxUInt32>(it->second);
        }
      }
      model.joints.push_back(joint);
    }
  }

  const urdf::ModelInterface& m_model;
  const PfxUrdfDocumentOrder& m_order;
  const std::string& m_folder;
  const PfxUrdfLoadParam& m_param;
  const PfxFloat m_subStepTime;
  PfxUrdfBuild& m_build;
  PfxUrdfError& m_error;

  std::vector<LinkNode> m_links;
  std::vector<JointNode> m_joints;
  std::vector<int> m_treeOrder;
  std::vector<Group> m_groups;
  std::vector<Chain> m_chains;
  std::vector<BodyNode> m_bodies;
  std::map<std::string, PfxShape> m_meshShapes;
  std::map<int, int> m_couplingOf;
  int m_root = 0;
  bool m_fixedRoot = false;
};

}  // namespace

void PfxLargeTriMeshRelease::operator()(PfxLargeTriMesh* mesh) const {
  pfxDeleteLargeTriMesh(mesh);
}

void PfxConvexMeshRelease::operator()(PfxConvexMesh* mesh) const { pfxDeleteConvexMesh(mesh); }

PfxInt32 pfxBuildUrdf(const urdf::ModelInterface& urdfModel, const PfxUrdfDocumentOrder& order,
                      const std::string& urdfFolder, const PfxUrdfLoadParam& param,
                      PfxFloat subStepTime, PfxUrdfBuild& build, PfxUrdfError& error) {
  return UrdfBuilder(urdfModel, order, urdfFolder, param, subStepTime, build, error).run();
}

}  // namespace pfx
