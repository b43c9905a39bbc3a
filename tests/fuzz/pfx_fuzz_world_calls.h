// The world's API as an application drives it, for fuzz_world_api and fuzz_world_threads:
// the input is decoded into at most kMaxCalls calls on a PfxWorld (add a body, a stack of
// boxes or a joint, set a state, a body, a joint or the step parameters, apply a force, move
// a keyframe body, step, cast rays, query contacts, exclude a pair, couple joints, remove,
// truncate, save and load). After every call either it succeeded and every state is finite
// with a unit orientation, or it was refused and the world is exactly what it was before
// (compared with a snapshot).
#pragma once

#include <cstdint>
#include <cmath>
#include <limits>
#include <cstring>
#include <string>
#include <vector>

#include "pfx/loaders/pfx_mesh_loader.h"
#include "pfx_fuzz_util.h"

namespace pfx_fuzz {

using namespace pfx;

constexpr int kMaxCalls = 48;
constexpr int kMaxSteps = 12;      // steps per input, so that each input runs in milliseconds
constexpr PfxUInt32 kMaxBodies = 24;
// Stacks may go beyond kMaxBodies: two threads solve a world in groups of islands only when
// each group weighs at least 32 bodies, contacts and joints (pfx_world_groups.cpp), two
// stacks of 16 boxes on a floor. Larger worlds would only slow every input down.
constexpr PfxUInt32 kMaxStackedBodies = 56;
constexpr PfxUInt8 kAddStackOp = 0xff;
constexpr PfxUInt32 kMaxRays = 80;  // above 64, so that castRays takes its sorted path

// Reads the input front to back; past its end every read gives zeros.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : m_data(data), m_size(size) {}
  bool empty() const { return m_pos >= m_size; }
  PfxUInt8 u8() { return m_pos < m_size ? m_data[m_pos++] : 0; }
  PfxUInt32 u32() {
    PfxUInt32 v = 0;
    for (int i = 0; i < 4; ++i) v = v << 8 | u8();
    return v;
  }
  // An id: mostly one that exists, sometimes one just past the end, sometimes anything.
  PfxUInt32 id(PfxUInt32 count) {
    const PfxUInt8 b = u8();
    if (b == 0xff) return u32();
    return b % (count + 1);
  }
  // A real over many magnitudes, and now and then one a check must refuse.
  PfxFloat real() {
    const PfxUInt16 bits = static_cast<PfxUInt16>(u8() << 8 | u8());
    const unsigned exponent = bits >> 12;
    if (exponent == 15) {
      static const PfxFloat special[16] = {
          0, 1, -1, PfxFloat(0.5), std::numeric_limits<PfxFloat>::quiet_NaN(),
          std::numeric_limits<PfxFloat>::infinity(), -std::numeric_limits<PfxFloat>::infinity(),
          std::numeric_limits<PfxFloat>::max(), std::numeric_limits<PfxFloat>::min(),
          std::numeric_limits<PfxFloat>::denorm_min(), PfxFloat(1e-7), PfxFloat(1e7),
          PfxFloat(-0.0), PfxFloat(1e20), PfxFloat(-1e20), PfxFloat(3.14159265)};
      return special[bits & 15];
    }
    const PfxFloat mantissa = PfxFloat(static_cast<int>(bits & 0xfff) - 2048) / 256;
    return mantissa * std::pow(PfxFloat(10), PfxFloat(static_cast<int>(exponent) - 7));
  }
  PfxFloat positive() { return std::fabs(real()); }
  PfxVector3 vec3() { return PfxVector3(real(), real(), real()); }
  // A unit quaternion mostly; one that is not when the first byte says so.
  PfxQuat quat() {
    const bool raw = u8() % 8 == 0;
    PfxQuat q(real(), real(), real(), real());
    if (!raw && q.coeffs().allFinite() && q.norm() > PfxFloat(1e-6)) q.normalize();
    if (!raw && !(q.norm() > PfxFloat(0.5))) q = PfxQuat::Identity();
    return q;
  }

