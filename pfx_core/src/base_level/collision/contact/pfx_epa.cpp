#include "base_level/collision/contact/pfx_epa.h"

#include <algorithm>
#include <cmath>

namespace pfx {

namespace {

constexpr PfxUInt32 kEpaMaxVertices = 128;
constexpr PfxUInt32 kEpaMaxFaces = 2 * kEpaMaxVertices;
constexpr PfxUInt32 kMaxHorizon = 3 * kEpaMaxFaces;
constexpr int kEpaMaxIterations = 124;
// Twice a face's area, squared, below which its normal is noise.
constexpr PfxFloat kMinFaceAreaSq = PfxFloat(1e-24);
// A face this close to coplanar with a new vertex is replaced too, so that no sliver of
// nearly coplanar faces folds the polytope inwards.
constexpr PfxFloat kCoplanarSlack = PfxFloat(1e-6);
// Support points closer than this (squared) to a vertex are that vertex.
constexpr PfxFloat kSameVertexSq = PfxFloat(1e-12);

struct EpaFace {
  PfxUInt8 v[3];
  PfxVector3 normal;  // outward, unit
  PfxFloat dist;      // of the origin's projection along the normal
};

class Polytope {
 public:
  Polytope(const PfxConvexCore& a, const PfxConvexCore& b) : m_a(a), m_b(b) {}

  PfxSimplexVertex supportAlong(const PfxVector3& dir) const {
    PfxSimplexVertex s;
    s.a = m_a.support(dir);
    s.b = m_b.support(-dir);
    s.w = s.a - s.b;
    return s;
  }

  bool start(const PfxSimplexVertex* simplex, PfxUInt32 size, PfxFloat minSpread) {
    for (PfxUInt32 i = 0; i < size; ++i) m_verts[i] = simplex[i];
    m_numVerts = size;
    if (m_numVerts == 1) growFromPoint(minSpread);
    if (m_numVerts == 2) growFromSegment(minSpread);
    if (m_numVerts == 3) growFromTriangle(minSpread);
    if (m_numVerts != 4) return false;
    const PfxVector3 centre =
        (m_verts[0].w + m_verts[1].w + m_verts[2].w + m_verts[3].w) * PfxFloat(0.25);
    m_interior = centre;
    static const PfxUInt8 kFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    for (const auto& f : kFaces) {
      if (!addFace(f[0], f[1], f[2])) return false;
    }
    return true;
  }

  // Expands towards the face nearest the origin until the support point no longer moves
  // the boundary by more than `tolerance`. Returns the index of that face.
  int expand(PfxFloat tolerance, bool& converged) {
    converged = false;
    int best = nearestFace();
    for (int iter = 0; iter < kEpaMaxIterations && best >= 0; ++iter) {
      const EpaFace& face = m_faces[best];
      const PfxSimplexVertex s = supportAlong(face.normal);
      if (face.normal.dot(s.w) - face.dist <= tolerance) {
        converged = true;
        break;
      }
      if (m_numVerts >= kEpaMaxVertices || isKnownVertex(s.w)) break;
      const PfxUInt8 newVert = static_cast<PfxUInt8>(m_numVerts);
      m_verts[m_numVerts++] = s;
      if (!carve(newVert)) break;
      best = nearestFace();
    }
    return best;
  }

  const EpaFace& face(int i) const { return m_faces[i]; }

  // A support point that is already a vertex cannot push the boundary out: round-off has
  // made the nearest face look further in than it is.
  bool isKnownVertex(const PfxVector3& w) const {
    for (PfxUInt32 i = 0; i < m_numVerts; ++i) {
      if ((m_verts[i].w - w).squaredNorm() <= kSameVertexSq) return true;
    }
    return false;
  }
  const PfxSimplexVertex& vert(PfxUInt32 i) const { return m_verts[i]; }

 private:
  void tryAdd(const PfxVector3& dir, PfxFloat minSpread, bool (Polytope::*isNew)(
                                                             const PfxVector3&, PfxFloat) const) {
    if (dir.squaredNorm() <= PfxFloat(0)) return;
    const PfxSimplexVertex s = supportAlong(dir);
    if ((this->*isNew)(s.w, minSpread)) m_verts[m_numVerts++] = s;
  }
  bool awayFromPoint(const PfxVector3& w, PfxFloat minSpread) const {
    return (w - m_verts[0].w).squaredNorm() > minSpread * minSpread;
  }
  bool awayFromLine(const PfxVector3& w, PfxFloat minSpread) const {
    const PfxVector3 e = (m_verts[1].w - m_verts[0].w).normalized();
    const PfxVector3 off = w - m_verts[0].w;
    return (off - e * e.dot(off)).squaredNorm() > minSpread * minSpread;
  }
  bool awayFromPlane(const PfxVector3& w, PfxFloat minSpread) const {
    const PfxVector3 n =
        (m_verts[1].w - m_verts[0].w).cross(m_verts[2].w - m_verts[0].w).normalized();
    return std::abs(n.dot(w - m_verts[0].w)) > minSpread;
  }

