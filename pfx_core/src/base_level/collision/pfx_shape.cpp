#include "pfx/base_level/collision/pfx_shape.h"

#include <algorithm>
#include <cstring>

#include "base_level/collision/contact/pfx_convex_core.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

void PfxShape::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_offsetPosition.setZero();
  m_offsetOrientation.setIdentity();
  m_type = kPfxShapeSphere;
}

void PfxShape::setSphere(const PfxSphere& sphere) {
  m_type = kPfxShapeSphere;
  m_vecData[0] = sphere.m_radius;
  m_vecData[1] = m_vecData[2] = 0;
}

void PfxShape::setBox(const PfxBox& box) {
  m_type = kPfxShapeBox;
  m_vecData[0] = box.m_half[0];
  m_vecData[1] = box.m_half[1];
  m_vecData[2] = box.m_half[2];
}

void PfxShape::setCapsule(const PfxCapsule& capsule) {
  m_type = kPfxShapeCapsule;
  m_vecData[0] = capsule.m_halfLen;
  m_vecData[1] = capsule.m_radius;
  m_vecData[2] = 0;
}

void PfxShape::setCylinder(const PfxCylinder& cylinder) {
  m_type = kPfxShapeCylinder;
  m_vecData[0] = cylinder.m_halfLen;
  m_vecData[1] = cylinder.m_radius;
  m_vecData[2] = 0;
}

void PfxShape::setConvexMesh(const PfxConvexMesh* mesh) {
  m_type = kPfxShapeConvexMesh;
  m_convexMesh = mesh;
}

void PfxShape::setLargeTriMesh(const PfxLargeTriMesh* mesh) {
  m_type = kPfxShapeLargeTriMesh;
  m_largeMesh = mesh;
}

PfxInt32 PfxShape::validate() const {
  PfxVector3 center, half;
  return validate(center, half);
}

PfxInt32 PfxShape::validate(PfxVector3& center, PfxVector3& half) const {
  if (m_type >= kPfxShapeCount) return PFX_ERR_INVALID_FLAG;
  if (!pfxIsFinite(m_offsetPosition) || !pfxIsUnitQuat(m_offsetOrientation)) {
    return PFX_ERR_INVALID_VALUE;
  }
  int numSizes = 0;
  switch (m_type) {
    case kPfxShapeSphere: numSizes = 1; break;
    case kPfxShapeBox: numSizes = 3; break;
    case kPfxShapeCapsule:
    case kPfxShapeCylinder: numSizes = 2; break;
    case kPfxShapeConvexMesh:
      if (!m_convexMesh) return PFX_ERR_NULL_POINTER;
      break;
    case kPfxShapeLargeTriMesh:
      if (!m_largeMesh) return PFX_ERR_NULL_POINTER;
      break;
    default: break;
  }
  for (int i = 0; i < numSizes; ++i) {
    if (!pfxIsFinite(m_vecData[i]) || m_vecData[i] < 0) return PFX_ERR_INVALID_VALUE;
  }
  // The bounds the collidable takes from the shape, as PfxCollidable::finish sums them, must
  // be finite too: a convex mesh at an offset of -3.4e38 passed the checks above, the sum of
  // its box's corners overflowed to infinity, and the step of the world holding it failed.
  getAabb(center, half);
  const PfxVector3 lo = center - half, hi = center + half;
  if (!pfxIsFinite(PfxVector3(lo + hi)) || !pfxIsFinite(PfxVector3(hi - lo))) {
    return PFX_ERR_INVALID_VALUE;
  }
  const PfxFloat reach = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  if (reach > kPfxMaxShapeReach) return PFX_ERR_INVALID_VALUE;
  return PFX_OK;
}

void PfxShape::getAabb(PfxVector3& center, PfxVector3& half) const {
  // Bounds in the shape's own frame, then rotated into the body frame: the rotated box of
  // half extents h has half extents |R| h.
  PfxVector3 localCenter = PfxVector3::Zero();
  PfxVector3 localHalf;
  switch (m_type) {
    case kPfxShapeSphere: localHalf.setConstant(m_vecData[0]); break;
    case kPfxShapeBox: localHalf = PfxVector3(m_vecData[0], m_vecData[1], m_vecData[2]); break;
    case kPfxShapeCapsule:
    case kPfxShapeCylinder:
      localHalf = PfxVector3(m_vecData[0] + (m_type == kPfxShapeCapsule ? m_vecData[1] : 0),
                             m_vecData[1], m_vecData[1]);
      break;
    case kPfxShapeConvexMesh:
      localCenter = m_convexMesh->m_aabbCenter;
      localHalf = m_convexMesh->m_aabbHalf;
      break;
    case kPfxShapeLargeTriMesh: {
      // The prisms reach `thickness` below the faces, in whatever direction they face.
      const PfxLargeTriMesh& mesh = *m_largeMesh;
      localCenter = (mesh.m_aabbMin + mesh.m_aabbMax) * PfxFloat(0.5);
      localHalf = (mesh.m_aabbMax - mesh.m_aabbMin) * PfxFloat(0.5) +
                  PfxVector3::Constant(mesh.m_thickness);
      break;
    }
    default: localHalf.setZero(); break;
  }
  const PfxMatrix3 rotation = m_offsetOrientation.toRotationMatrix();
  center = m_offsetPosition + rotation * localCenter;
  half = rotation.cwiseAbs() * localHalf;
}

PfxVector3 pfxGetSupportPoint(const PfxShape& shape, const PfxTransform3& transform,
                              const PfxVector3& direction) {
  if (shape.getType() == kPfxShapeLargeTriMesh) {
    PfxVector3 center, half;
    shape.getAabb(center, half);
    const PfxVector3 local = transform.linear().transpose() * direction;
    return transform * (center + half.cwiseProduct(local.cwiseSign()));
  }
  PfxConvexCore core;
  core.set(shape, transform);
  const PfxFloat length = direction.norm();
  const PfxVector3 unit = length > 0 ? PfxVector3(direction / length) : PfxVector3::Zero();
  return core.support(direction) + core.m_radius * unit;
}

}  // namespace pfx
