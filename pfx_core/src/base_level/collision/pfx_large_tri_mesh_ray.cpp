// Closest hit of a ray against a large mesh: front-to-back descent of the node hierarchy
// with the per-ray data computed once, and the watertight ray/triangle test of Woop,
// Benthin and Wald (2013, "Watertight Ray/Triangle Intersection", JCGT 2(1)).
//
// A quantized mesh is searched in its own integer space, p' = (p - origin) / step: the map
// is affine, so the ray's fraction is the same there, node bounds and vertices are exact
// small integers (no dequantizing in the loop), and shared vertices stay bit-identical,
// which is all the watertight test needs.
#include <algorithm>
#include <cmath>
#include <limits>

#include "base_level/collision/pfx_large_tri_mesh_access.h"

namespace pfx {

namespace {

// Slab distances are rounded; widening the far distance by a few ulps (Ize 2013,
// "Robust BVH Ray Traversal") keeps a box whose face the ray grazes from being missed.
constexpr PfxFloat kFarScale = PfxFloat(1) + PfxFloat(4) * std::numeric_limits<PfxFloat>::epsilon();

struct Ray {
  PfxFloat org[3];
  PfxFloat dir[3];
  PfxFloat inv[3];
  // The shear that maps the ray onto +z (Woop et al.): kz is the largest direction axis.
  int kx, ky, kz;
  PfxFloat sx, sy, sz;
};

void setUpRay(const PfxVector3& start, const PfxVector3& direction, Ray& ray) {
  for (int i = 0; i < 3; ++i) {
    ray.org[i] = start[i];
    ray.dir[i] = direction[i];
    // A zero component would give 0 * inf = NaN in the slab test; a tiny one gives huge
    // but ordered distances instead.
    const PfxFloat d = direction[i] != 0 ? direction[i] : std::numeric_limits<PfxFloat>::min();
    ray.inv[i] = PfxFloat(1) / d;
  }
  int kz = 0;
  if (std::abs(direction[1]) > std::abs(direction[kz])) kz = 1;
  if (std::abs(direction[2]) > std::abs(direction[kz])) kz = 2;
  int kx = (kz + 1) % 3;
  int ky = (kx + 1) % 3;
  // Keeps the winding of the sheared triangle, so the sign of U, V, W means the same side.
  if (direction[kz] < 0) std::swap(kx, ky);
  ray.kx = kx;
  ray.ky = ky;
  ray.kz = kz;
  ray.sx = direction[kx] / direction[kz];
  ray.sy = direction[ky] / direction[kz];
  ray.sz = PfxFloat(1) / direction[kz];
}

// Entry fraction of the ray into the box, or +inf when it misses it or enters beyond
// `limit`.
inline PfxFloat boxEntry(const Ray& ray, const PfxFloat lo[3], const PfxFloat hi[3],
                         PfxFloat limit) {
  PfxFloat tNear = 0;
  PfxFloat tFar = limit;
  for (int i = 0; i < 3; ++i) {
    const PfxFloat t0 = (lo[i] - ray.org[i]) * ray.inv[i];
    const PfxFloat t1 = (hi[i] - ray.org[i]) * ray.inv[i];
    tNear = std::max(tNear, std::min(t0, t1));
    tFar = std::min(tFar, std::max(t0, t1) * kFarScale);
  }
  return tNear <= tFar ? tNear : std::numeric_limits<PfxFloat>::infinity();
}

// The ray against triangle (a, b, c): on a hit at a fraction within [0, best], sets
// best to it. Both faces hit.
inline bool intersectTriangle(const Ray& ray, const PfxFloat a[3], const PfxFloat b[3],
                        const PfxFloat c[3], PfxFloat& best) {
  const PfxFloat az = a[ray.kz] - ray.org[ray.kz];
  const PfxFloat bz = b[ray.kz] - ray.org[ray.kz];
  const PfxFloat cz = c[ray.kz] - ray.org[ray.kz];
  const PfxFloat ax = (a[ray.kx] - ray.org[ray.kx]) - ray.sx * az;
  const PfxFloat ay = (a[ray.ky] - ray.org[ray.ky]) - ray.sy * az;
  const PfxFloat bx = (b[ray.kx] - ray.org[ray.kx]) - ray.sx * bz;
  const PfxFloat by = (b[ray.ky] - ray.org[ray.ky]) - ray.sy * bz;
  const PfxFloat cx = (c[ray.kx] - ray.org[ray.kx]) - ray.sx * cz;
  const PfxFloat cy = (c[ray.ky] - ray.org[ray.ky]) - ray.sy * cz;
  PfxFloat u = cx * by - cy * bx;
  PfxFloat v = ax * cy - ay * cx;
  PfxFloat w = bx * ay - by * ax;
  // An edge through the ray: the exact sign decides which triangle owns it, so the two
  // triangles of an edge agree and the ray cannot pass between them.
  if (u == 0 || v == 0 || w == 0) {
    u = static_cast<PfxFloat>(double(cx) * double(by) - double(cy) * double(bx));
    v = static_cast<PfxFloat>(double(ax) * double(cy) - double(ay) * double(cx));
    w = static_cast<PfxFloat>(double(bx) * double(ay) - double(by) * double(ax));
  }
  if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return false;
  const PfxFloat det = u + v + w;
  if (det == 0) return false;
  const PfxFloat t = (u * az + v * bz + w * cz) * ray.sz;
  if (det > 0 ? (t < 0 || t > best * det) : (t > 0 || t < best * det)) return false;
  best = t / det;
  return true;
}

// Front-to-back search over one storage kind. Node::bounds(node, lo, hi) and
// vertex(index, out) read the mesh in the space the ray was set up in.
template <class Nodes, class Vertices>
bool castRay(const PfxLargeTriMesh& mesh, const Ray& ray, const Nodes& nodes,
             const Vertices& vertex, PfxFloat& fraction, PfxUInt32& hitIndex) {
  PfxFloat best = 1;
  PfxUInt32 hit = PFX_LARGE_MESH_NO_TRIANGLE;
  PfxFloat lo[3], hi[3];
  nodes.bounds(0, lo, hi);
  if (boxEntry(ray, lo, hi, best) > best) return false;

  PfxUInt32 stackNode[PFX_LARGE_MESH_MAX_DEPTH];
  PfxFloat stackEntry[PFX_LARGE_MESH_MAX_DEPTH];
  PfxUInt32 depth = 0;
  PfxUInt32 node = 0;
  for (;;) {
    const PfxUInt32 link = nodes.link(node);
    if (pfxLargeMeshIsLeaf(link)) {
      const PfxLargeMeshIsland& island = mesh.m_islands[pfxLargeMeshLeafIsland(link)];
      const PfxUInt32 first = island.m_firstTriangle + pfxLargeMeshLeafOffset(link);
      const PfxUInt32 last = first + pfxLargeMeshLeafCount(link);
      for (PfxUInt32 t = first; t < last; ++t) {
        PfxUInt32 corners[3];
        pfxLargeMeshCorners(mesh, island, t, corners);
        PfxFloat a[3], b[3], c[3];
        vertex(corners[0], a);
        vertex(corners[1], b);
        vertex(corners[2], c);
        if (intersectTriangle(ray, a, b, c, best)) hit = t;
      }
    } else {
      const PfxUInt32 left = pfxLargeMeshFirstChild(link);
      const PfxUInt32 right = left + 1;
      nodes.bounds(left, lo, hi);
      const PfxFloat tLeft = boxEntry(ray, lo, hi, best);
      nodes.bounds(right, lo, hi);
      const PfxFloat tRight = boxEntry(ray, lo, hi, best);
      const bool hitLeft = tLeft <= best;
      const bool hitRight = tRight <= best;
      if (hitLeft && hitRight) {
        const bool leftFirst = tLeft <= tRight;
        stackNode[depth] = leftFirst ? right : left;
        stackEntry[depth] = leftFirst ? tRight : tLeft;
        ++depth;
        node = leftFirst ? left : right;
        continue;
      }
      if (hitLeft || hitRight) {
        node = hitLeft ? left : right;
        continue;
      }
    }
    // Next deferred node that the closest hit so far does not already rule out.
    for (;;) {
      if (depth == 0) {
        if (hit == PFX_LARGE_MESH_NO_TRIANGLE) return false;
        fraction = best;
        hitIndex = hit;
        return true;
      }
      --depth;
      if (stackEntry[depth] <= best) {
        node = stackNode[depth];
        break;
      }
    }
  }
}

struct FloatNodes {
  const PfxLargeMeshNode* nodes;
  PfxUInt32 link(PfxUInt32 i) const { return nodes[i].m_link; }
  void bounds(PfxUInt32 i, PfxFloat lo[3], PfxFloat hi[3]) const {
    for (int k = 0; k < 3; ++k) {
      lo[k] = nodes[i].m_min[k];
      hi[k] = nodes[i].m_max[k];
    }
  }
};

struct QuantizedNodes {
  const PfxLargeMeshQuantizedNode* nodes;
  PfxUInt32 link(PfxUInt32 i) const { return nodes[i].m_link; }
  void bounds(PfxUInt32 i, PfxFloat lo[3], PfxFloat hi[3]) const {
    for (int k = 0; k < 3; ++k) {
      lo[k] = PfxFloat(nodes[i].m_min[k]);
      hi[k] = PfxFloat(nodes[i].m_max[k]);
    }
  }
};

}  // namespace

bool pfxRayCastLargeTriMesh(const PfxLargeTriMesh& mesh, const PfxVector3& start,
                            const PfxVector3& direction, PfxFloat& fraction,
                            PfxVector3& normal, PfxUInt32& triangleIndex) {
  if (mesh.m_numNodes == 0 || !pfxIsFinite(start) || !pfxIsFinite(direction) ||
      direction.isZero(0)) {
    return false;
  }
  Ray ray;
  PfxFloat hitFraction = 0;
  PfxUInt32 hit = 0;
  bool found;
  if (pfxLargeMeshIsQuantized(mesh)) {
    setUpRay((start - mesh.m_quantOrigin).cwiseQuotient(mesh.m_quantStep),
             direction.cwiseQuotient(mesh.m_quantStep), ray);
    const PfxUInt16* q = mesh.m_quantizedVertices;
    found = castRay(mesh, ray, QuantizedNodes{mesh.m_quantizedNodes},
                    [q](PfxUInt32 v, PfxFloat out[3]) {
                      for (int k = 0; k < 3; ++k) out[k] = PfxFloat(q[3 * v + k]);
                    },
                    hitFraction, hit);
  } else {
    setUpRay(start, direction, ray);
    const PfxFloat* p = mesh.m_vertices;
    found = castRay(mesh, ray, FloatNodes{mesh.m_nodes},
                    [p](PfxUInt32 v, PfxFloat out[3]) {
                      for (int k = 0; k < 3; ++k) out[k] = p[3 * v + k];
                    },
                    hitFraction, hit);
  }
  if (!found) return false;
  PfxVector3 v0, v1, v2;
  pfxGetLargeTriMeshTriangle(mesh, hit, v0, v1, v2);
  PfxVector3 n = (v1 - v0).cross(v2 - v0);
  const PfxFloat length = n.norm();
  // A triangle flattened by quantization still stops the ray; it faces the ray then.
  n = length > 0 ? PfxVector3(n / length) : PfxVector3(-direction.normalized());
  if (n.dot(direction) > 0) n = -n;
  fraction = hitFraction;
  normal = n;
  triangleIndex = mesh.m_triangleSourceIds[hit];
  return true;
}

}  // namespace pfx
