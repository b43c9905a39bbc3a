// Triangle lists for the large-mesh tests: height-field grids and random triangle soups,
// plus an owner that releases the mesh at the end of a test.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx_test {

using namespace pfx;

struct MeshSource {
  std::vector<PfxFloat> vertices;
  std::vector<PfxUInt32> triangles;
  PfxUInt32 numVertices() const { return static_cast<PfxUInt32>(vertices.size() / 3); }
  PfxUInt32 numTriangles() const { return static_cast<PfxUInt32>(triangles.size() / 3); }
  PfxVector3 vertex(PfxUInt32 v) const {
    return PfxVector3(vertices[3 * v], vertices[3 * v + 1], vertices[3 * v + 2]);
  }
  PfxCreateLargeTriMeshParam param(PfxUInt32 flags, PfxFloat thickness = PfxFloat(0.1)) const {
    PfxCreateLargeTriMeshParam p;
    p.m_vertices = vertices.data();
    p.m_numVertices = numVertices();
    p.m_triangles = triangles.data();
    p.m_numTriangles = numTriangles();
    p.m_flags = flags;
    p.m_thickness = thickness;
    return p;
  }
};

// A grid of nx by nz cells of size `cell` in the XZ plane, centred on the origin, with
// height y = height(x, z); every cell is two triangles facing +Y (counter-clockwise seen
// from above). Vertices row by row, so an island's vertices lie close in the list.
inline MeshSource makeHeightField(PfxUInt32 nx, PfxUInt32 nz, PfxFloat cell,
                                  const std::function<PfxFloat(PfxFloat, PfxFloat)>& height) {
  MeshSource m;
  const PfxFloat x0 = -PfxFloat(nx) * cell / 2;
  const PfxFloat z0 = -PfxFloat(nz) * cell / 2;
  m.vertices.reserve(3 * std::size_t(nx + 1) * (nz + 1));
  for (PfxUInt32 j = 0; j <= nz; ++j) {
    for (PfxUInt32 i = 0; i <= nx; ++i) {
      const PfxFloat x = x0 + PfxFloat(i) * cell;
      const PfxFloat z = z0 + PfxFloat(j) * cell;
      m.vertices.insert(m.vertices.end(), {x, height(x, z), z});
    }
  }
  m.triangles.reserve(6 * std::size_t(nx) * nz);
  for (PfxUInt32 j = 0; j < nz; ++j) {
    for (PfxUInt32 i = 0; i < nx; ++i) {
      const PfxUInt32 a = j * (nx + 1) + i;
      const PfxUInt32 b = a + 1;
      const PfxUInt32 d = a + (nx + 1);
      const PfxUInt32 c = d + 1;
      // (d - a) x (c - a) = (0,0,1) x (1,0,1) = (0,1,0): up.
      m.triangles.insert(m.triangles.end(), {a, d, c, a, c, b});
    }
  }
  return m;
}

inline MeshSource makeFlatGrid(PfxUInt32 n, PfxFloat cell) {
  return makeHeightField(n, n, cell, [](PfxFloat, PfxFloat) { return PfxFloat(0); });
}

// Random triangles of edge up to `size` in the box [-extent, extent]^3, each with its own
// three vertices, facing roughly +Y (a rough, overlapping ground).
inline MeshSource makeRandomTriangles(PfxUInt32 count, PfxFloat extent, PfxFloat size,
                                      unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<PfxFloat> pos(-extent, extent);
  std::uniform_real_distribution<PfxFloat> off(-size, size);
  MeshSource m;
  for (PfxUInt32 t = 0; t < count; ++t) {
    const PfxVector3 c{pos(rng), pos(rng) * PfxFloat(0.2), pos(rng)};
    PfxVector3 p[3];
    for (auto& v : p) v = c + PfxVector3{off(rng), off(rng) * PfxFloat(0.3), off(rng)};
    if ((p[1] - p[0]).cross(p[2] - p[0]).y() < 0) std::swap(p[1], p[2]);
    for (const auto& v : p) m.vertices.insert(m.vertices.end(), {v.x(), v.y(), v.z()});
    m.triangles.insert(m.triangles.end(), {3 * t, 3 * t + 1, 3 * t + 2});
  }
  return m;
}

// Releases the mesh when the test ends.
struct MeshOwner {
  PfxLargeTriMesh mesh{};
  ~MeshOwner() { pfxReleaseLargeTriMesh(mesh); }
};

inline const PfxUInt32 kAllMeshFlagSets[] = {
    0,
    PFX_MESH_FLAG_USE_BVH,
    PFX_MESH_FLAG_USE_QUANTIZED,
    PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED,
    PFX_MESH_FLAG_HIGH_QUALITY,
    PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_HIGH_QUALITY,
    PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_HIGH_QUALITY,
    PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_HIGH_QUALITY,
};

// Half a quantization step along each axis, as a length: how far a quantized vertex may
// lie from the one it was made from.
inline PfxFloat quantizationError(const PfxLargeTriMesh& mesh) {
  return (mesh.m_quantizedVertices ? (mesh.m_quantStep * PfxFloat(0.5)).norm() : PfxFloat(0));
}

}  // namespace pfx_test
