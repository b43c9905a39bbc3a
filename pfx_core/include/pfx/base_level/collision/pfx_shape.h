// One collision shape and its pose relative to the rigid body (seed chapter 2, "Shape").
// Geometric shapes are stored by value; meshes by pointer, owned by the application.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/collision/pfx_box.h"
#include "pfx/base_level/collision/pfx_capsule.h"
#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx/base_level/collision/pfx_cylinder.h"
#include "pfx/base_level/collision/pfx_sphere.h"

namespace pfx {

struct PfxLargeTriMesh;

// How far a shape may reach from its body's origin (m): its bounds, offset included, lie
// within this of it. A contact's lever arm is at most that long, and in float its rounding
// (a metre at 1e7 m) is then still small beside the shapes it pushes apart; a saved sphere
// of radius 3.5e12 m overlapped every body by as much, and the split impulses, pushing along
// arms whose rounding was hundreds of kilometres, sent them to NaN in the first step.
constexpr PfxFloat kPfxMaxShapeReach = PfxFloat(1e7);

enum PfxShapeType : PfxUInt8 {
  kPfxShapeSphere = 0,
  kPfxShapeBox,
  kPfxShapeCapsule,
  kPfxShapeCylinder,
  kPfxShapeConvexMesh,
  kPfxShapeLargeTriMesh,
  kPfxShapeCount
};

class PfxShape {
 public:
  void reset();

  void setSphere(const PfxSphere& sphere);
  void setBox(const PfxBox& box);
  void setCapsule(const PfxCapsule& capsule);
  void setCylinder(const PfxCylinder& cylinder);
  void setConvexMesh(const PfxConvexMesh* mesh);
  void setLargeTriMesh(const PfxLargeTriMesh* mesh);

  PfxShapeType getType() const { return static_cast<PfxShapeType>(m_type); }
  PfxSphere getSphere() const { return PfxSphere(m_vecData[0]); }
  PfxBox getBox() const { return PfxBox(m_vecData[0], m_vecData[1], m_vecData[2]); }
  PfxCapsule getCapsule() const { return PfxCapsule(m_vecData[0], m_vecData[1]); }
  PfxCylinder getCylinder() const { return PfxCylinder(m_vecData[0], m_vecData[1]); }
  const PfxConvexMesh* getConvexMesh() const { return m_convexMesh; }
  const PfxLargeTriMesh* getLargeTriMesh() const { return m_largeMesh; }

  void setOffsetPosition(const PfxVector3& p) { m_offsetPosition = p; }
  void setOffsetOrientation(const PfxQuat& q) { m_offsetOrientation = q; }
  const PfxVector3& getOffsetPosition() const { return m_offsetPosition; }
  const PfxQuat& getOffsetOrientation() const { return m_offsetOrientation; }
  PfxTransform3 getOffsetTransform() const {
    return pfxMakeTransform(m_offsetOrientation, m_offsetPosition);
  }

  // Bounds in the frame of the rigid body (offset included).
  void getAabb(PfxVector3& center, PfxVector3& half) const;

  // Finite, non-negative sizes, a unit offset orientation, a mesh where one is named, and
  // bounds within kPfxMaxShapeReach of the body's origin.
  PfxInt32 validate() const;
  // The same, and where it returns PFX_OK the bounds getAabb gives, which it computes anyway.
  PfxInt32 validate(PfxVector3& center, PfxVector3& half) const;

 private:
  PfxVector3 m_offsetPosition;
  PfxQuat m_offsetOrientation;
  PfxFloat m_vecData[3];
  const PfxConvexMesh* m_convexMesh;
  const PfxLargeTriMesh* m_largeMesh;
  PfxUInt8 m_type;
};

// The point of a convex shape placed at `transform` (its offset already applied) that lies
// furthest along `direction`: the lowest point of a body for direction -up, for example.
// Large meshes are not convex and give their bounding box's corner.
PfxVector3 pfxGetSupportPoint(const PfxShape& shape, const PfxTransform3& transform,
                              const PfxVector3& direction);

}  // namespace pfx
