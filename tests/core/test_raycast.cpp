// Raycasts: known hit points and normals on every shape type at random poses, the
// documented answers for rays that start inside, graze, run along edges or cannot be cast,
// contact filters, compounds, the proxy walk against testing every body, watertightness,
// bad input, and the world's casts.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "pfx/base_level/raycast/pfx_ray_shapes.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"
#include "pfx/low_level/raycast/pfx_build_ray_bvh.h"
#include "pfx/low_level/raycast/pfx_cast_rays.h"
#include "pfx_contact_test_util.h"
#include "pfx_large_mesh_test_util.h"
#include "pfx_allocation_counter.h"


namespace pfx_test {
namespace {

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;

constexpr double kRelative = 1e-5;
constexpr PfxFloat kNaN = std::numeric_limits<PfxFloat>::quiet_NaN();
constexpr PfxFloat kInf = std::numeric_limits<PfxFloat>::infinity();

PfxRayInput makeRay(const PfxVector3& start, const PfxVector3& direction) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = start;
  ray.m_direction = direction;
  return ray;
}

// A hit of one shape in its own frame, through the public per-shape entry point.
struct ShapeHit {
  bool hit = false;
  PfxFloat fraction = 1;
  PfxVector3 normal = PfxVector3::Zero();
  PfxVector3 point = PfxVector3::Zero();
};

ShapeHit castShape(const PfxShape& shape, const PfxTransform3& transform,
                   const PfxVector3& start, const PfxVector3& direction) {
  ShapeHit h;
  PfxUInt32 triangle;
  h.hit = pfxRayCastShape(shape, transform, start, direction, h.fraction, h.normal, triangle);
  h.point = start + h.fraction * direction;
  return h;
}

ShapeHit castLocal(const PfxShape& shape, PfxFloat sx, PfxFloat sy, PfxFloat sz, PfxFloat dx,
                   PfxFloat dy, PfxFloat dz) {
  return castShape(shape, pose(PfxVector3::Zero()), PfxVector3(sx, sy, sz),
                   PfxVector3(dx, dy, dz));
}

void expectNear(const PfxVector3& got, const PfxVector3& want, double tolerance,
                const char* what) {
  EXPECT_LE((got.cast<double>() - want.cast<double>()).norm(), tolerance)
      << what << ": got " << got.transpose() << ", want " << want.transpose();
}

// ------------------------------------------------ analytic hits at random poses

// A point on a shape's surface with its outward normal, both in the shape's frame.
struct SurfacePoint {
  Vec3d point;
  Vec3d normal;
};

class RandomSource {
 public:
  explicit RandomSource(unsigned seed) : m_engine(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(m_engine); }
  int index(int n) { return std::uniform_int_distribution<int>(0, n - 1)(m_engine); }
  Vec3d unit() {
    for (;;) {
      const Vec3d v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
      const double n = v.norm();
      if (n > 0.1 && n <= 1) return v / n;
    }
  }
  PfxQuat rotation() {
    const Eigen::Vector4d v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
    const Eigen::Vector4d u = v.normalized();
    return PfxQuat(PfxFloat(u[0]), PfxFloat(u[1]), PfxFloat(u[2]), PfxFloat(u[3])).normalized();
  }
  PfxVector3 position(double range) {
    return PfxVector3{PfxFloat(uniform(-range, range)), PfxFloat(uniform(-range, range)),
                      PfxFloat(uniform(-range, range))};
  }

 private:
  std::mt19937 m_engine;
};

// Surface samplers keep off edges (5% margins), where the normal is not unique.
SurfacePoint sampleSphere(RandomSource& rng, double r) {
  const Vec3d n = rng.unit();
  return {r * n, n};
}

SurfacePoint sampleBox(RandomSource& rng, const Vec3d& half) {
  const int axis = rng.index(3);
  const double sign = rng.index(2) ? 1.0 : -1.0;
  Vec3d p;
  for (int a = 0; a < 3; ++a) p[a] = rng.uniform(-0.95, 0.95) * half[a];
  p[axis] = sign * half[axis];
  Vec3d n = Vec3d::Zero();
  n[axis] = sign;
  return {p, n};
}

SurfacePoint sampleCapsule(RandomSource& rng, double h, double r) {
  if (rng.index(2)) {
    const double angle = rng.uniform(0, 2 * M_PI);
    const Vec3d n(0, std::cos(angle), std::sin(angle));
    return {Vec3d(rng.uniform(-h, h), 0, 0) + r * n, n};
  }
  Vec3d n = rng.unit();
  const double endX = n[0] >= 0 ? h : -h;
  return {Vec3d(endX, 0, 0) + r * n, n};
}

SurfacePoint sampleCylinder(RandomSource& rng, double h, double r) {
  if (rng.index(2)) {
    const double angle = rng.uniform(0, 2 * M_PI);
    const Vec3d n(0, std::cos(angle), std::sin(angle));
    return {Vec3d(rng.uniform(-0.95, 0.95) * h, 0, 0) + r * n, n};
  }
  const double sign = rng.index(2) ? 1.0 : -1.0;
  const double angle = rng.uniform(0, 2 * M_PI);
  const double rho = r * std::sqrt(rng.uniform(0, 0.9));
  return {Vec3d(sign * h, rho * std::cos(angle), rho * std::sin(angle)), Vec3d(sign, 0, 0)};
}

// A point inside a facet (barycentrics at least 0.05) and the facet's outward normal,
// which the builder made counter-clockwise from outside.
SurfacePoint sampleConvexMesh(RandomSource& rng, const PfxConvexMesh& mesh) {
  const int facet = rng.index(mesh.m_numFacets);
  Vec3d v[3];
  for (int k = 0; k < 3; ++k) v[k] = mesh.m_verts[mesh.m_facetVertIds[facet][k]].cast<double>();
  double b0 = rng.uniform(0.05, 0.9);
  double b1 = rng.uniform(0.05, 0.95 - b0);
  const Vec3d p = b0 * v[0] + b1 * v[1] + (1 - b0 - b1) * v[2];
  return {p, (v[1] - v[0]).cross(v[2] - v[0]).normalized()};
}

// The PfxFloat vector nearest `v`, read back through memory. GCC 12's SLP vectorizer at -O2
// may fold "round a double to float, widen it again" back into the unrounded double, and the
// reference below would then describe a ray other than the one cast.
PfxVector3 roundToFloat(const Vec3d& v) {
  volatile PfxFloat c[3] = {PfxFloat(v[0]), PfxFloat(v[1]), PfxFloat(v[2])};
  return PfxVector3(PfxFloat(c[0]), PfxFloat(c[1]), PfxFloat(c[2]));
}

// Whether a point in the shape's frame lies in the closed solid, straight from the shape's
// definition: the reference that the hits are checked against.
bool insideShape(const PfxShape& shape, const Vec3d& p) {
  switch (shape.getType()) {
    case kPfxShapeSphere: return p.norm() <= shape.getSphere().m_radius;
    case kPfxShapeBox: {
      const Vec3d half = shape.getBox().m_half.cast<double>();
      return (p.cwiseAbs() - half).maxCoeff() <= 0;
    }
    case kPfxShapeCapsule: {
      const PfxCapsule c = shape.getCapsule();
      const Vec3d onSegment(std::clamp(p[0], -double(c.m_halfLen), double(c.m_halfLen)), 0, 0);
      return (p - onSegment).norm() <= c.m_radius;
    }
    case kPfxShapeCylinder: {
      const PfxCylinder c = shape.getCylinder();
      return std::abs(p[0]) <= c.m_halfLen && std::hypot(p[1], p[2]) <= c.m_radius;
    }
    default: {
      const PfxConvexMesh& m = *shape.getConvexMesh();
      for (int f = 0; f < m.m_numFacets; ++f) {
        const Vec3d v0 = m.m_verts[m.m_facetVertIds[f][0]].cast<double>();
        const Vec3d v1 = m.m_verts[m.m_facetVertIds[f][1]].cast<double>();
        const Vec3d v2 = m.m_verts[m.m_facetVertIds[f][2]].cast<double>();
        if ((v1 - v0).cross(v2 - v0).normalized().dot(p - v0) > 0) return false;
      }
      return true;
    }
  }
}

// The outward normal at a surface point sampled from `s`'s part of the surface: curved
// parts from the point itself, flat parts as sampled.
Vec3d referenceNormal(const PfxShape& shape, const SurfacePoint& s, const Vec3d& p) {
  switch (shape.getType()) {
    case kPfxShapeSphere: return p.normalized();
    case kPfxShapeCapsule: {
      const double h = shape.getCapsule().m_halfLen;
      return (p - Vec3d(std::clamp(p[0], -h, h), 0, 0)).normalized();
    }
    case kPfxShapeCylinder:
      return s.normal[0] == 0 ? Vec3d(0, p[1], p[2]).normalized() : s.normal;
    default: return s.normal;
  }
}

// Casts a float ray that enters `shape` (posed at `position`, `orientation`) at the surface
// point `s`, from outside, at a random angle and length: for a convex shape a ray heading
// inward at a surface point enters there, since the supporting plane at that point keeps
// everything before it outside. Rounding the ray to float moves its entry by about
// 1e-7 of the scene's scale, which on a 5 cm sphere 10 m away turns the normal by 1e-5; so
// the exact entry of the float ray itself is found by bisection on the inside test above,
// in double, and the hit is held to that within 1e-5 (points relative to the scene's scale,
// unit normals absolutely). Returns the larger error for the caller's maximum.
double checkAnalyticHit(RandomSource& rng, const PfxShape& shape, const PfxVector3& position,
                        const PfxQuat& orientation, const SurfacePoint& s) {
  const PfxTransform3 transform = pose(position, orientation);
  const Mat3d rotation = transform.linear().cast<double>();
  const Vec3d translation = transform.translation().cast<double>();
  const Vec3d worldPoint = translation + rotation * s.point;
  const Vec3d worldNormal = rotation * s.normal;
  Vec3d heading;
  do {
    heading = rng.unit();
  } while (heading.dot(worldNormal) > -0.25);
  const double length = rng.uniform(0.5, 4.0);
  const double fraction = rng.uniform(0.05, 0.95);
  const PfxVector3 start = roundToFloat(worldPoint - fraction * length * heading);
  const PfxVector3 direction = roundToFloat(length * heading);

  const Vec3d localStart = rotation.transpose() * (start.cast<double>() - translation);
  const Vec3d localDirection = rotation.transpose() * direction.cast<double>();
  double outside = fraction - 1e-4;
  double inside = fraction + 1e-4;
  EXPECT_FALSE(insideShape(shape, localStart + outside * localDirection));
  EXPECT_TRUE(insideShape(shape, localStart + inside * localDirection));
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (outside + inside);
    (insideShape(shape, localStart + mid * localDirection) ? inside : outside) = mid;
  }
  const Vec3d localEntry = localStart + inside * localDirection;
  const Vec3d entry = start.cast<double>() + inside * direction.cast<double>();
  const Vec3d entryNormal = rotation * referenceNormal(shape, s, localEntry);

