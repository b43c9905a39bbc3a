// OctoMap files (written by liboctomap: make_test_octomaps.cpp) as static geometry: the room
// of ~100,000 voxels placed at a pose in a Z-up world, bodies resting on it, rays hitting
// it, and files that must be refused with the world left as it was.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_octomap_loader.h"

namespace {

using namespace pfx;

std::string dataFile(const std::string& name) {
  return std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/" + name;
}

std::string readBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << file.rdbuf();
  return bytes.str();
}

// Where the tests put the map: 1 m along x, 2 m along y, 0.5 m up, turned 30 degrees
// about the vertical. The room's floor top (z = 0 in the map) is then at z = 0.5.
const PfxVector3 kMapPosition(1, 2, PfxFloat(0.5));
const PfxQuat kMapOrientation(Eigen::AngleAxis<PfxFloat>(PFX_PI / 6, PfxVector3::UnitZ()));
constexpr PfxFloat kFloorTop = 0;               // map frame, m
constexpr PfxFloat kTableTop = PfxFloat(0.75);  // see make_test_octomaps.cpp
constexpr PfxFloat kCabinetTop = 1;
constexpr PfxFloat kWallTop = PfxFloat(2.6);
constexpr PfxFloat kInnerWallX = PfxFloat(3.9);  // the +X wall's inner face
constexpr PfxUInt64 kRoomVoxels = 97784;

PfxVector3 toWorld(const PfxVector3& inMap) { return kMapOrientation * inMap + kMapPosition; }
PfxVector3 toMap(const PfxVector3& inWorld) {
  return kMapOrientation.conjugate() * (inWorld - kMapPosition);
}

PfxWorldParam zUpParam() {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  param.worldExtent = PfxVector3::Constant(50);
  return param;
}

PfxOctomapLoadParam mapPose() {
  PfxOctomapLoadParam param;
  param.position = kMapPosition;
  param.orientation = kMapOrientation;
  return param;
}

// What a PfxOctomap holds, to see that a refused load left it as it was.
struct MapSnapshot {
  explicit MapSnapshot(const PfxOctomap& map)
      : bodyId(map.bodyId),
        numOccupiedVoxels(map.numOccupiedVoxels),
        resolution(map.resolution),
        meshCreated(map.meshCreated),
        meshBlock(map.mesh.m_block),
        numTriangles(map.mesh.m_numTriangles) {}
  bool operator==(const MapSnapshot& o) const {
    return bodyId == o.bodyId && numOccupiedVoxels == o.numOccupiedVoxels &&
           resolution == o.resolution && meshCreated == o.meshCreated && meshBlock == o.meshBlock &&
           numTriangles == o.numTriangles;
  }
  PfxUInt32 bodyId;
  PfxUInt64 numOccupiedVoxels;
  PfxFloat resolution;
  bool meshCreated;
  const void* meshBlock;
  PfxUInt32 numTriangles;
};

PfxRayOutput castRay(PfxWorld& world, const PfxVector3& start, const PfxVector3& direction) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = start;
  ray.m_direction = direction;
  PfxRayOutput out;
  EXPECT_EQ(world.castRay(ray, out), PFX_OK);
  return out;
}

class OctomapRoom : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(m_world.initialize(zUpParam()), PFX_OK);
    std::string message;
    const auto start = std::chrono::steady_clock::now();
    ASSERT_EQ(pfxLoadOctomapFile(m_world, dataFile("room.bt"), mapPose(), m_map, &message), PFX_OK)
        << message;
    m_loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  PfxWorld m_world;
  PfxOctomap m_map;
  double m_loadSeconds = 0;
};

