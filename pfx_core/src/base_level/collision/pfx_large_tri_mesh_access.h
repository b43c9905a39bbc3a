// Reading a PfxLargeTriMesh: node links, triangle corners in either storage, and the
// bounding-box search that the contact routines run. Shared by the mesh's own source and
// the narrow phase; inline because they sit in the inner loops.
#pragma once

#include <algorithm>
#include <cmath>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

// Node link: bit 31 marks a leaf; an inner child's link is its node's index. A leaf packs
// (count - 1) in bits 0..5, the first triangle's offset within its island in bits 6..11 and
// the island in bits 12..30. An unused slot holds PFX_LARGE_MESH_EMPTY_LINK, which no leaf
// can be (offset + count never exceeds 64).
constexpr PfxUInt32 PFX_LARGE_MESH_LEAF_BIT = 1u << 31;
constexpr PfxUInt32 PFX_LARGE_MESH_EMPTY_LINK = 0xFFFFFFFFu;
constexpr PfxUInt32 PFX_LARGE_MESH_NO_TRIANGLE = 0xFFFFFFFFu;
// Deepest possible descent: the builder falls back to median splits below depth 48, and
// median splits of at most 2^25 triangles add at most 26 levels. Merging levels into
// four-wide nodes only makes the tree shallower.
constexpr PfxUInt32 PFX_LARGE_MESH_MAX_DEPTH = 80;
// A depth-first search leaves at most three siblings waiting per level.
constexpr PfxUInt32 PFX_LARGE_MESH_STACK_SIZE =
    (PFX_LARGE_MESH_NODE_WIDTH - 1) * PFX_LARGE_MESH_MAX_DEPTH + 1;

// Which arrays a mesh keeps in 16 bits.
struct PfxLargeMeshStorage {
  bool quantized;
  bool cornerOffsets;
  bool sourceOffsets;
};

// Allocates the one block for the counts `mesh` holds (vertices, triangles, islands,
// nodes) through the utility allocator, zeroed, and points the arrays of `storage` into it
// (the others null). PFX_ERR_OUT_OF_BUFFER, with `mesh` unchanged, when out of memory.
PfxInt32 pfxAllocateLargeTriMeshArrays(PfxLargeTriMesh& mesh, const PfxLargeMeshStorage& storage);

// Sets the bounds of every node from the vertices, and the mesh's bounds from the root:
// all that follows from the vertices and the links, whoever filled them in.
void pfxRefitLargeTriMesh(PfxLargeTriMesh& mesh);

inline bool pfxLargeMeshIsLeaf(PfxUInt32 link) { return (link & PFX_LARGE_MESH_LEAF_BIT) != 0; }
inline PfxUInt32 pfxLargeMeshLeafCount(PfxUInt32 link) { return (link & 63u) + 1; }
inline PfxUInt32 pfxLargeMeshLeafOffset(PfxUInt32 link) { return (link >> 6) & 63u; }
inline PfxUInt32 pfxLargeMeshLeafIsland(PfxUInt32 link) { return (link >> 12) & 0x7FFFFu; }
inline PfxUInt32 pfxLargeMeshMakeLeaf(PfxUInt32 island, PfxUInt32 offset, PfxUInt32 count) {
  return PFX_LARGE_MESH_LEAF_BIT | (island << 12) | (offset << 6) | (count - 1);
}

inline bool pfxLargeMeshIsQuantized(const PfxLargeTriMesh& mesh) {
  return mesh.m_quantizedVertices != nullptr;
}

// Vertex indices of a triangle (island order) whose island is known.
inline void pfxLargeMeshCorners(const PfxLargeTriMesh& mesh, const PfxLargeMeshIsland& island,
                                PfxUInt32 triangle, PfxUInt32 corners[3]) {
  if (mesh.m_triangleOffsets) {
    const PfxUInt16* offsets = mesh.m_triangleOffsets + 3 * triangle;
    for (int k = 0; k < 3; ++k) corners[k] = island.m_baseVertex + offsets[k];
  } else {
    const PfxUInt32* ids = mesh.m_triangleVertices + 3 * triangle;
    for (int k = 0; k < 3; ++k) corners[k] = ids[k];
  }
}

// The caller's index of a triangle (island order) whose island is known.
inline PfxUInt32 pfxLargeMeshSource(const PfxLargeTriMesh& mesh, const PfxLargeMeshIsland& island,
                                    PfxUInt32 triangle) {
  if (mesh.m_triangleSourceOffsets) return island.m_baseSource + mesh.m_triangleSourceOffsets[triangle];
  return mesh.m_triangleSourceIds[triangle];
}