 private:
  const std::uint8_t* m_data;
  std::size_t m_size;
  std::size_t m_pos = 0;
};

// Meshes the bodies may use, made once.
struct Meshes {
  PfxConvexMesh hull{};
  PfxLargeTriMesh ground{};
  Meshes() {
    PfxTriangleMesh points;
    points.vertices = {1, 0, 0, -1, 0, 0, 0, PfxFloat(0.7), 0, 0, -PfxFloat(0.7), 0,
                       0, 0, PfxFloat(0.4), PfxFloat(0.2), 0, -PfxFloat(0.5)};
    if (pfxCreateConvexHull(points, hull) != PFX_OK) fail("hull");
    PfxTriangleMesh grid;
    const int n = 4;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        grid.vertices.insert(grid.vertices.end(),
                             {PfxFloat(i - 2), PfxFloat((i * 7 + j * 3) % 5) * PfxFloat(0.1),
                              PfxFloat(j - 2)});
      }
    }
    for (PfxUInt32 i = 0; i < n; ++i) {
      for (PfxUInt32 j = 0; j < n; ++j) {
        const PfxUInt32 a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
        grid.triangles.insert(grid.triangles.end(), {a, b, c, b, d, c});
      }
    }
    if (pfxCreateLargeTriMeshFromMesh(grid, PFX_MESH_FLAG_USE_BVH, ground) != PFX_OK) {
      fail("ground mesh");
    }
  }
};

const Meshes& meshes() {
  static const Meshes made;
  return made;
}

PfxShape readShape(ByteReader& in, bool staticBody) {
  PfxShape shape;
  switch (in.u8() % 6) {
    case 0: shape = pfxMakeShape(PfxSphere(in.real())); break;
    case 1: shape = pfxMakeShape(PfxBox(in.vec3())); break;
    case 2: shape = pfxMakeShape(PfxCapsule(in.real(), in.real())); break;
    case 3: shape = pfxMakeShape(PfxCylinder(in.real(), in.real())); break;
    case 4: shape = pfxMakeShape(&meshes().hull); break;
    default:
      if (staticBody) {
        shape.reset();
        shape.setLargeTriMesh(&meshes().ground);
      } else {
        shape = pfxMakeShape(PfxBox(PfxFloat(0.3), PfxFloat(0.2), PfxFloat(0.1)));
      }
  }
  if (in.u8() % 4 == 0) {
    shape.setOffsetPosition(in.vec3());
    shape.setOffsetOrientation(in.quat());
  }
  return shape;
}

// What a refused call must leave as it was.
struct Snapshot {
  std::vector<PfxUInt8> stateBytes;
  std::vector<PfxUInt8> bodyBytes;
  std::vector<PfxUInt8> jointBytes;
  std::vector<PfxUInt8> present;
  PfxUInt32 counts[4] = {};
  double time = 0;

  template <typename T>
  static void append(std::vector<PfxUInt8>& out, const T& value) {
    const auto* bytes = reinterpret_cast<const PfxUInt8*>(&value);
    out.insert(out.end(), bytes, bytes + sizeof(T));
  }

  explicit Snapshot(const PfxWorld& world) {
    counts[0] = world.getNumRigidBodies();
    counts[1] = world.getNumJoints();
    counts[2] = world.getNumJointCouplings();
    counts[3] = world.getNumRemovedRigidBodies() + world.getNumRemovedJoints();
    time = world.getSimulatedTime();
    for (PfxUInt32 id = 0; id < counts[0]; ++id) {
      const PfxRigidState& s = world.getRigidState(id);
      append(stateBytes, s.getPosition());
      append(stateBytes, s.getOrientation().coeffs().eval());
      append(stateBytes, s.getLinearVelocity());
      append(stateBytes, s.getAngularVelocity());
      append(stateBytes, s.getMotionType());
      append(stateBytes, s.getContactFilterSelf());
      append(stateBytes, s.getContactFilterTarget());
      const PfxRigidBody& b = world.getRigidBody(id);
      append(bodyBytes, b.getMass());
      append(bodyBytes, b.getFriction());
      append(bodyBytes, b.getRestitution());
      append(bodyBytes, b.getInertia());
      present.push_back(world.hasRigidBody(id));
    }
    for (PfxUInt32 id = 0; id < counts[1]; ++id) {
      const PfxJoint& j = world.getJoint(id);
      append(jointBytes, j.m_rigidBodyIdA);
      append(jointBytes, j.m_rigidBodyIdB);
      append(jointBytes, j.m_active);
      for (const PfxJointConstraint& c : j.m_constraints) {
        append(jointBytes, c.m_lock);
        append(jointBytes, c.m_drive);
        append(jointBytes, c.m_movableLowerLimit);
        append(jointBytes, c.m_movableUpperLimit);
        append(jointBytes, c.m_driveTarget);
        append(jointBytes, c.m_driveMaxForce);
      }
      present.push_back(world.hasJoint(id));
    }
  }

