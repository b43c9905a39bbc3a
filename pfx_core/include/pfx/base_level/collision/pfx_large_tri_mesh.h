// A large, non-convex triangle mesh for static or deforming ground (seed chapter 2,
// "Large Mesh"), built by pfxCreateLargeTriMesh() and freed by pfxReleaseLargeTriMesh().
//
// Layout. Triangles are grouped into islands of at most 64 spatially close triangles and
// searched hierarchically: mesh -> island -> triangle. The seed stores the islands of a mesh
// in a flat array capped at 512 islands (32,768 triangles); a linear scan over the islands of
// a million-triangle terrain (15,625 islands) would cost every query tens of microseconds, so
// here a bounding volume hierarchy over the islands sits on top in every variant, and the
// seed's array/BVH choice applies inside an island:
//   - array (default): a query that reaches an island tests all its triangles in turn;
//   - PFX_MESH_FLAG_USE_BVH: the island continues the hierarchy down to leaves of at most
//     four triangles, which searches faster for about 9 bytes more per triangle.
// The hierarchy is four wide: each node holds the boxes of up to four children side by side,
// axis by axis (structure of arrays), so that a ray tests all four at once as vectors of
// four (Eigen's SSE2 packets), and a descent visits a third as many nodes as a binary tree
// would. It is built as a binary tree (median splits, or with
// PFX_MESH_FLAG_HIGH_QUALITY the surface area heuristic: slower to build, faster to search)
// whose levels are then merged, each node opening the largest of its children until it
// has four. All nodes live in one array, so a query walks mesh, island and triangle levels
// in one loop.
//
// Storage. Vertices are kept in the caller's order (deformation passes them in that order
// again); triangles are kept in island order, each remembering its index in the caller's
// list. Rays report the caller's index; contact points record the stored (island-order)
// index, which pfxGetLargeTriMeshSourceTriangle() turns into the caller's.
// PFX_MESH_FLAG_USE_QUANTIZED stores vertices and node bounds as 16-bit integers over the
// mesh's bounds (grown by m_deformationMargin), and triangle corners and caller's indices as
// 16-bit offsets from their island's lowest vertex and lowest caller's index: positions are
// then exact to half a step, (box extent) / 65535 / 2 per axis, and the mesh takes about
// half the bytes, 40 % in the double build (a quantized node is 64 bytes, one cache line,
// against 112, or 208 in double). Corners stay 32-bit indices when some island uses
// vertices more than 65,535 apart in the caller's order (a scrambled vertex list), and
// likewise the caller's indices.
// Face normals are not stored: they follow from the vertices, which keeps them right after
// a deformation.
//
// Triangles are one-sided: the front face is counter-clockwise seen from outside, and each
// triangle collides as a thin prism reaching `thickness` below its face, so that a body
// pushed deep into the ground is pushed back out upward rather than through.
//
// The mesh owns its buffers (one block that pfxCreateLargeTriMesh allocates through the
// utility allocator, pfx_utility_allocator.h). Copies of the
// struct share the block; release exactly one of them, once. PfxShape stores a pointer to the
// mesh, which must outlive every shape that names it.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

constexpr PfxUInt32 PFX_MESH_FLAG_USE_BVH = 1u << 0;
constexpr PfxUInt32 PFX_MESH_FLAG_USE_QUANTIZED = 1u << 1;
constexpr PfxUInt32 PFX_MESH_FLAG_HIGH_QUALITY = 1u << 2;

// The seed's island layout: at most 64 triangles per island. The seed also caps a mesh at
// 512 islands; this mesh accepts more (see the layout note above) up to the limit of the
// node encoding, 2^19 islands (33,554,432 triangles).
constexpr PfxUInt32 PFX_LARGE_MESH_MAX_TRIANGLES_PER_ISLAND = 64;
constexpr PfxUInt32 PFX_LARGE_MESH_SEED_MAX_ISLANDS = 512;
constexpr PfxUInt32 PFX_LARGE_MESH_MAX_ISLANDS = 1u << 19;
// Largest number of triangles in a BVH leaf below the islands (PFX_MESH_FLAG_USE_BVH).
constexpr PfxUInt32 PFX_LARGE_MESH_MAX_TRIANGLES_PER_LEAF = 4;