  const ShapeHit h = castShape(shape, transform, start, direction);
  EXPECT_TRUE(h.hit);
  if (!h.hit) return 1;
  const double scale = std::max({1.0, worldPoint.norm(), double(start.norm())});
  const double pointError = (h.point.cast<double>() - entry).norm() / scale;
  const double normalError = (h.normal.cast<double>() - entryNormal).norm();
  EXPECT_LE((entry - worldPoint).norm() / scale, kRelative) << "reference off the sample";
  EXPECT_LE(pointError, kRelative) << "type " << int(shape.getType()) << ": point "
                                   << h.point.transpose() << ", want " << entry.transpose();
  EXPECT_LE(normalError, kRelative) << "type " << int(shape.getType()) << ": normal "
                                    << h.normal.transpose() << ", want "
                                    << entryNormal.transpose();
  return std::max(pointError, normalError);
}

TEST(RayAnalytic, EveryConvexShapeTypeAtRandomPoses) {
  RandomSource rng(11);
  const PfxConvexMesh icosahedron = buildMesh(makeIcosahedronTriangles());
  const PfxConvexMesh tetrahedron = buildMesh(makeTetrahedronTriangles());
  double worst[kPfxShapeLargeTriMesh] = {};
  for (int trial = 0; trial < 4000; ++trial) {
    const PfxVector3 position = rng.position(8);
    const PfxQuat orientation = rng.rotation();
    const int type = trial % kPfxShapeLargeTriMesh;
    PfxShape shape;
    SurfacePoint s;
    switch (type) {
      case kPfxShapeSphere: {
        const PfxFloat r = PfxFloat(rng.uniform(0.05, 3));
        shape = makeSphere(r);
        s = sampleSphere(rng, r);
        break;
      }
      case kPfxShapeBox: {
        const PfxVector3 half{PfxFloat(rng.uniform(0.05, 3)), PfxFloat(rng.uniform(0.05, 3)),
                              PfxFloat(rng.uniform(0.05, 3))};
        shape = makeBox(half[0], half[1], half[2]);
        s = sampleBox(rng, half.cast<double>());
        break;
      }
      case kPfxShapeCapsule: {
        const PfxFloat h = PfxFloat(rng.uniform(0, 2)), r = PfxFloat(rng.uniform(0.05, 2));
        shape = makeCapsule(h, r);
        s = sampleCapsule(rng, h, r);
        break;
      }
      case kPfxShapeCylinder: {
        const PfxFloat h = PfxFloat(rng.uniform(0.05, 2)), r = PfxFloat(rng.uniform(0.05, 2));
        shape = makeCylinder(h, r);
        s = sampleCylinder(rng, h, r);
        break;
      }
      default: {
        const PfxConvexMesh& mesh = trial % 2 ? icosahedron : tetrahedron;
        shape = makeMeshShape(&mesh);
        s = sampleConvexMesh(rng, mesh);
        break;
      }
    }
    worst[type] = std::max(worst[type], checkAnalyticHit(rng, shape, position, orientation, s));
  }
  for (double w : worst) EXPECT_LE(w, kRelative);
}

TEST(RayAnalytic, ShapeOffsetsInACollidable) {
  // A box 2 m long offset by (3, 0, 0) and turned 90 degrees about Z inside a body at
  // (0, 10, 0): its long side runs along world Y, from y = 8 to 12 at x = 3 +- 0.5. A ray
  // down from (3, 20, 0) over 20 m meets its top at y = 12: fraction 8 / 20 = 0.4.
  PfxShape box = makeBox(2, 0.5f, 0.5f);
  box.setOffsetPosition(PfxVector3(3, 0, 0));
  box.setOffsetOrientation(rotZ(PFX_PI / 2));
  PfxCollidable collidable;
  collidable.reset();
  ASSERT_EQ(collidable.addShape(box), PFX_OK);
  ASSERT_EQ(collidable.finish(), PFX_OK);
  PfxRayOutput out;
  ASSERT_TRUE(pfxRayCastCollidable(makeRay(PfxVector3(3, 20, 0), PfxVector3(0, -20, 0)),
                                   collidable, pose(PfxVector3(0, 10, 0)), 1, out));
  EXPECT_NEAR(out.m_variable, 0.4f, 1e-6f);
  expectNear(out.m_contactPoint, PfxVector3(3, 12, 0), 1e-5, "point");
  expectNear(out.m_contactNormal, PfxVector3(0, 1, 0), 1e-6, "normal");
  EXPECT_EQ(out.m_shapeId, 0u);
  EXPECT_EQ(out.m_triangleIndex, PFX_RAY_NO_TRIANGLE);
}

// ------------------------------------------------ the documented corner cases

TEST(RayCornerCases, StartInsideASolidDoesNotHitIt) {
  const PfxConvexMesh box = buildMesh(makeBoxTriangles(1, 1, 1));
  const PfxShape shapes[] = {makeSphere(1), makeBox(1, 1, 1), makeCapsule(1, 0.5f),
                             makeCylinder(1, 0.5f), makeMeshShape(&box)};
  for (const PfxShape& shape : shapes) {
    for (const PfxVector3& d : {PfxVector3(3, 0, 0), PfxVector3(-1, 2, 0.5f),
                                PfxVector3(0, 0, -5)}) {
      EXPECT_FALSE(castShape(shape, pose(PfxVector3::Zero()), PfxVector3(0.1f, 0.1f, 0), d).hit)
          << "type " << int(shape.getType());
    }
  }
}

TEST(RayCornerCases, StartOnTheSurfaceHitsAtZeroGoingInAndMissesGoingOut) {
  // Unit sphere and unit box, start at (-1, 0, 0) on both surfaces.
  for (const PfxShape& shape : {makeSphere(1), makeBox(1, 1, 1)}) {
    const ShapeHit in = castLocal(shape, -1, 0, 0, 2, 0, 0);
    ASSERT_TRUE(in.hit);
    EXPECT_EQ(in.fraction, 0);
    expectNear(in.normal, PfxVector3(-1, 0, 0), 1e-6, "normal");
    EXPECT_FALSE(castLocal(shape, -1, 0, 0, -2, 0, 0).hit);
  }
}

