#include "base_level/collision/contact/pfx_gjk.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pfx {

namespace {

constexpr int kGjkMaxIterations = 64;
// Stop once the lower bound of the distance is within this fraction of the upper bound
// (squared terms): about 1e-5 relative in distance, near float resolution.
constexpr PfxFloat kRelativeTolerance = PfxFloat(1e-9);
// A step that does not shorten v by more than this (squared, relative) is rounding.
constexpr PfxFloat kStepRounding = PfxFloat(1e-6);
// Fresh starts of a descent that stalled with its bounds apart (see pfxGjkDistance).
constexpr int kGjkMaxRestarts = 2;

PfxFloat segmentWeight(const PfxVector3& a, const PfxVector3& b) {
  const PfxVector3 ab = b - a;
  const PfxFloat lenSq = ab.squaredNorm();
  if (lenSq <= PfxFloat(0)) return 0;
  return std::min(std::max(-a.dot(ab) / lenSq, PfxFloat(0)), PfxFloat(1));
}

// Keeps the simplex vertices with a positive weight and returns the closest point.
PfxVector3 reduce(PfxSimplexVertex* simplex, PfxUInt32& size, const PfxFloat* weights) {
  PfxVector3 v = PfxVector3::Zero();
  PfxUInt32 kept = 0;
  for (PfxUInt32 i = 0; i < size; ++i) {
    if (weights[i] <= 0) continue;
    v += simplex[i].w * weights[i];
    simplex[kept++] = simplex[i];
  }
  if (kept == 0) {  // only when every weight rounded to zero: keep the first vertex
    kept = 1;
    v = simplex[0].w;
  }
  size = kept;
  return v;
}

// Closest point of the simplex to the origin; shrinks the simplex to the smallest face that
// holds it. Returns false when the origin lies inside a full tetrahedron.
bool closestOnSimplex(PfxSimplexVertex* simplex, PfxUInt32& size, PfxVector3& v) {
  PfxFloat weights[4] = {1, 0, 0, 0};
  if (size == 2) {
    const PfxFloat t = segmentWeight(simplex[0].w, simplex[1].w);
    weights[0] = 1 - t;
    weights[1] = t;
  } else if (size == 3) {
    pfxClosestToOriginOnTriangle(simplex[0].w, simplex[1].w, simplex[2].w, weights);
  } else if (size == 4) {
    // The closest point lies on a face that the origin is in front of (seen from the
    // fourth vertex). A flat tetrahedron counts every face as such a face.
    static const int kFaces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
    PfxFloat bestDistSq = -1;
    for (const auto& f : kFaces) {
      const PfxVector3& a = simplex[f[0]].w;
      const PfxVector3& b = simplex[f[1]].w;
      const PfxVector3& c = simplex[f[2]].w;
      const PfxVector3 n = (b - a).cross(c - a);
      const PfxFloat originSide = -n.dot(a);
      const PfxFloat oppositeSide = n.dot(simplex[f[3]].w - a);
      if (originSide * oppositeSide > 0) continue;
      PfxFloat w[3];
      pfxClosestToOriginOnTriangle(a, b, c, w);
      const PfxFloat distSq = (a * w[0] + b * w[1] + c * w[2]).squaredNorm();
      if (bestDistSq < 0 || distSq < bestDistSq) {
        bestDistSq = distSq;
        weights[0] = weights[1] = weights[2] = weights[3] = 0;
        weights[f[0]] = w[0];
        weights[f[1]] = w[1];
        weights[f[2]] = w[2];
      }
    }
    if (bestDistSq < 0) {
      v.setZero();
      return false;
    }
  }
  v = reduce(simplex, size, weights);
  if (size == 3) {
    // Inside a triangle the closest point is the origin's projection on its plane. The sum
    // of weighted corners cancels corners half a metre out down to a millimetre and turned
    // v by a milliradian in float; the plane's normal keeps its direction to rounding.
    const PfxVector3 n = (simplex[1].w - simplex[0].w).cross(simplex[2].w - simplex[0].w);
    const PfxFloat nn = n.squaredNorm();
    if (nn > PfxFloat(0)) v = n * (n.dot(simplex[0].w) / nn);
  }
  return true;
}

}  // namespace

