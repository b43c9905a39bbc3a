#include "base_level/collision/contact/pfx_epa.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pfx {

namespace {

constexpr PfxUInt32 kEpaMaxVertices = 128;
constexpr PfxUInt32 kEpaMaxFaces = 2 * kEpaMaxVertices;
constexpr int kEpaMaxIterations = 124;
// A polytope whose nearest face has not moved out by the tolerance in this many steps
// makes no progress: on a curved surface thousands of times the tolerance across, each
// new vertex only trims a sliver (a box inside a cylinder of 780 km).
constexpr int kEpaStallSteps = 16;
// Twice a face's area, squared, below which its normal is noise.
constexpr PfxFloat kMinFaceAreaSq = PfxFloat(1e-24);
// A face this close to coplanar with a new vertex is replaced too, so that no sliver of
// nearly coplanar faces folds the polytope inwards.
constexpr PfxFloat kCoplanarSlack = PfxFloat(1e-6);
// Support points closer than this (squared) to a vertex are that vertex.
constexpr PfxFloat kSameVertexSq = PfxFloat(1e-12);
// The distance kept for a slot whose face was removed: never the nearest.
constexpr PfxFloat kFreeSlot = std::numeric_limits<PfxFloat>::infinity();

// A triangle of the polytope with its three neighbours, so that the faces a new vertex
// sees are found by a walk from the nearest face over its neighbours, and the horizon is
// the walk's edge: the work grows with the faces replaced, where testing every face and
// matching each removed edge against the horizon so far grew with the faces times the
// horizon (the classic expansion of EPA; van den Bergen 2001, Bullet's gjkepa2).
struct EpaFace {
  PfxUInt8 v[3];            // counter-clockwise seen from outside
  PfxUInt16 neighbour[3];   // the face across edge e, from v[e] to v[(e + 1) % 3]
  PfxUInt8 neighbourEdge[3];  // that edge's index in the neighbour
  PfxUInt32 walk;           // the last walk that took this face as one the new vertex sees
  PfxVector3 normal;        // outward, unit
};

// A horizon edge: a face that stays and its edge to a face that goes.
struct HorizonEdge {
  PfxUInt16 face;
  PfxUInt8 edge;
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
    // The faces are turned away from the tetrahedron's centre, which stays inside the
    // growing polytope, all alike (they are wound one way), so that each edge is walked
    // once in each direction by its two faces: by the face that sees the centre most
    // clearly, where a nearly flat tetrahedron leaves the others in doubt.
    PfxFloat clearest = 0;
    for (PfxUInt16 f = 0; f < 4; ++f) {
      const PfxVector3 n = faceCross(kFaces[f][0], kFaces[f][1], kFaces[f][2]);
      if (!(n.squaredNorm() > kMinFaceAreaSq)) return false;
      setFace(f, kFaces[f][0], kFaces[f][1], kFaces[f][2], n);
      const PfxFloat outwards = m_faces[f].normal.dot(m_verts[kFaces[f][0]].w - m_interior);
      if (std::abs(outwards) > std::abs(clearest)) clearest = outwards;
    }
    if (clearest < 0) {
      for (PfxUInt16 f = 0; f < 4; ++f) {
        std::swap(m_faces[f].v[1], m_faces[f].v[2]);
        m_faces[f].normal = -m_faces[f].normal;
        m_dist[f] = -m_dist[f];
      }
    }
    m_numSlots = 4;
    m_numLive = 4;
    return linkTetrahedron();
  }

