// Mesh files (assimp), convex hulls (qhull) and large meshes made from them: known answers
// on small files written for these tests, the KUKA iiwa's real meshes, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "pfx/base_level/collision/pfx_mass_properties.h"
#include "pfx/base_level/collision/pfx_shape.h"
#include "pfx/loaders/pfx_mesh_loader.h"

namespace {

using namespace pfx;

constexpr double kPi = 3.14159265358979323846;

std::string dataFile(const std::string& name) {
  return std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/" + name;
}

std::string kukaMesh(int link) {
  return std::string(PFX_SOURCE_DIR) + "/urdf/kuka_iiwa/meshes/link_" + std::to_string(link) +
         ".stl";
}

// A folder of its own for files a test writes, removed at the end.
class TempFolder {
 public:
  TempFolder() {
    m_path = std::filesystem::temp_directory_path() /
             ("pfx_mesh_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
              "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(m_path);
  }
  ~TempFolder() { std::filesystem::remove_all(m_path); }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string path = (m_path / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

 private:
  std::filesystem::path m_path;
};

struct Bounds {
  PfxVector3 lo = PfxVector3::Constant(std::numeric_limits<PfxFloat>::max());
  PfxVector3 hi = PfxVector3::Constant(-std::numeric_limits<PfxFloat>::max());
};

Bounds boundsOf(const PfxTriangleMesh& mesh) {
  Bounds b;
  for (std::size_t i = 0; i + 2 < mesh.vertices.size(); i += 3) {
    const PfxVector3 p(mesh.vertices[i], mesh.vertices[i + 1], mesh.vertices[i + 2]);
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

PfxVector3 vertexOf(const PfxTriangleMesh& mesh, PfxUInt32 v) {
  return PfxVector3(mesh.vertices[3 * v], mesh.vertices[3 * v + 1], mesh.vertices[3 * v + 2]);
}

// Volume enclosed by a closed mesh whose triangles all face outward (divergence theorem).
double enclosedVolume(const PfxTriangleMesh& mesh) {
  double v6 = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const Eigen::Vector3d a = vertexOf(mesh, mesh.triangles[t]).cast<double>();
    const Eigen::Vector3d b = vertexOf(mesh, mesh.triangles[t + 1]).cast<double>();
    const Eigen::Vector3d c = vertexOf(mesh, mesh.triangles[t + 2]).cast<double>();
    v6 += a.dot(b.cross(c));
  }
  return v6 / 6;
}

double volumeOf(const PfxConvexMesh& hull) {
  PfxShape shape;
  shape.reset();
  shape.setConvexMesh(&hull);
  return pfxCalcVolume(shape);
}

// Every undirected edge in exactly two triangles.
bool isClosed(const PfxTriangleMesh& mesh) {
  std::map<std::pair<PfxUInt32, PfxUInt32>, int> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const PfxUInt32 a = mesh.triangles[t + k], b = mesh.triangles[t + (k + 1) % 3];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  }
  return std::all_of(edges.begin(), edges.end(), [](const auto& e) { return e.second == 2; });
}

// A UV sphere of the given radius: `rings` bands from pole to pole, `segments` around,
// triangles facing outward. All its vertices lie on the sphere, so it is its own hull.
PfxTriangleMesh makeSphere(int rings, int segments, double radius) {
  PfxTriangleMesh mesh;
  const auto add = [&](double theta, double phi) {
    mesh.vertices.push_back(static_cast<PfxFloat>(radius * std::sin(theta) * std::cos(phi)));
    mesh.vertices.push_back(static_cast<PfxFloat>(radius * std::sin(theta) * std::sin(phi)));
    mesh.vertices.push_back(static_cast<PfxFloat>(radius * std::cos(theta)));
  };
  add(0, 0);  // north pole: vertex 0
  for (int r = 1; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) add(kPi * r / rings, 2 * kPi * s / segments);
  }
  add(kPi, 0);  // south pole
  const PfxUInt32 south = static_cast<PfxUInt32>(mesh.vertices.size() / 3 - 1);
  const auto ring = [&](int r, int s) {
    return static_cast<PfxUInt32>(1 + (r - 1) * segments + (s % segments));
  };
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.insert(mesh.triangles.end(), {0, ring(1, s), ring(1, s + 1)});
    mesh.triangles.insert(mesh.triangles.end(),
                          {south, ring(rings - 1, s + 1), ring(rings - 1, s)});
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.triangles.insert(mesh.triangles.end(), {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      mesh.triangles.insert(mesh.triangles.end(), {ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  }
  return mesh;
}

// A mesh and a convex mesh with recognisable contents, to see that a failed call left them.
PfxTriangleMesh sentinelMesh() {
  PfxTriangleMesh mesh;
  mesh.vertices = {7, 8, 9, 1, 2, 3, 4, 5, 6};
  mesh.triangles = {0, 1, 2};
  return mesh;
}

bool sameMesh(const PfxTriangleMesh& a, const PfxTriangleMesh& b) {
  return a.vertices == b.vertices && a.triangles == b.triangles;
}

PfxConvexMesh sentinelHull() {
  PfxConvexMesh hull;
  std::memset(static_cast<void*>(&hull), 0xAB, sizeof(hull));
  return hull;
}

bool sameBytes(const PfxConvexMesh& a, const PfxConvexMesh& b) {
  return std::memcmp(&a, &b, sizeof(a)) == 0;
}

// A binary STL of the given triangles (nine coordinates each).
std::string binaryStl(const std::vector<std::array<float, 9>>& triangles) {
  std::string bytes(80, ' ');
  const std::uint32_t count = static_cast<std::uint32_t>(triangles.size());
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 1};
    bytes.append(reinterpret_cast<const char*>(normal), sizeof(normal));
    bytes.append(reinterpret_cast<const char*>(t.data()), 9 * sizeof(float));
    bytes.append(2, '\0');
  }
  return bytes;
}

// --- pfxLoadMeshFile -----------------------------------------------------------------------

TEST(MeshLoader, UnitCubeStlWeldsToEightVerticesAndTwelveTriangles) {
  PfxTriangleMesh mesh;
  std::string message;
  ASSERT_EQ(pfxLoadMeshFile(dataFile("cube.stl"), PfxVector3(1, 1, 1), mesh, &message), PFX_OK)
      << message;
  EXPECT_EQ(mesh.vertices.size(), 8u * 3);
  EXPECT_EQ(mesh.triangles.size(), 12u * 3);
  EXPECT_TRUE(isClosed(mesh));
  const Bounds b = boundsOf(mesh);
  EXPECT_TRUE(b.lo.isApprox(PfxVector3::Constant(-0.5f))) << b.lo.transpose();
  EXPECT_TRUE(b.hi.isApprox(PfxVector3::Constant(0.5f))) << b.hi.transpose();
  EXPECT_NEAR(enclosedVolume(mesh), 1.0, 1e-6);  // the file's winding is kept: outward
}

TEST(MeshLoader, ScaleMultipliesEachAxis) {
  PfxTriangleMesh mesh;
  ASSERT_EQ(pfxLoadMeshFile(dataFile("cube.stl"), PfxVector3(2, 3, 4), mesh), PFX_OK);
  const Bounds b = boundsOf(mesh);
  EXPECT_TRUE(b.lo.isApprox(PfxVector3(-1, -1.5f, -2))) << b.lo.transpose();
  EXPECT_TRUE(b.hi.isApprox(PfxVector3(1, 1.5f, 2))) << b.hi.transpose();
  EXPECT_NEAR(enclosedVolume(mesh), 24.0, 1e-5);
}

TEST(MeshLoader, ObjAndColladaOfOneBoxGiveTheSameVertices) {
  // box.dae holds the box in units of 0.5 m, Z up, placed by its node's translation; the
  // unit and the node transform apply, the up axis does not (as in rviz).
  PfxTriangleMesh obj, dae;
  std::string message;
  ASSERT_EQ(pfxLoadMeshFile(dataFile("box.obj"), PfxVector3(1, 1, 1), obj, &message), PFX_OK)
      << message;
  ASSERT_EQ(pfxLoadMeshFile(dataFile("box.dae"), PfxVector3(1, 1, 1), dae, &message), PFX_OK)
      << message;
  EXPECT_EQ(obj.triangles.size(), 12u * 3);  // quads triangulated
  EXPECT_EQ(dae.triangles.size(), 12u * 3);
  const auto sorted = [](const PfxTriangleMesh& m) {
    std::set<std::array<PfxFloat, 3>> points;
    for (std::size_t i = 0; i < m.vertices.size(); i += 3) {
      points.insert({m.vertices[i], m.vertices[i + 1], m.vertices[i + 2]});
    }
    return points;
  };
  EXPECT_EQ(sorted(obj).size(), 8u);
  EXPECT_EQ(sorted(obj), sorted(dae));
  const Bounds b = boundsOf(dae);
  EXPECT_TRUE(b.lo.isApprox(PfxVector3(-0.25f, -0.5f, -0.5f))) << b.lo.transpose();
  EXPECT_TRUE(b.hi.isApprox(PfxVector3(0.75f, 1.5f, 2.5f))) << b.hi.transpose();
  EXPECT_NEAR(enclosedVolume(obj), 6.0, 1e-5);
  EXPECT_NEAR(enclosedVolume(dae), 6.0, 1e-5);
}

TEST(MeshLoader, KukaLinkMeshesLoad) {
  for (int link = 0; link <= 7; ++link) {
    PfxTriangleMesh mesh;
    std::string message;
    ASSERT_EQ(pfxLoadMeshFile(kukaMesh(link), PfxVector3(1, 1, 1), mesh, &message), PFX_OK)
        << message;
    EXPECT_GT(mesh.triangles.size() / 3, 1000u) << "link " << link;
    // STL repeats every corner per triangle; welded, a closed surface has about half as
    // many vertices as triangles.
    EXPECT_LT(mesh.vertices.size() / 3, mesh.triangles.size() / 3) << "link " << link;
    const Bounds b = boundsOf(mesh);
    EXPECT_GT((b.hi - b.lo).minCoeff(), 0.05f) << "link " << link;  // metres, not millimetres
    EXPECT_LT((b.hi - b.lo).maxCoeff(), 0.5f) << "link " << link;
  }
}

// Loads a file that must be refused with `code`: the mesh passed in stays as it was and the
// message names the file. Returns the reason after "<file>: ".
std::string refusedReason(const std::string& path, const PfxVector3& scale, PfxInt32 code) {
  PfxTriangleMesh mesh = sentinelMesh();
  std::string message;
  EXPECT_EQ(pfxLoadMeshFile(path, scale, mesh, &message), code) << path;
  EXPECT_TRUE(sameMesh(mesh, sentinelMesh())) << path;
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  return message.substr(std::min(message.size(), path.size() + 2));
}

TEST(MeshLoader, MissingFileIsRejectedAndTheMeshKept) {
  EXPECT_EQ(refusedReason(dataFile("no_such_mesh.stl"), PfxVector3(1, 1, 1), PFX_ERR_INVALID_VALUE),
            "no such file");
}

TEST(MeshLoader, GarbageAndEmptyFilesAreRejectedAndTheMeshKept) {
  TempFolder folder;
  const std::string files[] = {
      folder.write("garbage.stl", "this is not a mesh\n\x01\x02\x03"),
      folder.write("garbage.dae", "<COLLADA><library_geometries><geometry"),
      folder.write("garbage.bin", std::string(300, '\x7f')),
      folder.write("empty.stl", ""),
      folder.write("empty.obj", ""),
  };
  for (const std::string& path : files) {
    const std::string reason = refusedReason(path, PfxVector3(1, 1, 1), PFX_ERR_INVALID_VALUE);
    EXPECT_EQ(reason.rfind("cannot read as a mesh (", 0), 0u) << reason;
  }
}

TEST(MeshLoader, FileWithoutTrianglesIsRejected) {
  TempFolder folder;
  const std::string path = folder.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n");
  EXPECT_EQ(refusedReason(path, PfxVector3(1, 1, 1), PFX_ERR_DEGENERATE),
            "the file holds no triangles");
}

TEST(MeshLoader, NaNVertexIsRejected) {
  TempFolder folder;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::string path = folder.write(
      "nan.stl", binaryStl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 1, 0, nan, 0, 1}}));
  EXPECT_EQ(refusedReason(path, PfxVector3(1, 1, 1), PFX_ERR_INVALID_VALUE),
            "a vertex is NaN or infinite");
}