TEST(RayCornerCases, GrazingRaysHitAtTheTouchingPoint) {
  // Unit sphere, ray y = 1 from x = -5 over 10 m: tangent at (0, 1, 0), fraction 0.5.
  ShapeHit h = castLocal(makeSphere(1), -5, 1, 0, 10, 0, 0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  expectNear(h.normal, PfxVector3(0, 1, 0), 0, "sphere normal");
  // Cylinder (half length 1, radius 1, along X), ray along Z through (0, 1, 0): tangent to
  // the side at fraction 3 / 6.
  h = castLocal(makeCylinder(1, 1), 0, 1, -3, 0, 0, 6);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  expectNear(h.normal, PfxVector3(0, 1, 0), 0, "cylinder normal");
  // Capsule side, radius 0.5: ray along Z through (0.3, 0.5, 0).
  h = castLocal(makeCapsule(1, 0.5f), 0.3f, 0.5f, -2, 0, 0, 4);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  expectNear(h.normal, PfxVector3(0, 1, 0), 0, "capsule normal");
  // Unit box, ray from (0, 2, 0) along (2, -2, 0): x = 2t, y = 2 - 2t lies in the box only
  // at t = 0.5, on the edge (1, 1, 0). Entry through the Y slab (the X slab was entered at
  // t = -0.5), so the normal is +Y.
  h = castLocal(makeBox(1, 1, 1), 0, 2, 0, 2, -2, 0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  expectNear(h.normal, PfxVector3(0, 1, 0), 0, "box edge normal");
  // Just beside the tangents: misses.
  EXPECT_FALSE(castLocal(makeSphere(1), -5, 1.0001f, 0, 10, 0, 0).hit);
  EXPECT_FALSE(castLocal(makeBox(1, 1, 1), 0, 2.0001f, 0, 2, -2, 0).hit);
}

TEST(RayCornerCases, EdgesAndCornersTakeTheFirstFaceInOrder) {
  // Unit box, ray from (-2, -2, 0) along (2, 2, 0) reaches the edge (-1, -1, z) at 0.5
  // through X and Y at once: X comes first.
  ShapeHit h = castLocal(makeBox(1, 1, 1), -2, -2, 0, 2, 2, 0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  expectNear(h.normal, PfxVector3(-1, 0, 0), 0, "box");
  // Cylinder rim: from (-2, 2, 0) along (2, -2, 0) the cap x = -1 and the side y = 1 are
  // both reached at 0.5; the cap keeps the normal.
  h = castLocal(makeCylinder(1, 1), -2, 2, 0, 2, -2, 0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  expectNear(h.normal, PfxVector3(-1, 0, 0), 0, "cylinder");
}

TEST(RayCornerCases, RaysAlongAnEdgeOrAFaceHitTheFaceTheyMeetHeadOn) {
  // Unit box (and the same box as a convex mesh): from (-2, 1, 1) along the edge y = z = 1
  // over 4 m, and from (-2, 1, 0) along the top face; both meet the -X face at x = -1,
  // fraction 1/4.
  const PfxConvexMesh mesh = buildMesh(makeBoxTriangles(1, 1, 1));
  for (const PfxShape& shape : {makeBox(1, 1, 1), makeMeshShape(&mesh)}) {
    for (PfxFloat z : {PfxFloat(1), PfxFloat(0)}) {
      const ShapeHit h = castLocal(shape, -2, 1, z, 4, 0, 0);
      ASSERT_TRUE(h.hit);
      EXPECT_EQ(h.fraction, 0.25f);
      expectNear(h.point, PfxVector3(-1, 1, z), 0, "point");
      expectNear(h.normal, PfxVector3(-1, 0, 0), 1e-7, "normal");
    }
  }
  // Cylinder (half length 1, radius 1): along the side line y = 1, z = 0 meets the cap.
  const ShapeHit h = castLocal(makeCylinder(1, 1), -2, 1, 0, 4, 0, 0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.25f);
  expectNear(h.normal, PfxVector3(-1, 0, 0), 0, "cylinder");
}

TEST(RayCornerCases, RaysEndingShortOfTheSurfaceMiss) {
  // Unit sphere from x = -3: the surface is 2 m away.
  EXPECT_FALSE(castLocal(makeSphere(1), -3, 0, 0, 1.99f, 0, 0).hit);
  const ShapeHit h = castLocal(makeSphere(1), -3, 0, 0, 2, 0, 0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 1);
}

// ------------------------------------------------ rays that cannot be cast

TEST(RayInput, ZeroLengthNaNAndInfiniteRaysAreRejected) {
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(0, 0, 1))), PFX_OK);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3::Zero())), PFX_ERR_DEGENERATE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(1e-20f, 0, 0))),
            PFX_ERR_DEGENERATE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3(kNaN, 0, 0), PfxVector3(1, 0, 0))),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(0, kNaN, 0))),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(0, 0, kInf))),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(1e20f, 0, 0))),
            PFX_ERR_INVALID_VALUE);
  // The limits are float's in both precisions: what is infinite in float is rejected in
  // double too, and lengths just inside them can be cast.
  const PfxFloat beyondFloat = PfxFloat(std::numeric_limits<float>::max()) * 2;
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3(beyondFloat, 0, 0), PfxVector3(1, 0, 0))),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(0, -beyondFloat, 0))),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3::Constant(1e18f))), PFX_OK);
  EXPECT_EQ(pfxCheckRayInput(makeRay(PfxVector3::Zero(), PfxVector3(0, 0, 1e-18f))), PFX_OK);
  PfxRayInput reset;
  reset.reset();
  EXPECT_EQ(pfxCheckRayInput(reset), PFX_ERR_DEGENERATE);
  EXPECT_EQ(reset.m_contactFilterSelf, 0xffffffffu);
  EXPECT_EQ(reset.m_contactFilterTarget, 0xffffffffu);
}

// ------------------------------------------------ scenes cast through the proxy arrays

// Bodies in plain arrays and the six proxy arrays over them, as an application of the low
// level would keep them.
class Scene {
 public:
  explicit Scene(PfxFloat extent) : m_extent(PfxVector3::Constant(extent)) {}

  PfxUInt32 add(const PfxShape* shapes, PfxUInt32 numShapes, const PfxVector3& position,
                const PfxQuat& orientation = PfxQuat::Identity(), PfxUInt32 self = 0xffffffffu,
                PfxUInt32 target = 0xffffffffu) {
    PfxRigidState state;
    state.reset();
    state.setPosition(position);
    state.setOrientation(orientation);
    state.setRigidBodyId(numBodies());
    state.setContactFilterSelf(self);
    state.setContactFilterTarget(target);
    m_states.push_back(state);
    PfxCollidable collidable;
    collidable.reset();
    if (numShapes > 1) {
      m_compoundShapes.emplace_back(new PfxShape[numShapes]);
      m_compoundIds.emplace_back(new PfxUInt16[numShapes]);
      for (PfxUInt32 i = 0; i < numShapes; ++i) m_compoundIds.back()[i] = PfxUInt16(i);
      EXPECT_EQ(collidable.reset(m_compoundShapes.back().get(), m_compoundIds.back().get(),
                                 numShapes),
                PFX_OK);
    }
    for (PfxUInt32 i = 0; i < numShapes; ++i) EXPECT_EQ(collidable.addShape(shapes[i]), PFX_OK);
    EXPECT_EQ(collidable.finish(), PFX_OK);
    m_collidables.push_back(collidable);
    return numBodies() - 1;
  }
  PfxUInt32 add(const PfxShape& shape, const PfxVector3& position,
                const PfxQuat& orientation = PfxQuat::Identity(), PfxUInt32 self = 0xffffffffu,
                PfxUInt32 target = 0xffffffffu) {
    return add(&shape, 1, position, orientation, self, target);
  }

  void buildProxies() {
    const PfxUInt32 n = numBodies();
    for (auto& array : m_proxies) array.assign(n, PfxBroadphaseProxy());
    m_work.assign(n, PfxBroadphaseProxy());
    PfxUpdateBroadphaseProxiesParam param;
    param.workBuff = m_work.data();
    param.workBytes = pfxGetWorkBytesOfUpdateBroadphaseProxies(n);
    param.offsetRigidStates = m_states.data();
    param.offsetCollidables = m_collidables.data();
    param.numRigidBodies = n;
    param.proxiesX = m_proxies[0].data();
    param.proxiesY = m_proxies[1].data();
    param.proxiesZ = m_proxies[2].data();
    param.proxiesXb = m_proxies[3].data();
    param.proxiesYb = m_proxies[4].data();
    param.proxiesZb = m_proxies[5].data();
    param.worldCenter = PfxVector3::Zero();
    param.worldExtent = m_extent;
    PfxUpdateBroadphaseProxiesResult result;
    ASSERT_EQ(pfxUpdateBroadphaseProxies(param, result), PFX_OK);
    ASSERT_EQ(result.numProxies, n);
  }

  // The hierarchy over proxiesX, for rays that descend it instead of walking the arrays.
  void buildBvh() {
    const PfxUInt32 n = numBodies();
    m_bvh.assign(pfxGetNumRayBvhNodes(n), PfxRayBvhNode());
    m_bvhWork.assign(n / 4 + 1, PfxSortData16());
    PfxBuildRayBvhParam param;
    param.workBuff = m_bvhWork.data();
    param.workBytes = pfxGetWorkBytesOfBuildRayBvh(n);
    param.proxies = m_proxies[0].data();
    param.numProxies = n;
    param.nodes = m_bvh.data();
    param.maxNodes = PfxUInt32(m_bvh.size());
    ASSERT_EQ(pfxBuildRayBvh(param), PFX_OK);
  }
  PfxRayCastParam bvhParam() const {
    PfxRayCastParam p = param();
    p.proxiesX = p.proxiesY = p.proxiesZ = p.proxiesXb = p.proxiesYb = p.proxiesZb = nullptr;
    p.bvhNodes = m_bvh.data();
    p.bvhProxies = m_proxies[0].data();
    return p;
  }
  const std::vector<PfxRayBvhNode>& bvh() const { return m_bvh; }
  const std::vector<PfxBroadphaseProxy>& proxiesX() const { return m_proxies[0]; }

