// Mass, centre of mass and inertia of shapes, meshes and compounds (uniform density).
// Inertia tensors are about the centre of mass, in the frame the shape is given in.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/collision/pfx_convex_mesh.h"

namespace pfx {

class PfxShape;

PfxMatrix3 pfxCalcInertiaSphere(PfxFloat radius, PfxFloat mass);
PfxMatrix3 pfxCalcInertiaBox(const PfxVector3& halfExtent, PfxFloat mass);
// Capsule and cylinder lie along X, as the shapes do.
PfxMatrix3 pfxCalcInertiaCapsule(PfxFloat halfLength, PfxFloat radius, PfxFloat mass);
PfxMatrix3 pfxCalcInertiaCylinder(PfxFloat halfLength, PfxFloat radius, PfxFloat mass);

// Parallel-axis theorem: inertia about a point displaced by `offset` from the centre of mass.
PfxMatrix3 pfxMassTranslate(PfxFloat mass, const PfxMatrix3& inertia, const PfxVector3& offset);

struct PfxMassProperties {
  PfxFloat mass;
  PfxVector3 centerOfMass;
  PfxMatrix3 inertia;  // about centerOfMass
};

// A large mesh is an open surface for static ground: it has no volume and so no mass.
PfxFloat pfxCalcVolume(const PfxShape& shape);

// One shape of uniform density, including its offset pose.
PfxMassProperties pfxCalcMassProperties(const PfxShape& shape, PfxFloat density);

// A solid convex mesh of uniform density (divergence theorem over its triangles).
PfxMassProperties pfxCalcMassPropertiesConvexMesh(const PfxConvexMesh& mesh, PfxFloat density);

// Several shapes with a density each: masses add, the centre of mass is the mass-weighted
// mean, and each part's inertia is moved to it by the parallel-axis theorem. To put the
// body's origin at its centre of mass, shift each shape's offset by -centerOfMass.
PfxMassProperties pfxCalcMassPropertiesCompound(const PfxShape* shapes, const PfxFloat* densities,
                                                PfxUInt32 numShapes);

}  // namespace pfx
