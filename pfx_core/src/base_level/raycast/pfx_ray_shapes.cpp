#include "pfx/base_level/raycast/pfx_ray_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

namespace {

// The shape tests run in double whatever PfxFloat is: a float ray that starts 10 m from a
// 5 cm sphere would otherwise lose two digits of its normal to the rounding of the frame
// change alone, and the cost is a few conversions per shape.
using Real = double;
using Vec2 = Eigen::Matrix<Real, 2, 1>;
using Vec3 = Eigen::Matrix<Real, 3, 1>;

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

// Where the line m + t d (m: start relative to the centre) enters and leaves the ball of
// `radius`, in 2 or 3 dimensions; false when it passes outside. The discriminant comes
// from the line's distance to the centre, taken from the part of m perpendicular to d,
// and the near root from c / q: both keep their digits when the start lies far from a
// small ball, where the textbook b^2 - ac cancels (Haines et al., Ray Tracing Gems ch. 7).
// `d` must not be zero.
template <typename Vector>
bool intersectLineBall(const Vector& m, const Vector& d, Real radius, Real& tIn, Real& tOut) {
  const Real a = d.squaredNorm();
  const Real b = m.dot(d);
  const Vector perpendicular = m - (b / a) * d;
  const Real radiusSq = radius * radius;
  const Real h = radiusSq - perpendicular.squaredNorm();
  if (h < 0) return false;
  const Real q = -(b + std::copysign(std::sqrt(a * h), b));
  if (q == 0) {
    // b == 0 and h == 0: the start itself is the point of tangency.
    tIn = tOut = 0;
    return true;
  }
  const Real c = m.squaredNorm() - radiusSq;
  const Real t0 = q / a;
  const Real t1 = c / q;
  tIn = std::min(t0, t1);
  tOut = std::max(t0, t1);
  return true;
}

// Below this squared length a direction across the cylinder's axis is taken as parallel
// to it: dividing by it would overflow.
bool isParallelToAxis(Real acrossSq) { return acrossSq < std::numeric_limits<Real>::min(); }

// A unit vector along `v`, or against the ray where `v` is zero (a hit at the centre of a
// zero-radius shape, which has no surface direction of its own).
Vec3 unitOr(const Vec3& v, const Vec3& direction) {
  const Real lengthSq = v.squaredNorm();
  if (lengthSq > 0) return v / std::sqrt(lengthSq);
  return -direction.normalized();
}

bool acceptEntry(Real tIn, Real maxFraction) { return tIn >= 0 && tIn <= maxFraction; }

bool castSphere(Real radius, const Vec3& start, const Vec3& direction, Real& fraction,
                Vec3& normal) {
  Real tIn, tOut;
  if (!intersectLineBall(start, direction, radius, tIn, tOut)) return false;
  if (!acceptEntry(tIn, fraction)) return false;
  fraction = tIn;
  normal = unitOr(start + tIn * direction, direction);
  return true;
}

bool castBox(const Vec3& half, const Vec3& start, const Vec3& direction, Real& fraction,
             Vec3& normal) {
  Real tIn = -kInfinity;
  Real tOut = kInfinity;
  int entryAxis = -1;
  for (int axis = 0; axis < 3; ++axis) {
    const Real s = start[axis];
    const Real d = direction[axis];
    if (d == 0) {
      if (s < -half[axis] || s > half[axis]) return false;
      continue;
    }
    Real t0 = (-half[axis] - s) / d;
    Real t1 = (half[axis] - s) / d;
    if (t0 > t1) std::swap(t0, t1);
    // Strictly greater: on a tie at an edge or corner the first axis keeps the normal.
    if (t0 > tIn) {
      tIn = t0;
      entryAxis = axis;
    }
    tOut = std::min(tOut, t1);
  }
  if (entryAxis < 0 || tIn > tOut || !acceptEntry(tIn, fraction)) return false;
  fraction = tIn;
  normal.setZero();
  normal[entryAxis] = direction[entryAxis] > 0 ? -1 : 1;
  return true;
}

bool castCapsule(Real h, Real r, const Vec3& start, const Vec3& direction, Real& fraction,
                 Vec3& normal) {
  // The capsule is convex and the union of its side (between x = -h and x = h) and two
  // end spheres, so the line enters it at the earliest entry into any piece it meets.
  Real tIn = kInfinity;
  Real sphereX = 0;
  bool onSide = false;
  const Vec2 across(direction[1], direction[2]);
  Real t0, t1;
  if (!isParallelToAxis(across.squaredNorm()) &&
      intersectLineBall(Vec2(start[1], start[2]), across, r, t0, t1)) {
    const Real x = start[0] + t0 * direction[0];
    if (x >= -h && x <= h) {
      tIn = t0;
      onSide = true;
    }
  }
  for (Real endX : {-h, h}) {
    const Vec3 relative(start[0] - endX, start[1], start[2]);
    if (intersectLineBall(relative, direction, r, t0, t1) && t0 < tIn) {
      tIn = t0;
      sphereX = endX;
      onSide = false;
    }
  }
  if (!acceptEntry(tIn, fraction)) return false;
  fraction = tIn;
  const Vec3 point = start + tIn * direction;
  normal = unitOr(onSide ? Vec3(0, point[1], point[2]) : Vec3(point[0] - sphereX, point[1], point[2]),
                  direction);
  return true;
}

bool castCylinder(Real h, Real r, const Vec3& start, const Vec3& direction, Real& fraction,
                  Vec3& normal) {
  Real tIn = -kInfinity;
  Real tOut = kInfinity;
  bool onCap = false;
  if (direction[0] == 0) {
    if (start[0] < -h || start[0] > h) return false;
  } else {
    const Real t0 = (-h - start[0]) / direction[0];
    const Real t1 = (h - start[0]) / direction[0];
    tIn = std::min(t0, t1);
    tOut = std::max(t0, t1);
    onCap = true;
  }
  const Vec2 startAcross(start[1], start[2]);
  const Vec2 across(direction[1], direction[2]);
  if (isParallelToAxis(across.squaredNorm())) {
    if (startAcross.squaredNorm() > r * r) return false;
  } else {
    Real t0, t1;
    if (!intersectLineBall(startAcross, across, r, t0, t1)) return false;
    // Strictly greater: a ray entering exactly at the rim keeps the cap's normal.
    if (t0 > tIn) {
      tIn = t0;
      onCap = false;
    }
    tOut = std::min(tOut, t1);
  }
  if (tIn > tOut || !acceptEntry(tIn, fraction)) return false;
  fraction = tIn;
  if (onCap) {
    normal = Vec3(direction[0] > 0 ? -1 : 1, 0, 0);
  } else {
    const Vec3 point = start + tIn * direction;
    normal = unitOr(Vec3(0, point[1], point[2]), direction);
  }
  return true;
}

bool castConvexMesh(const PfxConvexMesh& mesh, const Vec3& start, const Vec3& direction,
                    Real& fraction, Vec3& normal) {
  Real tIn = -kInfinity;
  Real tOut = kInfinity;
  int entryFace = -1;
  for (int face = 0; face < mesh.m_numFaces; ++face) {
    const Vec3 faceNormal = mesh.m_faceNormals[face].cast<Real>();
    const Real height = faceNormal.dot(start) - Real(mesh.m_facePlaneDist[face]);
    const Real approach = faceNormal.dot(direction);
    if (approach == 0) {
      if (height > 0) return false;
      continue;
    }
    const Real t = -height / approach;
    if (approach < 0) {
      if (t > tIn) {
        tIn = t;
        entryFace = face;
      }
    } else {
      tOut = std::min(tOut, t);
    }
    if (tIn > tOut || tIn > fraction || tOut < 0) return false;
  }
  if (entryFace < 0 || !acceptEntry(tIn, fraction)) return false;
  fraction = tIn;
  normal = mesh.m_faceNormals[entryFace].cast<Real>();
  return true;
}

// Runs a double-precision test on a PfxFloat ray under the public contract: the fraction
// is read as the limit and written back only on a hit. Rounding the double fraction to
// PfxFloat keeps it within [0, limit], since the limit is itself a PfxFloat.
template <typename Cast>
bool castPublic(const PfxVector3& start, const PfxVector3& direction, PfxFloat& fraction,
                PfxVector3& normal, Cast cast) {
  Real t = fraction;
  Vec3 n;
  if (!cast(start.cast<Real>(), direction.cast<Real>(), t, n)) return false;
  fraction = static_cast<PfxFloat>(t);
  normal = n.cast<PfxFloat>();
  return true;
}

// The shape at the origin of its frame, with the ray already in that frame.
bool castLocal(const PfxShape& shape, const Vec3& start, const Vec3& direction, Real& fraction,
               Vec3& normal) {
  switch (shape.getType()) {
    case kPfxShapeSphere:
      return castSphere(shape.getSphere().m_radius, start, direction, fraction, normal);
    case kPfxShapeBox:
      return castBox(shape.getBox().m_half.cast<Real>(), start, direction, fraction, normal);
    case kPfxShapeCapsule: {
      const PfxCapsule capsule = shape.getCapsule();
      return castCapsule(capsule.m_halfLen, capsule.m_radius, start, direction, fraction, normal);
    }
    case kPfxShapeCylinder: {
      const PfxCylinder cylinder = shape.getCylinder();
      return castCylinder(cylinder.m_halfLen, cylinder.m_radius, start, direction, fraction,
                          normal);
    }
    case kPfxShapeConvexMesh:
      return castConvexMesh(*shape.getConvexMesh(), start, direction, fraction, normal);
    default: return false;
  }
}

}  // namespace