  PfxRayCastParam param() const {
    PfxRayCastParam p;
    p.offsetRigidStates = m_states.data();
    p.offsetCollidables = m_collidables.data();
    p.proxiesX = m_proxies[0].data();
    p.proxiesY = m_proxies[1].data();
    p.proxiesZ = m_proxies[2].data();
    p.proxiesXb = m_proxies[3].data();
    p.proxiesYb = m_proxies[4].data();
    p.proxiesZb = m_proxies[5].data();
    p.numProxies = numBodies();
    p.rangeCenter = PfxVector3::Zero();
    p.rangeExtent = m_extent;
    return p;
  }

  // The reference: every body in id order, under the same filter and tie rules.
  PfxRayOutput castEveryBody(const PfxRayInput& ray) const {
    PfxRayOutput closest;
    closest.setMiss(ray);
    for (PfxUInt32 id = 0; id < numBodies(); ++id) {
      const PfxRigidState& state = m_states[id];
      if (!pfxContactFiltersMatch(ray.m_contactFilterSelf, ray.m_contactFilterTarget,
                                  state.getContactFilterSelf(), state.getContactFilterTarget())) {
        continue;
      }
      PfxRayOutput hit;
      if (pfxRayCastCollidable(ray, m_collidables[id], state.getTransform(), closest.m_variable,
                               hit) &&
          (!closest.m_contactFlag || hit.m_variable < closest.m_variable)) {
        closest = hit;
        closest.m_objectId = id;
      }
    }
    return closest;
  }

  PfxUInt32 numBodies() const { return static_cast<PfxUInt32>(m_states.size()); }
  const PfxRigidState& state(PfxUInt32 id) const { return m_states[id]; }

 private:
  PfxVector3 m_extent;
  std::vector<PfxRigidState> m_states;
  std::vector<PfxCollidable> m_collidables;
  std::vector<std::unique_ptr<PfxShape[]>> m_compoundShapes;
  std::vector<std::unique_ptr<PfxUInt16[]>> m_compoundIds;
  std::vector<PfxBroadphaseProxy> m_proxies[6];
  std::vector<PfxBroadphaseProxy> m_work;
  std::vector<PfxRayBvhNode> m_bvh;
  // 16-byte aligned scratch for the hierarchy's build (PfxUInt32 per proxy).
  std::vector<PfxSortData16> m_bvhWork;
};

void expectSameOutput(const PfxRayOutput& a, const PfxRayOutput& b, const char* what) {
  EXPECT_EQ(a.m_contactFlag, b.m_contactFlag) << what;
  EXPECT_EQ(a.m_objectId, b.m_objectId) << what;
  EXPECT_EQ(a.m_shapeId, b.m_shapeId) << what;
  EXPECT_EQ(a.m_triangleIndex, b.m_triangleIndex) << what;
  EXPECT_EQ(a.m_variable, b.m_variable) << what;
  EXPECT_EQ(a.m_contactPoint, b.m_contactPoint) << what;
  EXPECT_EQ(a.m_contactNormal, b.m_contactNormal) << what;
}

// Bytes that no cast writes, to prove an output untouched.
PfxRayOutput poisonedOutput() {
  PfxRayOutput out;
  std::memset(static_cast<void*>(&out), 0xab, sizeof(out));
  return out;
}

bool isPoisoned(const PfxRayOutput& out) {
  const PfxRayOutput poison = poisonedOutput();
  return std::memcmp(&out, &poison, sizeof(out)) == 0;
}

TEST(RayCastStage, ContactFiltersPickTheBodiesARayMaySee) {
  // The seed's third raycast scene: four unit boxes in a row along +X at x = 0, 3, 6, 9,
  // whose self bits are 1, 2, 4, 8. The fourth accepts only rays whose self has bit 2
  // (target 2). A ray along +X from x = -5 over 20 m meets the first box it may see at its
  // -X face, x = 3k - 1: fraction (3k - 1 + 5) / 20.
  Scene scene(100);
  for (PfxUInt32 k = 0; k < 4; ++k) {
    scene.add(makeBox(1, 1, 1), PfxVector3(3.0f * k, 0, 0), PfxQuat::Identity(), 1u << k,
              k == 3 ? 2u : 0xffffffffu);
  }
  scene.buildProxies();
  const PfxRayCastParam param = scene.param();
  struct Case {
    PfxUInt32 self, target;
    bool hit;
    PfxUInt32 body;
  };
  const Case cases[] = {
      {0xffffffffu, 0xffffffffu, true, 0},  // sees everything: the first box
      {0xffffffffu, 0x2, true, 1},          // looks for bit 2 only
      {0xffffffffu, 0x4 | 0x8, true, 2},    // the nearer of the third and fourth
      {0x1, 0x8, false, 0},                 // the fourth wants a ray with self bit 2
      {0x2, 0x8, true, 3},                  // and sees this one
      {0xffffffffu, 0x10, false, 0},        // no body has bit 16
      {0, 0xffffffffu, false, 0},           // a ray with no self bits is wanted by nobody
  };
  for (const Case& c : cases) {
    PfxRayInput ray = makeRay(PfxVector3(-5, 0.25f, 0.25f), PfxVector3(20, 0, 0));
    ray.m_contactFilterSelf = c.self;
    ray.m_contactFilterTarget = c.target;
    PfxRayOutput out;
    ASSERT_EQ(pfxCastSingleRay(ray, out, param), PFX_OK);
    ASSERT_EQ(out.m_contactFlag, c.hit) << std::hex << c.self << " " << c.target;
    if (!c.hit) {
      EXPECT_EQ(out.m_objectId, PFX_RAY_NO_OBJECT);
      EXPECT_EQ(out.m_variable, 1);
      EXPECT_EQ(out.m_contactPoint, PfxVector3(15, 0.25f, 0.25f));
      continue;
    }
    EXPECT_EQ(out.m_objectId, c.body);
    EXPECT_NEAR(out.m_variable, (3.0f * c.body + 4) / 20, 1e-6f);
    expectNear(out.m_contactNormal, PfxVector3(-1, 0, 0), 0, "normal");
  }
}

TEST(RayCastStage, CompoundsReportTheShapeHit) {
  // Sphere (r 0.5) at x = -2, box (half 0.5) at x = 0, capsule (half length 0.5, r 0.5,
  // along X) at x = 2, in one body at (0, 5, 0). Rays straight down from y = 10 over 10 m
  // meet each top at y = 5.5: fraction 0.45.
  PfxShape shapes[3] = {makeSphere(0.5f), makeBox(0.5f, 0.5f, 0.5f), makeCapsule(0.5f, 0.5f)};
  shapes[0].setOffsetPosition(PfxVector3(-2, 0, 0));
  shapes[2].setOffsetPosition(PfxVector3(2, 0, 0));
  Scene scene(100);
  scene.add(makeBox(10, 0.5f, 10), PfxVector3(0, -0.5f, 0));
  const PfxUInt32 compound = scene.add(shapes, 3, PfxVector3(0, 5, 0));
  scene.buildProxies();
  const PfxRayCastParam param = scene.param();
  for (PfxUInt32 i = 0; i < 3; ++i) {
    const PfxFloat x = -2.0f + 2.0f * i;
    PfxRayOutput out;
    ASSERT_EQ(pfxCastSingleRay(makeRay(PfxVector3(x, 10, 0), PfxVector3(0, -10, 0)), out, param),
              PFX_OK);
    ASSERT_TRUE(out.m_contactFlag);
    EXPECT_EQ(out.m_objectId, compound);
    EXPECT_EQ(out.m_shapeId, i);
    EXPECT_NEAR(out.m_variable, 0.45f, 1e-6f);
    expectNear(out.m_contactPoint, PfxVector3(x, 5.5f, 0), 1e-5, "point");
    expectNear(out.m_contactNormal, PfxVector3(0, 1, 0), 1e-6, "normal");
  }
  // From the sphere's centre along +X: out of the sphere without a hit, then the box's -X
  // face at x = -0.5, 1.5 m on: fraction 1.5 / 4.
  PfxRayOutput out;
  ASSERT_EQ(pfxCastSingleRay(makeRay(PfxVector3(-2, 5, 0), PfxVector3(4, 0, 0)), out, param),
            PFX_OK);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_shapeId, 1u);
  EXPECT_NEAR(out.m_variable, 0.375f, 1e-6f);
  // Between the pieces, down to the ground at y = 0: fraction 1, shape 0 of body 0.
  ASSERT_EQ(pfxCastSingleRay(makeRay(PfxVector3(-1, 10, 0), PfxVector3(0, -10, 0)), out, param),
            PFX_OK);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_objectId, 0u);
  EXPECT_EQ(out.m_shapeId, 0u);
  EXPECT_EQ(out.m_variable, 1);
}