TEST_F(OctomapRoom, LoadsAsOneFixedBodyOfFewTriangles) {
  EXPECT_EQ(m_world.getNumRigidBodies(), 1u);
  EXPECT_EQ(m_map.bodyId, 0u);
  EXPECT_TRUE(m_map.meshCreated);
  EXPECT_EQ(m_map.numOccupiedVoxels, kRoomVoxels);
  EXPECT_FLOAT_EQ(m_map.resolution, 0.05f);
  const PfxRigidState& state = m_world.getRigidState(m_map.bodyId);
  EXPECT_EQ(state.getMotionType(), kPfxMotionTypeFixed);
  EXPECT_TRUE(state.getPosition().isApprox(kMapPosition));
  EXPECT_TRUE(state.getOrientation().isApprox(kMapOrientation));
  const PfxCollidable& collidable = m_world.getCollidable(m_map.bodyId);
  ASSERT_EQ(collidable.getNumShapes(), 1u);
  EXPECT_EQ(collidable.getShape(0).getLargeTriMesh(), &m_map.mesh);

  // The surface in the map's frame: the floor slab's bottom to the walls' top.
  EXPECT_TRUE(m_map.mesh.m_aabbMin.isApprox(PfxVector3(-4, -3, PfxFloat(-0.1)), PfxFloat(1e-6)))
      << m_map.mesh.m_aabbMin.transpose();
  EXPECT_TRUE(m_map.mesh.m_aabbMax.isApprox(PfxVector3(4, 3, kWallTop), PfxFloat(1e-6)))
      << m_map.mesh.m_aabbMax.transpose();
  // A box per voxel would be 12 triangles each; exposed faces merged per plane are a few
  // hundred for the whole room.
  EXPECT_LT(m_map.mesh.m_numTriangles, kRoomVoxels / 100);
  EXPECT_EQ(m_map.mesh.m_numDroppedTriangles, 0u);
  std::printf(
      "[ figures  ] room.bt: %llu voxels at 5 cm -> %u triangles, %u vertices, "
      "%zu bytes; loaded in %.1f ms\n",
      static_cast<unsigned long long>(m_map.numOccupiedVoxels), m_map.mesh.m_numTriangles,
      m_map.mesh.m_numVertices, m_map.mesh.m_bytes, 1000 * m_loadSeconds);
}

TEST_F(OctomapRoom, RayDownHitsTheFloorAndTheTableTops) {
  struct Probe {
    PfxFloat x, y, height;
  };
  const Probe probes[] = {{-2, 1, kFloorTop},
                          {2.5f, -1.5f, kFloorTop},
                          {0.3f, 0.1f, kTableTop},
                          {-0.55f, -0.35f, kTableTop},
                          {3.3f, 2.3f, kCabinetTop}};
  for (const Probe& p : probes) {
    const PfxVector3 start = toWorld(PfxVector3(p.x, p.y, 3));
    const PfxRayOutput out = castRay(m_world, start, PfxVector3(0, 0, -4));
    ASSERT_TRUE(out.m_contactFlag) << p.x << " " << p.y;
    EXPECT_EQ(out.m_objectId, m_map.bodyId);
    EXPECT_NEAR(out.m_contactPoint.z(), kMapPosition.z() + p.height, 1e-4) << p.x << " " << p.y;
    EXPECT_NEAR(out.m_contactNormal.z(), 1, 1e-5);
  }
}

TEST_F(OctomapRoom, RayIntoAWallHitsItsFaceAndOneThroughTheDoorMissesIt) {
  // Along the map's +x from the room's middle: the +X wall's inner face.
  const PfxVector3 alongX = kMapOrientation * PfxVector3(10, 0, 0);
  PfxRayOutput out = castRay(m_world, toWorld(PfxVector3(0.2f, -1, 1.5f)), alongX);
  ASSERT_TRUE(out.m_contactFlag);
  const PfxVector3 hit = toMap(out.m_contactPoint);
  EXPECT_NEAR(hit.x(), kInnerWallX, 1e-4);
  EXPECT_NEAR(hit.z(), 1.5, 1e-4);
  EXPECT_TRUE(out.m_contactNormal.isApprox(kMapOrientation * PfxVector3(-1, 0, 0), 1e-5f))
      << out.m_contactNormal.transpose();

  // Along -y: the -Y wall at x = -2, but nothing at x = 0, where the door is.
  const PfxVector3 alongMinusY = kMapOrientation * PfxVector3(0, -10, 0);
  out = castRay(m_world, toWorld(PfxVector3(-2, 0, 1)), alongMinusY);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_NEAR(toMap(out.m_contactPoint).y(), -2.9, 1e-4);
  out = castRay(m_world, toWorld(PfxVector3(0, 0, 1)), alongMinusY);
  EXPECT_FALSE(out.m_contactFlag);
}