TEST(MeshLoader, ScaleThatIsNotPositiveAndFiniteIsRejected) {
  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  const PfxFloat inf = std::numeric_limits<PfxFloat>::infinity();
  const PfxVector3 scales[] = {PfxVector3(1, nan, 1), PfxVector3(0, 1, 1), PfxVector3(1, 1, -2),
                               PfxVector3(inf, 1, 1)};
  for (const PfxVector3& scale : scales) {
    const std::string reason = refusedReason(dataFile("cube.stl"), scale, PFX_ERR_INVALID_VALUE);
    EXPECT_EQ(reason.rfind("scale must be positive and finite", 0), 0u) << reason;
  }
}

// --- pfxCreateConvexHull -------------------------------------------------------------------

// The hull of a mesh with what pfxCreateConvexHull said about it.
struct HullResult {
  PfxInt32 err = PFX_OK;
  PfxConvexMesh mesh;
  PfxConvexHullInfo info;
  std::string message;
};

HullResult hullOf(const PfxTriangleMesh& mesh) {
  HullResult result;
  result.err = pfxCreateConvexHull(mesh, result.mesh, &result.message, &result.info);
  return result;
}

TEST(ConvexHull, CubeFileGivesTheCube) {
  PfxTriangleMesh mesh;
  ASSERT_EQ(pfxLoadMeshFile(dataFile("cube.stl"), PfxVector3(1, 1, 1), mesh), PFX_OK);
  const HullResult result = hullOf(mesh);
  ASSERT_EQ(result.err, PFX_OK) << result.message;
  const PfxConvexMesh& hull = result.mesh;
  const PfxConvexHullInfo& info = result.info;
  EXPECT_EQ(hull.m_numVerts, 8);
  EXPECT_EQ(hull.m_numFacets, 12);
  EXPECT_EQ(hull.m_numFaces, 6);  // coplanar triangles merged into the cube's quads
  EXPECT_NEAR(volumeOf(hull), 1.0, 1e-5);
  EXPECT_EQ(info.numHullVertices, 8u);
  EXPECT_NEAR(info.hullVolume, 1.0, 1e-9);
  EXPECT_NEAR(info.volume, 1.0, 1e-9);
}

