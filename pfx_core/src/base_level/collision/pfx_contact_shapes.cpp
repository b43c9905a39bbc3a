#include "pfx/base_level/collision/pfx_contact_shapes.h"

#include <algorithm>

#include "base_level/collision/contact/pfx_contact_pairs.h"
#include "base_level/collision/pfx_contact_checked.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

namespace {

bool isSweptSphere(PfxShapeType type) {
  return type == kPfxShapeSphere || type == kPfxShapeCapsule;
}

// A box with a zero extent is left to GJK/EPA: its faces of zero area make the Gauss map
// of its edges meet only at arc ends, where the separating-axis pruning is not reliable.
bool isSolidPolyhedron(const PfxShape& shape) {
  return shape.getType() == kPfxShapeConvexMesh ||
         (shape.getType() == kPfxShapeBox && shape.getBox().m_half.minCoeff() > PFX_EPSILON);
}

// A mesh within the layout limits; pfxCreateConvexMesh builds only such meshes, but a
// hand-made one must not index past its arrays.
bool isUsableMesh(const PfxConvexMesh* mesh) {
  if (!mesh || mesh->m_numVerts == 0 || mesh->m_numFaces == 0 ||
      mesh->m_numVerts > PFX_CONVEX_MESH_MAX_VERTICES ||
      mesh->m_numFaces > PFX_CONVEX_MESH_MAX_FACETS ||
      mesh->m_numEdges > PFX_CONVEX_MESH_MAX_EDGES) {
    return false;
  }
  for (PfxUInt32 f = 0; f < mesh->m_numFaces; ++f) {
    const PfxUInt32 first = mesh->m_faceFirstVert[f];
    const PfxUInt32 count = mesh->m_faceNumVerts[f];
    if (count < 3 || first + count > PFX_CONVEX_MESH_MAX_FACE_VERTICES) return false;
    for (PfxUInt32 k = 0; k < count; ++k) {
      if (mesh->m_faceVertIds[first + k] >= mesh->m_numVerts) return false;
    }
  }
  for (PfxUInt32 e = 0; e < mesh->m_numEdges; ++e) {
    if (mesh->m_edgeVertIds[e][0] >= mesh->m_numVerts ||
        mesh->m_edgeVertIds[e][1] >= mesh->m_numVerts) {
      return false;
    }
  }
  return true;
}

bool isConvexShape(const PfxShape& shape) {
  if (shape.getType() == kPfxShapeLargeTriMesh || shape.validate() != PFX_OK) return false;
  return shape.getType() != kPfxShapeConvexMesh || isUsableMesh(shape.getConvexMesh());
}

bool isLargeMeshShape(const PfxShape& shape) {
  return shape.getType() == kPfxShapeLargeTriMesh && shape.validate() == PFX_OK &&
         shape.getLargeTriMesh()->m_numNodes > 0;
}

// The segment of a sphere (both ends at the centre) or a capsule, in the world.
void sweptSegment(const PfxShape& shape, const PfxTransform3& transform, PfxVector3& p0,
                  PfxVector3& p1, PfxFloat& radius) {
  const PfxFloat halfLen = shape.getType() == kPfxShapeCapsule ? shape.getCapsule().m_halfLen : 0;
  radius = shape.getType() == kPfxShapeCapsule ? shape.getCapsule().m_radius
                                               : shape.getSphere().m_radius;
  const PfxVector3 axis = transform.linear().col(0) * halfLen;
  p0 = transform.translation() - axis;
  p1 = transform.translation() + axis;
}

// Routes a checked pair to its routine, swapping the shapes where the routine wants a
// particular one first; the sink swaps the results back.
void contactPair(const PfxShape& shapeA, const PfxTransform3& transformA, const PfxShape& shapeB,
                 const PfxTransform3& transformB, PfxContactSink& sink) {
  const PfxShapeType typeA = shapeA.getType();
  const PfxShapeType typeB = shapeB.getType();
  if (isSweptSphere(typeA) && isSweptSphere(typeB)) {
    PfxVector3 a0, a1, b0, b1;
    PfxFloat radiusA, radiusB;
    sweptSegment(shapeA, transformA, a0, a1, radiusA);
    sweptSegment(shapeB, transformB, b0, b1, radiusB);
    pfxContactSweptSpheres(a0, a1, radiusA, b0, b1, radiusB, transformA.linear(), sink);
  } else if (typeA == kPfxShapeBox && isSweptSphere(typeB)) {
    PfxVector3 p0, p1;
    PfxFloat radius;
    sweptSegment(shapeB, transformB, p0, p1, radius);
    pfxContactBoxSweptSphere(shapeA.getBox().m_half, transformA, p0, p1, radius, sink);
  } else if (isSweptSphere(typeA) && typeB == kPfxShapeBox) {
    sink.setSwapped(true);
    contactPair(shapeB, transformB, shapeA, transformA, sink);
    sink.setSwapped(false);
  } else if (typeA == kPfxShapeCylinder && typeB == kPfxShapeSphere) {
    pfxContactCylinderSphere(shapeA.getCylinder().m_halfLen, shapeA.getCylinder().m_radius,
                             transformA, transformB.translation(), shapeB.getSphere().m_radius,
                             sink);
  } else if (typeA == kPfxShapeSphere && typeB == kPfxShapeCylinder) {
    sink.setSwapped(true);
    contactPair(shapeB, transformB, shapeA, transformA, sink);
    sink.setSwapped(false);
  } else if (isSolidPolyhedron(shapeA) && isSolidPolyhedron(shapeB)) {
    if (typeA == kPfxShapeBox && typeB == kPfxShapeBox) {
      pfxContactBoxBox(shapeA.getBox().m_half, transformA, shapeB.getBox().m_half, transformB,
                       sink);
      return;
    }
    pfxContactPolyhedra(shapeA, transformA, shapeB, transformB, sink);
  } else {
    pfxContactConvexGeneral(shapeA, transformA, shapeB, transformB, sink);
  }
}

// The world bounds of two shapes (body-frame bounds from getAabb), grown by `threshold`,
// overlap.
bool boundsOverlap(const PfxVector3& centreA, const PfxVector3& halfA,
                   const PfxTransform3& transformA, const PfxVector3& centreB,
                   const PfxVector3& halfB, const PfxTransform3& transformB, PfxFloat threshold) {
  const PfxVector3 worldCentreA = transformA * centreA;
  const PfxVector3 worldCentreB = transformB * centreB;
  const PfxVector3 reach = transformA.linear().cwiseAbs() * halfA +
                           transformB.linear().cwiseAbs() * halfB +
                           PfxVector3::Constant(threshold);
  return ((worldCentreB - worldCentreA).cwiseAbs().array() <= reach.array()).all();
}

}  // namespace

