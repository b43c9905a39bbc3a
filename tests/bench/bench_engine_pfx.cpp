// pfx behind the benchmark's interface: the stable pipeline (cached pairs and contacts,
// warm-started solver), sub-steps by stepping the world several times at dt / substeps.
#include <string>

#include "bench_engine.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfxbench {

namespace {

using namespace pfx;

PfxVector3 toPfx(const Vec3& v) { return v.cast<PfxFloat>(); }
PfxQuat toPfx(const Quat& q) { return q.cast<PfxFloat>().normalized(); }

PfxShape makePfxShape(const ShapeDesc& shape) {
  const auto half = static_cast<PfxFloat>(shape.halfLength);
  const auto radius = static_cast<PfxFloat>(shape.radius);
  switch (shape.type) {
    case ShapeType::Sphere: return pfxMakeShape(PfxSphere(radius));
    case ShapeType::Box: return pfxMakeShape(PfxBox(toPfx(shape.halfExtents)));
    case ShapeType::Capsule: return pfxMakeShape(PfxCapsule(half, radius));
    case ShapeType::Cylinder: return pfxMakeShape(PfxCylinder(half, radius));
  }
  return pfxMakeShape(PfxSphere(radius));
}

class PfxEngine final : public Engine {
 public:
  bool build(const Scene& scene, const EngineSettings& settings, std::string& error) override {
    PfxWorldParam param;
    param.pipeline = kPfxPipelineStable;
    param.gravity = toPfx(scene.gravity);
    param.timeStep = static_cast<PfxFloat>(settings.dt / settings.substeps);
    param.iteration = static_cast<PfxUInt32>(settings.iterations);
    if (const PfxInt32 err = m_world.initialize(param); err != PFX_OK) {
      error = std::string("pfx: world parameters rejected: ") + pfxErrorString(err);
      return false;
    }
    m_substeps = settings.substeps;
    for (const BodyDesc& desc : scene.bodies) {
      PfxRigidState state;
      state.reset();
      state.setPosition(toPfx(desc.position));
      state.setOrientation(toPfx(desc.orientation));
      state.setLinearVelocity(toPfx(desc.linearVelocity));
      state.setAngularVelocity(toPfx(desc.angularVelocity));
      state.setMotionType(desc.fixed ? kPfxMotionTypeFixed : kPfxMotionTypeActive);
      PfxRigidBody body;
      body.reset();
      body.setFriction(static_cast<PfxFloat>(desc.friction));
      body.setRestitution(static_cast<PfxFloat>(desc.restitution));
      if (!desc.fixed) {
        body.setMass(static_cast<PfxFloat>(desc.mass));
        body.setInertia(toPfx(desc.inertia).asDiagonal());
      }
      const PfxShape shape = makePfxShape(desc.shape);
      if (const PfxInt32 err = m_world.addRigidBody(state, body, &shape, 1); err != PFX_OK) {
        error = std::string("pfx: body rejected: ") + pfxErrorString(err);
        return false;
      }
    }
    return true;
  }

  bool step(std::string& error) override {
    for (int i = 0; i < m_substeps; ++i) {
      if (const PfxInt32 err = m_world.step(); err != PFX_OK) {
        error = std::string("pfx: step failed: ") + pfxErrorString(err);
        return false;
      }
    }
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    states.resize(m_world.getNumRigidBodies());
    for (PfxUInt32 i = 0; i < m_world.getNumRigidBodies(); ++i) {
      const PfxRigidState& s = m_world.getRigidState(i);
      states[i].position = s.getPosition().cast<double>();
      states[i].orientation = s.getOrientation().cast<double>();
      states[i].linearVelocity = s.getLinearVelocity().cast<double>();
      states[i].angularVelocity = s.getAngularVelocity().cast<double>();
    }
  }

 private:
  PfxWorld m_world;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createPfxEngine() { return std::make_unique<PfxEngine>(); }

}  // namespace pfxbench
