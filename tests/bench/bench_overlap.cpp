#include "bench_overlap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace pfxbench {

namespace {

using Mat3 = Eigen::Matrix3d;

double sphereSphere(double ra, const Vec3& ca, double rb, const Vec3& cb) {
  return std::max(0.0, ra + rb - (ca - cb).norm());
}

double sphereBox(double radius, const Vec3& centre, const Vec3& half, const BodyState& box) {
  const Vec3 local = box.orientation.normalized().conjugate() * (centre - box.position);
  const Vec3 clamped = local.cwiseMax(-half).cwiseMin(half);
  if (clamped != local) return std::max(0.0, radius - (local - clamped).norm());
  // Centre inside the box: it leaves through the nearest face.
  return radius + (half - local.cwiseAbs()).minCoeff();
}

// Separating-axis test over the 15 candidate axes. For two convex polytopes the least
// overlap over the face normals of both and the cross products of their edges is the
// penetration depth, since the Minkowski difference has no other face normals.
double boxBox(const Vec3& halfA, const BodyState& a, const Vec3& halfB, const BodyState& b) {
  const Mat3 ra = a.orientation.normalized().toRotationMatrix();
  const Mat3 rb = b.orientation.normalized().toRotationMatrix();
  const Vec3 offset = b.position - a.position;
  double least = std::numeric_limits<double>::infinity();
  auto test = [&](const Vec3& axis) {
    const double length = axis.norm();
    if (length < 1e-9) return;  // parallel edges: their cross product is no new axis
    const Vec3 n = axis / length;
    const double reachA = (ra.transpose() * n).cwiseAbs().dot(halfA);
    const double reachB = (rb.transpose() * n).cwiseAbs().dot(halfB);
    least = std::min(least, reachA + reachB - std::abs(offset.dot(n)));
  };
  for (int i = 0; i < 3; ++i) {
    test(ra.col(i));
    test(rb.col(i));
    for (int j = 0; j < 3; ++j) test(ra.col(i).cross(rb.col(j)));
  }
  return std::max(0.0, least);
}

}  // namespace

std::optional<double> overlapDepth(const ShapeDesc& a, const BodyState& poseA,
                                   const ShapeDesc& b, const BodyState& poseB) {
  const bool sphereA = a.type == ShapeType::Sphere, sphereB = b.type == ShapeType::Sphere;
  const bool boxA = a.type == ShapeType::Box, boxB = b.type == ShapeType::Box;
  if (sphereA && sphereB) return sphereSphere(a.radius, poseA.position, b.radius, poseB.position);
  if (sphereA && boxB) return sphereBox(a.radius, poseA.position, b.halfExtents, poseB);
  if (boxA && sphereB) return sphereBox(b.radius, poseB.position, a.halfExtents, poseA);
  if (boxA && boxB) return boxBox(a.halfExtents, poseA, b.halfExtents, poseB);
  return std::nullopt;
}

// Sweep and prune along X over bounding spheres, then the exact test.
double deepestOverlap(const Scene& scene, const std::vector<BodyState>& states) {
  const std::size_t n = scene.bodies.size();
  for (const BodyState& s : states) {
    if (!s.position.allFinite() || !s.orientation.coeffs().allFinite()) {
      return std::numeric_limits<double>::quiet_NaN();
    }
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  auto lowX = [&](std::size_t i) {
    return states[i].position.x() - scene.bodies[i].shape.outerRadius();
  };
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return lowX(i) < lowX(j); });

  // Bodies held by a joint never collide in any engine (bench_engine.h): boxes bounding
  // two links of an arm may overlap at their hinge by construction.
  std::vector<std::pair<int, int>> jointed;
  for (const JointDesc& joint : scene.joints) {
    if (joint.bodyA == kWorld) continue;
    jointed.emplace_back(std::min(joint.bodyA, joint.bodyB), std::max(joint.bodyA, joint.bodyB));
  }
  std::sort(jointed.begin(), jointed.end());
  auto isJointed = [&](std::size_t i, std::size_t j) {
    const std::pair<int, int> pair(static_cast<int>(std::min(i, j)), static_cast<int>(std::max(i, j)));
    return std::binary_search(jointed.begin(), jointed.end(), pair);
  };

  double deepest = 0;
  for (std::size_t oi = 0; oi < n; ++oi) {
    const std::size_t i = order[oi];
    const double ri = scene.bodies[i].shape.outerRadius();
    const double highX = states[i].position.x() + ri;
    for (std::size_t oj = oi + 1; oj < n && lowX(order[oj]) <= highX; ++oj) {
      const std::size_t j = order[oj];
      if (scene.bodies[i].fixed && scene.bodies[j].fixed) continue;
      const double reach = ri + scene.bodies[j].shape.outerRadius();
      if ((states[i].position - states[j].position).squaredNorm() > reach * reach) continue;
      if (isJointed(i, j)) continue;
      const std::optional<double> depth =
          overlapDepth(scene.bodies[i].shape, states[i], scene.bodies[j].shape, states[j]);
      if (depth) deepest = std::max(deepest, *depth);
    }
  }
  return deepest;
}

}  // namespace pfxbench