TEST_F(OctomapRoom, SpheresComeToRestOnTheFloorAndOnTheTable) {
  // The table top is one voxel thick; the second sphere lands on its middle.
  const PfxFloat radius = 0.1f;
  const PfxVector3 drops[] = {PfxVector3(-2, 1, 1), PfxVector3(0, 0, 1.5f)};
  const PfxFloat rest[] = {kFloorTop + radius, kTableTop + radius};
  PfxUInt32 ids[2];
  for (int i = 0; i < 2; ++i) {
    PfxBodyInit init;
    init.position = toWorld(drops[i]);
    init.mass = 1;
    ASSERT_EQ(pfxAddBody(m_world, pfxMakeShape(PfxSphere(radius)), init, &ids[i]), PFX_OK);
  }
  for (int step = 0; step < 180; ++step) ASSERT_EQ(m_world.step(), PFX_OK);
  for (int i = 0; i < 2; ++i) {
    const PfxVector3 p = toMap(m_world.getRigidState(ids[i]).getPosition());
    EXPECT_NEAR(p.z(), rest[i], 0.003) << "sphere " << i;
    EXPECT_NEAR(p.x(), drops[i].x(), 0.01) << "sphere " << i;
    EXPECT_NEAR(p.y(), drops[i].y(), 0.01) << "sphere " << i;
    EXPECT_LT(m_world.getRigidState(ids[i]).getLinearVelocity().norm(), 1e-3f);
  }
}