// A vertex in the mesh's frame.
inline PfxVector3 pfxLargeMeshVertex(const PfxLargeTriMesh& mesh, PfxUInt32 v) {
  if (mesh.m_quantizedVertices) {
    const PfxUInt16* q = mesh.m_quantizedVertices + 3 * v;
    return PfxVector3(mesh.m_quantOrigin[0] + PfxFloat(q[0]) * mesh.m_quantStep[0],
                      mesh.m_quantOrigin[1] + PfxFloat(q[1]) * mesh.m_quantStep[1],
                      mesh.m_quantOrigin[2] + PfxFloat(q[2]) * mesh.m_quantStep[2]);
  }
  const PfxFloat* p = mesh.m_vertices + 3 * v;
  return PfxVector3(p[0], p[1], p[2]);
}

// The island holding triangle `triangle` (island order): islands are laid out in
// increasing m_firstTriangle.
inline PfxUInt32 pfxLargeMeshIslandOf(const PfxLargeTriMesh& mesh, PfxUInt32 triangle) {
  PfxUInt32 lo = 0;
  PfxUInt32 hi = mesh.m_numIslands;
  while (hi - lo > 1) {
    const PfxUInt32 mid = (lo + hi) / 2;
    if (mesh.m_islands[mid].m_firstTriangle <= triangle) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// Calls visit(island, triangle) for every triangle (island order) whose node bounds meet
// the box [lo, hi] in the mesh's frame. Allocates nothing.
template <class Visit>
void pfxQueryLargeTriMesh(const PfxLargeTriMesh& mesh, const PfxVector3& lo, const PfxVector3& hi,
                          Visit&& visit) {
  if (mesh.m_numNodes == 0) return;
  // Depth first over nodes of either storage, with the box in the nodes' own units. The
  // children wait on the stack in slot order, so triangles are visited left to right.
  const auto walk = [&](const auto* nodes, const auto& boxLo, const auto& boxHi) {
    PfxUInt32 stack[PFX_LARGE_MESH_STACK_SIZE + PFX_LARGE_MESH_NODE_WIDTH];
    stack[0] = 0;  // the root node
    PfxUInt32 depth = 1;
    while (depth > 0) {
      const PfxUInt32 link = stack[--depth];
      if (pfxLargeMeshIsLeaf(link)) {
        const PfxLargeMeshIsland& island = mesh.m_islands[pfxLargeMeshLeafIsland(link)];
        const PfxUInt32 first = island.m_firstTriangle + pfxLargeMeshLeafOffset(link);
        const PfxUInt32 count = pfxLargeMeshLeafCount(link);
        for (PfxUInt32 t = first; t < first + count; ++t) visit(island, t);
        continue;
      }
      const auto& n = nodes[link];
      for (PfxUInt32 c = PFX_LARGE_MESH_NODE_WIDTH; c-- > 0;) {
        if (n.m_links[c] == PFX_LARGE_MESH_EMPTY_LINK) continue;
        if (n.m_min[0][c] <= boxHi[0] && n.m_max[0][c] >= boxLo[0] &&
            n.m_min[1][c] <= boxHi[1] && n.m_max[1][c] >= boxLo[1] &&
            n.m_min[2][c] <= boxHi[2] && n.m_max[2][c] >= boxLo[2]) {
          stack[depth++] = n.m_links[c];
        }
      }
    }
  };
  if (pfxLargeMeshIsQuantized(mesh)) {
    // The box in quantization steps, rounded outward; a box that misses the quantization
    // box misses every node.
    PfxInt32 qlo[3], qhi[3];
    for (int i = 0; i < 3; ++i) {
      const PfxFloat a = std::floor((lo[i] - mesh.m_quantOrigin[i]) / mesh.m_quantStep[i]);
      const PfxFloat b = std::ceil((hi[i] - mesh.m_quantOrigin[i]) / mesh.m_quantStep[i]);
      if (!(b >= 0) || !(a <= PfxFloat(65535))) return;
      qlo[i] = static_cast<PfxInt32>(std::max(a, PfxFloat(0)));
      qhi[i] = static_cast<PfxInt32>(std::min(b, PfxFloat(65535)));
    }
    walk(mesh.m_quantizedNodes, qlo, qhi);
    return;
  }
  walk(mesh.m_nodes, lo, hi);
}

}  // namespace pfx
