// The pair routines behind pfxContactConvexShapes. Each reports contacts with the normal
// pointing from its first shape to its second, through a PfxContactSink that keeps only
// those within the sink's threshold.
#pragma once

#include "base_level/collision/contact/pfx_contact_sink.h"
#include "pfx/base_level/collision/pfx_shape.h"

namespace pfx {

// Two swept spheres: a sphere is a zero-length segment, a capsule a segment (world end
// points) with a radius. When the segments touch, the normal is the common perpendicular
// of two crossing segments, or else A's +Y (then +Z) made perpendicular to the segments.
void pfxContactSweptSpheres(const PfxVector3& a0, const PfxVector3& a1, PfxFloat radiusA,
                            const PfxVector3& b0, const PfxVector3& b1, PfxFloat radiusB,
                            const PfxMatrix3& rotationA, PfxContactSink& sink);

// A box against a swept sphere (world end points p0, p1 of its segment). Exact closest
// points while the segment is outside the box, separating axes once it is inside.
void pfxContactBoxSweptSphere(const PfxVector3& half, const PfxTransform3& boxTransform,
                              const PfxVector3& p0, const PfxVector3& p1, PfxFloat radius,
                              PfxContactSink& sink);

// A cylinder (half length and radius along its X, world pose) against a sphere (world
// centre, radius), in closed form: the nearest point of the solid cylinder to the centre,
// or from inside the nearer of the cap and the side. EPA met the side's curve with facets
// and tilted the normal by up to 0.02 rad where the centre lay near the surface.
void pfxContactCylinderSphere(PfxFloat halfLen, PfxFloat radius,
                              const PfxTransform3& cylinderTransform, const PfxVector3& centre,
                              PfxFloat sphereRadius, PfxContactSink& sink);

// Two boxes (half extents, world poses): separating axes, then face clipping, as
// pfxContactPolyhedra does for any two polyhedra.
void pfxContactBoxBox(const PfxVector3& halfA, const PfxTransform3& transformA,
                      const PfxVector3& halfB, const PfxTransform3& transformB,
                      PfxContactSink& sink);

// Two polyhedra (boxes or convex meshes): separating axes, then face clipping.
void pfxContactPolyhedra(const PfxShape& shapeA, const PfxTransform3& transformA,
                         const PfxShape& shapeB, const PfxTransform3& transformB,
                         PfxContactSink& sink);

// Any two convex shapes: GJK distance, EPA depth, then clipping of the supporting faces.
void pfxContactConvexGeneral(const PfxShape& shapeA, const PfxTransform3& transformA,
                             const PfxShape& shapeB, const PfxTransform3& transformB,
                             PfxContactSink& sink);

// A convex shape against a large mesh: every triangle near the shape is a thin prism below
// its face; contacts on internal edges take the face normal. Reported mesh first (normal
// from the mesh to the convex shape), with the triangle and the point's corner weights.
void pfxContactLargeMesh(const PfxShape& meshShape, const PfxTransform3& meshTransform,
                         const PfxShape& convexShape, const PfxTransform3& convexTransform,
                         PfxContactSink& sink);

}  // namespace pfx