TEST_F(OctomapRoom, HundredThousandRandomRaysDownHitKnownHeights) {
  // Over the map and a margin around it: inside the walls every ray meets the floor, the
  // table, the cabinet or a wall's top; outside, nothing.
  constexpr PfxUInt32 kRays = 100000;
  std::mt19937 rng(7);
  std::uniform_real_distribution<PfxFloat> x(-4.5f, 4.5f), y(-3.5f, 3.5f);
  std::vector<PfxRayInput> rays(kRays);
  std::vector<PfxRayOutput> hits(kRays);
  for (PfxRayInput& ray : rays) {
    ray.reset();
    ray.m_startPosition = toWorld(PfxVector3{x(rng), y(rng), 3});
    ray.m_direction = PfxVector3(0, 0, -4);
  }
  ASSERT_EQ(m_world.castRays(rays.data(), hits.data(), 1), PFX_OK);  // builds the rays' proxies
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(m_world.castRays(rays.data(), hits.data(), kRays), PFX_OK);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  PfxUInt32 numHits = 0, wrong = 0;
  const PfxFloat heights[] = {kFloorTop, kTableTop, kCabinetTop, kWallTop};
  for (PfxUInt32 i = 0; i < kRays; ++i) {
    const PfxVector3 above = toMap(rays[i].m_startPosition);
    const bool over = std::abs(above.x()) < 4 && std::abs(above.y()) < 3;
    if (!over) {
      wrong += hits[i].m_contactFlag;
      continue;
    }
    ++numHits;
    const PfxFloat z = hits[i].m_contactPoint.z() - kMapPosition.z();
    bool known = false;
    for (PfxFloat h : heights) known = known || std::abs(z - h) < 1e-4f;
    wrong += !(hits[i].m_contactFlag && known);
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(numHits, kRays / 2);
  std::printf("[ figures  ] room.bt: %u rays down in one castRays: %.0f rays/s\n", kRays,
              kRays / seconds);
}

TEST(OctomapLoader, BinaryAndFullFormatsGiveTheSameSurface) {
  // small.bt and small.ot hold the same tree: a plate of 100 voxels at 10 cm, a 2 x 2 x 2
  // block on it that liboctomap pruned into one leaf of 20 cm, and a free voxel.
  PfxWorld worlds[2];
  PfxOctomap maps[2];
  const char* names[] = {"small.bt", "small.ot"};
  for (int i = 0; i < 2; ++i) {
    ASSERT_EQ(worlds[i].initialize(zUpParam()), PFX_OK);
    std::string message;
    ASSERT_EQ(
        pfxLoadOctomapFile(worlds[i], dataFile(names[i]), PfxOctomapLoadParam(), maps[i], &message),
        PFX_OK)
        << message;
    EXPECT_EQ(maps[i].numOccupiedVoxels, 108u) << names[i];
    EXPECT_FLOAT_EQ(maps[i].resolution, 0.1f);
  }
  EXPECT_EQ(maps[0].mesh.m_numTriangles, maps[1].mesh.m_numTriangles);
  const auto vertexSet = [](const PfxLargeTriMesh& mesh) {
    std::set<std::array<PfxFloat, 3>> set;
    for (PfxUInt32 v = 0; v < mesh.m_numVertices; ++v) {
      set.insert({mesh.m_vertices[3 * v], mesh.m_vertices[3 * v + 1], mesh.m_vertices[3 * v + 2]});
    }
    return set;
  };
  EXPECT_EQ(vertexSet(maps[0].mesh), vertexSet(maps[1].mesh));
  for (PfxWorld& world : worlds) {
    // The block's top, the plate's top beside it, and the plate under the free voxel.
    EXPECT_NEAR(castRay(world, PfxVector3(0.1f, 0.13f, 1), PfxVector3(0, 0, -2)).m_contactPoint.z(),
                0.2, 1e-5);
    EXPECT_NEAR(castRay(world, PfxVector3(0.33f, 0.1f, 1), PfxVector3(0, 0, -2)).m_contactPoint.z(),
                0, 1e-5);
    EXPECT_NEAR(
        castRay(world, PfxVector3(-0.25f, -0.27f, 1), PfxVector3(0, 0, -2)).m_contactPoint.z(), 0,
        1e-5);
    // The plate is 10 cm thick: a ray up from below meets its bottom.
    const PfxRayOutput up = castRay(world, PfxVector3(-0.4f, 0.2f, -1), PfxVector3(0, 0, 2));
    ASSERT_TRUE(up.m_contactFlag);
    EXPECT_NEAR(up.m_contactPoint.z(), -0.1, 1e-5);
    EXPECT_NEAR(up.m_contactNormal.z(), -1, 1e-5);
  }
}

// Two bytes per node of a .bt file: two bits per child, 2 = occupied leaf, 3 = children.
std::string binaryNode(unsigned child, unsigned code) {
  const unsigned bits = code << (2 * child);
  return std::string{static_cast<char>(bits & 0xff), static_cast<char>(bits >> 8)};
}

TEST(OctomapLoader, LargePrunedLeafBesideOneVoxel) {
  // The root's first child is one occupied leaf of 32,768^3 cells; its +x face meets a
  // single voxel at the bottom of the root's second child, sixteen levels down. The large
  // face is left as squares of every size from 16,384 cells down to one around the voxel,
  // too many cells to cut at one grain: the mesh stays small all the same.
  std::string bytes = "# Octomap OcTree binary file\nid OcTree\nsize 18\nres 0.05\ndata\n";
  bytes += std::string{static_cast<char>(0x02 | 0x03 << 2), 0};  // leaf, then children
  for (int depth = 1; depth < 15; ++depth) bytes += binaryNode(0, 3);
  bytes += binaryNode(0, 2);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "pfx_octomap_test_large_leaf.bt";
  std::ofstream(path, std::ios::binary) << bytes;

  PfxWorld world;
  PfxWorldParam param = zUpParam();
  param.worldExtent = PfxVector3::Constant(4000);
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxOctomap map;
  std::string message;
  const PfxInt32 err =
      pfxLoadOctomapFile(world, path.string(), PfxOctomapLoadParam(), map, &message);
  std::filesystem::remove(path);
  ASSERT_EQ(err, PFX_OK) << message;
  EXPECT_EQ(map.numOccupiedVoxels, (PfxUInt64(1) << 45) + 1);
  EXPECT_LT(map.mesh.m_numTriangles, 1000u);
  // The large cube spans [-1638.4, 0) on every axis; the voxel sits at x in [0, 0.05) on
  // its +x face's lowest corner.
  PfxRayOutput out = castRay(world, PfxVector3(10, -800, -800), PfxVector3(-20, 0, 0));
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_NEAR(out.m_contactPoint.x(), 0, 1e-4);
  EXPECT_NEAR(out.m_contactNormal.x(), 1, 1e-5);
  out = castRay(world, PfxVector3(0.025f, -1638.375f, -1630), PfxVector3(0, 0, -20));
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_NEAR(out.m_contactPoint.z(), -1638.35, 1e-3);
}

// --- refused input -------------------------------------------------------------------------

class OctomapRefused : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(m_world.initialize(zUpParam()), PFX_OK);
    PfxBodyInit init;
    init.position = PfxVector3(0, 0, 1);
    init.linearVelocity = PfxVector3(0.5f, 0, 0);
    ASSERT_EQ(pfxAddBody(m_world, pfxMakeShape(PfxBox(0.1f, 0.2f, 0.3f)), init), PFX_OK);
    for (int i = 0; i < 3; ++i) ASSERT_EQ(m_world.step(), PFX_OK);
    m_before = m_world.getRigidState(0);
    m_folder = std::filesystem::temp_directory_path() /
               ("pfx_octomap_test_" +
                std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(m_folder);
  }
  void TearDown() override { std::filesystem::remove_all(m_folder); }

  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string path = (m_folder / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  // Loads and expects the code, a message "<path>: <reason>", nothing printed, and the
  // world and the map as they were.
  void expectRefused(const std::string& path, const PfxOctomapLoadParam& param, PfxInt32 code,
                     const std::string& reason, PfxOctomap& map) {
    const MapSnapshot before(map);
    std::string message;
    ::testing::internal::CaptureStderr();
    ::testing::internal::CaptureStdout();
    const PfxInt32 err = pfxLoadOctomapFile(m_world, path, param, map, &message);
    const std::string printed =
        ::testing::internal::GetCapturedStdout() + ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, code) << path;
    EXPECT_EQ(message, path + ": " + reason);
    EXPECT_EQ(printed, "");
    EXPECT_EQ(m_world.getNumRigidBodies(), 1u);
    EXPECT_EQ(std::memcmp(&m_world.getRigidState(0), &m_before, sizeof(m_before)), 0);
    EXPECT_TRUE(MapSnapshot(map) == before);
  }
  void expectRefused(const std::string& path, PfxInt32 code, const std::string& reason) {
    PfxOctomap map;
    expectRefused(path, mapPose(), code, reason, map);
  }

  PfxWorld m_world;
  PfxRigidState m_before;
  std::filesystem::path m_folder;
};