TEST(ConvexHull, InnerPointsAndPointsOnEdgesAndFacesAddNothing) {
  // The cube's corners, its edge midpoints, face centres and centre, twice over.
  PfxTriangleMesh mesh;
  for (int repeat = 0; repeat < 2; ++repeat) {
    for (int x = -1; x <= 1; ++x) {
      for (int y = -1; y <= 1; ++y) {
        for (int z = -1; z <= 1; ++z) {
          mesh.vertices.insert(mesh.vertices.end(), {PfxFloat(x), PfxFloat(y), PfxFloat(z)});
        }
      }
    }
  }
  const HullResult result = hullOf(mesh);
  ASSERT_EQ(result.err, PFX_OK) << result.message;
  const PfxConvexMesh& hull = result.mesh;
  EXPECT_LE(hull.m_numVerts, PFX_CONVEX_MESH_MAX_VERTICES);
  EXPECT_EQ(hull.m_numFaces, 6);
  EXPECT_NEAR(volumeOf(hull), 8.0, 1e-5);
  for (int i = 0; i < hull.m_numVerts; ++i) {
    EXPECT_NEAR(hull.m_verts[i].cwiseAbs().maxCoeff(), 1, 1e-6);  // on the surface
  }
}

TEST(ConvexHull, CoarseSphereIsKeptWhole) {
  // 26 vertices and 48 triangles: within the limits, so the hull is the mesh itself.
  const PfxTriangleMesh sphere = makeSphere(4, 8, 1.0);
  ASSERT_EQ(sphere.vertices.size() / 3, 26u);
  const HullResult result = hullOf(sphere);
  ASSERT_EQ(result.err, PFX_OK) << result.message;
  const PfxConvexMesh& hull = result.mesh;
  const PfxConvexHullInfo& info = result.info;
  EXPECT_EQ(hull.m_numVerts, 26);
  EXPECT_EQ(hull.m_numFacets, 48);
  EXPECT_NEAR(volumeOf(hull), enclosedVolume(sphere), 1e-5);
  EXPECT_NEAR(info.volume, info.hullVolume, 1e-12);
}

