#include "loaders/pfx_voxel_surface.h"

#include <algorithm>
#include <unordered_map>

namespace pfx {

namespace {

struct Rect {
  PfxUInt8 axis;
  PfxUInt8 positive;
  PfxUInt32 plane;
  PfxUInt32 u0, v0, u1, v1;  // [u0, u1) x [v0, v1) in cells
};

bool samePlane(const PfxVoxelFace& a, const PfxVoxelFace& b) {
  return a.axis == b.axis && a.positive == b.positive && a.plane == b.plane;
}

// Greedy meshing of squares of one plane: they are cut into cells of `grain` (no larger
// than any of them), and each unclaimed cell in row order grows into the widest run of
// unclaimed cells, then into as many following rows as the whole run fits. Rectangles never
// overlap and cover exactly the squares.
void mergeSquares(const PfxVoxelFace* faces, std::size_t count, PfxUInt32 grain,
                  std::vector<Rect>& rects) {
  std::vector<PfxUInt64> cells;  // row (v) in the high half, column (u) in the low half
  for (std::size_t i = 0; i < count; ++i) {
    const PfxVoxelFace& f = faces[i];
    const PfxUInt32 n = f.size / grain;
    for (PfxUInt32 dv = 0; dv < n; ++dv) {
      for (PfxUInt32 du = 0; du < n; ++du) {
        cells.push_back(PfxUInt64(f.v / grain + dv) << 32 | (f.u / grain + du));
      }
    }
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<char> claimed(cells.size(), 0);
  const auto find = [&](PfxUInt64 key) -> std::size_t {
    const auto it = std::lower_bound(cells.begin(), cells.end(), key);
    return it != cells.end() && *it == key ? static_cast<std::size_t>(it - cells.begin())
                                           : cells.size();
  };
  // A row's cells are contiguous in the sorted list, so a run is checked entry by entry.
  const auto runIsFree = [&](std::size_t first, PfxUInt64 key, PfxUInt32 width) {
    if (first + width > cells.size()) return false;
    for (PfxUInt32 k = 0; k < width; ++k) {
      if (cells[first + k] != key + k || claimed[first + k]) return false;
    }
    return true;
  };

  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (claimed[i]) continue;
    PfxUInt32 width = 1;
    while (i + width < cells.size() && cells[i + width] == cells[i] + width &&
           !claimed[i + width]) {
      ++width;
    }
    PfxUInt32 height = 1;
    std::vector<std::size_t> rowStarts{i};
    for (;;) {
      const PfxUInt64 key = cells[i] + (PfxUInt64(height) << 32);
      const std::size_t first = find(key);
      if (first == cells.size() || !runIsFree(first, key, width)) break;
      rowStarts.push_back(first);
      ++height;
    }
    for (std::size_t start : rowStarts) {
      std::fill(claimed.begin() + static_cast<std::ptrdiff_t>(start),
                claimed.begin() + static_cast<std::ptrdiff_t>(start + width), 1);
    }
    const PfxUInt32 u = static_cast<PfxUInt32>(cells[i] & 0xffffffffu);
    const PfxUInt32 v = static_cast<PfxUInt32>(cells[i] >> 32);
    rects.push_back({faces[0].axis, faces[0].positive, faces[0].plane, u * grain, v * grain,
                     (u + width) * grain, (v + height) * grain});
  }
}

// Cells of the smallest square's size let squares of every size merge, but where a large
// pruned leaf meets single voxels that would take (large / small)^2 cells; from this many
// cells per square on, squares merge only with squares of their own size.
constexpr PfxUInt64 kMaxCellsPerSquare = 256;

// The squares of one plane, sorted by size, as rectangles.
void mergePlane(const PfxVoxelFace* faces, std::size_t count, std::vector<Rect>& rects) {
  const PfxUInt32 grain = faces[0].size;
  PfxUInt64 cells = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const PfxUInt64 n = faces[i].size / grain;
    cells += n * n;
  }
  if (cells <= kMaxCellsPerSquare * count) {
    mergeSquares(faces, count, grain, rects);
    return;
  }
  for (std::size_t first = 0; first < count;) {
    std::size_t last = first + 1;
    while (last < count && faces[last].size == faces[first].size) ++last;
    mergeSquares(faces + first, last - first, faces[first].size, rects);
    first = last;
  }
}

// The corner of a rectangle as integer boundary indices per axis.
struct Corner {
  PfxUInt32 xyz[3];
};

Corner corner(const Rect& r, PfxUInt32 u, PfxUInt32 v) {
  Corner c;
  c.xyz[r.axis] = r.plane;
  c.xyz[(r.axis + 1) % 3] = u;
  c.xyz[(r.axis + 2) % 3] = v;
  return c;
}

constexpr int kIndexBits = 17;

// A point on an axis-parallel line: the line (its axis and the other two coordinates) in the
// high bits, the position along it in the low bits, so that the points of one line sort
// together and in order.
PfxUInt64 linePoint(const Corner& c, int edgeAxis) {
  const PfxUInt64 line = PfxUInt64(edgeAxis) << (2 * kIndexBits) |
                         PfxUInt64(c.xyz[(edgeAxis + 1) % 3]) << kIndexBits |
                         c.xyz[(edgeAxis + 2) % 3];
  return line << kIndexBits | c.xyz[edgeAxis];
}

class SurfaceBuilder {
 public:
  SurfaceBuilder(PfxInt32 origin, double cellSize, PfxTriangleMesh& mesh)
      : m_origin(origin), m_cellSize(cellSize), m_mesh(mesh) {}

