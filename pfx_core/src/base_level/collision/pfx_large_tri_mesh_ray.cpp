// Closest hit of a ray against a large mesh: front-to-back descent of the four-wide node
// hierarchy with the per-ray data computed once, and the watertight ray/triangle test of
// Woop, Benthin and Wald (2013, "Watertight Ray/Triangle Intersection", JCGT 2(1)).
//
// A node's four boxes are tested at once as Eigen arrays of four, which Eigen computes with
// SSE2 on any x86-64 (NEON on ARM, plain code elsewhere), so the build needs no particular
// instruction set. The ray reads each axis's near plane
// (the minimum for an axis it travels up, the maximum otherwise) and far plane through
// offsets fixed once per ray, so the test takes no per-box minimum or maximum of the two
// slab distances.
//
// A quantized mesh is searched in its own integer space, p' = (p - origin) / step: the map
// is affine, so the ray's fraction is the same there, node bounds and vertices are exact
// small integers (no dequantizing in the loop), and shared vertices stay bit-identical,
// which is all the watertight test needs.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "base_level/collision/pfx_large_tri_mesh_access.h"

namespace pfx {

namespace {

// Slab distances are rounded; widening the far distance by a few ulps (Ize 2013,
// "Robust BVH Ray Traversal") keeps a box whose face the ray grazes from being missed.
constexpr PfxFloat kFarScale = PfxFloat(1) + PfxFloat(4) * std::numeric_limits<PfxFloat>::epsilon();

constexpr PfxUInt32 kWidth = PFX_LARGE_MESH_NODE_WIDTH;

struct Ray {
  PfxFloat org[3];
  PfxFloat inv[3];
  // Where the near and far planes' coordinates along each axis start among a node's 24
  // bound coordinates (the minima axis by axis, then the maxima).
  PfxUInt32 nearPlane[3];
  PfxUInt32 farPlane[3];
  // The shear that maps the ray onto +z (Woop et al.): kz is the largest direction axis.
  int kx, ky, kz;
  PfxFloat sx, sy, sz;
};

void setUpRay(const PfxVector3& start, const PfxVector3& direction, Ray& ray) {
  for (int i = 0; i < 3; ++i) {
    ray.org[i] = start[i];
    // A zero component would give 0 * inf = NaN in the slab test; a tiny one gives huge
    // but ordered distances instead.
    const PfxFloat d = direction[i] != 0 ? direction[i] : std::numeric_limits<PfxFloat>::min();
    ray.inv[i] = PfxFloat(1) / d;
    const PfxUInt32 minimum = i * kWidth;
    const PfxUInt32 maximum = (3 + i) * kWidth;
    ray.nearPlane[i] = d > 0 ? minimum : maximum;
    ray.farPlane[i] = d > 0 ? maximum : minimum;
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

// A node's 24 bound coordinates as floats: the node's own for a float node; for a
// quantized one converted in a loop the compiler does eight at a time.
using Bounds = PfxFloat[6 * kWidth];

inline const PfxFloat* boundsOf(const PfxLargeMeshNode& node, Bounds&) {
  static_assert(offsetof(PfxLargeMeshNode, m_max) == sizeof(PfxFloat) * 3 * kWidth,
                "the maxima follow the minima");
  return &node.m_min[0][0];
}

inline const PfxFloat* boundsOf(const PfxLargeMeshQuantizedNode& node, Bounds& converted) {
  static_assert(offsetof(PfxLargeMeshQuantizedNode, m_max) == sizeof(PfxUInt16) * 3 * kWidth,
                "the maxima follow the minima");
  const PfxUInt16* q = &node.m_min[0][0];
  for (PfxUInt32 i = 0; i < 6 * kWidth; ++i) converted[i] = PfxFloat(q[i]);
  return converted;
}

// One coordinate of a node's four boxes as one packet: Eigen adds, multiplies and compares
// the four at once with SSE2, which every x86-64 has (and with NEON on ARM).
using Lanes = Eigen::Array<PfxFloat, kWidth, 1>;

// Entry fractions of the ray into the node's boxes; bit c of the result is set when the
// ray meets box c at a fraction within [0, limit].
template <class Node>
inline unsigned boxEntries(const Ray& ray, const Node& node, PfxFloat limit, Lanes& entry) {
  alignas(16) Bounds converted;
  const PfxFloat* bounds = boundsOf(node, converted);
  const auto plane = [&](PfxUInt32 first, int axis) -> Lanes {
    return (Eigen::Map<const Lanes>(bounds + first) - ray.org[axis]) * ray.inv[axis];
  };
  const Lanes nx = plane(ray.nearPlane[0], 0);
  const Lanes ny = plane(ray.nearPlane[1], 1);
  const Lanes nz = plane(ray.nearPlane[2], 2);
  const Lanes fx = plane(ray.farPlane[0], 0);
  const Lanes fy = plane(ray.farPlane[1], 1);
  const Lanes fz = plane(ray.farPlane[2], 2);
  entry = nx.max(ny).max(nz.max(Lanes::Zero()));
  const Lanes exit = (fx.min(fy).min(fz) * kFarScale).min(Lanes::Constant(limit));
  const auto met = entry <= exit;
  unsigned mask = 0;
  for (PfxUInt32 c = 0; c < kWidth; ++c) mask |= unsigned(met[c]) << c;
  return mask;
}

// The ray against triangle (a, b, c), given by coordinate(corner, axis): on a hit at a
// fraction within [0, best], sets best to it. Both faces hit.
template <class Coordinate>
inline bool intersectTriangle(const Ray& ray, const PfxUInt32 corners[3],
                              const Coordinate& coordinate, PfxFloat& best) {
  const PfxFloat ox = ray.org[ray.kx], oy = ray.org[ray.ky], oz = ray.org[ray.kz];
  const PfxFloat az = coordinate(corners[0], ray.kz) - oz;
  const PfxFloat bz = coordinate(corners[1], ray.kz) - oz;
  const PfxFloat cz = coordinate(corners[2], ray.kz) - oz;
  const PfxFloat ax = (coordinate(corners[0], ray.kx) - ox) - ray.sx * az;
  const PfxFloat ay = (coordinate(corners[0], ray.ky) - oy) - ray.sy * az;
  const PfxFloat bx = (coordinate(corners[1], ray.kx) - ox) - ray.sx * bz;
  const PfxFloat by = (coordinate(corners[1], ray.ky) - oy) - ray.sy * bz;
  const PfxFloat cx = (coordinate(corners[2], ray.kx) - ox) - ray.sx * cz;
  const PfxFloat cy = (coordinate(corners[2], ray.ky) - oy) - ray.sy * cz;
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

struct RayHit {
  PfxFloat fraction;
  PfxUInt32 triangle;  // island order
  PfxUInt32 island;
};

// Front-to-back search over one storage kind: of the boxes a node's ray meets, the nearest
// is entered at once and the others wait on a stack, nearest on top; a waiting box is
// dropped when the closest hit so far comes before its entry. coordinate(vertex, axis)
// reads the mesh in the space the ray was set up in.
template <class Node, class Coordinate>
bool castRay(const PfxLargeTriMesh& mesh, const Ray& ray, const Node* nodes,
             const Coordinate& coordinate, RayHit& result) {
  PfxFloat best = 1;
  PfxUInt32 hit = PFX_LARGE_MESH_NO_TRIANGLE;
  PfxUInt32 hitIsland = 0;
  PfxUInt32 stackLink[PFX_LARGE_MESH_STACK_SIZE];
  PfxFloat stackEntry[PFX_LARGE_MESH_STACK_SIZE];
  PfxUInt32 depth = 0;
  PfxUInt32 link = 0;  // the root node
  for (;;) {
    if (!pfxLargeMeshIsLeaf(link)) {
      const Node& node = nodes[link];
      Lanes entry;
      const unsigned mask = boxEntries(ray, node, best, entry);
      // The boxes met, nearest first.
      PfxUInt32 order[kWidth];
      PfxUInt32 count = 0;
      for (PfxUInt32 c = 0; c < kWidth; ++c) {
        if (!(mask & (1u << c)) || node.m_links[c] == PFX_LARGE_MESH_EMPTY_LINK) continue;
        PfxUInt32 i = count++;
        for (; i > 0 && entry[order[i - 1]] > entry[c]; --i) order[i] = order[i - 1];
        order[i] = c;
      }
      if (count > 0) {
        for (PfxUInt32 i = count; i-- > 1;) {
          stackLink[depth] = node.m_links[order[i]];
          stackEntry[depth] = entry[order[i]];
          ++depth;
        }
        link = node.m_links[order[0]];
        continue;
      }
    } else {
      const PfxUInt32 islandId = pfxLargeMeshLeafIsland(link);
      const PfxLargeMeshIsland& island = mesh.m_islands[islandId];
      const PfxUInt32 first = island.m_firstTriangle + pfxLargeMeshLeafOffset(link);
      const PfxUInt32 last = first + pfxLargeMeshLeafCount(link);
      for (PfxUInt32 t = first; t < last; ++t) {
        PfxUInt32 corners[3];
        pfxLargeMeshCorners(mesh, island, t, corners);
        if (intersectTriangle(ray, corners, coordinate, best)) {
          hit = t;
          hitIsland = islandId;
        }
      }
    }
    // Next waiting box that the closest hit so far does not already rule out.
    for (;;) {
      if (depth == 0) {
        if (hit == PFX_LARGE_MESH_NO_TRIANGLE) return false;
        result = {best, hit, hitIsland};
        return true;
      }
      --depth;
      if (stackEntry[depth] <= best) {
        link = stackLink[depth];
        break;
      }
    }
  }
}

}  // namespace

bool pfxRayCastLargeTriMesh(const PfxLargeTriMesh& mesh, const PfxVector3& start,
                            const PfxVector3& direction, PfxFloat& fraction,
                            PfxVector3& normal, PfxUInt32& triangleIndex) {
  if (mesh.m_numNodes == 0 || !pfxIsFinite(start) || !pfxIsFinite(direction) ||
      direction.isZero(0)) {
    return false;
  }
  Ray ray;
  RayHit hit;
  bool found;
  if (pfxLargeMeshIsQuantized(mesh)) {
    setUpRay((start - mesh.m_quantOrigin).cwiseQuotient(mesh.m_quantStep),
                                        direction.cwiseQuotient(mesh.m_quantStep), ray);
    const PfxUInt16* q = mesh.m_quantizedVertices;
    found = castRay(mesh, ray, mesh.m_quantizedNodes,
                    [q](PfxUInt32 v, int axis) { return PfxFloat(q[3 * v + axis]); }, hit);
  } else {
    setUpRay(start, direction, ray);
    const PfxFloat* p = mesh.m_vertices;
    found = castRay(mesh, ray, mesh.m_nodes, [p](PfxUInt32 v, int axis) { return p[3 * v + axis]; },
                    hit);
  }
  if (!found) return false;
  const PfxLargeMeshIsland& island = mesh.m_islands[hit.island];
  PfxUInt32 corners[3];
  pfxLargeMeshCorners(mesh, island, hit.triangle, corners);
  const PfxVector3 v0 = pfxLargeMeshVertex(mesh, corners[0]);
  PfxVector3 n = (pfxLargeMeshVertex(mesh, corners[1]) - v0).cross(pfxLargeMeshVertex(mesh, corners[2]) - v0);
  const PfxFloat length = n.norm();
  // A triangle flattened by quantization still stops the ray; it faces the ray then.
  n = length > 0 ? PfxVector3(n / length) : PfxVector3(-direction.normalized());
  if (n.dot(direction) > 0) n = -n;
  fraction = hit.fraction;
  normal = n;
  triangleIndex = pfxLargeMeshSource(mesh, island, hit.triangle);
  return true;
}

}  // namespace pfx