bool pfxRayCastSphere(const PfxSphere& sphere, const PfxVector3& start,
                      const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal) {
  return castPublic(start, direction, fraction, normal,
                    [&](const Vec3& s, const Vec3& d, Real& t, Vec3& n) {
                      return castSphere(sphere.m_radius, s, d, t, n);
                    });
}

bool pfxRayCastBox(const PfxBox& box, const PfxVector3& start, const PfxVector3& direction,
                   PfxFloat& fraction, PfxVector3& normal) {
  return castPublic(start, direction, fraction, normal,
                    [&](const Vec3& s, const Vec3& d, Real& t, Vec3& n) {
                      return castBox(box.m_half.cast<Real>(), s, d, t, n);
                    });
}

bool pfxRayCastCapsule(const PfxCapsule& capsule, const PfxVector3& start,
                       const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal) {
  return castPublic(start, direction, fraction, normal,
                    [&](const Vec3& s, const Vec3& d, Real& t, Vec3& n) {
                      return castCapsule(capsule.m_halfLen, capsule.m_radius, s, d, t, n);
                    });
}

bool pfxRayCastCylinder(const PfxCylinder& cylinder, const PfxVector3& start,
                        const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal) {
  return castPublic(start, direction, fraction, normal,
                    [&](const Vec3& s, const Vec3& d, Real& t, Vec3& n) {
                      return castCylinder(cylinder.m_halfLen, cylinder.m_radius, s, d, t, n);
                    });
}