TEST(ConvexHull, FineSphereIsSimplifiedInsideItsHullAndCloseInVolume) {
  const PfxTriangleMesh sphere = makeSphere(24, 48, 1.0);  // 1,106 vertices
  const double sphereMeshVolume = enclosedVolume(sphere);
  const HullResult result = hullOf(sphere);
  ASSERT_EQ(result.err, PFX_OK) << result.message;
  const PfxConvexMesh& hull = result.mesh;
  const PfxConvexHullInfo& info = result.info;
  EXPECT_EQ(info.numHullVertices, sphere.vertices.size() / 3);
  // qhull merges each band's two triangles, coplanar but for float rounding, into one face.
  EXPECT_NEAR(info.hullVolume, sphereMeshVolume, 1e-6 * sphereMeshVolume);
  EXPECT_LE(hull.m_numVerts, PFX_CONVEX_MESH_MAX_VERTICES);
  EXPECT_LE(hull.m_numFacets, PFX_CONVEX_MESH_MAX_FACETS);
  EXPECT_EQ(hull.m_numVerts, PFX_CONVEX_MESH_MAX_VERTICES);  // every corner allowed is used
  EXPECT_NEAR(info.volume, volumeOf(hull), 1e-5);

  // Inside: its corners are corners of the input, and no corner pokes outside any of the
  // input's (outward) triangle planes.
  std::set<std::array<PfxFloat, 3>> input;
  for (std::size_t i = 0; i < sphere.vertices.size(); i += 3) {
    input.insert({sphere.vertices[i], sphere.vertices[i + 1], sphere.vertices[i + 2]});
  }
  for (int i = 0; i < hull.m_numVerts; ++i) {
    const PfxVector3& p = hull.m_verts[i];
    EXPECT_EQ(input.count({p.x(), p.y(), p.z()}), 1u) << p.transpose();
    for (std::size_t t = 0; t < sphere.triangles.size(); t += 3) {
      const PfxVector3 a = vertexOf(sphere, sphere.triangles[t]);
      const PfxVector3 n = (vertexOf(sphere, sphere.triangles[t + 1]) - a)
                               .cross(vertexOf(sphere, sphere.triangles[t + 2]) - a)
                               .normalized();
      ASSERT_LE(n.dot(p - a), 1e-6f);
    }
  }
  // 34 points spread evenly over a sphere (a Fibonacci lattice) span 83 % of its volume;
  // the greedy choice among the mesh's corners spans as much (83 % measured).
  const double ratio = volumeOf(hull) / sphereMeshVolume;
  std::printf("[ figures  ] sphere of %zu vertices: 34-vertex hull holds %.1f %% of it\n",
              sphere.vertices.size() / 3, 100 * ratio);
  EXPECT_GT(ratio, 0.80);
  EXPECT_LT(ratio, 1.0);
}