// A scene of `count` bodies of every kind, compounds and a large-mesh ground included,
// with random poses and filters; a few stick out of the range or lie beyond it.
struct RandomScene {
  PfxConvexMesh icosahedron;
  MeshOwner ground;
  std::unique_ptr<Scene> scene;
};

void fillRandomScene(RandomScene& r, PfxUInt32 count, unsigned seed) {
  r.icosahedron = buildMesh(makeIcosahedronTriangles());
  const MeshSource groundSource = makeHeightField(
      16, 16, 6, [](PfxFloat x, PfxFloat z) { return PfxFloat(2 * std::sin(0.3 * x) * std::cos(0.2 * z)); });
  ASSERT_EQ(pfxCreateLargeTriMesh(r.ground.mesh, groundSource.param(PFX_MESH_FLAG_USE_BVH)),
            PFX_OK);
  r.scene.reset(new Scene(60));
  Scene& scene = *r.scene;
  PfxShape ground;
  ground.reset();
  ground.setLargeTriMesh(&r.ground.mesh);
  scene.add(ground, PfxVector3(0, -30, 0));
  RandomSource rng(seed);
  for (PfxUInt32 i = 1; i < count; ++i) {
    PfxShape shapes[3];
    const PfxUInt32 numShapes = i % 7 == 6 ? 3 : 1;
    for (PfxUInt32 k = 0; k < numShapes; ++k) {
      const PfxFloat a = PfxFloat(rng.uniform(0.2, 2)), b = PfxFloat(rng.uniform(0.2, 2));
      switch ((i + k) % 6) {
        case 0: shapes[k] = makeSphere(a); break;
        case 1: shapes[k] = makeBox(a, b, PfxFloat(rng.uniform(0.2, 2))); break;
        case 2: shapes[k] = makeCapsule(a, b); break;
        case 3: shapes[k] = makeCylinder(a, b); break;
        default: shapes[k] = makeMeshShape(&r.icosahedron); break;
      }
      if (numShapes > 1) {
        shapes[k].setOffsetPosition(rng.position(2));
        shapes[k].setOffsetOrientation(rng.rotation());
      }
    }
    // Most well inside the range of 60; one in twenty reaching out of it or lying beyond.
    const PfxVector3 position = rng.position(i % 20 == 0 ? 66 : 40);
    const PfxUInt32 self = i % 3 == 0 ? (1u << rng.index(4)) : 0xffffffffu;
    const PfxUInt32 target = i % 5 == 0 ? (1u << rng.index(4)) : 0xffffffffu;
    scene.add(shapes, numShapes, position, rng.rotation(), self, target);
  }
  scene.buildProxies();
  scene.buildBvh();
}

std::vector<PfxRayInput> randomRays(PfxUInt32 count, unsigned seed) {
  RandomSource rng(seed);
  std::vector<PfxRayInput> rays;
  for (PfxUInt32 i = 0; i < count; ++i) {
    PfxVector3 direction = (rng.unit() * rng.uniform(1, 150)).cast<PfxFloat>();
    // Some along an axis or in a coordinate plane, where the walk meets zero components.
    if (i % 7 == 0) direction[rng.index(3)] = 0;
    if (i % 11 == 0) direction = PfxVector3::Unit(rng.index(3)) * PfxFloat(rng.uniform(-120, 120));
    if (direction.isZero()) direction = PfxVector3(0, -100, 0);
    PfxRayInput ray = makeRay(rng.position(i % 9 == 0 ? 90 : 45), direction);
    if (i % 4 == 0) ray.m_contactFilterTarget = 1u << rng.index(4);
    if (i % 6 == 0) ray.m_contactFilterSelf = 1u << rng.index(4);
    rays.push_back(ray);
  }
  return rays;
}

// Under the sanitizers a third of the rays: each still walks the cells and descends the
// hierarchy of every scene, where a memory error would be, and the reference's cast against
// every body took 44 s there; the release and double builds cast them all.
#if defined(PFX_TEST_SANITIZED)
constexpr PfxUInt32 kRaysPerRandomScene = 1000;
#else
constexpr PfxUInt32 kRaysPerRandomScene = 3000;
#endif

TEST(RayCastStage, WalkAndHierarchyEqualTestingEveryBodyInRandomScenes) {
  PfxUInt32 hits = 0, total = 0;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    RandomScene r;
    fillRandomScene(r, 300, seed);
    const PfxRayCastParam walk = r.scene->param();
    const PfxRayCastParam hierarchy = r.scene->bvhParam();
    for (const PfxRayInput& ray : randomRays(kRaysPerRandomScene, 100 + seed)) {
      const PfxRayOutput reference = r.scene->castEveryBody(ray);
      PfxRayOutput walked, descended;
      ASSERT_EQ(pfxCastSingleRay(ray, walked, walk), PFX_OK);
      ASSERT_EQ(pfxCastSingleRay(ray, descended, hierarchy), PFX_OK);
      expectSameOutput(walked, reference, "walk against every body");
      expectSameOutput(descended, reference, "hierarchy against every body");
      hits += walked.m_contactFlag;
      ++total;
    }
  }
  // Enough of both answers for the comparison to mean something.
  EXPECT_GT(hits, total / 5);
  EXPECT_LT(hits, total - total / 10);
}

TEST(RayCastStage, BatchEqualsSingleRays) {
  RandomScene r;
  fillRandomScene(r, 200, 9);
  const PfxRayCastParam param = r.scene->param();
  const std::vector<PfxRayInput> rays = randomRays(2000, 77);
  for (const PfxRayCastParam& p : {param, r.scene->bvhParam()}) {
    std::vector<PfxRayOutput> batch(rays.size());
    ASSERT_EQ(pfxCastRays(rays.data(), batch.data(), PfxUInt32(rays.size()), p), PFX_OK);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      PfxRayOutput single;
      ASSERT_EQ(pfxCastSingleRay(rays[i], single, p), PFX_OK);
      expectSameOutput(batch[i], single, "batch against single");
    }
  }
}

TEST(RayCastStage, MortonOrderedBatchEqualsSingleRaysInTheCallersPlaces) {
  RandomScene r;
  fillRandomScene(r, 200, 12);
  std::vector<PfxRayInput> rays = randomRays(3000, 31);
  // Rays from one point, as a range sensor casts them: equal start cells, ordered by
  // direction alone.
  RandomSource rng(2);
  for (int i = 0; i < 500; ++i) {
    rays.push_back(makeRay(PfxVector3(1, 20, -3), (rng.unit() * 80).cast<PfxFloat>()));
  }
  const PfxUInt32 numRays = PfxUInt32(rays.size());
  std::vector<PfxSortData16> work(pfxGetWorkBytesOfCastRays(numRays) / sizeof(PfxSortData16));
  PfxUInt32 hits = 0;
  for (PfxRayCastParam p : {r.scene->param(), r.scene->bvhParam()}) {
    p.workBuff = work.data();
    p.workBytes = pfxGetWorkBytesOfCastRays(numRays);
    std::vector<PfxRayOutput> batch(rays.size());
    ASSERT_EQ(pfxCastRays(rays.data(), batch.data(), numRays, p), PFX_OK);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      PfxRayOutput single;
      ASSERT_EQ(pfxCastSingleRay(rays[i], single, p), PFX_OK);
      expectSameOutput(batch[i], single, "ordered batch against single");
      hits += single.m_contactFlag;
    }
  }
  EXPECT_GT(hits, numRays / 5);
}