  // Expands towards the face nearest the origin until the support point no longer moves
  // the boundary by more than `tolerance`, or the nearest face stops moving out. Returns the
  // index of that face; `leastOverlap` is the smallest overlap of the shapes seen along a
  // face's normal on the way (each is an upper bound of the depth), `leastOverlapNormal`
  // that normal.
  int expand(PfxFloat tolerance, bool& converged, PfxFloat& leastOverlap,
             PfxVector3& leastOverlapNormal) {
    converged = false;
    leastOverlap = std::numeric_limits<PfxFloat>::infinity();
    int best = nearestFace();
    PfxFloat stallStart = best >= 0 ? m_dist[best] : 0;
    int stalledSteps = 0;
    for (int iter = 0; iter < kEpaMaxIterations && best >= 0; ++iter) {
      const EpaFace& face = m_faces[best];
      const PfxSimplexVertex s = supportAlong(face.normal);
      const PfxFloat overlap = face.normal.dot(s.w);
      if (overlap < leastOverlap) {
        leastOverlap = overlap;
        leastOverlapNormal = face.normal;
      }
      if (overlap - m_dist[best] <= tolerance) {
        converged = true;
        break;
      }
      if (m_dist[best] > stallStart + tolerance) {
        stallStart = m_dist[best];
        stalledSteps = 0;
      } else if (++stalledSteps > kEpaStallSteps) {
        break;
      }
      if (m_numVerts >= kEpaMaxVertices) break;
      const PfxUInt8 newVert = static_cast<PfxUInt8>(m_numVerts);
      m_verts[m_numVerts++] = s;
      if (!carve(static_cast<PfxUInt16>(best), newVert)) break;
      best = nearestFace();
    }
    return best;
  }

  const EpaFace& face(int i) const { return m_faces[i]; }
  PfxFloat dist(int i) const { return m_dist[i]; }

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

  // (j - i) x (k - i): twice the area of the face (i, j, k) along its normal.
  PfxVector3 faceCross(PfxUInt8 i, PfxUInt8 j, PfxUInt8 k) const {
    const PfxVector3& a = m_verts[i].w;
    return (m_verts[j].w - a).cross(m_verts[k].w - a);
  }

  // Writes the face (i, j, k) into slot f, given its faceCross; the links to its neighbours
  // are the caller's.
  void setFace(PfxUInt16 f, PfxUInt8 i, PfxUInt8 j, PfxUInt8 k, const PfxVector3& cross) {
    EpaFace& face = m_faces[f];
    face.v[0] = i;
    face.v[1] = j;
    face.v[2] = k;
    face.normal = cross.normalized();
    m_dist[f] = face.normal.dot(m_verts[i].w);
    face.walk = 0;
  }

  // Links each edge of the first four faces to the one that walks it the other way.
  bool linkTetrahedron() {
    for (PfxUInt16 f = 0; f < 4; ++f) {
      for (PfxUInt8 e = 0; e < 3; ++e) {
        const PfxUInt8 from = m_faces[f].v[e];
        const PfxUInt8 to = m_faces[f].v[(e + 1) % 3];
        bool linked = false;
        for (PfxUInt16 g = 0; g < 4 && !linked; ++g) {
          for (PfxUInt8 k = 0; k < 3 && !linked && g != f; ++k) {
            if (m_faces[g].v[k] == to && m_faces[g].v[(k + 1) % 3] == from) {
              m_faces[f].neighbour[e] = g;
              m_faces[f].neighbourEdge[e] = k;
              linked = true;
            }
          }
        }
        if (!linked) return false;
      }
    }
    return true;
  }

  int nearestFace() const {
    int best = -1;
    PfxFloat bestDist = kFreeSlot;
    for (PfxUInt32 i = 0; i < m_numSlots; ++i) {
      if (m_dist[i] < bestDist) {
        bestDist = m_dist[i];
        best = static_cast<int>(i);
      }
    }
    return best;
  }

  bool sees(const EpaFace& f, const PfxVector3& w) const {
    return f.normal.dot(w - m_verts[f.v[0]].w) > -kCoplanarSlack;
  }