bool pfxRayCastConvexMesh(const PfxConvexMesh& mesh, const PfxVector3& start,
                          const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal) {
  return castPublic(start, direction, fraction, normal,
                    [&](const Vec3& s, const Vec3& d, Real& t, Vec3& n) {
                      return castConvexMesh(mesh, s, d, t, n);
                    });
}

bool pfxRayCastShape(const PfxShape& shape, const PfxTransform3& shapeTransform,
                     const PfxVector3& start, const PfxVector3& direction, PfxFloat& fraction,
                     PfxVector3& normal, PfxUInt32& triangleIndex) {
  const Eigen::Matrix<Real, 3, 3> rotation = shapeTransform.linear().cast<Real>();
  const Vec3 localStart =
      rotation.transpose() * (start.cast<Real>() - shapeTransform.translation().cast<Real>());
  const Vec3 localDirection = rotation.transpose() * direction.cast<Real>();
  if (shape.getType() == kPfxShapeLargeTriMesh) {
    PfxFloat meshFraction;
    PfxVector3 meshNormal;
    PfxUInt32 meshTriangle;
    if (!pfxRayCastLargeTriMesh(*shape.getLargeTriMesh(), localStart.cast<PfxFloat>(),
                                localDirection.cast<PfxFloat>(), meshFraction, meshNormal,
                                meshTriangle) ||
        !(meshFraction <= fraction)) {
      return false;
    }
    fraction = meshFraction;
    normal = (rotation * meshNormal.cast<Real>()).cast<PfxFloat>();
    triangleIndex = meshTriangle;
    return true;
  }
  Real t = fraction;
  Vec3 localNormal;
  if (!castLocal(shape, localStart, localDirection, t, localNormal)) return false;
  fraction = static_cast<PfxFloat>(t);
  normal = (rotation * localNormal).cast<PfxFloat>();
  triangleIndex = PFX_RAY_NO_TRIANGLE;
  return true;
}

bool pfxRayCastCollidable(const PfxRayInput& ray, const PfxCollidable& collidable,
                          const PfxTransform3& bodyTransform, PfxFloat maxFraction,
                          PfxRayOutput& out) {
  PfxFloat closest = maxFraction;
  PfxVector3 closestNormal = PfxVector3::Zero();
  PfxUInt32 closestShape = 0;
  PfxUInt32 closestTriangle = PFX_RAY_NO_TRIANGLE;
  bool hit = false;
  for (PfxUInt32 i = 0; i < collidable.getNumShapes(); ++i) {
    const PfxShape& shape = collidable.getShape(i);
    PfxFloat fraction = closest;
    PfxVector3 normal;
    PfxUInt32 triangle;
    if (!pfxRayCastShape(shape, bodyTransform * shape.getOffsetTransform(), ray.m_startPosition,
                         ray.m_direction, fraction, normal, triangle)) {
      continue;
    }
    // Strictly closer: of shapes hit at the same fraction the first keeps the hit.
    if (hit && !(fraction < closest)) continue;
    hit = true;
    closest = fraction;
    closestNormal = normal;
    closestShape = i;
    closestTriangle = triangle;
  }
  if (!hit) return false;
  out.m_contactFlag = true;
  out.m_variable = closest;
  out.m_contactPoint = ray.m_startPosition + closest * ray.m_direction;
  out.m_contactNormal = closestNormal;
  out.m_shapeId = static_cast<PfxUInt8>(closestShape);
  out.m_triangleIndex = closestTriangle;
  return true;
}

}  // namespace pfx