TEST(RayCastStageRejects, BadWorkBufferForTheOrderedBatch) {
  Scene scene(100);
  scene.add(makeSphere(1), PfxVector3::Zero());
  scene.buildProxies();
  PfxRayInput rays[4];
  for (PfxRayInput& ray : rays) ray = makeRay(PfxVector3(0, 5, 0), PfxVector3(0, -10, 0));
  alignas(16) PfxRayOutput out[4] = {poisonedOutput(), poisonedOutput(), poisonedOutput(),
                                     poisonedOutput()};
  const PfxUInt32 bytes = pfxGetWorkBytesOfCastRays(4);
  EXPECT_EQ(bytes, 4 * 2 * sizeof(PfxSortData16));
  std::vector<PfxSortData16> work(bytes / sizeof(PfxSortData16) + 1);
  PfxRayCastParam param = scene.param();
  param.workBuff = work.data();
  param.workBytes = bytes - 1;
  EXPECT_EQ(pfxCastRays(rays, out, 4, param), PFX_ERR_OUT_OF_BUFFER);
  param.workBuff = reinterpret_cast<char*>(work.data()) + 4;
  param.workBytes = bytes;
  EXPECT_EQ(pfxCastRays(rays, out, 4, param), PFX_ERR_INVALID_ALIGNMENT);
  // Scratch that is the output or the rays themselves.
  ASSERT_GE(sizeof(out), bytes);
  param.workBuff = out;
  param.workBytes = sizeof(out);
  EXPECT_EQ(pfxCastRays(rays, out, 4, param), PFX_ERR_INVALID_VALUE);
  for (const PfxRayOutput& o : out) EXPECT_TRUE(isPoisoned(o));
  alignas(16) PfxRayInput copies[4];
  ASSERT_GE(sizeof(copies), bytes);
  std::copy(rays, rays + 4, copies);
  param.workBuff = copies;
  param.workBytes = sizeof(copies);
  EXPECT_EQ(pfxCastRays(copies, out, 4, param), PFX_ERR_INVALID_VALUE);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(std::memcmp(&copies[i], &rays[i], sizeof(PfxRayInput)), 0);
  for (const PfxRayOutput& o : out) EXPECT_TRUE(isPoisoned(o));
  // A bad ray is still found before anything is sorted or written.
  param.workBuff = work.data();
  param.workBytes = bytes;
  rays[2].m_startPosition[0] = kNaN;
  EXPECT_EQ(pfxCastRays(rays, out, 4, param), PFX_ERR_INVALID_VALUE);
  for (const PfxRayOutput& o : out) EXPECT_TRUE(isPoisoned(o));
  rays[2] = rays[0];
  ASSERT_EQ(pfxCastRays(rays, out, 4, param), PFX_OK);
  for (const PfxRayOutput& o : out) EXPECT_NEAR(o.m_variable, 0.4f, 1e-6f);
}

// Every node's box holds its children's, every proxy is in exactly one leaf with its own
// box, and no path is longer than the median splits allow: ceil(log2 n) + 1 nodes.
TEST(RayBvh, NodesBoundTheirChildrenAndLeavesCoverEveryProxyOnce) {
  RandomScene r;
  fillRandomScene(r, 777, 5);
  const std::vector<PfxRayBvhNode>& nodes = r.scene->bvh();
  const std::vector<PfxBroadphaseProxy>& proxies = r.scene->proxiesX();
  ASSERT_EQ(nodes.size(), 2 * proxies.size() - 1);
  std::vector<int> seen(proxies.size(), 0);
  auto contains = [](const PfxRayBvhNode& outer, const PfxRayBvhNode& inner) {
    for (int a = 0; a < 3; ++a) {
      if (inner.m_min[a] < outer.m_min[a] || inner.m_max[a] > outer.m_max[a]) return false;
    }
    return true;
  };
  int deepest = 0;
  std::vector<std::pair<PfxUInt32, int>> pending = {{0, 1}};
  while (!pending.empty()) {
    const auto [index, depth] = pending.back();
    pending.pop_back();
    ASSERT_LT(index, nodes.size());
    deepest = std::max(deepest, depth);
    const PfxRayBvhNode& node = nodes[index];
    if (node.m_link & PFX_RAY_BVH_LEAF) {
      const PfxUInt32 p = node.m_link & ~PFX_RAY_BVH_LEAF;
      ASSERT_LT(p, proxies.size());
      ++seen[p];
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(node.m_min[a], pfxGetXMin(proxies[p], a));
        EXPECT_EQ(node.m_max[a], pfxGetXMax(proxies[p], a));
      }
      continue;
    }
    EXPECT_TRUE(contains(node, nodes[index + 1]));
    EXPECT_TRUE(contains(node, nodes[node.m_link]));
    pending.push_back({index + 1, depth + 1});
    pending.push_back({node.m_link, depth + 1});
  }
  for (int count : seen) EXPECT_EQ(count, 1);
  EXPECT_LE(deepest, 11);  // 777 proxies: ceil(log2 777) + 1 = 11
}

TEST(RayBvh, RejectsBadBuffersAndWritesNothing) {
  Scene scene(100);
  for (int i = 0; i < 8; ++i) scene.add(makeSphere(1), PfxVector3(3.0f * i, 0, 0));
  scene.buildProxies();
  std::vector<PfxRayBvhNode> nodes(pfxGetNumRayBvhNodes(8));
  std::memset(static_cast<void*>(nodes.data()), 0xab, nodes.size() * sizeof(PfxRayBvhNode));
  const std::vector<PfxRayBvhNode> untouched = nodes;
  alignas(16) PfxUInt32 work[12];
  PfxBuildRayBvhParam good;
  good.workBuff = work;
  good.workBytes = pfxGetWorkBytesOfBuildRayBvh(8);
  good.proxies = scene.proxiesX().data();
  good.numProxies = 8;
  good.nodes = nodes.data();
  good.maxNodes = PfxUInt32(nodes.size());
  auto rejects = [&](PfxBuildRayBvhParam p, PfxInt32 expected, const char* what) {
    EXPECT_EQ(pfxBuildRayBvh(p), expected) << what;
    EXPECT_EQ(std::memcmp(nodes.data(), untouched.data(), nodes.size() * sizeof(PfxRayBvhNode)), 0)
        << what;
  };
  PfxBuildRayBvhParam p = good;
  p.proxies = nullptr;
  rejects(p, PFX_ERR_NULL_POINTER, "no proxies");
  p = good;
  p.maxNodes = 14;
  rejects(p, PFX_ERR_OUT_OF_BUFFER, "14 nodes for 8 proxies");
  p = good;
  p.workBytes = 28;
  rejects(p, PFX_ERR_OUT_OF_BUFFER, "short work buffer");
  p = good;
  p.workBuff = reinterpret_cast<unsigned char*>(work) + 4;
  rejects(p, PFX_ERR_INVALID_ALIGNMENT, "misaligned work buffer");
  p = good;
  p.workBuff = nodes.data();
  rejects(p, PFX_ERR_INVALID_VALUE, "work buffer inside the nodes");
  p = good;
  p.numProxies = 0;
  EXPECT_EQ(pfxBuildRayBvh(p), PFX_OK);
  EXPECT_EQ(pfxBuildRayBvh(good), PFX_OK);
  // A hierarchy named without its proxies cannot be descended.
  PfxRayCastParam cast = scene.param();
  cast.bvhNodes = nodes.data();
  PfxRayOutput out = poisonedOutput();
  EXPECT_EQ(pfxCastSingleRay(makeRay(PfxVector3(-5, 0, 0), PfxVector3(10, 0, 0)), out, cast),
            PFX_ERR_NULL_POINTER);
  EXPECT_TRUE(isPoisoned(out));
  cast.bvhProxies = scene.proxiesX().data();
  ASSERT_EQ(pfxCastSingleRay(makeRay(PfxVector3(-5, 0, 0), PfxVector3(10, 0, 0)), out, cast),
            PFX_OK);
  EXPECT_EQ(out.m_variable, PfxFloat(0.4));
}

TEST(RayCastStage, EmptySceneMissesEverything) {
  PfxRayCastParam param;  // no proxies, no arrays
  PfxRayOutput out = poisonedOutput();
  const PfxRayInput ray = makeRay(PfxVector3(1, 2, 3), PfxVector3(0, 0, 10));
  ASSERT_EQ(pfxCastSingleRay(ray, out, param), PFX_OK);
  EXPECT_FALSE(out.m_contactFlag);
  EXPECT_EQ(out.m_contactPoint, PfxVector3(1, 2, 13));
  EXPECT_EQ(out.m_objectId, PFX_RAY_NO_OBJECT);
}

// ------------------------------------------------ watertightness

TEST(RayWatertight, ConvexMeshSphereStopsEveryRayAimedAtItsCentre) {
  // The icosahedron (circumradius sqrt(1 + phi^2) = 1.902, inradius 1.512) posed at random;
  // 100,000 rays from 3 to 20 m away aimed through its centre, each 1.5 times the distance
  // long, must all hit a face between the in- and circumsphere.
  const PfxConvexMesh mesh = buildMesh(makeIcosahedronTriangles());
  const PfxShape shape = makeMeshShape(&mesh);
  RandomSource rng(3);
  const PfxVector3 centre(1.5f, -2, 0.5f);
  const PfxTransform3 transform = pose(centre, rng.rotation());
  PfxUInt32 misses = 0, outside = 0;
  for (int i = 0; i < 100000; ++i) {
    const PfxVector3 start = centre + (rng.unit() * rng.uniform(3, 20)).cast<PfxFloat>();
    const PfxVector3 direction = (centre - start) * 1.5f;
    const ShapeHit h = castShape(shape, transform, start, direction);
    if (!h.hit) {
      ++misses;
      continue;
    }
    const PfxFloat r = (h.point - centre).norm();
    if (r < 1.511f || r > 1.903f) ++outside;
  }
  EXPECT_EQ(misses, 0u);
  EXPECT_EQ(outside, 0u);
}

