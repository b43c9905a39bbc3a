// ODE behind the benchmark's interface: dWorldQuickStep (projected Gauss-Seidel) with
// contact joints made each sub-step from dCollide, at most kContactsPerPair per pair, and
// the scene's joints as dJointCreateBall / dJointCreateHinge (body 0 for the world), motors
// as the hinges' own motors (dParamVel within dParamFMax).
// ODE's capsules and cylinders lie along Z; their geoms are turned onto the body's X axis.
#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "bench_engine.h"

namespace pfxbench {

namespace {

constexpr int kContactsPerPair = 4;  // as many as a pfx contact manifold holds
// ODE's hinge angle is its first body's turn relative to its second. For a joint to the
// world, attached as (0, B), ODE makes B its first body: the scene's angle as it is.
double hingeAngleSign(const JointDesc& joint) { return joint.bodyA == kWorld ? 1 : -1; }

struct Material {
  double friction;
  double restitution;
};

void initOdeOnce() {
  static const bool initialised = [] {
    dInitODE2(0);
    dAllocateODEDataForThread(dAllocateMaskAll);
    return true;
  }();
  (void)initialised;
}

// Rotation taking Z onto X: a quarter turn about Y.
Quat zToX() { return Quat(std::sqrt(0.5), 0, std::sqrt(0.5), 0); }

void toOde(const Quat& q, dQuaternion out) {
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}

dGeomID makeGeom(dSpaceID space, const ShapeDesc& shape) {
  switch (shape.type) {
    case ShapeType::Sphere: return dCreateSphere(space, shape.radius);
    case ShapeType::Box:
      return dCreateBox(space, 2 * shape.halfExtents.x(), 2 * shape.halfExtents.y(),
                        2 * shape.halfExtents.z());
    case ShapeType::Capsule: return dCreateCapsule(space, shape.radius, 2 * shape.halfLength);
    case ShapeType::Cylinder: return dCreateCylinder(space, shape.radius, 2 * shape.halfLength);
  }
  return nullptr;
}

bool alongZ(const ShapeDesc& shape) {
  return shape.type == ShapeType::Capsule || shape.type == ShapeType::Cylinder;
}

class OdeEngine final : public Engine {
 public:
  OdeEngine() {
    initOdeOnce();
    m_world = dWorldCreate();
    m_space = dHashSpaceCreate(nullptr);
    m_contacts = dJointGroupCreate(0);
  }
  ~OdeEngine() override {
    dJointGroupDestroy(m_contacts);
    dSpaceDestroy(m_space);  // destroys the geoms it holds
    dWorldDestroy(m_world);  // destroys the bodies
  }

  bool build(const Scene& scene, const EngineSettings& settings, std::string&) override {
    dWorldSetGravity(m_world, scene.gravity.x(), scene.gravity.y(), scene.gravity.z());
    dWorldSetQuickStepNumIterations(m_world, settings.iterations);
    dWorldSetERP(m_world, 0.2);
    dWorldSetContactSurfaceLayer(m_world, 0.005);
    m_subTimeStep = settings.dt / settings.substeps;
    m_substeps = settings.substeps;

    m_materials.reserve(scene.bodies.size());
    for (const BodyDesc& desc : scene.bodies) {
      m_materials.push_back({desc.friction, desc.restitution});
      dGeomID geom = makeGeom(m_space, desc.shape);
      dGeomSetData(geom, &m_materials.back());
      dQuaternion orientation;
      toOde(desc.orientation, orientation);
      dBodyID body = nullptr;
      if (desc.fixed) {
        const Quat pose = alongZ(desc.shape) ? desc.orientation * zToX() : desc.orientation;
        dQuaternion geomOrientation;
        toOde(pose, geomOrientation);
        dGeomSetPosition(geom, desc.position.x(), desc.position.y(), desc.position.z());
        dGeomSetQuaternion(geom, geomOrientation);
        m_fixedStates.push_back({desc.position, desc.orientation, Vec3::Zero(), Vec3::Zero()});
      } else {
        body = dBodyCreate(m_world);
        dMass mass;
        dMassSetParameters(&mass, desc.mass, 0, 0, 0, desc.inertia.x(), desc.inertia.y(),
                           desc.inertia.z(), 0, 0, 0);
        dBodySetMass(body, &mass);
        dBodySetPosition(body, desc.position.x(), desc.position.y(), desc.position.z());
        dBodySetQuaternion(body, orientation);
        dBodySetLinearVel(body, desc.linearVelocity.x(), desc.linearVelocity.y(),
                          desc.linearVelocity.z());
        dBodySetAngularVel(body, desc.angularVelocity.x(), desc.angularVelocity.y(),
                           desc.angularVelocity.z());
        dGeomSetBody(geom, body);
        if (alongZ(desc.shape)) {
          dQuaternion offset;
          toOde(zToX(), offset);
          dGeomSetOffsetQuaternion(geom, offset);
        }
        m_fixedStates.push_back({});
      }
      m_bodies.push_back(body);
    }
    for (const JointDesc& desc : scene.joints) addJoint(desc);
    for (const JointMotorDesc& motor : scene.motors) {
      const dJointID hinge = m_joints[motor.joint];
      dJointSetHingeParam(hinge, dParamFMax, motor.maxTorque);
      m_motors.push_back({hinge, hingeAngleSign(scene.joints[motor.joint])});
    }
    return true;
  }