  bool operator==(const Snapshot& o) const {
    return stateBytes == o.stateBytes && bodyBytes == o.bodyBytes && jointBytes == o.jointBytes &&
           present == o.present && std::memcmp(counts, o.counts, sizeof(counts)) == 0 &&
           time == o.time;
  }
};

// What one call did: its result, its ray hits in bytes, and the world after it.
struct CallRecord {
  PfxUInt8 op;
  PfxInt32 err;
  std::vector<PfxUInt8> hits;
  Snapshot world;

  bool operator==(const CallRecord& o) const {
    return op == o.op && err == o.err && hits == o.hits && world == o.world;
  }
};

class Driver {
 public:
  // With PFX_FUZZ_TRACE set, each call and its result go to stderr: how a saved input is
  // turned back into the calls of a regression test.
  // Each call's result, the world after it and its ray hits go to *record when given.
  Driver(ByteReader& in, PfxUInt32 numThreads, std::vector<CallRecord>* record = nullptr)
      : m_in(in),
        m_trace(std::getenv("PFX_FUZZ_TRACE") != nullptr),
        m_numThreads(numThreads),
        m_record(record) {}

  void run() {
    PfxWorldParam param;
    param.numThreads = m_numThreads;
    param.gravity = m_in.vec3();
    param.timeStep = m_in.u8() % 4 == 0 ? m_in.real() : PfxFloat(1) / 60;
    param.subStep = 1 + m_in.u8() % 4;
    param.iteration = 1 + m_in.u8() % 16;
    param.pipeline = m_in.u8() % 2 ? kPfxPipelineStable : kPfxPipelineSimple;
    param.enableSleep = m_in.u8() % 2;
    param.worldExtent = PfxVector3::Constant(m_in.u8() % 2 ? 1000 : 20);
    if (m_world.initialize(param) != PFX_OK) {
      PfxWorldParam defaults;
      defaults.numThreads = m_numThreads;
      if (m_world.initialize(defaults) != PFX_OK) fail("default initialize");
    }
    for (int call = 0; call < kMaxCalls && !m_in.empty(); ++call) {
      const PfxUInt8 op = m_in.u8();
      const Snapshot before(m_world);
      m_hits.clear();
      const PfxInt32 err = apply(op);
      if (m_trace) traceCall(op, err);
      if (err == PFX_OK) {
        checkStatesFinite(m_world, opName(op));
      } else if (!(Snapshot(m_world) == before)) {
        fail("a refused call changed the world:", opName(op));
      }
      // A refused call has just been found to leave the world as `before`.
      if (m_record) {
        m_record->push_back(
            CallRecord{op, err, m_hits, err == PFX_OK ? Snapshot(m_world) : before});
      }
    }
  }

  static const char* opName(PfxUInt8 op) {
    static const char* names[] = {"addRigidBody", "addRigidBody (mass properties)", "addJoint",
                                  "setRigidState", "setRigidBody", "applyForce", "step",
                                  "castRay", "castRays", "removeRigidBody", "removeJoint",
                                  "setKeyframeTarget", "setStepParam", "excludeCollision",
                                  "addJointCoupling", "setJoint", "truncate", "queryContacts",
                                  "save and load"};
    if (op == kAddStackOp) return "add a stack";
    return names[op % (sizeof(names) / sizeof(names[0]))];
  }