  // Removes the faces that see the new vertex, found by a walk over neighbours from
  // `first` (the nearest face, which the vertex lies beyond), and closes the hole with a
  // fan from it. Checks everything before changing anything: on false the polytope is as
  // it was. False too where the faces seen do not make one disc bounded by one loop of
  // edges, which only round-off on nearly flat faces brings about.
  bool carve(PfxUInt16 first, PfxUInt8 newVert) {
    const PfxVector3& w = m_verts[newVert].w;
    ++m_walk;
    PfxUInt16 removed[kEpaMaxFaces];
    PfxUInt32 numRemoved = 0;
    HorizonEdge horizon[kEpaMaxFaces + 2];
    PfxUInt32 numHorizon = 0;
    m_faces[first].walk = m_walk;
    removed[numRemoved++] = first;
    // `removed` doubles as the walk's queue: faces up to numRemoved are taken, those from
    // `next` on still have their neighbours to look at.
    for (PfxUInt32 next = 0; next < numRemoved; ++next) {
      const EpaFace& f = m_faces[removed[next]];
      for (int e = 0; e < 3; ++e) {
        const PfxUInt16 g = f.neighbour[e];
        if (m_faces[g].walk == m_walk) continue;
        if (sees(m_faces[g], w)) {
          m_faces[g].walk = m_walk;
          removed[numRemoved++] = g;
        } else {
          if (numHorizon >= kEpaMaxFaces + 2) return false;
          horizon[numHorizon++] = {g, f.neighbourEdge[e]};
        }
      }
    }
    if (numHorizon < 3 || m_numLive - numRemoved + numHorizon > kEpaMaxFaces) return false;

    // The horizon in order: each edge, walked as the removed face walked it (from the kept
    // face's second corner to its first), starts where the one before it ends.
    PfxUInt32 startsAt[kEpaMaxVertices];
    for (PfxUInt32 h = 0; h < numHorizon; ++h) {
      const PfxUInt8 from = horizonFrom(horizon[h]);
      if (m_vertexWalk[from] == m_walk) return false;  // two loops meet at a corner
      m_vertexWalk[from] = m_walk;
      startsAt[from] = h;
    }
    HorizonEdge loop[kEpaMaxFaces + 2];
    PfxUInt32 h = 0;
    for (PfxUInt32 k = 0; k < numHorizon; ++k) {
      loop[k] = horizon[h];
      const PfxUInt8 to = horizonTo(horizon[h]);
      if (m_vertexWalk[to] != m_walk) return false;
      h = startsAt[to];
      if ((h == 0) != (k + 1 == numHorizon)) return false;  // more than one loop
    }
    // A support point that is already a corner here cannot push the boundary out:
    // round-off has made the nearest face look further in than it is.
    for (PfxUInt32 r = 0; r < numRemoved; ++r) {
      for (const PfxUInt8 corner : m_faces[removed[r]].v) {
        if ((m_verts[corner].w - w).squaredNorm() <= kSameVertexSq) return false;
      }
    }
    PfxVector3 crosses[kEpaMaxFaces + 2];
    for (PfxUInt32 k = 0; k < numHorizon; ++k) {
      const PfxUInt8 from = horizonFrom(loop[k]);
      crosses[k] = faceCross(from, horizonTo(loop[k]), newVert);
      if (!(crosses[k].squaredNorm() > kMinFaceAreaSq)) return false;
      // A new face wound inwards (seen from the first tetrahedron's centre) would fold the
      // polytope.
      if (crosses[k].dot(m_verts[from].w - m_interior) < 0) return false;
    }

    for (PfxUInt32 r = 0; r < numRemoved; ++r) {
      m_dist[removed[r]] = kFreeSlot;
      m_freeSlots[m_numFree++] = removed[r];
    }
    PfxUInt16 made[kEpaMaxFaces + 2];
    for (PfxUInt32 k = 0; k < numHorizon; ++k) {
      made[k] = m_numFree > 0 ? m_freeSlots[--m_numFree] : static_cast<PfxUInt16>(m_numSlots++);
      const HorizonEdge& edge = loop[k];
      setFace(made[k], horizonFrom(edge), horizonTo(edge), newVert, crosses[k]);
      // Edge 0 of the new face lies on the kept face; edges 1 and 2 on the fan's next and
      // previous faces.
      EpaFace& kept = m_faces[edge.face];
      kept.neighbour[edge.edge] = made[k];
      kept.neighbourEdge[edge.edge] = 0;
      m_faces[made[k]].neighbour[0] = edge.face;
      m_faces[made[k]].neighbourEdge[0] = edge.edge;
    }
    for (PfxUInt32 k = 0; k < numHorizon; ++k) {
      const PfxUInt32 following = (k + 1) % numHorizon;
      m_faces[made[k]].neighbour[1] = made[following];
      m_faces[made[k]].neighbourEdge[1] = 2;
      m_faces[made[following]].neighbour[2] = made[k];
      m_faces[made[following]].neighbourEdge[2] = 1;
    }
    m_numLive = m_numLive - numRemoved + numHorizon;
    return true;
  }