TEST_F(OctomapRefused, MissingFileOrFolder) {
  expectRefused(dataFile("no_such_map.bt"), PFX_ERR_INVALID_VALUE, "no such file");
  expectRefused(m_folder.string(), PFX_ERR_INVALID_VALUE, "not a regular file");
}

TEST_F(OctomapRefused, FilesThatAreNotOctoMaps) {
  expectRefused(write("garbage.bt", "this is not a map\n\x01\x02"), PFX_ERR_INVALID_VALUE,
                "not an OctoMap file (neither the .bt nor the .ot header)");
  expectRefused(write("empty_file.bt", ""), PFX_ERR_INVALID_VALUE,
                "not an OctoMap file (neither the .bt nor the .ot header)");
  expectRefused(dataFile("box.obj"), PFX_ERR_INVALID_VALUE,
                "not an OctoMap file (neither the .bt nor the .ot header)");
}

TEST_F(OctomapRefused, BrokenHeadersAndCutOffData) {
  const std::string room = readBytes(dataFile("room.bt"));
  const std::size_t data = room.find("\ndata\n") + 6;
  ASSERT_LT(data, room.size());
  expectRefused(write("no_data_line.bt", room.substr(0, data - 5)), PFX_ERR_INVALID_VALUE,
                "header has no 'data' line");
  expectRefused(write("header_only.bt", room.substr(0, data - 1)), PFX_ERR_INVALID_VALUE,
                "file ends after the header");
  expectRefused(write("no_nodes.bt", room.substr(0, data)), PFX_ERR_INVALID_VALUE,
                "node data is cut off or deeper than 16 levels");
  expectRefused(write("cut.bt", room.substr(0, room.size() - 100)), PFX_ERR_INVALID_VALUE,
                "node data is cut off or deeper than 16 levels");

  std::string wrongSize = room;
  const std::size_t size = wrongSize.find("size ");
  const std::size_t end = wrongSize.find('\n', size);
  const long long nodes = std::stoll(wrongSize.substr(size + 5, end - size - 5));
  wrongSize.replace(size, end - size, "size " + std::to_string(nodes + 1));
  expectRefused(write("wrong_size.bt", wrongSize), PFX_ERR_INVALID_VALUE,
                "header says " + std::to_string(nodes + 1) + " nodes, the data holds " +
                    std::to_string(nodes));

  std::string badResolution = room;
  badResolution.replace(badResolution.find("res 0.05"), 8, "res -1");
  expectRefused(write("bad_res.bt", badResolution), PFX_ERR_INVALID_VALUE,
                "resolution must be positive and finite");

  std::string noId = room;
  noId.erase(noId.find("id OcTree\n"), 10);
  expectRefused(write("no_id.bt", noId), PFX_ERR_INVALID_VALUE,
                "header lacks its id, size or res line");

  const std::string smallOt = readBytes(dataFile("small.ot"));
  expectRefused(write("cut.ot", smallOt.substr(0, smallOt.size() - 7)), PFX_ERR_INVALID_VALUE,
                "node data is cut off or deeper than 16 levels");

  // Seventeen levels, each a node whose first child has children: one below the finest.
  std::string deep = "# Octomap OcTree binary file\nid OcTree\nsize 17\nres 0.1\ndata\n";
  for (int level = 0; level < 17; ++level) deep += std::string("\x03\x00", 2);
  expectRefused(write("deep.bt", deep), PFX_ERR_INVALID_VALUE,
                "node data is cut off or deeper than 16 levels");
}