 private:
  void traceCall(PfxUInt8 op, PfxInt32 err) const {
    std::fprintf(stderr, "%s -> %s\n", opName(op), pfxErrorString(err));
    for (PfxUInt32 id = 0; id < numBodies(); ++id) {
      const PfxRigidState& s = m_world.getRigidState(id);
      const PfxRigidBody& b = m_world.getRigidBody(id);
      std::fprintf(stderr, "  body %u motion %d p (%g %g %g) v (%g %g %g) w (%g %g %g) mass %g I (%g %g %g)\n",
                   id, s.getMotionType(), s.getPosition().x(), s.getPosition().y(),
                   s.getPosition().z(), s.getLinearVelocity().x(), s.getLinearVelocity().y(),
                   s.getLinearVelocity().z(), s.getAngularVelocity().x(),
                   s.getAngularVelocity().y(), s.getAngularVelocity().z(), b.getMass(),
                   b.getInertia()(0, 0), b.getInertia()(1, 1), b.getInertia()(2, 2));
    }
  }

  PfxUInt32 numBodies() const { return m_world.getNumRigidBodies(); }

  PfxInt32 apply(PfxUInt8 op) {
    if (op == kAddStackOp) return addStack();
    switch (op % 19) {
      case 0: return addBody();
      case 1: return addBodyWithMassProperties();
      case 2: return addJoint();
      case 3: return setState();
      case 4: return setBody();
      case 5: return m_world.applyForce(m_in.id(numBodies()), m_in.vec3(), m_in.vec3());
      case 6: return step();
      case 7: return castRay();
      case 8: return castRays();
      case 9: return m_world.removeRigidBody(m_in.id(numBodies()));
      case 10: return m_world.removeJoint(m_in.id(m_world.getNumJoints()));
      case 11: return m_world.setKeyframeTarget(m_in.id(numBodies()), m_in.vec3(), m_in.quat());
      case 12:
        return m_world.setStepParam(m_in.real(), m_in.u8() % 5, 1 + m_in.u8() % 20, m_in.vec3());
      case 13: return m_world.excludeCollision(m_in.id(numBodies()), m_in.id(numBodies()));
      case 14: return addCoupling();
      case 15: return setJoint();
      case 16: return truncate();
      case 17: return queryContacts();
      default: return saveAndLoad();
    }
  }

  PfxInt32 addBody() {
    if (numBodies() >= kMaxBodies) return PFX_ERR_OUT_OF_RANGE;
    PfxBodyInit init;
    init.motionType = static_cast<PfxMotionType>(m_in.u8() % (kPfxMotionTypeCount + 1));
    init.mass = m_in.u8() % 4 == 0 ? 0 : m_in.real();
    init.position = m_in.vec3();
    init.orientation = m_in.quat();
    init.linearVelocity = m_in.vec3();
    init.angularVelocity = m_in.vec3();
    init.friction = m_in.real();
    init.restitution = m_in.real();
    const bool staticBody = init.mass == 0 || init.motionType == kPfxMotionTypeFixed ||
                            init.motionType == kPfxMotionTypeKeyframe;
    PfxShape shapes[3];
    const PfxUInt32 numShapes = 1 + m_in.u8() % 3;
    for (PfxUInt32 i = 0; i < numShapes; ++i) shapes[i] = readShape(m_in, staticBody);
    return pfxAddBody(m_world, shapes, numShapes, init);
  }