  // A horizon edge's corners in the order the removed face walked it.
  PfxUInt8 horizonFrom(const HorizonEdge& e) const {
    return m_faces[e.face].v[(e.edge + 1) % 3];
  }
  PfxUInt8 horizonTo(const HorizonEdge& e) const { return m_faces[e.face].v[e.edge]; }

  const PfxConvexCore& m_a;
  const PfxConvexCore& m_b;
  PfxSimplexVertex m_verts[kEpaMaxVertices];
  EpaFace m_faces[kEpaMaxFaces];
  // Each face's distance from the origin along its normal, apart from the faces so that
  // the search for the nearest reads one short array.
  PfxFloat m_dist[kEpaMaxFaces];
  PfxUInt32 m_numVerts = 0;
  PfxUInt32 m_numSlots = 0;  // slots ever used; removed faces' slots are used again
  PfxUInt32 m_numLive = 0;
  PfxUInt16 m_freeSlots[kEpaMaxFaces];
  PfxUInt32 m_numFree = 0;
  PfxUInt32 m_walk = 0;      // the number of carve's walks so far
  PfxUInt32 m_vertexWalk[kEpaMaxVertices] = {};  // the last walk a horizon edge began at it
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
  PfxFloat leastOverlap;
  // Set whenever leastOverlap is finite, which is when it is read; zero keeps GCC from
  // warning that it might not be.
  PfxVector3 leastOverlapNormal = PfxVector3::Zero();
  const int best = polytope.expand(tolerance, converged, leastOverlap, leastOverlapNormal);
  if (best < 0) return false;
  const EpaFace& face = polytope.face(best);
  const PfxSimplexVertex& v0 = polytope.vert(face.v[0]);
  const PfxSimplexVertex& v1 = polytope.vert(face.v[1]);
  const PfxSimplexVertex& v2 = polytope.vert(face.v[2]);
  // The witness points share the weights of the origin's projection on the nearest face.
  PfxFloat weights[3];
  const PfxFloat dist = polytope.dist(best);
  const PfxVector3 shift = face.normal * dist;
  pfxClosestToOriginOnTriangle(v0.w - shift, v1.w - shift, v2.w - shift, weights);
  const PfxVector3 pointA = v0.a * weights[0] + v1.a * weights[1] + v2.a * weights[2];
  const PfxVector3 pointB = v0.b * weights[0] + v1.b * weights[1] + v2.b * weights[2];
  const PfxFloat overlap = face.normal.dot(a.support(face.normal) - b.support(-face.normal));
  if (!pfxIsFinite(pointA) || !pfxIsFinite(pointB) || !pfxIsFinite(overlap)) return false;
  if (!converged && leastOverlap < overlap) {
    // Stopped short, an earlier face's normal may separate the shapes with a shorter push
    // than the nearest face's (by 1,900 m of 780,000 for the box in the cylinder): the
    // points move, about their midpoint, to that normal and its overlap.
    const PfxVector3 middle = (pointA + pointB) * PfxFloat(0.5);
    result.normal = leastOverlapNormal;
    result.depth = leastOverlap;
    result.pointA = middle + leastOverlapNormal * (leastOverlap * PfxFloat(0.5));
    result.pointB = middle - leastOverlapNormal * (leastOverlap * PfxFloat(0.5));
    return true;
  }
  const PfxFloat correction = std::max(overlap - dist, PfxFloat(0)) * PfxFloat(0.5);
  result.normal = face.normal;
  result.depth = dist + 2 * correction;
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
