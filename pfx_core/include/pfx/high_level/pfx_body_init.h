// Shortcuts for the common case of a body with one shape whose mass properties follow
// from the shape: one call instead of filling a state, a body and a collidable by hand.
#pragma once

#include "pfx/high_level/pfx_world.h"

namespace pfx {

PfxShape pfxMakeShape(const PfxSphere& sphere);
PfxShape pfxMakeShape(const PfxBox& box);
PfxShape pfxMakeShape(const PfxCapsule& capsule);
PfxShape pfxMakeShape(const PfxCylinder& cylinder);
PfxShape pfxMakeShape(const PfxConvexMesh* mesh);

struct PfxBodyInit {
  PfxVector3 position = PfxVector3::Zero();
  PfxQuat orientation = PfxQuat::Identity();
  PfxVector3 linearVelocity = PfxVector3::Zero();
  PfxVector3 angularVelocity = PfxVector3::Zero();
  PfxFloat mass = 1;  // 0 makes a fixed body
  PfxFloat friction = PfxFloat(0.6);
  PfxFloat restitution = 0;
  // Used when mass > 0; fixed otherwise. Keyframe, one-way and trigger bodies say so here.
  PfxMotionType motionType = kPfxMotionTypeActive;
};

// Adds a body of one shape (or a compound) with the inertia of a uniform solid of the
// given mass, about the body's origin. The shapes' offsets should put their common centre
// of mass at the origin; use pfxCalcMassPropertiesCompound to find it.
PfxInt32 pfxAddBody(PfxWorld& world, const PfxShape* shapes, PfxUInt32 numShapes,
                    const PfxBodyInit& init, PfxUInt32* outId = nullptr);

inline PfxInt32 pfxAddBody(PfxWorld& world, const PfxShape& shape, const PfxBodyInit& init,
                           PfxUInt32* outId = nullptr) {
  return pfxAddBody(world, &shape, 1, init, outId);
}

}  // namespace pfx