TEST_F(OctomapRefused, CorruptedBytesAreRefusedOrRead) {
  // Bytes of the room's node data changed at random, or the file cut anywhere: every load
  // either succeeds or is refused with the world as it was, and none reads past the end.
  const std::string room = readBytes(dataFile("room.bt"));
  const std::size_t data = room.find("\ndata\n") + 6;
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::size_t> position(data, room.size() - 1), cut(0, room.size());
  std::uniform_int_distribution<int> byte(0, 255), count(1, 4);
  int loaded = 0;
  for (int trial = 0; trial < 120; ++trial) {
    std::string bytes = room;
    if (trial % 4 == 3) {
      bytes.resize(cut(rng));
    } else {
      for (int k = count(rng); k > 0; --k) bytes[position(rng)] = static_cast<char>(byte(rng));
    }
    const std::string path = write("corrupt.bt", bytes);
    PfxOctomap map;
    std::string message;
    if (pfxLoadOctomapFile(m_world, path, mapPose(), map, &message) == PFX_OK) {
      ++loaded;
      EXPECT_GT(map.numOccupiedVoxels, 0u);
      ASSERT_EQ(m_world.initialize(zUpParam()), PFX_OK);  // drops the map's body
      continue;
    }
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_LE(m_world.getNumRigidBodies(), 1u);
  }
  EXPECT_LT(loaded, 120);
}

TEST_F(OctomapRefused, TreesThatAreNotOcTreesOrHoldNoOccupiedVoxel) {
  expectRefused(dataFile("color.ot"), PFX_ERR_INVALID_VALUE, "holds a ColorOcTree, not an OcTree");
  expectRefused(dataFile("free.bt"), PFX_ERR_DEGENERATE, "the map has no occupied voxel");
  expectRefused(dataFile("empty.bt"), PFX_ERR_DEGENERATE, "the map has no occupied voxel");
}

TEST_F(OctomapRefused, PoseThatIsNaNOrNotARotation) {
  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  PfxOctomapLoadParam nanPosition = mapPose();
  nanPosition.position.y() = nan;
  PfxOctomapLoadParam nanOrientation = mapPose();
  nanOrientation.orientation.w() = nan;
  PfxOctomapLoadParam notUnit = mapPose();
  notUnit.orientation = PfxQuat(2, 0, 0, 0);
  PfxOctomapLoadParam negativeFriction = mapPose();
  negativeFriction.friction = -0.1f;
  const std::string path = dataFile("room.bt");
  for (const PfxOctomapLoadParam& param : {nanPosition, nanOrientation, notUnit}) {
    PfxOctomap map;
    expectRefused(path, param, PFX_ERR_INVALID_VALUE, "pose must be finite with a unit orientation",
                  map);
  }
  PfxOctomap map;
  expectRefused(path, negativeFriction, PFX_ERR_INVALID_VALUE,
                "friction and restitution must be finite and not negative", map);
}

TEST_F(OctomapRefused, PrismThicknessOutsideOneVoxel) {
  for (PfxFloat thickness :
       {PfxFloat(0), PfxFloat(1), PfxFloat(-0.5f), std::numeric_limits<PfxFloat>::quiet_NaN()}) {
    PfxOctomapLoadParam param = mapPose();
    param.thicknessPerVoxel = thickness;
    PfxOctomap map;
    expectRefused(dataFile("small.bt"), param, PFX_ERR_INVALID_VALUE,
                  "thicknessPerVoxel must lie between 0 and 1", map);
  }
}

TEST_F(OctomapRefused, MapObjectThatHoldsAMapAlready) {
  PfxOctomap map;
  ASSERT_EQ(pfxLoadOctomapFile(m_world, dataFile("small.bt"), mapPose(), map), PFX_OK);
  ASSERT_EQ(m_world.getNumRigidBodies(), 2u);
  const MapSnapshot loaded(map);
  std::string message;
  EXPECT_EQ(pfxLoadOctomapFile(m_world, dataFile("room.bt"), mapPose(), map, &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(message, dataFile("room.bt") + ": the map object holds a loaded map already");
  EXPECT_EQ(m_world.getNumRigidBodies(), 2u);
  EXPECT_TRUE(MapSnapshot(map) == loaded);
}

}  // namespace