// A closed sphere of unit radius: poles plus `rings - 1` rings of `segments` vertices,
// counter-clockwise from outside.
MeshSource makeClosedSphere(PfxUInt32 rings, PfxUInt32 segments) {
  MeshSource m;
  m.vertices.insert(m.vertices.end(), {0, 1, 0});
  for (PfxUInt32 r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (PfxUInt32 s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      m.vertices.insert(m.vertices.end(), {PfxFloat(std::sin(theta) * std::cos(phi)),
                                           PfxFloat(std::cos(theta)),
                                           PfxFloat(std::sin(theta) * std::sin(phi))});
    }
  }
  const PfxUInt32 south = m.numVertices();
  m.vertices.insert(m.vertices.end(), {0, -1, 0});
  auto ring = [&](PfxUInt32 r, PfxUInt32 s) { return 1 + (r - 1) * segments + s % segments; };
  for (PfxUInt32 s = 0; s < segments; ++s) {
    m.triangles.insert(m.triangles.end(), {0, ring(1, s + 1), ring(1, s)});
    for (PfxUInt32 r = 1; r + 1 < rings; ++r) {
      const PfxUInt32 a = ring(r, s), b = ring(r, s + 1), c = ring(r + 1, s + 1),
                      d = ring(r + 1, s);
      m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    }
    m.triangles.insert(m.triangles.end(), {south, ring(rings - 1, s), ring(rings - 1, s + 1)});
  }
  return m;
}

TEST(RayWatertight, LargeMeshSphereStopsEveryRayAimedAtItsCentre) {
  // A closed sphere of 3,200 triangles scaled to radius 2 as a body at a random pose, cast
  // through the batch stage: 100,000 rays from outside through its centre, a quarter of
  // them aimed at its vertices (where six triangles meet), all hit, and on the surface. A
  // triangle's corners are 4.5 degrees apart between rings and at most 9 along a ring, so
  // seen from the centre no point of it is 6 degrees from its corners, and none lies deeper
  // than 2 (1 - cos 6 deg) = 0.011 inside the sphere: hits between 1.989 and 2.
  MeshSource source = makeClosedSphere(40, 40);
  for (PfxFloat& v : source.vertices) v *= 2;
  for (const PfxUInt32 flags : {0u, PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED}) {
    MeshOwner owner;
    ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, source.param(flags)), PFX_OK);
    PfxShape shape;
    shape.reset();
    shape.setLargeTriMesh(&owner.mesh);
    Scene scene(100);
    RandomSource rng(8);
    const PfxVector3 centre(3, 1, -2);
    const PfxQuat orientation = rng.rotation();
    scene.add(shape, centre, orientation);
    scene.buildProxies();
    const PfxTransform3 transform = pose(centre, orientation);
    std::vector<PfxRayInput> rays;
    for (int i = 0; i < 100000; ++i) {
      PfxVector3 target = centre;
      Vec3d away = rng.unit();
      if (i % 4 == 0) {
        target = transform * source.vertex(PfxUInt32(i / 4) % source.numVertices());
        // From within 60 degrees of the vertex's outward direction, so that the ray goes on
        // into the solid; a ray that only touches a corner would be a grazing ray.
        const Vec3d outward = (target - centre).cast<double>().normalized();
        while (away.dot(outward) < 0.5) away = rng.unit();
      }
      const PfxVector3 start = target + (away * rng.uniform(3, 30)).cast<PfxFloat>();
      rays.push_back(makeRay(start, (target - start) * 1.2f));
    }
    std::vector<PfxRayOutput> out(rays.size());
    ASSERT_EQ(pfxCastRays(rays.data(), out.data(), PfxUInt32(rays.size()), scene.param()), PFX_OK);
    PfxUInt32 misses = 0, offSurface = 0;
    for (const PfxRayOutput& o : out) {
      if (!o.m_contactFlag) {
        ++misses;
        continue;
      }
      const PfxFloat r = (o.m_contactPoint - centre).norm();
      if (r < 1.989f || r > 2 + 1e-3f) ++offSurface;
    }
    EXPECT_EQ(misses, 0u) << "flags " << flags;
    EXPECT_EQ(offSurface, 0u) << "flags " << flags;
  }
}

TEST(RayLargeMesh, TriangleIndexPointAndNormalOnAPosedGrid) {
  // A flat 8 x 8 grid of 1 m cells (128 triangles facing +Y) turned and moved at random.
  // Rays aimed at a random point inside a random triangle from either side hit that
  // triangle there, with the face normal turned against the ray.
  const MeshSource grid = makeFlatGrid(8, 1);
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&owner.mesh);
  RandomSource rng(21);
  for (int i = 0; i < 500; ++i) {
    const PfxVector3 position = rng.position(5);
    const PfxQuat orientation = rng.rotation();
    Scene scene(50);
    scene.add(shape, position, orientation);
    scene.buildProxies();
    const PfxUInt32 triangle = PfxUInt32(rng.index(int(grid.numTriangles())));
    const double b0 = rng.uniform(0.05, 0.9), b1 = rng.uniform(0.05, 0.95 - b0);
    const PfxVector3 local = grid.vertex(grid.triangles[3 * triangle]) * PfxFloat(b0) +
                             grid.vertex(grid.triangles[3 * triangle + 1]) * PfxFloat(b1) +
                             grid.vertex(grid.triangles[3 * triangle + 2]) * PfxFloat(1 - b0 - b1);
    const PfxTransform3 transform = pose(position, orientation);
    const PfxVector3 target = transform * local;
    const PfxVector3 up = transform.linear() * PfxVector3(0, 1, 0);
    Vec3d heading;
    do {
      heading = rng.unit();
    } while (std::abs(heading.dot(up.cast<double>())) < 0.3);
    const PfxVector3 start = target - (heading * 2).cast<PfxFloat>();
    PfxRayOutput out;
    ASSERT_EQ(pfxCastSingleRay(makeRay(start, (target - start) * 2), out, scene.param()), PFX_OK);
    ASSERT_TRUE(out.m_contactFlag);
    EXPECT_EQ(out.m_triangleIndex, triangle);
    EXPECT_EQ(out.m_shapeId, 0u);
    EXPECT_NEAR(out.m_variable, 0.5f, 1e-5f);
    expectNear(out.m_contactPoint, target, 1e-5 * std::max(1.0, double(target.norm())), "point");
    expectNear(out.m_contactNormal, heading.dot(up.cast<double>()) < 0 ? up : PfxVector3(-up),
               1e-5, "normal");
  }
}

// ------------------------------------------------ bad input

TEST(RayCastStageRejects, BadRaysAndParametersLeaveTheOutputUntouched) {
  Scene scene(100);
  scene.add(makeSphere(1), PfxVector3::Zero());
  scene.buildProxies();
  const PfxRayCastParam good = scene.param();
  const PfxRayInput ray = makeRay(PfxVector3(-5, 0, 0), PfxVector3(10, 0, 0));
  struct Case {
    const char* what;
    PfxRayInput ray;
    PfxRayCastParam param;
    PfxInt32 expected;
  };
  std::vector<Case> cases;
  cases.push_back({"NaN start", makeRay(PfxVector3(kNaN, 0, 0), PfxVector3(1, 0, 0)), good,
                   PFX_ERR_INVALID_VALUE});
  cases.push_back({"infinite direction", makeRay(PfxVector3::Zero(), PfxVector3(kInf, 0, 0)),
                   good, PFX_ERR_INVALID_VALUE});
  cases.push_back({"zero length", makeRay(PfxVector3::Zero(), PfxVector3::Zero()), good,
                   PFX_ERR_DEGENERATE});
  PfxRayCastParam p = good;
  p.rangeExtent = PfxVector3(100, 0, 100);
  cases.push_back({"zero range", ray, p, PFX_ERR_INVALID_VALUE});
  p = good;
  p.rangeCenter[1] = kNaN;
  cases.push_back({"NaN range", ray, p, PFX_ERR_INVALID_VALUE});
  p = good;
  p.offsetRigidStates = nullptr;
  cases.push_back({"no states", ray, p, PFX_ERR_NULL_POINTER});
  p = good;
  p.offsetCollidables = nullptr;
  cases.push_back({"no collidables", ray, p, PFX_ERR_NULL_POINTER});
  p = good;
  p.proxiesX = nullptr;
  cases.push_back({"no +X array for a +X ray", ray, p, PFX_ERR_NULL_POINTER});
  for (const Case& c : cases) {
    PfxRayOutput out = poisonedOutput();
    EXPECT_EQ(pfxCastSingleRay(c.ray, out, c.param), c.expected) << c.what;
    EXPECT_TRUE(isPoisoned(out)) << c.what;
    PfxRayOutput batch[2] = {poisonedOutput(), poisonedOutput()};
    const PfxRayInput rays[2] = {ray, c.ray};
    EXPECT_EQ(pfxCastRays(rays, batch, 2, c.param), c.expected) << c.what;
    EXPECT_TRUE(isPoisoned(batch[0]) && isPoisoned(batch[1])) << c.what;
  }
  // Only the array that a ray needs is required: -X uses proxiesXb.
  p = good;
  p.proxiesX = nullptr;
  PfxRayOutput out;
  ASSERT_EQ(pfxCastSingleRay(makeRay(PfxVector3(5, 0, 0), PfxVector3(-10, 0, 0)), out, p), PFX_OK);
  EXPECT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_variable, PfxFloat(0.4));
}