TEST(ConvexHull, KukaLinksFitTheLimitsAndKeepMostOfTheirVolume) {
  for (int link = 0; link <= 7; ++link) {
    PfxTriangleMesh mesh;
    ASSERT_EQ(pfxLoadMeshFile(kukaMesh(link), PfxVector3(1, 1, 1), mesh), PFX_OK);
    const HullResult result = hullOf(mesh);
    ASSERT_EQ(result.err, PFX_OK) << result.message;
    const PfxConvexMesh& hull = result.mesh;
    const PfxConvexHullInfo& info = result.info;
    EXPECT_LE(hull.m_numVerts, PFX_CONVEX_MESH_MAX_VERTICES);
    EXPECT_LE(hull.m_numFacets, PFX_CONVEX_MESH_MAX_FACETS);
    EXPECT_GT(info.numHullVertices, PFX_CONVEX_MESH_MAX_VERTICES);
    EXPECT_NEAR(info.volume, volumeOf(hull), 1e-6 * info.volume);
    const double loss = 1 - info.volume / info.hullVolume;
    EXPECT_GT(loss, 0);
    EXPECT_LT(loss, 0.12) << "link " << link;
    // The hull holds the mesh's own volume less what the simplification cut off.
    EXPECT_GT(info.volume, (1 - loss) * enclosedVolume(mesh) - 1e-9) << "link " << link;
    std::printf(
        "[ figures  ] KUKA iiwa link_%d.stl: hull of %u vertices, %.4f l; "
        "34-vertex hull %.4f l, %.1f %% less\n",
        link, info.numHullVertices, 1000 * info.hullVolume, 1000 * info.volume, 100 * loss);
  }
}