PfxUInt32 pfxContactConvexShapes(const PfxShape& shapeA, const PfxTransform3& transformA,
                                 const PfxShape& shapeB, const PfxTransform3& transformB,
                                 PfxFloat contactThreshold, PfxContactCandidate* out,
                                 PfxUInt32 maxOut) {
  // The count return leaves no room for an error code: input that cannot be measured
  // (null output, NaN poses or sizes, a negative threshold, a large mesh) gives no contact.
  if (!out || maxOut == 0 || !(contactThreshold >= 0) || !pfxIsFinite(contactThreshold)) return 0;
  if (!isConvexShape(shapeA) || !isConvexShape(shapeB)) return 0;
  if (!pfxIsRigidTransform(transformA) || !pfxIsRigidTransform(transformB)) return 0;
  return pfxContactCheckedConvexShapes(shapeA, transformA, shapeB, transformB, contactThreshold,
                                       out, maxOut);
}

PfxUInt32 pfxContactCheckedConvexShapes(const PfxShape& shapeA, const PfxTransform3& transformA,
                                        const PfxShape& shapeB, const PfxTransform3& transformB,
                                        PfxFloat contactThreshold, PfxContactCandidate* out,
                                        PfxUInt32 maxOut) {
  PfxContactSink sink(out, std::min(maxOut, PFX_MAX_CONTACT_CANDIDATES), contactThreshold);
  contactPair(shapeA, transformA, shapeB, transformB, sink);
  return sink.getCount();
}

