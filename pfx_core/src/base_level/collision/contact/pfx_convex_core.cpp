#include "base_level/collision/contact/pfx_convex_core.h"

#include <cmath>

namespace pfx {

namespace {

// Faces are used only when they lie within about 11.5 degrees of the contact plane: a
// shape tipped further touches along an edge or a rim point, which the single deepest
// point describes better than a clipped polygon.
constexpr PfxFloat kFaceCosine = PfxFloat(0.98);
constexpr PfxFloat kSideSine = PfxFloat(0.2);

PfxFloat signOf(PfxFloat x) { return x < 0 ? PfxFloat(-1) : PfxFloat(1); }

}  // namespace

void PfxConvexCore::set(const PfxShape& shape, const PfxTransform3& transform) {
  m_type = shape.getType();
  m_rotation = transform.linear();
  m_position = transform.translation();
  m_mesh = nullptr;
  m_radius = 0;
  m_size.setZero();
  switch (m_type) {
    case kPfxShapeSphere: m_radius = shape.getSphere().m_radius; break;
    case kPfxShapeBox: m_size = shape.getBox().m_half; break;
    case kPfxShapeCapsule:
      m_size[0] = shape.getCapsule().m_halfLen;
      m_radius = shape.getCapsule().m_radius;
      break;
    case kPfxShapeCylinder:
      m_size = PfxVector3(shape.getCylinder().m_halfLen, shape.getCylinder().m_radius, 0);
      break;
    default: m_mesh = shape.getConvexMesh(); break;
  }
}

PfxFloat PfxConvexCore::boundingRadius() const {
  if (m_mesh) {
    return (m_mesh->m_aabbCenter.cwiseAbs() + m_mesh->m_aabbHalf).norm();
  }
  if (m_type == kPfxShapeCylinder) return std::hypot(m_size[0], m_size[1]);
  return m_size.norm() + m_radius;
}

PfxVector3 PfxConvexCore::supportLocal(const PfxVector3& dir) const {
  switch (m_type) {
    case kPfxShapeSphere: return PfxVector3::Zero();
    case kPfxShapeBox:
      return PfxVector3(signOf(dir[0]) * m_size[0], signOf(dir[1]) * m_size[1],
                        signOf(dir[2]) * m_size[2]);
    case kPfxShapeCapsule: return PfxVector3(signOf(dir[0]) * m_size[0], 0, 0);
    case kPfxShapeCylinder: {
      // The rim is the support unless the direction lies along the axis to rounding, judged
      // against the direction's axial part: GJK asks along its closest point, a few
      // hundredths of a millimetre long near contact, and an absolute floor there took the
      // cap's centre for the support, so two overlapping cylinders seemed 0.04 mm apart.
      const PfxFloat radial = std::hypot(dir[1], dir[2]);
      PfxVector3 point(signOf(dir[0]) * m_size[0], 0, 0);
      if (radial > PFX_EPSILON * std::abs(dir[0])) {
        point[1] = m_size[1] * (dir[1] / radial);
        point[2] = m_size[1] * (dir[2] / radial);
      }
      return point;
    }
    default: {
      PfxUInt32 best = 0;
      PfxFloat bestDot = dir.dot(m_mesh->m_verts[0]);
      for (PfxUInt32 v = 1; v < m_mesh->m_numVerts; ++v) {
        const PfxFloat d = dir.dot(m_mesh->m_verts[v]);
        if (d > bestDot) {
          bestDot = d;
          best = v;
        }
      }
      return m_mesh->m_verts[best];
    }
  }
}

PfxUInt32 PfxConvexCore::supportingFace(const PfxVector3& worldDir, PfxVector3* points,
                                        PfxVector3& faceNormal) const {
  const PfxVector3 dir = m_rotation.transpose() * worldDir;
  PfxVector3 local[PFX_MAX_SUPPORTING_FACE_POINTS];
  PfxVector3 localNormal;
  PfxUInt32 count = 0;
  switch (m_type) {
    case kPfxShapeBox: {
      int axis = 0;
      for (int i = 1; i < 3; ++i) {
        if (std::abs(dir[i]) > std::abs(dir[axis])) axis = i;
      }
      const int j = (axis + 1) % 3;
      const int k = (axis + 2) % 3;
      if (std::abs(dir[axis]) < kFaceCosine) break;
      localNormal.setZero();
      localNormal[axis] = signOf(dir[axis]);
      PfxVector3 centre = PfxVector3::Zero();
      centre[axis] = localNormal[axis] * m_size[axis];
      PfxVector3 alongJ = PfxVector3::Zero();
      PfxVector3 alongK = PfxVector3::Zero();
      alongJ[j] = m_size[j];
      alongK[k] = m_size[k];
      // A flat box's side is a segment; a box of zero size has no face.
      const bool wideJ = m_size[j] > PFX_EPSILON;
      const bool wideK = m_size[k] > PFX_EPSILON;
      if (wideJ && wideK) {
        local[count++] = centre - alongJ - alongK;
        local[count++] = centre + alongJ - alongK;
        local[count++] = centre + alongJ + alongK;
        local[count++] = centre - alongJ + alongK;
      } else if (wideJ || wideK) {
        const PfxVector3 along = wideJ ? alongJ : alongK;
        local[count++] = centre - along;
        local[count++] = centre + along;
      }
      break;
    }
    case kPfxShapeCapsule:
    case kPfxShapeCylinder: {
      const PfxFloat radial = std::hypot(dir[1], dir[2]);
      const PfxFloat halfLen = m_size[0];
      const PfxFloat radius = m_size[1];
      if (m_type == kPfxShapeCylinder && std::abs(dir[0]) >= kFaceCosine &&
          radius > PFX_EPSILON) {
        localNormal = PfxVector3(signOf(dir[0]), 0, 0);
        for (PfxUInt32 c = 0; c < PFX_CYLINDER_CAP_POINTS; ++c) {
          const PfxFloat angle = PfxFloat(2) * PFX_PI * PfxFloat(c) / PFX_CYLINDER_CAP_POINTS;
          local[count++] = PfxVector3(localNormal[0] * halfLen, radius * std::cos(angle),
                                      radius * std::sin(angle));
        }
      } else if (std::abs(dir[0]) <= kSideSine && halfLen > PFX_EPSILON) {
        localNormal = PfxVector3(0, dir[1] / radial, dir[2] / radial);
        const PfxVector3 side = m_type == kPfxShapeCylinder
                                    ? PfxVector3(localNormal * radius)
                                    : PfxVector3::Zero();
        local[count++] = PfxVector3(-halfLen, 0, 0) + side;
        local[count++] = PfxVector3(halfLen, 0, 0) + side;
      }
      break;
    }
    case kPfxShapeConvexMesh: {
      PfxUInt32 best = 0;
      for (PfxUInt32 f = 1; f < m_mesh->m_numFaces; ++f) {
        if (dir.dot(m_mesh->m_faceNormals[f]) > dir.dot(m_mesh->m_faceNormals[best])) best = f;
      }
      if (dir.dot(m_mesh->m_faceNormals[best]) < kFaceCosine) break;
      localNormal = m_mesh->m_faceNormals[best];
      const PfxUInt32 first = m_mesh->m_faceFirstVert[best];
      const PfxUInt32 size = m_mesh->m_faceNumVerts[best];
      for (PfxUInt32 k = 0; k < size && count < PFX_MAX_SUPPORTING_FACE_POINTS; ++k) {
        local[count++] = m_mesh->m_verts[m_mesh->m_faceVertIds[first + k]];
      }
      break;
    }
    default: break;
  }
  if (count < 2) return 0;
  faceNormal = m_rotation * localNormal;
  // A swept radius moves the face out along the contact direction.
  const PfxVector3 offset = m_position + worldDir * m_radius;
  for (PfxUInt32 k = 0; k < count; ++k) points[k] = m_rotation * local[k] + offset;
  return count;
}

}  // namespace pfx