TEST(ConvexHull, DegeneratePointSetsAreRejectedQuietlyAndTheHullKept) {
  struct Case {
    const char* name;
    std::vector<PfxFloat> vertices;
    const char* reason;
  };
  std::vector<PfxFloat> plane, line;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) plane.insert(plane.end(), {PfxFloat(i), PfxFloat(j), 2});
    line.insert(line.end(), {PfxFloat(i), PfxFloat(2 * i), PfxFloat(-i)});
  }
  const Case cases[] = {
      {"coplanar", plane, "convex hull: all 25 vertices lie on one plane"},
      {"collinear", line, "convex hull: all 5 vertices lie on one line"},
      {"one point",
       {1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3},
       "convex hull: all 4 vertices are one point"},
      {"three points",
       {0, 0, 0, 1, 0, 0, 0, 1, 0},
       "convex hull: needs at least 4 vertices, got 3"},
  };
  for (const Case& c : cases) {
    PfxTriangleMesh mesh;
    mesh.vertices = c.vertices;
    PfxConvexMesh hull = sentinelHull();
    std::string message;
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    const PfxInt32 err = pfxCreateConvexHull(mesh, hull, &message);
    const std::string out = ::testing::internal::GetCapturedStdout();
    const std::string errOut = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, PFX_ERR_DEGENERATE) << c.name;
    EXPECT_EQ(message, c.reason) << c.name;
    EXPECT_TRUE(sameBytes(hull, sentinelHull())) << c.name;
    EXPECT_EQ(out + errOut, "") << c.name;
  }
}