void pfxClosestToOriginOnTriangle(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c,
                                  PfxFloat weights[3]) {
  // Voronoi regions of the vertices, then the edges, then the inside (Ericson 5.1.5).
  const PfxVector3 ab = b - a;
  const PfxVector3 ac = c - a;
  const PfxFloat d1 = -ab.dot(a);
  const PfxFloat d2 = -ac.dot(a);
  weights[0] = weights[1] = weights[2] = 0;
  if (d1 <= 0 && d2 <= 0) {
    weights[0] = 1;
    return;
  }
  const PfxFloat d3 = -ab.dot(b);
  const PfxFloat d4 = -ac.dot(b);
  if (d3 >= 0 && d4 <= d3) {
    weights[1] = 1;
    return;
  }
  const PfxFloat vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
    weights[1] = d1 / (d1 - d3);
    weights[0] = 1 - weights[1];
    return;
  }
  const PfxFloat d5 = -ab.dot(c);
  const PfxFloat d6 = -ac.dot(c);
  if (d6 >= 0 && d5 <= d6) {
    weights[2] = 1;
    return;
  }
  const PfxFloat vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) {
    weights[2] = d2 / (d2 - d6);
    weights[0] = 1 - weights[2];
    return;
  }
  const PfxFloat va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0) {
    weights[2] = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    weights[1] = 1 - weights[2];
    return;
  }
  const PfxFloat denom = va + vb + vc;
  if (denom > PfxFloat(1e-12) * (ab.cross(ac).squaredNorm() + PfxFloat(1e-30)) && denom > 0) {
    weights[1] = vb / denom;
    weights[2] = vc / denom;
    weights[0] = 1 - weights[1] - weights[2];
    return;
  }
  // A degenerate (flat) triangle: the best of its three edges.
  const PfxVector3* corners[3] = {&a, &b, &c};
  PfxFloat bestDistSq = -1;
  for (int e = 0; e < 3; ++e) {
    const PfxVector3& p = *corners[e];
    const PfxVector3& q = *corners[(e + 1) % 3];
    const PfxFloat t = segmentWeight(p, q);
    const PfxFloat distSq = (p + (q - p) * t).squaredNorm();
    if (bestDistSq < 0 || distSq < bestDistSq) {
      bestDistSq = distSq;
      weights[0] = weights[1] = weights[2] = 0;
      weights[e] = 1 - t;
      weights[(e + 1) % 3] = t;
    }
  }
}

namespace {

// One descent from the support point along `dir` (towards A from B), carrying the best
// separation seen before it (`separation` along `separatingNormal`, minus infinity for none).
PfxGjkResult descend(const PfxConvexCore& a, const PfxConvexCore& b, PfxFloat tolerance,
                     const PfxVector3& dir, PfxFloat separation,
                     const PfxVector3& separatingNormal) {
  PfxGjkResult result;
  PfxSimplexVertex* simplex = result.simplex;
  PfxUInt32 size = 1;

  simplex[0].a = a.support(-dir);
  simplex[0].b = b.support(dir);
  simplex[0].w = simplex[0].a - simplex[0].b;
  PfxVector3 v = simplex[0].w;
  const PfxFloat toleranceSq = tolerance * tolerance;
  bool overlap = false;
  // The largest separation seen along a search direction: every point of A - B lies at
  // least this far from the origin along v. Once it exceeds the tolerance the cores are
  // apart for certain, whatever a nearly flat simplex later rounds to.
  result.separation = separation;
  result.separatingNormal = separatingNormal;

  for (int iter = 0; iter < kGjkMaxIterations; ++iter) {
    const PfxFloat vv = v.squaredNorm();
    if (vv <= toleranceSq) {
      overlap = true;
      break;
    }
    PfxSimplexVertex next;
    next.a = a.support(-v);
    next.b = b.support(v);
    next.w = next.a - next.b;
    // The last direction counts too: where the descent converges it is the exact normal,
    // taken from the simplex's plane, while the closest points, weighted sums of corners
    // half a metre out on a sliver of a triangle, turned it by up to 3 mrad in float (a
    // capsule's core 2 mm from a mesh's).
    const PfxFloat length = std::sqrt(vv);
    if (v.dot(next.w) > result.separation * length) {
      result.separation = v.dot(next.w) / length;
      result.separatingNormal = -v / length;
    }
    if (vv - v.dot(next.w) <= kRelativeTolerance * vv) break;
    bool repeated = false;
    for (PfxUInt32 i = 0; i < size; ++i) {
      if ((simplex[i].w - next.w).squaredNorm() <= PfxFloat(1e-12) * vv) repeated = true;
    }
    if (repeated) break;

    PfxSimplexVertex saved[4];
    const PfxUInt32 savedSize = size;
    std::copy(simplex, simplex + size, saved);
    simplex[size++] = next;
    PfxVector3 closest;
    const bool enclosed = !closestOnSimplex(simplex, size, closest);
    if (enclosed && result.separation <= tolerance) {
      overlap = true;
      v.setZero();
      break;
    }
    // On a cylinder's rim the simplex turns into slivers: every other new support point
    // shortens v by a few parts in a billion, below float resolution, before the next one
    // drops it by a millimetre. Such a step is taken while the bounds still lie apart.
    const bool stepWithinRounding = closest.squaredNorm() < vv * (1 + kStepRounding) &&
                                    vv - v.dot(next.w) > kStepRounding * vv;
    if (enclosed || (closest.squaredNorm() >= vv && !stepWithinRounding)) {
      // Round-off stalled the descent (a support point a hair from an edge of the simplex
      // makes a tetrahedron so flat that the origin seems inside it, 3.8 cm from a cylinder):
      // the previous simplex was as close as it gets.
      std::copy(saved, saved + savedSize, simplex);
      size = savedSize;
      break;
    }
    v = closest;
  }

  result.simplexSize = size;
  if (overlap) {
    result.distance = 0;
  } else {
    result.distance = v.norm();
  }
  // The closest points share the barycentric weights of v on the final simplex.
  PfxFloat weights[4] = {1, 0, 0, 0};
  if (size == 2) {
    const PfxFloat t = segmentWeight(simplex[0].w, simplex[1].w);
    weights[0] = 1 - t;
    weights[1] = t;
  } else if (size == 3) {
    pfxClosestToOriginOnTriangle(simplex[0].w, simplex[1].w, simplex[2].w, weights);
  } else if (size == 4) {
    weights[0] = weights[1] = weights[2] = weights[3] = PfxFloat(0.25);
  }
  result.pointA.setZero();
  result.pointB.setZero();
  for (PfxUInt32 i = 0; i < size; ++i) {
    result.pointA += simplex[i].a * weights[i];
    result.pointB += simplex[i].b * weights[i];
  }
  return result;
}

}  // namespace