  // Boxes stacked against gravity, each overlapping the one below a little: one island
  // of as many bodies and contacts. Added all or none, as one call.
  PfxInt32 addStack() {
    const PfxUInt32 count = 2 + m_in.u8() % 23;
    const PfxFloat halfSize = PfxFloat(0.1) + PfxFloat(m_in.u8() % 16) * PfxFloat(0.05);
    const PfxVector3 base = m_in.vec3();
    if (numBodies() + count > kMaxStackedBodies) return PFX_ERR_OUT_OF_RANGE;
    const PfxVector3 gravity = m_world.getParam().gravity;
    const PfxVector3 up = gravity.allFinite() && gravity.norm() > PfxFloat(1e-3)
                              ? PfxVector3(-gravity.normalized())
                              : PfxVector3::UnitY();
    const PfxFloat spacing = 2 * halfSize * PfxFloat(0.98);
    auto position = [&](PfxUInt32 i) { return PfxVector3(base + up * (spacing * PfxFloat(i))); };
    // The world refuses a position whose squared length overflows (PfxRigidState::isValid).
    for (PfxUInt32 i = 0; i < count; ++i) {
      if (!pfxIsFinite(position(i).squaredNorm())) return PFX_ERR_INVALID_VALUE;
    }
    const PfxShape box = pfxMakeShape(PfxBox(halfSize, halfSize, halfSize));
    for (PfxUInt32 i = 0; i < count; ++i) {
      PfxBodyInit init;
      init.position = position(i);
      if (const PfxInt32 err = pfxAddBody(m_world, &box, 1, init); err != PFX_OK) {
        fail("a box of a stack was refused:", pfxErrorString(err));
      }
    }
    return PFX_OK;
  }

  PfxInt32 addBodyWithMassProperties() {
    if (numBodies() >= kMaxBodies) return PFX_ERR_OUT_OF_RANGE;
    PfxRigidState state;
    state.reset();
    state.setMotionType(static_cast<PfxMotionType>(m_in.u8() % (kPfxMotionTypeCount + 1)));
    state.setPosition(m_in.vec3());
    state.setOrientation(m_in.quat());
    state.setContactFilterSelf(m_in.u8() % 2 ? 0xffffffffu : m_in.u32());
    state.setContactFilterTarget(m_in.u8() % 2 ? 0xffffffffu : m_in.u32());
    PfxRigidBody body = readBody();
    const PfxShape shape = readShape(m_in, !pfxMotionTypeIsDynamic(state.getMotionType()));
    return m_world.addRigidBody(state, body, &shape, 1);
  }

  PfxRigidBody readBody() {
    PfxRigidBody body;
    body.reset();
    body.setMass(m_in.real());
    PfxMatrix3 inertia = PfxMatrix3::Zero();
    inertia.diagonal() = m_in.vec3();
    if (m_in.u8() % 4 == 0) {
      inertia(0, 1) = inertia(1, 0) = m_in.real();
      inertia(0, 2) = inertia(2, 0) = m_in.real();
    }
    body.setInertia(inertia);
    body.setFriction(m_in.real());
    body.setRestitution(m_in.positive());
    return body;
  }