  void growFromPoint(PfxFloat minSpread) {
    for (int axis = 0; axis < 6 && m_numVerts == 1; ++axis) {
      PfxVector3 dir = PfxVector3::Zero();
      dir[axis / 2] = axis % 2 ? PfxFloat(-1) : PfxFloat(1);
      tryAdd(dir, minSpread, &Polytope::awayFromPoint);
    }
  }
  void growFromSegment(PfxFloat minSpread) {
    const PfxVector3 e = m_verts[1].w - m_verts[0].w;
    int least = 0;
    for (int i = 1; i < 3; ++i) {
      if (std::abs(e[i]) < std::abs(e[least])) least = i;
    }
    PfxVector3 axis = PfxVector3::Zero();
    axis[least] = 1;
    const PfxVector3 d1 = e.cross(axis);
    const PfxVector3 d2 = e.cross(d1);
    const PfxVector3 dirs[4] = {d1, -d1, d2, -d2};
    for (int i = 0; i < 4 && m_numVerts == 2; ++i) {
      tryAdd(dirs[i], minSpread, &Polytope::awayFromLine);
    }
  }
  void growFromTriangle(PfxFloat minSpread) {
    const PfxVector3 n = (m_verts[1].w - m_verts[0].w).cross(m_verts[2].w - m_verts[0].w);
    tryAdd(n, minSpread, &Polytope::awayFromPlane);
    if (m_numVerts == 3) tryAdd(-n, minSpread, &Polytope::awayFromPlane);
  }

  bool addFace(PfxUInt8 i, PfxUInt8 j, PfxUInt8 k) {
    if (m_numFaces >= kEpaMaxFaces) return false;
    const PfxVector3& a = m_verts[i].w;
    PfxVector3 n = (m_verts[j].w - a).cross(m_verts[k].w - a);
    if (!(n.squaredNorm() > kMinFaceAreaSq)) return false;
    n.normalize();
    EpaFace& f = m_faces[m_numFaces++];
    f.v[0] = i;
    f.v[1] = j;
    f.v[2] = k;
    // Every face is turned away from the first tetrahedron's centre, which stays inside the
    // growing polytope: round-off cannot leave a face wound inwards.
    if (n.dot(a - m_interior) < 0) {
      n = -n;
      f.v[1] = k;
      f.v[2] = j;
    }
    f.normal = n;
    f.dist = n.dot(a);
    return true;
  }

  int nearestFace() const {
    int best = -1;
    for (PfxUInt32 i = 0; i < m_numFaces; ++i) {
      if (best < 0 || m_faces[i].dist < m_faces[best].dist) {
        best = static_cast<int>(i);
      }
    }
    return best;
  }

  // Removes the faces that see the new vertex and closes the hole with a fan from it. Checks
  // everything before changing anything: on false the polytope is as it was.
  bool carve(PfxUInt8 newVert) {
    const PfxVector3& w = m_verts[newVert].w;
    bool visible[kEpaMaxFaces];
    PfxUInt8 horizon[kMaxHorizon][2];
    PfxUInt32 numHorizon = 0;
    PfxUInt32 numVisible = 0;
    for (PfxUInt32 i = 0; i < m_numFaces; ++i) {
      const EpaFace& f = m_faces[i];
      visible[i] = f.normal.dot(w - m_verts[f.v[0]].w) > -kCoplanarSlack;
      if (!visible[i]) continue;
      ++numVisible;
      for (int e = 0; e < 3; ++e) {
        const PfxUInt8 from = f.v[e];
        const PfxUInt8 to = f.v[(e + 1) % 3];
        // An edge shared by two removed faces is walked both ways and is not horizon.
        bool shared = false;
        for (PfxUInt32 h = 0; h < numHorizon; ++h) {
          if (horizon[h][0] == to && horizon[h][1] == from) {
            horizon[h][0] = horizon[numHorizon - 1][0];
            horizon[h][1] = horizon[numHorizon - 1][1];
            --numHorizon;
            shared = true;
            break;
          }
        }
        if (!shared) {
          if (numHorizon >= kMaxHorizon) return false;
          horizon[numHorizon][0] = from;
          horizon[numHorizon][1] = to;
          ++numHorizon;
        }
      }
    }
    if (numHorizon == 0 || m_numFaces - numVisible + numHorizon > kEpaMaxFaces) return false;
    for (PfxUInt32 h = 0; h < numHorizon; ++h) {
      const PfxVector3& a = m_verts[horizon[h][0]].w;
      if ((m_verts[horizon[h][1]].w - a).cross(w - a).squaredNorm() <= kMinFaceAreaSq) {
        return false;
      }
    }
    PfxUInt32 kept = 0;
    for (PfxUInt32 i = 0; i < m_numFaces; ++i) {
      if (!visible[i]) m_faces[kept++] = m_faces[i];
    }
    m_numFaces = kept;
    for (PfxUInt32 h = 0; h < numHorizon; ++h) addFace(horizon[h][0], horizon[h][1], newVert);
    return true;
  }