// Per-triangle edge flags (PfxLargeTriMesh::m_edgeFlags). Edge i runs from corner i to
// corner (i + 1) % 3. An edge shared with exactly one other triangle whose faces meet flat
// or folded inward (concave) is "internal": a contact found on it takes the face normal, so
// that a body sliding across it does not catch on the edge.
constexpr PfxUInt8 PFX_LARGE_MESH_EDGE_INTERNAL_0 = 1u << 0;
constexpr PfxUInt8 PFX_LARGE_MESH_EDGE_INTERNAL_1 = 1u << 1;
constexpr PfxUInt8 PFX_LARGE_MESH_EDGE_INTERNAL_2 = 1u << 2;
// The same edge shared with another triangle at all (internal or a convex fold).
constexpr PfxUInt8 PFX_LARGE_MESH_EDGE_SHARED_0 = 1u << 3;
constexpr PfxUInt8 PFX_LARGE_MESH_EDGE_SHARED_1 = 1u << 4;
constexpr PfxUInt8 PFX_LARGE_MESH_EDGE_SHARED_2 = 1u << 5;

struct PfxCreateLargeTriMeshParam {
  const PfxFloat* m_vertices = nullptr;   // xyz per vertex
  PfxUInt32 m_numVertices = 0;
  const PfxUInt32* m_triangles = nullptr;  // three vertex indices per triangle, CCW from above
  PfxUInt32 m_numTriangles = 0;
  PfxUInt32 m_flags = 0;  // PFX_MESH_FLAG_*
  // Depth of the prism below each face; a body found deeper than this under a face is
  // taken to be beneath the mesh and is not pushed up through it.
  PfxFloat m_thickness = PfxFloat(0.1);
  // Islands hold at most this many triangles (1 to 64).
  PfxUInt32 m_islandSize = PFX_LARGE_MESH_MAX_TRIANGLES_PER_ISLAND;
  // Two faces sharing an edge whose normals differ by less than this angle (radians) count
  // as flat: the edge is internal even when it folds slightly outward.
  PfxFloat m_flatEdgeAngle = PfxFloat(0.01);
  // Quantized meshes only: how far beyond the creation bounds a deformation may move
  // vertices (the quantization box is grown by this on every side).
  PfxFloat m_deformationMargin = 0;
};

// Children per node of the hierarchy.
constexpr PfxUInt32 PFX_LARGE_MESH_NODE_WIDTH = 4;

// A node of the hierarchy: the boxes of its children, [axis][child], and a link per child
// (see pfx_large_tri_mesh.cpp for the packing). A node may hold fewer than four children;
// an unused slot has an inverted box (minimum above maximum) and an empty link.
struct PfxLargeMeshNode {
  PfxFloat m_min[3][PFX_LARGE_MESH_NODE_WIDTH];
  PfxFloat m_max[3][PFX_LARGE_MESH_NODE_WIDTH];
  PfxUInt32 m_links[PFX_LARGE_MESH_NODE_WIDTH];
};

struct PfxLargeMeshQuantizedNode {
  PfxUInt16 m_min[3][PFX_LARGE_MESH_NODE_WIDTH];
  PfxUInt16 m_max[3][PFX_LARGE_MESH_NODE_WIDTH];
  PfxUInt32 m_links[PFX_LARGE_MESH_NODE_WIDTH];
};

struct PfxLargeMeshIsland {
  PfxUInt32 m_firstTriangle;  // into the island-ordered triangle arrays
  PfxUInt32 m_baseVertex;     // lowest vertex index of the island's triangles
  PfxUInt32 m_baseSource;     // lowest caller's triangle index of the island's triangles
  PfxUInt32 m_numTriangles;
};

struct PfxLargeTriMesh {
  PfxUInt32 m_flags;
  PfxUInt32 m_numVertices;
  PfxUInt32 m_numTriangles;         // kept, after dropping degenerate ones
  PfxUInt32 m_numSourceTriangles;   // in the caller's list at creation
  PfxUInt32 m_numDroppedTriangles;  // zero-area triangles left out at creation
  PfxUInt32 m_numIslands;
  PfxUInt32 m_numNodes;
  PfxFloat m_thickness;
  PfxVector3 m_aabbMin;  // local bounds of the current vertices
  PfxVector3 m_aabbMax;
  // Quantization box: q = (p - m_quantOrigin) / m_quantStep per axis, rounded. Fixed at
  // creation; a deformation must keep the vertices inside it.
  PfxVector3 m_quantOrigin;
  PfxVector3 m_quantStep;

  // Exactly one of each pair is set: vertices and nodes by PFX_MESH_FLAG_USE_QUANTIZED,
  // corners as described in the storage note above.
  PfxFloat* m_vertices;             // xyz, caller's order
  PfxUInt16* m_quantizedVertices;   // xyz, caller's order
  PfxUInt32* m_triangleVertices;    // three per triangle, island order
  PfxUInt16* m_triangleOffsets;     // three per triangle, from the island's m_baseVertex
  PfxLargeMeshNode* m_nodes;
  PfxLargeMeshQuantizedNode* m_quantizedNodes;