namespace {

// Whether a shape of a collidable takes part in contacts, whether it is a large mesh, and
// its bounds in the body's frame; validated once for all that (getAabb is most of the check).
struct ShapeUse {
  bool usable = false;
  bool mesh = false;
  PfxVector3 centre;
  PfxVector3 half;
};

// With `shapesChecked`, the shape passed pfxIsContactShape already.
ShapeUse useShape(const PfxShape& shape, bool shapesChecked) {
  ShapeUse use;
  use.mesh = shape.getType() == kPfxShapeLargeTriMesh;
  if (shapesChecked) {
    use.usable = true;
    shape.getAabb(use.centre, use.half);
  } else if (shape.validate(use.centre, use.half) == PFX_OK) {
    // As isLargeMeshShape and isConvexShape decide, past validate.
    use.usable = use.mesh ? shape.getLargeTriMesh()->m_numNodes > 0
                          : shape.getType() != kPfxShapeConvexMesh ||
                                isUsableMesh(shape.getConvexMesh());
  }
  return use;
}

PfxUInt32 contactCollidables(const PfxCollidable& collidableA, const PfxTransform3& transformA,
                             const PfxCollidable& collidableB, const PfxTransform3& transformB,
                             PfxFloat contactThreshold, PfxContactCandidate* out,
                             PfxUInt32 maxOut, bool shapesChecked) {
  // One sink for all shape pairs: when more contacts come than fit, the deepest stay.
  PfxContactSink sink(out, maxOut, contactThreshold);
  // A large mesh meets convex shapes only: two meshes have no inside to push apart.
  for (PfxUInt32 i = 0; i < collidableA.getNumShapes(); ++i) {
    const PfxShape& shapeA = collidableA.getShape(i);
    const ShapeUse useA = useShape(shapeA, shapesChecked);
    if (!useA.usable) continue;
    const PfxTransform3 poseA = transformA * shapeA.getOffsetTransform();
    for (PfxUInt32 j = 0; j < collidableB.getNumShapes(); ++j) {
      const PfxShape& shapeB = collidableB.getShape(j);
      if (useA.mesh && shapeB.getType() == kPfxShapeLargeTriMesh) continue;
      const ShapeUse useB = useShape(shapeB, shapesChecked);
      if (!useB.usable) continue;
      if (!boundsOverlap(useA.centre, useA.half, transformA, useB.centre, useB.half, transformB,
                         contactThreshold)) {
        continue;
      }
      sink.setShapeIds(static_cast<PfxUInt8>(i), static_cast<PfxUInt8>(j));
      const PfxTransform3 poseB = transformB * shapeB.getOffsetTransform();
      if (useA.mesh) {
        pfxContactLargeMesh(shapeA, poseA, shapeB, poseB, sink);
      } else if (useB.mesh) {
        sink.setSwapped(true);
        pfxContactLargeMesh(shapeB, poseB, shapeA, poseA, sink);
        sink.setSwapped(false);
      } else {
        contactPair(shapeA, poseA, shapeB, poseB, sink);
      }
    }
  }
  return sink.getCount();
}

}  // namespace

PfxUInt32 pfxContactCollidables(const PfxCollidable& collidableA, const PfxTransform3& transformA,
                                const PfxCollidable& collidableB, const PfxTransform3& transformB,
                                PfxFloat contactThreshold, PfxContactCandidate* out,
                                PfxUInt32 maxOut) {
  if (!out || maxOut == 0 || !(contactThreshold >= 0) || !pfxIsFinite(contactThreshold)) return 0;
  if (!pfxIsRigidTransform(transformA) || !pfxIsRigidTransform(transformB)) return 0;
  return contactCollidables(collidableA, transformA, collidableB, transformB, contactThreshold,
                            out, maxOut, false);
}

PfxUInt32 pfxContactCheckedCollidables(const PfxCollidable& collidableA,
                                       const PfxTransform3& transformA,
                                       const PfxCollidable& collidableB,
                                       const PfxTransform3& transformB, PfxFloat contactThreshold,
                                       PfxContactCandidate* out, PfxUInt32 maxOut) {
  return contactCollidables(collidableA, transformA, collidableB, transformB, contactThreshold,
                            out, maxOut, true);
}

bool pfxIsRigidTransform(const PfxTransform3& t) {
  return pfxIsFinite(PfxVector3(t.translation())) && pfxIsFinite(PfxMatrix3(t.linear())) &&
         (t.linear() * t.linear().transpose() - PfxMatrix3::Identity()).cwiseAbs().maxCoeff() <
             PfxFloat(1e-3);
}

bool pfxIsContactShape(const PfxShape& shape) {
  return isConvexShape(shape) || isLargeMeshShape(shape);
}

}  // namespace pfx