  const PfxConvexCore& m_a;
  const PfxConvexCore& m_b;
  PfxSimplexVertex m_verts[kEpaMaxVertices];
  EpaFace m_faces[kEpaMaxFaces];
  PfxUInt32 m_numVerts = 0;
  PfxUInt32 m_numFaces = 0;
  PfxVector3 m_interior = PfxVector3::Zero();
};

}  // namespace

namespace {

// One EPA run from `simplex`. The reported depth is the overlap of the shapes along the
// found normal: an upper bound of the true depth, where the face distance is a lower bound
// that falls short by the chord error on curved surfaces.
bool runEpa(const PfxConvexCore& a, const PfxConvexCore& b, const PfxSimplexVertex* simplex,
            PfxUInt32 simplexSize, PfxFloat tolerance, PfxEpaResult& result, bool& converged) {
  Polytope polytope(a, b);
  if (!polytope.start(simplex, simplexSize, tolerance)) return false;
  const int best = polytope.expand(tolerance, converged);
  if (best < 0) return false;
  const EpaFace& face = polytope.face(best);
  const PfxSimplexVertex& v0 = polytope.vert(face.v[0]);
  const PfxSimplexVertex& v1 = polytope.vert(face.v[1]);
  const PfxSimplexVertex& v2 = polytope.vert(face.v[2]);
  // The witness points share the weights of the origin's projection on the nearest face.
  PfxFloat weights[3];
  const PfxVector3 shift = face.normal * face.dist;
  pfxClosestToOriginOnTriangle(v0.w - shift, v1.w - shift, v2.w - shift, weights);
  const PfxVector3 pointA = v0.a * weights[0] + v1.a * weights[1] + v2.a * weights[2];
  const PfxVector3 pointB = v0.b * weights[0] + v1.b * weights[1] + v2.b * weights[2];
  const PfxFloat overlap = face.normal.dot(a.support(face.normal) - b.support(-face.normal));
  const PfxFloat correction = std::max(overlap - face.dist, PfxFloat(0)) * PfxFloat(0.5);
  if (!pfxIsFinite(pointA) || !pfxIsFinite(pointB) || !pfxIsFinite(overlap)) return false;
  result.normal = face.normal;
  result.depth = face.dist + 2 * correction;
  result.pointA = pointA + face.normal * correction;
  result.pointB = pointB - face.normal * correction;
  return true;
}

}  // namespace

bool pfxEpaPenetration(const PfxConvexCore& a, const PfxConvexCore& b,
                       const PfxSimplexVertex* simplex, PfxUInt32 simplexSize,
                       PfxFloat tolerance, PfxEpaResult& result) {
  PfxEpaResult first;
  bool converged = false;
  const bool found = runEpa(a, b, simplex, simplexSize, tolerance, first, converged);
  if (found && converged && simplexSize == 4) {
    result = first;
    return true;
  }
  // GJK stops on any simplex that touches the origin, which for shapes with coincident
  // centres is a diagonal through the inside; a polytope grown from there can stall or
  // settle on a face of its own. A tetrahedron of supports in four spread directions holds
  // the origin well inside; both depths are overlaps along real directions, so the
  // smaller is the better answer.
  PfxSimplexVertex spread[4];
  const PfxFloat corners[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  for (int i = 0; i < 4; ++i) {
    const PfxVector3 dir(corners[i][0], corners[i][1], corners[i][2]);
    spread[i].a = a.support(dir);
    spread[i].b = b.support(-dir);
    spread[i].w = spread[i].a - spread[i].b;
  }
  PfxEpaResult second;
  const bool foundAgain = runEpa(a, b, spread, 4, tolerance, second, converged);
  if (foundAgain && (!found || second.depth < first.depth)) {
    result = second;
    return true;
  }
  if (!found) return false;
  result = first;
  return true;
}

}  // namespace pfx
