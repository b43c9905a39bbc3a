#include "pfx/high_level/pfx_body_init.h"

#include "pfx/base_level/collision/pfx_mass_properties.h"

namespace pfx {

namespace {

template <typename Setter>
PfxShape makeShape(Setter set) {
  PfxShape shape;
  shape.reset();
  set(shape);
  return shape;
}

}  // namespace

PfxShape pfxMakeShape(const PfxSphere& sphere) {
  return makeShape([&](PfxShape& s) { s.setSphere(sphere); });
}
PfxShape pfxMakeShape(const PfxBox& box) {
  return makeShape([&](PfxShape& s) { s.setBox(box); });
}
PfxShape pfxMakeShape(const PfxCapsule& capsule) {
  return makeShape([&](PfxShape& s) { s.setCapsule(capsule); });
}
PfxShape pfxMakeShape(const PfxCylinder& cylinder) {
  return makeShape([&](PfxShape& s) { s.setCylinder(cylinder); });
}
PfxShape pfxMakeShape(const PfxConvexMesh* mesh) {
  return makeShape([&](PfxShape& s) { s.setConvexMesh(mesh); });
}

PfxInt32 pfxAddBody(PfxWorld& world, const PfxShape* shapes, PfxUInt32 numShapes,
                    const PfxBodyInit& init, PfxUInt32* outId) {
  if (!shapes) return PFX_ERR_NULL_POINTER;
  if (numShapes == 0 || numShapes > PFX_MAX_SHAPES_PER_COLLIDABLE) return PFX_ERR_OUT_OF_RANGE;
  if (!(init.mass >= 0) || !pfxIsFinite(init.mass)) return PFX_ERR_INVALID_VALUE;
  for (PfxUInt32 i = 0; i < numShapes; ++i) {
    if (const PfxInt32 err = shapes[i].validate(); err != PFX_OK) return err;
  }

  PfxRigidState state;
  state.reset();
  state.setPosition(init.position);
  state.setOrientation(init.orientation);
  state.setLinearVelocity(init.linearVelocity);
  state.setAngularVelocity(init.angularVelocity);
  state.setMotionType(init.mass > 0 ? init.motionType : kPfxMotionTypeFixed);

  PfxRigidBody body;
  body.reset();
  body.setFriction(init.friction);
  body.setRestitution(init.restitution);
  if (init.mass > 0) {
    // Inertia of the solid at unit density, scaled to the requested mass, about the origin.
    PfxFloat densities[PFX_MAX_SHAPES_PER_COLLIDABLE];
    for (PfxUInt32 i = 0; i < numShapes; ++i) densities[i] = 1;
    const PfxMassProperties unit = pfxCalcMassPropertiesCompound(shapes, densities, numShapes);
    if (!(unit.mass > 0)) return PFX_ERR_DEGENERATE;
    const PfxFloat scale = init.mass / unit.mass;
    body.setMass(init.mass);
    body.setInertia(pfxMassTranslate(init.mass, unit.inertia * scale, -unit.centerOfMass));
  }
  return world.addRigidBody(state, body, shapes, numShapes, outId);
}

}  // namespace pfx