  // Every corner goes onto the lines of its rectangle's two edges through it: a corner of
  // one rectangle inside the edge of another is where that edge must be split.
  void addLinePoints(const std::vector<Rect>& rects) {
    for (const Rect& r : rects) {
      const int ua = (r.axis + 1) % 3, va = (r.axis + 2) % 3;
      for (const Corner& c : {corner(r, r.u0, r.v0), corner(r, r.u1, r.v0), corner(r, r.u1, r.v1),
                              corner(r, r.u0, r.v1)}) {
        m_linePoints.push_back(linePoint(c, ua));
        m_linePoints.push_back(linePoint(c, va));
      }
    }
    std::sort(m_linePoints.begin(), m_linePoints.end());
    m_linePoints.erase(std::unique(m_linePoints.begin(), m_linePoints.end()), m_linePoints.end());
  }

  // The rectangle's boundary, counter-clockwise about its normal, with every point where
  // another rectangle's corner splits an edge; then two triangles when nothing splits it,
  // else a fan around its centre, which needs no care about collinear boundary points.
  void triangulate(const Rect& r) {
    const int ua = (r.axis + 1) % 3, va = (r.axis + 2) % 3;
    const Corner corners[4] = {corner(r, r.u0, r.v0), corner(r, r.u1, r.v0), corner(r, r.u1, r.v1),
                               corner(r, r.u0, r.v1)};
    const int edgeAxis[4] = {ua, va, ua, va};
    m_loop.clear();
    for (int e = 0; e < 4; ++e) {
      const Corner& from = corners[e];
      const Corner& to = corners[(e + 1) % 4];
      m_loop.push_back(vertex(from));
      const int axis = edgeAxis[e];
      const PfxUInt64 a = linePoint(from, axis), b = linePoint(to, axis);
      const auto lo = std::upper_bound(m_linePoints.begin(), m_linePoints.end(), std::min(a, b));
      const auto hi = std::lower_bound(m_linePoints.begin(), m_linePoints.end(), std::max(a, b));
      const std::size_t first = m_loop.size();
      for (auto it = lo; it < hi; ++it) {
        Corner c = from;
        c.xyz[axis] = static_cast<PfxUInt32>(*it & ((PfxUInt64(1) << kIndexBits) - 1));
        m_loop.push_back(vertex(c));
      }
      if (b < a) std::reverse(m_loop.begin() + static_cast<std::ptrdiff_t>(first), m_loop.end());
    }
    if (!r.positive) std::reverse(m_loop.begin(), m_loop.end());
    auto& tris = m_mesh.triangles;
    if (m_loop.size() == 4) {
      tris.insert(tris.end(), {m_loop[0], m_loop[1], m_loop[2], m_loop[0], m_loop[2], m_loop[3]});
      return;
    }
    const PfxUInt32 center = static_cast<PfxUInt32>(m_mesh.vertices.size() / 3);
    double xyz[3];
    xyz[r.axis] = r.plane;
    xyz[ua] = 0.5 * (double(r.u0) + double(r.u1));
    xyz[va] = 0.5 * (double(r.v0) + double(r.v1));
    for (double c : xyz) m_mesh.vertices.push_back(position(c));
    for (std::size_t k = 0; k < m_loop.size(); ++k) {
      tris.insert(tris.end(), {center, m_loop[k], m_loop[(k + 1) % m_loop.size()]});
    }
  }

 private:
  PfxFloat position(double index) const {
    return static_cast<PfxFloat>((index - m_origin) * m_cellSize);
  }

  PfxUInt32 vertex(const Corner& c) {
    const PfxUInt64 key =
        PfxUInt64(c.xyz[0]) << (2 * kIndexBits) | PfxUInt64(c.xyz[1]) << kIndexBits | c.xyz[2];
    const auto found = m_ids.emplace(key, static_cast<PfxUInt32>(m_mesh.vertices.size() / 3));
    if (found.second) {
      for (PfxUInt32 i : c.xyz) m_mesh.vertices.push_back(position(i));
    }
    return found.first->second;
  }

  PfxInt32 m_origin;
  double m_cellSize;
  PfxTriangleMesh& m_mesh;
  std::vector<PfxUInt64> m_linePoints;
  std::unordered_map<PfxUInt64, PfxUInt32> m_ids;
  std::vector<PfxUInt32> m_loop;
};

}  // namespace

void pfxMeshVoxelFaces(std::vector<PfxVoxelFace>& faces, PfxInt32 origin, double cellSize,
                       PfxTriangleMesh& mesh) {
  std::sort(faces.begin(), faces.end(), [](const PfxVoxelFace& a, const PfxVoxelFace& b) {
    if (a.axis != b.axis) return a.axis < b.axis;
    if (a.positive != b.positive) return a.positive < b.positive;
    if (a.plane != b.plane) return a.plane < b.plane;
    return a.size < b.size;
  });
  std::vector<Rect> rects;
  for (std::size_t first = 0; first < faces.size();) {
    std::size_t last = first + 1;
    while (last < faces.size() && samePlane(faces[first], faces[last])) ++last;
    mergePlane(&faces[first], last - first, rects);
    first = last;
  }
  mesh = PfxTriangleMesh();
  SurfaceBuilder builder(origin, cellSize, mesh);
  builder.addLinePoints(rects);
  for (const Rect& r : rects) builder.triangulate(r);
}

}  // namespace pfx