  // Index in the caller's triangle list, island order; exactly one is set, as for corners
  // (read it with pfxGetLargeTriMeshSourceTriangle).
  PfxUInt32* m_triangleSourceIds;
  PfxUInt16* m_triangleSourceOffsets;  // from the island's m_baseSource
  PfxUInt8* m_edgeFlags;           // PFX_LARGE_MESH_EDGE_*, island order
  PfxLargeMeshIsland* m_islands;

  void* m_block;        // the one allocation all arrays live in (64-byte aligned)
  std::size_t m_bytes;  // its size: the mesh's memory
};

// Builds a mesh. Rejects: a null vertex or triangle array (PFX_ERR_NULL_POINTER); no
// vertices or no triangles, a vertex index >= m_numVertices, an island size outside 1..64,
// or more islands than PFX_LARGE_MESH_MAX_ISLANDS (PFX_ERR_OUT_OF_RANGE); a NaN or infinite
// vertex, a negative or non-finite thickness, flat-edge angle or deformation margin
// (PFX_ERR_INVALID_VALUE); an
// unknown flag (PFX_ERR_INVALID_FLAG); a mesh whose triangles all have zero area
// (PFX_ERR_DEGENERATE). Zero-area triangles among others are dropped and counted in
// m_numDroppedTriangles. `mesh` is only written on success; it must not hold a live mesh
// (release it first). Allocates; not for use inside a step.
PfxInt32 pfxCreateLargeTriMesh(PfxLargeTriMesh& mesh, const PfxCreateLargeTriMeshParam& param);

// Frees the mesh's buffers and zeroes it. Safe on a zeroed mesh.
void pfxReleaseLargeTriMesh(PfxLargeTriMesh& mesh);

// A zeroed mesh struct from the utility allocator (pfx_utility_allocator.h), to build into
// with pfxCreateLargeTriMesh when the mesh lives on the heap; null when out of memory.
PfxLargeTriMesh* pfxNewLargeTriMesh();
// Releases the mesh's buffers (pfxReleaseLargeTriMesh) and frees a struct that
// pfxNewLargeTriMesh made. Safe on null.
void pfxDeleteLargeTriMesh(PfxLargeTriMesh* mesh);

// Moves every vertex (xyz, the caller's order, as many as at creation) and refits the
// bounds of every node and island without rebuilding the hierarchy, so a deformed mesh stays
// exact but may search a little slower when triangles travel far. Edge flags keep their
// creation values. Rejects a null array (PFX_ERR_NULL_POINTER), a count that differs from
// the mesh's (PFX_ERR_OUT_OF_RANGE), a NaN or infinite vertex (PFX_ERR_INVALID_VALUE) and,
// for a quantized mesh, a vertex outside its quantization box (PFX_ERR_OUT_OF_RANGE).
// Allocates nothing; the caller then refreshes the bounds of the collidable that holds the
// mesh (PfxCollidable::finish); PfxWorld::deformLargeTriMesh does both.
PfxInt32 pfxUpdateLargeTriMeshVertices(PfxLargeTriMesh& mesh, const PfxFloat* vertices,
                                       PfxUInt32 numVertices);

// The corners of triangle `triangleIndex` (island order, 0 .. m_numTriangles - 1) in the
// mesh's frame, dequantized where the mesh is quantized.
void pfxGetLargeTriMeshTriangle(const PfxLargeTriMesh& mesh, PfxUInt32 triangleIndex,
                                PfxVector3& v0, PfxVector3& v1, PfxVector3& v2);

// The caller's index of triangle `triangleIndex` (island order, 0 .. m_numTriangles - 1).
PfxUInt32 pfxGetLargeTriMeshSourceTriangle(const PfxLargeTriMesh& mesh, PfxUInt32 triangleIndex);

// The stored triangle (island order) that came from the caller's triangle `sourceIndex`, or
// 0xFFFFFFFF when that triangle was dropped or is out of range. A linear search (the mesh
// keeps no map this way round, to stay small): for tools and tests, not per step.
PfxUInt32 pfxFindLargeTriMeshTriangle(const PfxLargeTriMesh& mesh, PfxUInt32 sourceIndex);

// Closest hit of a ray against the mesh, in the mesh's local frame. start + fraction *
// direction is the hit; returns false when the segment misses. The test must be
// watertight (e.g. Woop, Benthin & Wald 2013): a ray never slips between two triangles.
// Both faces are hit; `normal` is the unit face normal turned against `direction`, and
// `triangleIndex` is the index in the caller's triangle list at creation.
bool pfxRayCastLargeTriMesh(const PfxLargeTriMesh& mesh, const PfxVector3& start,
                            const PfxVector3& direction, PfxFloat& fraction,
                            PfxVector3& normal, PfxUInt32& triangleIndex);

}  // namespace pfx