  PfxInt32 addJoint() {
    const PfxUInt32 a = m_in.id(numBodies()), b = m_in.id(numBodies());
    if (!m_world.hasRigidBody(a) || !m_world.hasRigidBody(b)) {
      PfxJoint joint{};
      joint.m_rigidBodyIdA = a;
      joint.m_rigidBodyIdB = b;
      return m_world.addJoint(joint);
    }
    const PfxRigidState& stateA = m_world.getRigidState(a);
    const PfxRigidState& stateB = m_world.getRigidState(b);
    PfxJoint joint;
    PfxInt32 err = PFX_OK;
    const PfxUInt8 type = m_in.u8() % 6;
    auto common = [&](PfxJointInitParamBase& p) {
      p.anchorPoint = m_in.u8() % 2 ? PfxVector3((stateA.getPosition() + stateB.getPosition()) / 2)
                                    : m_in.vec3();
      p.damping = m_in.positive();
      p.bias = m_in.positive();
      if (m_in.u8() % 4 == 0) {
        p.enableJointFrame = true;
        p.jointFrame = m_in.quat().toRotationMatrix();
      }
    };
    switch (type) {
      case 0: {
        PfxBallJointInitParam p;
        common(p);
        err = pfxInitializeBallJoint(joint, stateA, stateB, p);
        break;
      }
      case 1: {
        PfxSwingTwistJointInitParam p;
        common(p);
        p.twistAxis = m_in.vec3();
        p.twistLowerAngle = m_in.real();
        p.twistUpperAngle = m_in.real();
        p.swingUpperAngle = m_in.real();
        err = pfxInitializeSwingTwistJoint(joint, stateA, stateB, p);
        break;
      }
      case 2: {
        PfxHingeJointInitParam p;
        common(p);
        p.axis = m_in.vec3();
        p.lowerAngle = m_in.real();
        p.upperAngle = m_in.real();
        err = pfxInitializeHingeJoint(joint, stateA, stateB, p);
        break;
      }
      case 3: {
        PfxSliderJointInitParam p;
        common(p);
        p.direction = m_in.vec3();
        p.lowerDistance = m_in.real();
        p.upperDistance = m_in.real();
        err = pfxInitializeSliderJoint(joint, stateA, stateB, p);
        break;
      }
      case 4: {
        PfxFixedJointInitParam p;
        common(p);
        err = pfxInitializeFixedJoint(joint, stateA, stateB, p);
        break;
      }
      default: {
        PfxUniversalJointInitParam p;
        common(p);
        p.axis = m_in.vec3();
        p.upVec = m_in.vec3();
        p.swing1LowerAngle = m_in.real();
        p.swing1UpperAngle = m_in.real();
        p.swing2LowerAngle = m_in.real();
        p.swing2UpperAngle = m_in.real();
        err = pfxInitializeUniversalJoint(joint, stateA, stateB, p);
      }
    }
    if (err != PFX_OK) return err;
    joint.m_rigidBodyIdA = a;
    joint.m_rigidBodyIdB = b;
    return m_world.addJoint(joint);
  }

  PfxInt32 setJoint() {
    const PfxUInt32 id = m_in.id(m_world.getNumJoints());
    if (!m_world.hasJoint(id)) return m_world.setJoint(id, PfxJoint{});
    PfxJoint joint = m_world.getJoint(id);
    PfxJointConstraint& axis = joint.m_constraints[m_in.u8() % 6];
    axis.m_lock = m_in.u8() % 4;
    axis.m_movableLowerLimit = m_in.real();
    axis.m_movableUpperLimit = m_in.real();
    axis.m_drive = m_in.u8() % 5;
    axis.m_driveTarget = m_in.real();
    axis.m_driveMaxForce = m_in.real();
    axis.m_damping = m_in.real();
    axis.m_friction = m_in.real();
    return m_world.setJoint(id, joint);
  }

  PfxInt32 addCoupling() {
    PfxJointCoupling coupling{};
    coupling.m_leaderJointId = m_in.id(m_world.getNumJoints());
    coupling.m_followerJointId = m_in.id(m_world.getNumJoints());
    coupling.m_leaderAxis = m_in.u8() % 7;
    coupling.m_followerAxis = m_in.u8() % 7;
    coupling.m_active = 1;
    coupling.m_multiplier = m_in.real();
    coupling.m_offset = m_in.real();
    coupling.m_bias = m_in.positive();
    coupling.m_maxImpulseForce = m_in.real();
    return m_world.addJointCoupling(coupling);
  }

  PfxInt32 setState() {
    const PfxUInt32 id = m_in.id(numBodies());
    PfxRigidState state;
    state.reset();
    if (m_world.hasRigidBody(id)) state = m_world.getRigidState(id);
    switch (m_in.u8() % 4) {
      case 0: state.setPosition(m_in.vec3()); break;
      case 1: state.setOrientation(m_in.quat()); break;
      case 2: state.setLinearVelocity(m_in.vec3()); break;
      default:
        state.setAngularVelocity(m_in.vec3());
        state.setMotionType(static_cast<PfxMotionType>(m_in.u8() % (kPfxMotionTypeCount + 1)));
    }
    return m_world.setRigidState(id, state);
  }

  PfxInt32 setBody() {
    const PfxUInt32 id = m_in.id(numBodies());
    return m_world.setRigidBody(id, readBody());
  }