  void setMotorRates(const std::vector<double>& rates) override {
    for (std::size_t i = 0; i < rates.size(); ++i) {
      dJointSetHingeParam(m_motors[i].hinge, dParamVel, m_motors[i].angleSign * rates[i]);
    }
  }

  bool step(std::string&) override {
    for (int i = 0; i < m_substeps; ++i) {
      dSpaceCollide(m_space, this, &OdeEngine::nearCallback);
      dWorldQuickStep(m_world, m_subTimeStep);
      dJointGroupEmpty(m_contacts);
    }
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    states.resize(m_bodies.size());
    for (std::size_t i = 0; i < m_bodies.size(); ++i) {
      const dBodyID body = m_bodies[i];
      if (!body) {
        states[i] = m_fixedStates[i];
        continue;
      }
      const dReal* p = dBodyGetPosition(body);
      const dReal* q = dBodyGetQuaternion(body);
      const dReal* v = dBodyGetLinearVel(body);
      const dReal* w = dBodyGetAngularVel(body);
      states[i].position = Vec3(p[0], p[1], p[2]);
      states[i].orientation = Quat(q[0], q[1], q[2], q[3]);
      states[i].linearVelocity = Vec3(v[0], v[1], v[2]);
      states[i].angularVelocity = Vec3(w[0], w[1], w[2]);
    }
  }

  // ODE keeps each joint's anchor on its first and on its second body (the world point
  // where that side is the world), which are the two sides of the scene's joint.
  void readJointAnchors(std::vector<JointAnchors>& anchors) const override {
    anchors.resize(m_joints.size());
    for (std::size_t i = 0; i < m_joints.size(); ++i) {
      const dJointID joint = m_joints[i];
      dVector3 onA, onB;
      if (dJointGetType(joint) == dJointTypeBall) {
        dJointGetBallAnchor(joint, onA);
        dJointGetBallAnchor2(joint, onB);
      } else {
        dJointGetHingeAnchor(joint, onA);
        dJointGetHingeAnchor2(joint, onB);
      }
      anchors[i].onA = Vec3(onA[0], onA[1], onA[2]);
      anchors[i].onB = Vec3(onB[0], onB[1], onB[2]);
    }
  }

 private:
  void addJoint(const JointDesc& desc) {
    const dBodyID a = desc.bodyA == kWorld ? nullptr : m_bodies[desc.bodyA];
    const dBodyID b = m_bodies[desc.bodyB];
    const Vec3& p = desc.anchor;
    dJointID joint = nullptr;
    if (desc.type == JointType::Ball) {
      joint = dJointCreateBall(m_world, nullptr);
      dJointAttach(joint, a, b);
      dJointSetBallAnchor(joint, p.x(), p.y(), p.z());
    } else {
      const Vec3 axis = desc.axis.normalized();
      joint = dJointCreateHinge(m_world, nullptr);
      dJointAttach(joint, a, b);
      dJointSetHingeAnchor(joint, p.x(), p.y(), p.z());
      dJointSetHingeAxis(joint, axis.x(), axis.y(), axis.z());
      if (desc.limited()) {
        const double sign = hingeAngleSign(desc);
        const double one = sign * desc.lowerLimit, other = sign * desc.upperLimit;
        dJointSetHingeParam(joint, dParamLoStop, std::min(one, other));
        dJointSetHingeParam(joint, dParamHiStop, std::max(one, other));
      }
    }
    m_joints.push_back(joint);
  }

  static void nearCallback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<OdeEngine*>(data);
    const dBodyID bodyA = dGeomGetBody(a);
    const dBodyID bodyB = dGeomGetBody(b);
    if (!bodyA && !bodyB) return;
    // Bodies held together by a joint do not collide, as in pfx.
    if (bodyA && bodyB && dAreConnectedExcluding(bodyA, bodyB, dJointTypeContact)) return;
    dContact contacts[kContactsPerPair];
    const int n = dCollide(a, b, kContactsPerPair, &contacts[0].geom, sizeof(dContact));
    if (n <= 0) return;
    const auto* ma = static_cast<const Material*>(dGeomGetData(a));
    const auto* mb = static_cast<const Material*>(dGeomGetData(b));
    const double restitution = std::max(ma->restitution, mb->restitution);
    for (int i = 0; i < n; ++i) {
      dSurfaceParameters& surface = contacts[i].surface;
      surface.mode = dContactApprox1 | (restitution > 0 ? dContactBounce : 0);
      surface.mu = std::sqrt(ma->friction * mb->friction);
      surface.bounce = restitution;
      surface.bounce_vel = 0.2;  // pfx's restitutionThreshold
      const dJointID joint = dJointCreateContact(self->m_world, self->m_contacts, &contacts[i]);
      dJointAttach(joint, bodyA, bodyB);
    }
  }

  dWorldID m_world;
  dSpaceID m_space;
  dJointGroupID m_contacts;
  std::vector<Material> m_materials;
  std::vector<dBodyID> m_bodies;           // null where the body is fixed
  std::vector<BodyState> m_fixedStates;    // indexed like m_bodies, set where fixed
  std::vector<dJointID> m_joints;          // the scene's joints, destroyed with the world
  struct Motor {
    dJointID hinge;
    double angleSign;
  };
  std::vector<Motor> m_motors;             // per motor of the scene
  double m_subTimeStep = 1.0 / 60;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createOdeEngine() { return std::make_unique<OdeEngine>(); }

}  // namespace pfxbench
