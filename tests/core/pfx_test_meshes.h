// Small closed convex meshes as vertex and index lists, for tests that build a
// PfxConvexMesh from known geometry.
#pragma once

#include <cmath>
#include <vector>

#include "pfx/base_level/base/pfx_common.h"

namespace pfx_test {

struct TriangleList {
  std::vector<pfx::PfxFloat> vertices;  // x, y, z per vertex
  std::vector<pfx::PfxUInt16> indices;  // three per triangle
  pfx::PfxUInt32 numVertices() const { return static_cast<pfx::PfxUInt32>(vertices.size() / 3); }
  pfx::PfxUInt32 numIndices() const { return static_cast<pfx::PfxUInt32>(indices.size()); }
};

// Box [-hx,hx]x[-hy,hy]x[-hz,hz]: vertex i has x = +hx if bit 0 of i is set, y from bit 1,
// z from bit 2. Two triangles per side, counter-clockwise seen from outside (checked by
// hand: e.g. (0,4,6) on -X has (4-0) x (6-0) = (0,0,2hz) x (0,2hy,2hz) pointing to -X).
inline TriangleList makeBoxTriangles(pfx::PfxFloat hx, pfx::PfxFloat hy, pfx::PfxFloat hz) {
  TriangleList box;
  for (int i = 0; i < 8; ++i) {
    box.vertices.push_back(i & 1 ? hx : -hx);
    box.vertices.push_back(i & 2 ? hy : -hy);
    box.vertices.push_back(i & 4 ? hz : -hz);
  }
  box.indices = {0, 4, 6, 0, 6, 2,   // -X
                 1, 3, 7, 1, 7, 5,   // +X
                 0, 1, 5, 0, 5, 4,   // -Y
                 2, 6, 7, 2, 7, 3,   // +Y
                 0, 2, 3, 0, 3, 1,   // -Z
                 4, 5, 7, 4, 7, 6};  // +Z
  return box;
}

// Regular tetrahedron on alternate corners of the cube [-1,1]^3: edge 2*sqrt(2), volume
// 8 - 4 * (8/6) = 8/3 (the cube less four corner pyramids).
inline TriangleList makeTetrahedronTriangles() {
  TriangleList tet;
  tet.vertices = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
  // Winding deliberately mixed: the builder orients each triangle outward.
  tet.indices = {0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3};
  return tet;
}

// Regular icosahedron with vertices (0, ±1, ±φ) and their cyclic permutations: edge 2,
// volume (5/12)(3 + √5) * 8. Its 20 triangles are the triples of mutually adjacent
// vertices, found here by edge length, in whatever winding that gives.
inline TriangleList makeIcosahedronTriangles() {
  const pfx::PfxFloat phi = static_cast<pfx::PfxFloat>((1.0 + std::sqrt(5.0)) / 2.0);
  TriangleList ico;
  for (int perm = 0; perm < 3; ++perm) {
    for (int s1 = -1; s1 <= 1; s1 += 2) {
      for (int s2 = -1; s2 <= 1; s2 += 2) {
        const pfx::PfxFloat p[3] = {0, pfx::PfxFloat(s1), s2 * phi};
        ico.vertices.push_back(p[(0 + perm) % 3]);
        ico.vertices.push_back(p[(1 + perm) % 3]);
        ico.vertices.push_back(p[(2 + perm) % 3]);
      }
    }
  }
  auto adjacent = [&](int a, int b) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = ico.vertices[3 * a + k] - ico.vertices[3 * b + k];
      d2 += d * d;
    }
    return std::abs(d2 - 4.0) < 1e-3;
  };
  for (int a = 0; a < 12; ++a) {
    for (int b = a + 1; b < 12; ++b) {
      for (int c = b + 1; c < 12; ++c) {
        if (adjacent(a, b) && adjacent(b, c) && adjacent(a, c)) {
          ico.indices.insert(ico.indices.end(), {pfx::PfxUInt16(a), pfx::PfxUInt16(b),
                                                 pfx::PfxUInt16(c)});
        }
      }
    }
  }
  return ico;
}

}  // namespace pfx_test