TEST(ConvexHull, NaNVertexAndBadLengthAreRejected) {
  PfxTriangleMesh mesh = makeSphere(4, 8, 1.0);
  mesh.vertices[3 * 5 + 1] = std::numeric_limits<PfxFloat>::quiet_NaN();
  PfxConvexMesh hull = sentinelHull();
  std::string message;
  EXPECT_EQ(pfxCreateConvexHull(mesh, hull, &message), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(message, "convex hull: vertex 5 is NaN or infinite");
  mesh = makeSphere(4, 8, 1.0);
  mesh.vertices.pop_back();
  EXPECT_EQ(pfxCreateConvexHull(mesh, hull, &message), PFX_ERR_OUT_OF_RANGE);
  EXPECT_TRUE(sameBytes(hull, sentinelHull()));
}

// --- pfxCreateLargeTriMeshFromMesh ---------------------------------------------------------

struct LargeMeshOwner {
  PfxLargeTriMesh mesh{};
  ~LargeMeshOwner() { pfxReleaseLargeTriMesh(mesh); }
};

TEST(LargeMeshFromMesh, KeepsTheTrianglesAndDropsZeroAreaOnes) {
  PfxTriangleMesh mesh;
  ASSERT_EQ(pfxLoadMeshFile(dataFile("cube.stl"), PfxVector3(1, 1, 1), mesh), PFX_OK);
  mesh.triangles.insert(mesh.triangles.end(), {0, 1, 1});  // no area
  LargeMeshOwner owner;
  std::string message;
  ASSERT_EQ(pfxCreateLargeTriMeshFromMesh(mesh, PFX_MESH_FLAG_USE_BVH, owner.mesh, &message),
            PFX_OK)
      << message;
  EXPECT_EQ(owner.mesh.m_numTriangles, 12u);
  EXPECT_EQ(owner.mesh.m_numDroppedTriangles, 1u);
  EXPECT_EQ(owner.mesh.m_flags, PFX_MESH_FLAG_USE_BVH);
  EXPECT_FLOAT_EQ(owner.mesh.m_thickness, PFX_MESH_DEFAULT_THICKNESS);

  // A ray from above meets the cube's top at z = 0.5.
  PfxFloat fraction = 0;
  PfxVector3 normal;
  PfxUInt32 triangle = 0;
  ASSERT_TRUE(pfxRayCastLargeTriMesh(owner.mesh, PfxVector3(0.1f, 0.2f, 2), PfxVector3(0, 0, -4),
                                     fraction, normal, triangle));
  EXPECT_NEAR(2 - 4 * fraction, 0.5, 1e-6);
  EXPECT_NEAR(normal.z(), 1, 1e-6);
}

TEST(LargeMeshFromMesh, EmptyOrBrokenMeshIsRejectedAndTheOutputKept) {
  PfxTriangleMesh empty;
  PfxTriangleMesh outOfRange;
  outOfRange.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  outOfRange.triangles = {0, 1, 3};
  PfxTriangleMesh allFlat;
  allFlat.vertices = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  allFlat.triangles = {0, 1, 2};
  PfxLargeTriMesh mesh;
  std::memset(static_cast<void*>(&mesh), 0, sizeof(mesh));
  mesh.m_numTriangles = 77;  // a mark: nothing may overwrite it
  std::string message;
  EXPECT_EQ(pfxCreateLargeTriMeshFromMesh(empty, 0, mesh, &message), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(message, "large mesh: no triangles");
  EXPECT_EQ(pfxCreateLargeTriMeshFromMesh(outOfRange, 0, mesh, &message), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(message.rfind("large mesh: ", 0), 0u);
  EXPECT_EQ(pfxCreateLargeTriMeshFromMesh(allFlat, 0, mesh, &message), PFX_ERR_DEGENERATE);
  EXPECT_EQ(pfxCreateLargeTriMeshFromMesh(sentinelMesh(), 1u << 7, mesh, &message),
            PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(mesh.m_numTriangles, 77u);
  EXPECT_EQ(mesh.m_block, nullptr);
}

}  // namespace