PfxGjkResult pfxGjkDistance(const PfxConvexCore& a, const PfxConvexCore& b, PfxFloat tolerance) {
  PfxVector3 dir = a.m_position - b.m_position;
  if (dir.squaredNorm() <= PFX_EPSILON * PFX_EPSILON) dir = a.m_rotation.col(1);
  PfxGjkResult result = descend(a, b, tolerance, dir, -std::numeric_limits<PfxFloat>::infinity(),
                                PfxVector3::Zero());
  // Where one shape is ruled (a cylinder's side, a capsule's or box's edge) nearly across
  // the search direction, its support point jumps between the line's two ends, and the
  // simplex keeps corners taken along early, poor directions: its faces are chords that
  // cut 0.03 mm inside the surface, and each new support point shortens the closest point
  // by less than float resolves (a capsule 0.05 m from a cylinder, 10,000 poses of seed
  // 7). A descent that stops with its bounds further apart than the tolerance starts again
  // from its best separating direction, with a simplex all of whose corners lie near the
  // answer; the shorter distance and the larger separation are kept. So does a descent
  // that never saw the cores apart along any of its directions: a mesh 2.3e-5 m from a
  // cylinder's side, whose simplex of slivers turned its closest point up to 0.9 rad away
  // from the normal in its last steps, shows a separation within 1.2e-6 m of the true one
  // on a fresh start from its best direction.
  for (int restart = 0; restart < kGjkMaxRestarts && result.distance > 0 &&
                        result.distance - result.separation > tolerance;
       ++restart) {
    PfxGjkResult again = descend(a, b, tolerance, -result.separatingNormal, result.separation,
                                 result.separatingNormal);
    if (again.distance > 0 && again.distance < result.distance) {
      result = again;
    } else {
      result.separation = again.separation;
      result.separatingNormal = again.separatingNormal;
    }
  }
  return result;
}

bool pfxGjkGap(const PfxConvexCore& a, const PfxConvexCore& b, PfxFloat tolerance,
               PfxGjkResult& result, PfxCoreGap& gap) {
  result = pfxGjkDistance(a, b, tolerance);
  const PfxVector3 between = result.pointB - result.pointA;
  if (result.distance <= tolerance || between.squaredNorm() <= tolerance * tolerance) {
    return false;
  }
  // The points are rebuilt from the simplex separately, so their gap, not the simplex
  // distance, gives the unit normal.
  gap.normal = between.normalized();
  gap.pointA = result.pointA;
  gap.pointB = result.pointB;
  gap.distance = result.distance;
  // Against a flat face of a curved shape (a cylinder's cap) the supports jump from rim
  // point to rim point and the descent can stall a tenth of a millimetre from touching with
  // its last direction a degree off, along which the cores overlap by millimetres; and
  // closest points half a metre out, 0.01 mm apart, give their difference's direction only
  // to a few milliradians in float. A direction seen earlier that separates them by more is
  // then the answer: its separation is certain, and the points move to it about their
  // midpoint. (Asking that it also separate them by more than the tolerance kept a normal
  // along which a wide cylinder and a box overlapped by 3.7 mm, the search's best direction
  // showing them 0.01 mm apart.) So is a separation larger than the simplex's distance,
  // which only rounding makes: a sliver's plane, from corners far apart, tilts enough in
  // float to bring the origin's projection on it 0.03 mm closer than the shapes are.
  const PfxFloat alongPoints =
      gap.normal.dot(b.support(-gap.normal) - a.support(gap.normal));
  if (result.separation > 0 &&
      (result.separation > alongPoints + tolerance || result.separation > result.distance)) {
    const PfxVector3 middle = (result.pointA + result.pointB) * PfxFloat(0.5);
    gap.normal = result.separatingNormal;
    gap.distance = result.separation;
    gap.pointA = middle - gap.normal * (gap.distance * PfxFloat(0.5));
    gap.pointB = middle + gap.normal * (gap.distance * PfxFloat(0.5));
  }
  return true;
}

bool pfxGjkGap(const PfxConvexCore& a, const PfxConvexCore& b, PfxCoreGap& gap) {
  PfxGjkResult result;
  const PfxFloat scale = a.boundingRadius() + b.boundingRadius() + PFX_EPSILON;
  return pfxGjkGap(a, b, PfxFloat(1e-5) * scale, result, gap);
}

}  // namespace pfx