  PfxInt32 step() {
    if (m_steps >= kMaxSteps) return PFX_ERR_OUT_OF_RANGE;
    ++m_steps;
    const PfxInt32 err = m_world.step();
    if (err != PFX_OK) fail("step refused", pfxErrorString(err));
    return err;
  }

  PfxRayInput readRay() {
    PfxRayInput ray;
    ray.m_startPosition = m_in.vec3();
    ray.m_direction = m_in.vec3();
    ray.m_contactFilterSelf = m_in.u8() % 4 ? 0xffffffffu : m_in.u32();
    ray.m_contactFilterTarget = m_in.u8() % 4 ? 0xffffffffu : m_in.u32();
    return ray;
  }

  void checkAndRecordHit(const PfxRayOutput& out) {
    Snapshot::append(m_hits, out.m_contactFlag);
    if (!out.m_contactFlag) return;
    Snapshot::append(m_hits, out.m_objectId);
    Snapshot::append(m_hits, out.m_variable);
    Snapshot::append(m_hits, out.m_contactPoint);
    Snapshot::append(m_hits, out.m_contactNormal);
    if (!(out.m_variable >= 0 && out.m_variable <= 1) || !pfxIsFinite(out.m_contactPoint) ||
        !pfxIsFinite(out.m_contactNormal) || !m_world.hasRigidBody(out.m_objectId)) {
      fail("a ray hit that is not on the ray or names no body");
    }
  }

  PfxInt32 castRay() {
    const PfxRayInput ray = readRay();
    PfxRayOutput out;
    const PfxInt32 err = m_world.castRay(ray, out);
    if (err == PFX_OK) checkAndRecordHit(out);
    return err;
  }

  PfxInt32 castRays() {
    const PfxUInt32 count = 1 + m_in.u8() % kMaxRays;
    const PfxRayInput first = readRay();
    const PfxVector3 spread = m_in.vec3();
    std::vector<PfxRayInput> rays(count, first);
    for (PfxUInt32 i = 0; i < count; ++i) {
      rays[i].m_startPosition += spread * PfxFloat(i);
    }
    std::vector<PfxRayOutput> out(count);
    const PfxInt32 err = m_world.castRays(rays.data(), out.data(), count);
    if (err == PFX_OK) {
      for (const PfxRayOutput& o : out) checkAndRecordHit(o);
    }
    return err;
  }

  PfxInt32 queryContacts() {
    PfxCollidable collidable;
    collidable.reset();
    if (collidable.addShape(readShape(m_in, false)) != PFX_OK || collidable.finish() != PFX_OK) {
      return PFX_ERR_INVALID_VALUE;
    }
    PfxContactQueryInput query;
    query.collidable = &collidable;
    query.transform = pfxMakeTransform(m_in.quat(), m_in.vec3());
    query.contactThreshold = m_in.real();
    PfxQueryContact out[8];
    PfxQueryContactsResult result;
    const PfxInt32 err = m_world.queryContacts(query, out, 8, result);
    if (err == PFX_OK) {
      if (result.numContacts > 8) fail("query wrote past its output");
      for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
        if (!m_world.hasRigidBody(out[i].m_rigidBodyId)) fail("query names no body");
      }
    }
    return err;
  }

  PfxInt32 truncate() {
    return m_world.truncate(m_in.id(numBodies()), m_in.id(m_world.getNumJoints()),
                            m_in.id(m_world.getNumJointCouplings()));
  }

  // The world saved, loaded into another and saved again must give the same bytes; the
  // world itself is not changed.
  PfxInt32 saveAndLoad() {
    checkSaveLoadRoundTrip(m_world);
    return PFX_OK;
  }

  ByteReader& m_in;
  const bool m_trace;
  const PfxUInt32 m_numThreads;
  std::vector<CallRecord>* const m_record;
  std::vector<PfxUInt8> m_hits;  // the ray hits of the call being made
  PfxWorld m_world;
  int m_steps = 0;
};

}  // namespace pfx_fuzz