TEST(RayCastStageRejects, BatchArraysMissingOrSharingBytes) {
  Scene scene(100);
  scene.add(makeSphere(1), PfxVector3::Zero());
  scene.buildProxies();
  const PfxRayCastParam param = scene.param();
  PfxRayInput rays[4];
  for (PfxRayInput& r : rays) r = makeRay(PfxVector3(0, 5, 0), PfxVector3(0, -10, 0));
  PfxRayOutput out[4] = {poisonedOutput(), poisonedOutput(), poisonedOutput(), poisonedOutput()};
  EXPECT_EQ(pfxCastRays(nullptr, out, 4, param), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(pfxCastRays(rays, nullptr, 4, param), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(pfxCastRays(nullptr, nullptr, 0, param), PFX_OK);
  for (const PfxRayOutput& o : out) EXPECT_TRUE(isPoisoned(o));
  // Output written over the rays it reads.
  alignas(16) unsigned char shared[sizeof(PfxRayInput) * 4 + sizeof(PfxRayOutput) * 4];
  auto* sharedRays = reinterpret_cast<PfxRayInput*>(shared);
  for (int i = 0; i < 4; ++i) sharedRays[i] = rays[i];
  auto* sharedOut = reinterpret_cast<PfxRayOutput*>(shared + sizeof(PfxRayInput));
  EXPECT_EQ(pfxCastRays(sharedRays, sharedOut, 4, param), PFX_ERR_INVALID_VALUE);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(std::memcmp(&sharedRays[i], &rays[i], sizeof(PfxRayInput)), 0);
  }
  // A bad ray anywhere in the batch: nothing is written, not even the good rays before it.
  rays[3].m_direction.setZero();
  EXPECT_EQ(pfxCastRays(rays, out, 4, param), PFX_ERR_DEGENERATE);
  for (const PfxRayOutput& o : out) EXPECT_TRUE(isPoisoned(o));
  // The single cast may write its answer over its own ray.
  PfxRayInput& in = rays[0];
  ASSERT_EQ(pfxCastSingleRay(in, reinterpret_cast<PfxRayOutput&>(shared), param), PFX_OK);
}

// ------------------------------------------------ the world

TEST(WorldRaycast, RaysSeeBodiesAsTheyAreAfterStepsAndChanges) {
  PfxWorldParam param;
  param.worldExtent = PfxVector3::Constant(50);
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxRayOutput out;
  const PfxRayInput down = makeRay(PfxVector3(0, 20, 0), PfxVector3(0, -40, 0));
  // An empty world: a miss over the whole ray.
  ASSERT_EQ(world.castRay(down, out), PFX_OK);
  EXPECT_FALSE(out.m_contactFlag);

  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -1, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 1, 20)), ground), PFX_OK);
  // The ground's top at y = 0 is 20 m down the 40 m ray.
  ASSERT_EQ(world.castRay(down, out), PFX_OK);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_objectId, 0u);
  EXPECT_EQ(out.m_variable, 0.5f);

  // A sphere added after that cast is seen by the next: top at 10 + 1 = 11, 9 m down.
  PfxBodyInit ball;
  ball.position = PfxVector3(0, 10, 0);
  PfxUInt32 ballId;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(1)), ball, &ballId), PFX_OK);
  ASSERT_EQ(world.castRay(down, out), PFX_OK);
  EXPECT_EQ(out.m_objectId, ballId);
  EXPECT_NEAR(out.m_variable, 9.0f / 40, 1e-6f);

  // After half a second of free fall the ball's top is where the world says it is.
  for (int i = 0; i < 30; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxFloat top = world.getRigidState(ballId).getPosition().y() + 1;
  ASSERT_LT(top, 11 - 1);
  ASSERT_EQ(world.castRay(down, out), PFX_OK);
  EXPECT_EQ(out.m_objectId, ballId);
  EXPECT_NEAR(out.m_contactPoint.y(), top, 1e-5f);

  // Moved aside by setRigidState: the ray reaches the ground again.
  PfxRigidState moved = world.getRigidState(ballId);
  moved.setPosition(PfxVector3(5, 10, 0));
  ASSERT_EQ(world.setRigidState(ballId, moved), PFX_OK);
  ASSERT_EQ(world.castRay(down, out), PFX_OK);
  EXPECT_EQ(out.m_objectId, 0u);

  // A body beyond the world's bounds is still seen; filters apply as in the stage.
  PfxBodyInit far;
  far.mass = 0;
  far.position = PfxVector3(80, 0, 0);
  PfxUInt32 farId;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(1, 1, 1)), far, &farId), PFX_OK);
  PfxRayInput sideways = makeRay(PfxVector3(60, 0, 0), PfxVector3(40, 0, 0));
  ASSERT_EQ(world.castRay(sideways, out), PFX_OK);
  EXPECT_EQ(out.m_objectId, farId);
  EXPECT_NEAR(out.m_variable, 19.0f / 40, 1e-6f);
  sideways.m_contactFilterTarget = 0;
  ASSERT_EQ(world.castRay(sideways, out), PFX_OK);
  EXPECT_FALSE(out.m_contactFlag);
}

TEST(WorldRaycast, BatchEqualsSingleAndBadInputChangesNothing) {
  PfxWorld world;
  RandomSource rng(4);
  for (int i = 0; i < 100; ++i) {
    PfxBodyInit init;
    init.mass = 0;
    init.position = rng.position(20);
    init.orientation = rng.rotation();
    const PfxShape shape = i % 2 ? pfxMakeShape(PfxBox(0.5f, 1, 1.5f)) : pfxMakeShape(PfxCapsule(1, 0.5f));
    ASSERT_EQ(pfxAddBody(world, shape, init), PFX_OK);
  }
  std::vector<PfxRayInput> rays;
  for (int i = 0; i < 500; ++i) {
    rays.push_back(makeRay(rng.position(25), (rng.unit() * 40).cast<PfxFloat>()));
  }
  std::vector<PfxRayOutput> batch(rays.size());
  ASSERT_EQ(world.castRays(rays.data(), batch.data(), PfxUInt32(rays.size())), PFX_OK);
  PfxUInt32 hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    PfxRayOutput single;
    ASSERT_EQ(world.castRay(rays[i], single), PFX_OK);
    expectSameOutput(batch[i], single, "world batch against single");
    hits += single.m_contactFlag;
  }
  EXPECT_GT(hits, 25u);

  PfxRayOutput out = poisonedOutput();
  EXPECT_EQ(world.castRay(makeRay(PfxVector3(0, kNaN, 0), PfxVector3(1, 0, 0)), out),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.castRay(makeRay(PfxVector3::Zero(), PfxVector3::Zero()), out),
            PFX_ERR_DEGENERATE);
  EXPECT_TRUE(isPoisoned(out));
  rays[250].m_direction[2] = kInf;
  std::vector<PfxRayOutput> untouched(rays.size());
  std::memset(static_cast<void*>(untouched.data()), 0xab, sizeof(PfxRayOutput) * untouched.size());
  EXPECT_EQ(world.castRays(rays.data(), untouched.data(), PfxUInt32(rays.size())),
            PFX_ERR_INVALID_VALUE);
  for (const PfxRayOutput& o : untouched) ASSERT_TRUE(isPoisoned(o));
  EXPECT_EQ(world.castRays(nullptr, untouched.data(), 3), PFX_ERR_NULL_POINTER);
}

TEST(WorldRaycast, CastsAndStepsAllocateNothingOnceWarm) {
  PfxWorld world;
  PfxBodyInit ground;
  ground.mass = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 1, 20)), ground), PFX_OK);
  for (int i = 0; i < 20; ++i) {
    PfxBodyInit box;
    box.position = PfxVector3(PfxFloat(i % 5) * 2 - 4, 2 + PfxFloat(i / 5) * 2, 0);
    ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.4f, 0.4f, 0.4f)), box), PFX_OK);
  }
  const PfxRayInput ray = makeRay(PfxVector3(0, 20, 0.1f), PfxVector3(0, -30, 0));
  PfxRayOutput out;
  // Warm: the boxes have landed and the pair buffers hold every contact they will.
  for (int i = 0; i < 120; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    ASSERT_EQ(world.castRay(ray, out), PFX_OK);
  }
  const long before = pfx_test::pfxAllocationCount();
  for (int i = 0; i < 60; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    ASSERT_EQ(world.castRay(ray, out), PFX_OK);
    ASSERT_EQ(world.castRays(&ray, &out, 1), PFX_OK);
  }
  EXPECT_EQ(pfx_test::pfxAllocationCount() - before, 0);
  EXPECT_TRUE(out.m_contactFlag);
}

}  // namespace
}  // namespace pfx_test
