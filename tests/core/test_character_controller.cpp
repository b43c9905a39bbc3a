// The character controller (pfx_character_controller.h) and the world's contact query it
// senses with (pfx_query_contacts.h): known answers first (a query's distance and normal,
// the step climbed and the one refused, the slope limit, a jump's height, the push force),
// then behaviour over time (stairs and slopes down, no false step at a steep ramp's foot, a
// moving platform, walls at speed, a
// large-mesh floor, characters meeting), then bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_character_controller.h"
#include "pfx_allocation_counter.h"

using namespace pfx;

namespace {

constexpr PfxFloat kDegree = PFX_PI / 180;
constexpr PfxFloat kTimeStep = PfxFloat(1) / 60;

void initWorld(PfxWorld& world) {
  PfxWorldParam param;
  param.timeStep = kTimeStep;
  ASSERT_EQ(world.initialize(param), PFX_OK);
}

PfxUInt32 addBox(PfxWorld& world, const PfxVector3& center, const PfxVector3& half,
                 PfxFloat mass = 0, const PfxQuat& orientation = PfxQuat::Identity(),
                 PfxMotionType type = kPfxMotionTypeActive) {
  PfxBodyInit init;
  init.position = center;
  init.orientation = orientation;
  init.mass = mass;
  init.motionType = type;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(half)), init, &id), PFX_OK);
  return id;
}

// A floor whose top is at height 0.
void addFloor(PfxWorld& world) { addBox(world, PfxVector3(0, -0.5f, 0), PfxVector3(50, 0.5f, 50)); }

// A ramp rising along +X at `angle`, whose top surface leaves the floor at x = `start`.
void addRamp(PfxWorld& world, PfxFloat angle, PfxFloat start, PfxFloat length) {
  const PfxVector3 along(std::cos(angle), std::sin(angle), 0);
  const PfxVector3 normal(-std::sin(angle), std::cos(angle), 0);
  const PfxFloat halfThickness = 0.25f;
  const PfxVector3 center = PfxVector3(start, 0, 0) + along * (length / 2) - normal * halfThickness;
  addBox(world, center, PfxVector3(length / 2, halfThickness, 2), 0,
         PfxQuat(Eigen::AngleAxis<PfxFloat>(angle, PfxVector3::UnitZ())));
}

PfxCharacterStatus statusOf(const PfxCharacterController& controller, PfxUInt32 id) {
  PfxCharacterStatus status;
  EXPECT_EQ(controller.getStatus(id, status), PFX_OK);
  return status;
}

// Steps the controller and the world; `each` sees every step's statuses.
template <typename Each>
void run(PfxWorld& world, PfxCharacterController& controller, PfxFloat seconds, Each each) {
  const int steps = static_cast<int>(std::lround(seconds / kTimeStep));
  for (int i = 0; i < steps; ++i) {
    ASSERT_EQ(controller.update(), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    each();
  }
}

void run(PfxWorld& world, PfxCharacterController& controller, PfxFloat seconds) {
  run(world, controller, seconds, [] {});
}

PfxCollidable sphereCollidable(PfxFloat radius) {
  PfxCollidable collidable;
  collidable.reset();
  EXPECT_EQ(collidable.addShape(pfxMakeShape(PfxSphere(radius))), PFX_OK);
  EXPECT_EQ(collidable.finish(), PFX_OK);
  return collidable;
}

// A flat square grid of triangles at height 0, `cells` by `cells` of 1 m.
struct GridMesh {
  std::vector<PfxFloat> vertices;
  std::vector<PfxUInt32> triangles;
  PfxLargeTriMesh mesh{};

  explicit GridMesh(int cells) {
    const PfxFloat half = PfxFloat(cells) / 2;
    for (int z = 0; z <= cells; ++z) {
      for (int x = 0; x <= cells; ++x) {
        vertices.insert(vertices.end(), {PfxFloat(x) - half, 0, PfxFloat(z) - half});
      }
    }
    for (int z = 0; z < cells; ++z) {
      for (int x = 0; x < cells; ++x) {
        const PfxUInt32 a = z * (cells + 1) + x, b = a + 1, c = a + cells + 1, d = c + 1;
        triangles.insert(triangles.end(), {a, c, b, b, c, d});
      }
    }
    PfxCreateLargeTriMeshParam param;
    param.m_vertices = vertices.data();
    param.m_numVertices = static_cast<PfxUInt32>(vertices.size() / 3);
    param.m_triangles = triangles.data();
    param.m_numTriangles = static_cast<PfxUInt32>(triangles.size() / 3);
    EXPECT_EQ(pfxCreateLargeTriMesh(mesh, param), PFX_OK);
  }
  ~GridMesh() { pfxReleaseLargeTriMesh(mesh); }
};

}  // namespace

// ---- The world's contact query ----

TEST(QueryContacts, SphereAboveBoxKnownDistanceAndNormal) {
  PfxWorld world;
  initWorld(world);
  const PfxUInt32 box = addBox(world, PfxVector3(0, -0.5f, 0), PfxVector3(2, 0.5f, 2));
  const PfxCollidable sphere = sphereCollidable(0.5f);
  PfxContactQueryInput query;
  query.collidable = &sphere;
  query.transform = pfxMakeTransform(PfxQuat::Identity(), PfxVector3(0.3f, 0.6f, 0));
  query.contactThreshold = 0.2f;
  PfxQueryContact out[8];
  PfxQueryContactsResult result;
  ASSERT_EQ(world.queryContacts(query, out, 8, result), PFX_OK);
  ASSERT_EQ(result.numContacts, 1u);
  EXPECT_FALSE(result.truncated);
  EXPECT_EQ(out[0].m_rigidBodyId, box);
  EXPECT_NEAR(out[0].m_contact.m_distance, 0.1f, 1e-4f);
  EXPECT_NEAR(out[0].m_contact.m_normal.y(), -1, 1e-4f);  // from the query to the body
  EXPECT_NEAR(out[0].m_contact.m_pointB.y(), 0, 1e-4f);

  // Beyond the threshold nothing; overlapping, a negative distance.
  query.contactThreshold = 0.05f;
  ASSERT_EQ(world.queryContacts(query, out, 8, result), PFX_OK);
  EXPECT_EQ(result.numContacts, 0u);
  query.transform.translation() = PfxVector3(0, 0.4f, 0);
  ASSERT_EQ(world.queryContacts(query, out, 8, result), PFX_OK);
  ASSERT_EQ(result.numContacts, 1u);
  EXPECT_NEAR(out[0].m_contact.m_distance, -0.1f, 1e-4f);

  // The ignored body and a filter that excludes it hide it.
  query.ignoreRigidBodyId = box;
  ASSERT_EQ(world.queryContacts(query, out, 8, result), PFX_OK);
  EXPECT_EQ(result.numContacts, 0u);
  query.ignoreRigidBodyId = PFX_QUERY_IGNORE_NONE;
  query.contactFilterTarget = 0;
  ASSERT_EQ(world.queryContacts(query, out, 8, result), PFX_OK);
  EXPECT_EQ(result.numContacts, 0u);
}

TEST(QueryContacts, FindsOnlyNearBodiesAmongManyAndReportsTruncation) {
  PfxWorld world;
  initWorld(world);
  for (int i = 0; i < 200; ++i) {
    addBox(world, PfxVector3(PfxFloat(i % 20) * 2, 0, PfxFloat(i / 20) * 2),
           PfxVector3(0.5f, 0.5f, 0.5f));
  }
  const PfxCollidable sphere = sphereCollidable(0.8f);
  PfxContactQueryInput query;
  query.collidable = &sphere;
  // Midway between the four boxes around (1, 0, 1): 0.914 from each box's corner edge.
  query.transform = pfxMakeTransform(PfxQuat::Identity(), PfxVector3(1, 0, 1));
  query.contactThreshold = 0.2f;
  PfxQueryContact out[16];
  PfxQueryContactsResult result;
  ASSERT_EQ(world.queryContacts(query, out, 16, result), PFX_OK);
  ASSERT_EQ(result.numContacts, 4u);
  std::vector<PfxUInt32> ids;
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) ids.push_back(out[i].m_rigidBodyId);
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<PfxUInt32>{0, 1, 20, 21}));
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
    EXPECT_NEAR(out[i].m_contact.m_distance, std::sqrt(PfxFloat(0.5)) - 0.8f + 0.0f, 1e-3f);
  }
  ASSERT_EQ(world.queryContacts(query, out, 3, result), PFX_OK);
  EXPECT_EQ(result.numContacts, 3u);
  EXPECT_TRUE(result.truncated);
}

TEST(QueryContacts, LargeMeshFloor) {
  PfxWorld world;
  initWorld(world);
  GridMesh grid(16);
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&grid.mesh);
  PfxBodyInit init;
  init.mass = 0;
  PfxUInt32 meshId = 0;
  ASSERT_EQ(pfxAddBody(world, shape, init, &meshId), PFX_OK);
  const PfxCollidable sphere = sphereCollidable(0.5f);
  PfxContactQueryInput query;
  query.collidable = &sphere;
  query.transform = pfxMakeTransform(PfxQuat::Identity(), PfxVector3(0.25f, 0.52f, 0.4f));
  query.contactThreshold = 0.05f;
  PfxQueryContact out[16];
  PfxQueryContactsResult result;
  ASSERT_EQ(world.queryContacts(query, out, 16, result), PFX_OK);
  ASSERT_GE(result.numContacts, 1u);
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
    EXPECT_EQ(out[i].m_rigidBodyId, meshId);
    EXPECT_NEAR(out[i].m_contact.m_distance, 0.02f, 1e-3f);
    EXPECT_NEAR(out[i].m_contact.m_normal.y(), -1, 1e-3f);
  }
}

TEST(QueryContacts, RejectsBadInputAndLeavesOutputUntouched) {
  PfxWorld world;
  initWorld(world);
  addBox(world, PfxVector3::Zero(), PfxVector3(1, 1, 1));
  const PfxCollidable sphere = sphereCollidable(0.5f);
  PfxCollidable empty;
  empty.reset();
  PfxContactQueryInput good;
  good.collidable = &sphere;
  good.contactThreshold = 0.1f;
  PfxQueryContact out[4];
  out[0].m_rigidBodyId = 77;
  PfxQueryContactsResult result;
  result.numContacts = 55;

  PfxContactQueryInput bad = good;
  bad.collidable = nullptr;
  EXPECT_EQ(world.queryContacts(bad, out, 4, result), PFX_ERR_INVALID_VALUE);
  bad = good;
  bad.collidable = &empty;
  EXPECT_EQ(world.queryContacts(bad, out, 4, result), PFX_ERR_INVALID_VALUE);
  bad = good;
  bad.contactThreshold = -0.1f;
  EXPECT_EQ(world.queryContacts(bad, out, 4, result), PFX_ERR_INVALID_VALUE);
  bad = good;
  bad.contactThreshold = std::nanf("");
  EXPECT_EQ(world.queryContacts(bad, out, 4, result), PFX_ERR_INVALID_VALUE);
  bad = good;
  bad.transform.translation().x() = std::numeric_limits<PfxFloat>::infinity();
  EXPECT_EQ(world.queryContacts(bad, out, 4, result), PFX_ERR_INVALID_VALUE);
  bad = good;
  bad.transform.linear() *= 2;  // not a rotation
  EXPECT_EQ(world.queryContacts(bad, out, 4, result), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.queryContacts(good, nullptr, 4, result), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(out[0].m_rigidBodyId, 77u);
  EXPECT_EQ(result.numContacts, 55u);
}

TEST(QueryContacts, LowLevelRejectsMissingArraysAndBadRange) {
  const PfxCollidable sphere = sphereCollidable(0.5f);
  PfxContactQueryInput query;
  query.collidable = &sphere;
  PfxRigidState state;
  state.reset();
  PfxCollidable collidable = sphereCollidable(1);
  PfxRayBvhNode node{};
  PfxBroadphaseProxy proxy{};
  PfxQueryContactsParam param;
  param.offsetRigidStates = &state;
  param.offsetCollidables = &collidable;
  param.bvhNodes = &node;
  param.bvhProxies = &proxy;
  param.numProxies = 1;
  PfxQueryContact out[2];
  PfxQueryContactsResult result;
  result.numContacts = 9;
  PfxQueryContactsParam bad = param;
  bad.bvhNodes = nullptr;
  EXPECT_EQ(pfxQueryContacts(query, bad, out, 2, result), PFX_ERR_NULL_POINTER);
  bad = param;
  bad.offsetRigidStates = nullptr;
  EXPECT_EQ(pfxQueryContacts(query, bad, out, 2, result), PFX_ERR_NULL_POINTER);
  bad = param;
  bad.rangeExtent = PfxVector3(1, 0, 1);
  EXPECT_EQ(pfxQueryContacts(query, bad, out, 2, result), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(result.numContacts, 9u);
  // Without proxies nothing is needed and nothing is found.
  PfxQueryContactsParam none;
  ASSERT_EQ(pfxQueryContacts(query, none, out, 2, result), PFX_OK);
  EXPECT_EQ(result.numContacts, 0u);
}

// ---- Characters ----

TEST(CharacterController, StandsStillOnTheFloor) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(1, 0, 2), &id), PFX_OK);
  run(world, controller, 2);
  const PfxCharacterStatus status = statusOf(controller, id);
  EXPECT_EQ(status.state, kPfxCharacterStanding);
  EXPECT_NEAR(status.footPosition.y(), 0, 0.01f);
  EXPECT_NEAR(status.footPosition.x(), 1, 1e-3f);
  EXPECT_NEAR(status.footPosition.z(), 2, 1e-3f);
  EXPECT_EQ(status.groundBodyId, 0u);
  EXPECT_NEAR(status.groundNormal.y(), 1, 1e-3f);
}

TEST(CharacterController, WalksAtTheDesiredVelocityAfterAcceleratingAtMaxForce) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxCharacterParam param;
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3::Zero(), &id), PFX_OK);
  run(world, controller, 0.5f);
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(3, 7, 0)), PFX_OK);  // up ignored
  // maxForce / mass = 20 m/s^2: 3 m/s after 0.15 s.
  run(world, controller, 0.1f);
  EXPECT_NEAR(statusOf(controller, id).velocity.x(), 2.0f, 0.05f);
  run(world, controller, 1.9f);
  const PfxCharacterStatus status = statusOf(controller, id);
  EXPECT_EQ(status.state, kPfxCharacterWalking);
  EXPECT_NEAR(status.velocity.x(), 3, 0.03f);
  EXPECT_NEAR(status.velocity.y(), 0, 0.03f);
  EXPECT_NEAR(status.footPosition.y(), 0, 0.01f);
}

// Steps of 0.30 m and 0.40 m in front of a character that climbs 0.35 m.
TEST(CharacterController, ClimbsAStepBelowMaxStepHeightAndNotOneAbove) {
  for (const PfxFloat rise : {0.30f, 0.40f}) {
    PfxWorld world;
    initWorld(world);
    addFloor(world);
    addBox(world, PfxVector3(3, rise / 2, 0), PfxVector3(1.5f, rise / 2, 2));
    PfxCharacterController controller(world);
    PfxCharacterParam param;
    param.maxStepHeight = 0.35f;
    PfxUInt32 id = 0;
    ASSERT_EQ(controller.addCharacter(param, PfxVector3::Zero(), &id), PFX_OK);
    ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(1.5f, 0, 0)), PFX_OK);
    run(world, controller, 2.5f);
    const PfxCharacterStatus status = statusOf(controller, id);
    std::printf("maxStepHeight %.2f m, step %.2f m: foot at x %.3f, y %.3f m, %u steps\n",
                double(param.maxStepHeight), double(rise), double(status.footPosition.x()),
                double(status.footPosition.y()), status.numSteps);
    if (rise < param.maxStepHeight) {
      EXPECT_NEAR(status.footPosition.y(), rise, 0.01f) << "rise " << rise;
      EXPECT_GT(status.footPosition.x(), 2.0f);
      EXPECT_EQ(status.numSteps, 1u);
    } else {
      EXPECT_NEAR(status.footPosition.y(), 0, 0.01f) << "rise " << rise;
      EXPECT_NEAR(status.footPosition.x(), 1.5f - param.radius, 0.02f);
      EXPECT_EQ(status.numSteps, 0u);
    }
    EXPECT_EQ(status.state, kPfxCharacterWalking);
  }
}

// With maxSlope 30 and 45 degrees: a ramp one degree less steep is walked up, one a degree
// steeper is not.
TEST(CharacterController, SlopeLimitWithinOneDegree) {
  for (const PfxFloat limit : {30.0f, 45.0f}) {
    for (const PfxFloat slope : {limit - 1, limit + 1}) {
      PfxWorld world;
      initWorld(world);
      addFloor(world);
      addRamp(world, slope * kDegree, 1, 8);
      PfxCharacterController controller(world);
      PfxCharacterParam param;
      param.maxSlope = limit * kDegree;
      param.maxStepHeight = 0.1f;
      PfxUInt32 id = 0;
      ASSERT_EQ(controller.addCharacter(param, PfxVector3::Zero(), &id), PFX_OK);
      ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(2, 0, 0)), PFX_OK);
      PfxFloat highest = 0;
      run(world, controller, 3,
          [&] { highest = std::max(highest, statusOf(controller, id).footPosition.y()); });
      const PfxCharacterStatus status = statusOf(controller, id);
      std::printf("maxSlope %.0f deg, ramp %.0f deg: highest foot %.3f m\n", double(limit),
                  double(slope), double(highest));
      if (slope < limit) {
        // 2 m/s for 2.5 s up the ramp: well over 1.5 m high.
        EXPECT_GT(status.footPosition.y(), 1.5f) << "slope " << slope;
        EXPECT_EQ(status.state, kPfxCharacterWalking);
      } else {
        EXPECT_LT(highest, 0.15f) << "slope " << slope;
        EXPECT_LT(status.footPosition.x(), 1.2f);
      }
    }
  }
}

TEST(CharacterController, SlidesDownASteepSlope) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  addRamp(world, 50 * kDegree, 0, 8);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  // Dropped onto the ramp 2 m up its surface.
  const PfxVector3 onRamp =
      PfxVector3(std::cos(50 * kDegree), std::sin(50 * kDegree), 0) * 2 + PfxVector3(0, 0.3f, 0);
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), onRamp, &id), PFX_OK);
  // Walking up it does not help.
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(2, 0, 0)), PFX_OK);
  bool slid = false;
  run(world, controller, 3,
      [&] { slid = slid || statusOf(controller, id).state == kPfxCharacterSliding; });
  EXPECT_TRUE(slid);
  EXPECT_LT(statusOf(controller, id).footPosition.y(), 0.05f);
}

// Walking into the foot of a ramp too steep to climb with the foot 4 mm deep in the floor,
// which the world leaves as it is (within its contact slop, 5 mm) and which a crowd pressing
// on a character brings about: the floor under the foot is no step to climb (taking it
// for one moved the capsule a radius forward, 0.19 m into the ramp, in the characters
// benchmark), so the character stays out of the ramp.
TEST(CharacterController, TakesNoStepOntoItsOwnFloorAtASteepRampsFoot) {
  PfxWorld world;
  PfxWorldParam worldParam;
  worldParam.timeStep = PfxFloat(1) / 30;
  ASSERT_EQ(world.initialize(worldParam), PFX_OK);
  addFloor(world);
  const PfxFloat angle = 50 * kDegree;
  addRamp(world, angle, 0, 4);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  const PfxCharacterParam param;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(-1, -0.004f, 0), &id), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(3, 0, 0)), PFX_OK);
  // How deep the capsule's lower half sphere is in the ramp's top face.
  const PfxVector3 normal(-std::sin(angle), std::cos(angle), 0);
  PfxFloat deepest = 0;
  for (int i = 0; i < 90; ++i) {
    ASSERT_EQ(controller.update(), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxVector3 center =
        statusOf(controller, id).footPosition + PfxVector3(0, param.radius, 0);
    deepest = std::max(deepest, param.radius - normal.dot(center));
  }
  std::printf("deepest in the ramp %.4f m, %u steps climbed\n", double(deepest),
              statusOf(controller, id).numSteps);
  EXPECT_EQ(statusOf(controller, id).numSteps, 0u);
  EXPECT_LT(deepest, 0.02f);
}

// Walking off the side of a 0.3 m step (a staircase's side, in the characters benchmark),
// not over its front edge: the snap down to the floor must not drive the capsule into the
// step's side face, which the rim holds it above until it has slid off (it went 5.8 cm in).
TEST(CharacterController, WalksOffTheSideOfAStepWithoutSinkingIntoIt) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  const PfxVector3 stepCenter(0, 0.15f, -1), stepHalf(3, 0.15f, 1);  // its side at z = 0
  addBox(world, stepCenter, stepHalf);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  const PfxCharacterParam param;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(-2, 0.3f, -0.4f), &id), PFX_OK);
  run(world, controller, 0.3f);
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(1.5f, 0, 0.4f)), PFX_OK);
  // The capsule's overlap with the step: its radius less the distance from its axis
  // (sampled every 5 cm) to the box.
  const auto overlap = [&](const PfxVector3& foot) {
    PfxFloat nearest = 1e9f;
    for (PfxFloat up = param.radius; up <= param.height - param.radius; up += 0.05f) {
      const PfxVector3 d =
          ((foot + PfxVector3(0, up, 0) - stepCenter).cwiseAbs() - stepHalf).eval();
      nearest = std::min(nearest, d.cwiseMax(0).norm() + std::min(d.maxCoeff(), PfxFloat(0)));
    }
    return std::max(PfxFloat(0), param.radius - nearest);
  };
  PfxFloat deepest = 0;
  run(world, controller, 2.5f,
      [&] { deepest = std::max(deepest, overlap(statusOf(controller, id).footPosition)); });
  const PfxCharacterStatus status = statusOf(controller, id);
  std::printf("deepest in the step's side %.4f m; foot at z %.2f, y %.3f\n", double(deepest),
              double(status.footPosition.z()), double(status.footPosition.y()));
  EXPECT_GT(status.footPosition.z(), param.radius);  // off the step
  EXPECT_NEAR(status.footPosition.y(), 0, 0.01f);    // on the floor
  EXPECT_LT(deepest, 0.02f);
}

TEST(CharacterController, StaysOnTheGroundDownStairsAndSlopes) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  // Five steps of 0.25 m down along +X from a landing 1.5 m high; further on, a 25 degree
  // ramp rising along +X from x = 10, walked down from 3 m up.
  addBox(world, PfxVector3(-1, 0.75f, 0), PfxVector3(1, 0.75f, 2));
  for (int i = 0; i < 5; ++i) {
    const PfxFloat top = 1.25f - 0.25f * PfxFloat(i);
    addBox(world, PfxVector3(0.2f + 0.4f * PfxFloat(i), top / 2, 0), PfxVector3(0.2f, top / 2, 2));
  }
  const PfxFloat slope = 25 * kDegree;
  addRamp(world, slope, 10, 8);
  PfxCharacterController controller(world);
  PfxUInt32 stairs = 0, ramp = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(-1.5f, 1.5f, 0), &stairs),
            PFX_OK);
  ASSERT_EQ(
      controller.addCharacter(PfxCharacterParam(),
                              PfxVector3(10 + 7 * std::cos(slope), 7 * std::sin(slope), 0), &ramp),
      PFX_OK);
  run(world, controller, 0.5f);
  ASSERT_EQ(controller.setDesiredVelocity(stairs, PfxVector3(1.5f, 0, 0)), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(ramp, PfxVector3(-1.5f, 0, 0)), PFX_OK);
  int airborne = 0;
  PfxFloat furthestFromRamp = 0;
  run(world, controller, 3, [&] {
    for (const PfxUInt32 id : {stairs, ramp}) {
      if (statusOf(controller, id).groundBodyId == PFX_CHARACTER_NO_GROUND) ++airborne;
    }
    const PfxVector3 foot = statusOf(controller, ramp).footPosition;
    furthestFromRamp =
        std::max(furthestFromRamp, std::abs(foot.y() - (foot.x() - 10) * std::tan(slope)));
  });
  EXPECT_EQ(airborne, 0);
  const PfxCharacterStatus status = statusOf(controller, stairs);
  EXPECT_GT(status.footPosition.x(), 2.5f);
  EXPECT_NEAR(status.footPosition.y(), 0, 0.01f);
  EXPECT_LT(statusOf(controller, ramp).footPosition.x(), 12.5f);
  // The capsule's round foot touches the ramp beside its lowest point: up to
  // radius (1 / cos - 1) = 3 cm above the surface below it.
  EXPECT_LT(furthestFromRamp, 0.04f);
}

TEST(CharacterController, JumpsToTheHeightOfItsJumpSpeed) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxCharacterParam param;
  param.jumpSpeed = 5;
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3::Zero(), &id), PFX_OK);
  run(world, controller, 0.5f);
  ASSERT_EQ(controller.requestJump(id), PFX_OK);
  PfxFloat highest = 0;
  std::vector<PfxCharacterState> states;
  run(world, controller, 2, [&] {
    const PfxCharacterStatus status = statusOf(controller, id);
    highest = std::max(highest, status.footPosition.y());
    if (states.empty() || states.back() != status.state) states.push_back(status.state);
  });
  // v^2 / 2g = 1.275 m; the discrete step loses about v dt / 2.
  const PfxFloat expected = 25 / (2 * 9.80665f);
  std::printf("jump at 5 m/s: highest foot %.3f m, v^2/2g %.3f m\n", double(highest),
              double(expected));
  EXPECT_NEAR(highest, expected, 0.05f);
  EXPECT_EQ(states, (std::vector<PfxCharacterState>{kPfxCharacterJumping, kPfxCharacterFalling,
                                                    kPfxCharacterLanding, kPfxCharacterStanding}));
}

// A keyframe platform starts at once to move at 1 m/s, bob and turn at 0.5 rad/s, under a
// character standing on it 1 m from its centre. The feet take the platform's sudden speed
// (1.118 m/s there) at maxForce / mass = 20 m/s^2, slipping |v|^2 / 2a - |v| dt / 2 = 2.2 cm
// over the first three steps; from then on the character rides where it stands.
TEST(CharacterController, RidesAMovingTurningPlatformWithoutSlipping) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  const PfxUInt32 platform = addBox(world, PfxVector3(0, 0.2f, 0), PfxVector3(2, 0.2f, 2), 100,
                                    PfxQuat::Identity(), kPfxMotionTypeKeyframe);
  PfxCharacterController controller(world);
  PfxCharacterParam param;
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(1, 0.4f, 0), &id), PFX_OK);
  run(world, controller, 0.5f);
  const auto inPlatformFrame = [&] {
    return PfxVector3(world.getRigidState(platform).getTransform().inverse() *
                      statusOf(controller, id).footPosition);
  };
  const PfxVector3 start = inPlatformFrame();
  PfxVector3 caughtUp = start;
  const PfxFloat seconds = 5;
  const int steps = static_cast<int>(seconds / kTimeStep);
  const int catchUpSteps = 3;
  PfxFloat time = 0;
  for (int i = 0; i < steps + catchUpSteps; ++i) {
    time += kTimeStep;
    const PfxVector3 position(time, 0.2f + 0.1f * std::sin(time), 0);
    const PfxQuat orientation(Eigen::AngleAxis<PfxFloat>(0.5f * time, PfxVector3::UnitY()));
    ASSERT_EQ(world.setKeyframeTarget(platform, position, orientation), PFX_OK);
    ASSERT_EQ(controller.update(), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    if (i + 1 == catchUpSteps) caughtUp = inPlatformFrame();
  }
  const PfxFloat speed = std::sqrt(PfxFloat(1.25));
  const PfxFloat acceleration = param.maxForce / param.mass;
  const PfxFloat expectedStartSlip = speed * speed / (2 * acceleration) - speed * kTimeStep / 2;
  const PfxFloat startSlip = (caughtUp - start).norm();
  const PfxFloat slip = (inPlatformFrame() - caughtUp).norm();
  std::printf(
      "platform starting at 1 m/s and 0.5 rad/s: slip %.4f m over the first %d steps "
      "(expected %.4f m), then %.2e m in %.0f s (%.2e m/s)\n",
      double(startSlip), catchUpSteps, double(expectedStartSlip), double(slip), double(seconds),
      double(slip / seconds));
  EXPECT_NEAR(startSlip, expectedStartSlip, 0.002f);
  EXPECT_LT(slip, 0.001f);  // 0.2 mm/s, against the 1 cm/s asked of it
  EXPECT_EQ(statusOf(controller, id).groundBodyId, platform);
  EXPECT_EQ(statusOf(controller, id).state, kPfxCharacterStanding);
}

// The push force: against a box that friction holds (200 kg, 0.6: 1177 N) a character of
// maxForce 500 N pushes with 500 N once the bump of its arrival is over (that one impulse is
// bounded by its momentum, 80 kg at 1 m/s), and the box stays; a 10 kg box it pushes along.
TEST(CharacterController, PushesWithAtMostMaxForce) {
  for (const PfxFloat boxMass : {200.0f, 10.0f}) {
    PfxWorld world;
    initWorld(world);
    addFloor(world);
    const PfxUInt32 box =
        addBox(world, PfxVector3(1.5f, 0.5f, 0), PfxVector3(0.5f, 0.5f, 0.5f), boxMass);
    PfxCharacterController controller(world);
    PfxCharacterParam param;
    param.maxForce = 500;
    PfxUInt32 id = 0;
    ASSERT_EQ(controller.addCharacter(param, PfxVector3::Zero(), &id), PFX_OK);
    ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(1, 0, 0)), PFX_OK);
    const PfxUInt32 body = statusOf(controller, id).rigidBodyId;
    PfxFloat largestImpulse = 0, largestForce = 0;
    double forceSum = 0;
    int forceSteps = 0, step = 0;
    run(world, controller, 3, [&] {
      ++step;
      for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
        const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(i));
        const bool ours =
            (manifold.getRigidBodyIdA() == body && manifold.getRigidBodyIdB() == box) ||
            (manifold.getRigidBodyIdA() == box && manifold.getRigidBodyIdB() == body);
        if (!ours) continue;
        PfxFloat impulse = 0;
        for (PfxUInt32 p = 0; p < manifold.getNumContacts(); ++p) {
          impulse += manifold.getContactPoint(p).m_constraintRow[0].m_accumImpulse;
        }
        largestImpulse = std::max(largestImpulse, impulse);
        if (step * kTimeStep < 1.5f) continue;  // arrives at about 0.8 s
        largestForce = std::max(largestForce, impulse / kTimeStep);
        forceSum += impulse / kTimeStep;
        ++forceSteps;
      }
    });
    const PfxFloat boxMoved = world.getRigidState(box).getPosition().x() - 1.5f;
    std::printf(
        "maxForce %.0f N against a %.0f kg box: arrival impulse %.1f N s, then force "
        "mean %.1f N, largest %.1f N; box moved %.3f m\n",
        double(param.maxForce), double(boxMass), double(largestImpulse),
        forceSteps > 0 ? forceSum / forceSteps : 0.0, double(largestForce), double(boxMoved));
    EXPECT_LT(largestImpulse, param.mass * 1.0f * 1.05f) << "box " << boxMass;
    if (boxMass > 100) {
      EXPECT_LT(largestForce, param.maxForce * 1.02f);
      ASSERT_GT(forceSteps, 60);
      EXPECT_NEAR(forceSum / forceSteps, param.maxForce, param.maxForce * 0.02f);
      EXPECT_LT(boxMoved, 0.02f);
    } else {
      EXPECT_GT(boxMoved, 1.0f);
    }
  }
}

TEST(CharacterController, IsPushedByAHeavierPushAndBlocksAnEqualOne) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxCharacterParam strong;
  strong.maxForce = 3000;
  PfxCharacterParam weak;
  weak.maxForce = 800;
  PfxUInt32 pusher = 0, pushed = 0, left = 0, right = 0;
  ASSERT_EQ(controller.addCharacter(strong, PfxVector3(0, 0, 0), &pusher), PFX_OK);
  ASSERT_EQ(controller.addCharacter(weak, PfxVector3(1, 0, 0), &pushed), PFX_OK);
  ASSERT_EQ(controller.addCharacter(weak, PfxVector3(0, 0, 5), &left), PFX_OK);
  ASSERT_EQ(controller.addCharacter(weak, PfxVector3(2, 0, 5), &right), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(pusher, PfxVector3(1, 0, 0)), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(left, PfxVector3(1, 0, 0)), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(right, PfxVector3(-1, 0, 0)), PFX_OK);
  PfxFloat closest = 10;
  run(world, controller, 3, [&] {
    closest = std::min(closest, (statusOf(controller, right).footPosition -
                                 statusOf(controller, left).footPosition)
                                    .norm());
  });
  EXPECT_GT(statusOf(controller, pushed).footPosition.x(), 2.0f);
  // The two equal ones meet in the middle and hold each other there.
  EXPECT_GT(closest, 2 * weak.radius - 0.02f);
  EXPECT_NEAR(statusOf(controller, left).footPosition.x(), 1 - weak.radius, 0.02f);
  EXPECT_NEAR(statusOf(controller, right).footPosition.x(), 1 + weak.radius, 0.02f);
}

// A 100 kg box sliding at 4 m/s on ice into a standing 80 kg character: they go on together
// at 400 / 180 = 2.22 m/s, and the character's 1600 N brings both to rest at 8.9 m/s^2,
// after 2.22^2 / (2 * 8.9) = 0.28 m.
TEST(CharacterController, IsPushedByAHeavyBodyThatHitsIt) {
  PfxWorld world;
  initWorld(world);
  PfxBodyInit ice;
  ice.mass = 0;
  ice.friction = 0;
  ice.position = PfxVector3(0, -0.5f, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(50, 0.5f, 50)), ice), PFX_OK);
  PfxBodyInit sled;
  sled.mass = 100;
  sled.friction = 0;
  sled.position = PfxVector3(-3, 0.5f, 0);
  sled.linearVelocity = PfxVector3(4, 0, 0);
  PfxUInt32 box = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), sled, &box), PFX_OK);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3::Zero(), &id), PFX_OK);
  run(world, controller, 1.5f);
  const PfxCharacterStatus status = statusOf(controller, id);
  std::printf("hit by a 100 kg box at 4 m/s: shoved %.2f m, box slowed to %.2f m/s\n",
              double(status.footPosition.x()),
              double(world.getRigidState(box).getLinearVelocity().x()));
  const PfxFloat together = 400.0f / 180;
  EXPECT_NEAR(status.footPosition.x(), together * together / (2 * 1600 / 180.0f), 0.04f);
  EXPECT_NEAR(world.getRigidState(box).getLinearVelocity().x(), 0, 0.05f);
  // Neither passed through the other.
  EXPECT_GT(status.footPosition.x() - world.getRigidState(box).getPosition().x(), 0.8f - 0.02f);
}

TEST(CharacterController, NeverPassesThroughAThinWallOrFloorAtItsTopSpeeds) {
  PfxWorld world;
  initWorld(world);
  // A floor and a wall 2 cm thick; the walker has 43 m to reach its top speed.
  addBox(world, PfxVector3(0, -0.01f, 0), PfxVector3(50, 0.01f, 20));
  addBox(world, PfxVector3(3, 1, 0), PfxVector3(0.01f, 1, 3));
  PfxCharacterController controller(world);
  PfxCharacterParam param;
  param.maxSpeed = 30;
  param.maxFallSpeed = 60;
  PfxUInt32 walker = 0, faller = 0;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(-40, 0, 0), &walker), PFX_OK);
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(-10, 300, 0), &faller), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(walker, PfxVector3(30, 0, 0)), PFX_OK);
  PfxFloat fastestFall = 0, fastestWalk = 0, lowest = 300;
  run(world, controller, 9, [&] {
    const PfxCharacterStatus walk = statusOf(controller, walker);
    const PfxCharacterStatus fall = statusOf(controller, faller);
    fastestWalk = std::max(fastestWalk, walk.velocity.x());
    fastestFall = std::max(fastestFall, -fall.velocity.y());
    lowest = std::min(lowest, fall.footPosition.y());
    ASSERT_LT(walk.footPosition.x(), 3 - 0.01f - param.radius + 0.01f);
  });
  EXPECT_GT(fastestWalk, 25.0f);
  EXPECT_NEAR(fastestFall, param.maxFallSpeed, 1.0f);
  EXPECT_GT(lowest, -0.01f);
  EXPECT_NEAR(statusOf(controller, faller).footPosition.y(), 0, 0.01f);
}

TEST(CharacterController, WalksOnAndLandsOnALargeMesh) {
  PfxWorld world;
  initWorld(world);
  GridMesh grid(40);
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&grid.mesh);
  PfxBodyInit init;
  init.mass = 0;
  PfxUInt32 meshId = 0;
  ASSERT_EQ(pfxAddBody(world, shape, init, &meshId), PFX_OK);
  PfxCharacterController controller(world);
  PfxCharacterParam param;
  param.maxFallSpeed = 60;
  PfxUInt32 walker = 0, faller = 0;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(-15, 0, 0.3f), &walker), PFX_OK);
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(5.3f, 250, 5.7f), &faller), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(walker, PfxVector3(4, 0, 0)), PFX_OK);
  PfxFloat lowest = 1000, fastestFall = 0;
  run(world, controller, 8, [&] {
    lowest = std::min({lowest, statusOf(controller, walker).footPosition.y(),
                       statusOf(controller, faller).footPosition.y()});
    fastestFall = std::max(fastestFall, -statusOf(controller, faller).velocity.y());
  });
  EXPECT_GT(fastestFall, 55.0f);
  EXPECT_GT(lowest, -0.02f);
  EXPECT_GT(statusOf(controller, walker).footPosition.x(), 15.0f);
  EXPECT_EQ(statusOf(controller, walker).groundBodyId, meshId);
  EXPECT_NEAR(statusOf(controller, faller).footPosition.y(), 0, 0.01f);
  EXPECT_EQ(statusOf(controller, faller).groundBodyId, meshId);
}

// The same grid stood up as a wall (the body turned a quarter about Z), run into at 30 m/s.
TEST(CharacterController, NeverPassesThroughALargeMeshWall) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  GridMesh grid(40);
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&grid.mesh);
  PfxBodyInit init;
  init.mass = 0;
  init.position = PfxVector3(3, 0, 0);
  init.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitZ()));
  ASSERT_EQ(pfxAddBody(world, shape, init), PFX_OK);
  PfxCharacterController controller(world);
  PfxCharacterParam param;
  param.maxSpeed = 30;
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(param, PfxVector3(-40, 0, 0.5f), &id), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(30, 0, 0)), PFX_OK);
  PfxFloat fastest = 0, furthest = -40;
  run(world, controller, 3, [&] {
    fastest = std::max(fastest, statusOf(controller, id).velocity.x());
    furthest = std::max(furthest, statusOf(controller, id).footPosition.x());
  });
  EXPECT_GT(fastest, 25.0f);
  EXPECT_LT(furthest, 3 - param.radius + 0.01f);
  EXPECT_GT(furthest, 3 - param.radius - 0.05f);
}

// A trigger box across the way and under the feet neither blocks nor holds a character.
TEST(CharacterController, WalksThroughTriggers) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  addBox(world, PfxVector3(2, 1, 0), PfxVector3(0.5f, 1, 2), 1, PfxQuat::Identity(),
         kPfxMotionTypeTrigger);
  PfxCharacterController controller(world);
  PfxUInt32 walker = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3::Zero(), &walker), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(walker, PfxVector3(2, 0, 0)), PFX_OK);
  run(world, controller, 2.5f);
  const PfxCharacterStatus status = statusOf(controller, walker);
  EXPECT_GT(status.footPosition.x(), 4.0f);
  EXPECT_NEAR(status.footPosition.y(), 0, 0.01f);
  EXPECT_EQ(status.numSteps, 0u);
  EXPECT_EQ(status.groundBodyId, 0u);
}

TEST(CharacterController, IsABodyThatRaysAndContactsSee) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(0, 0, 0), &id), PFX_OK);
  const PfxUInt32 body = statusOf(controller, id).rigidBodyId;
  // A box dropped on its head lands there.
  const PfxUInt32 box = addBox(world, PfxVector3(0, 2.5f, 0), PfxVector3(0.2f, 0.2f, 0.2f), 5);
  run(world, controller, 1);
  EXPECT_NEAR(world.getRigidState(box).getPosition().y(), 1.8f + 0.2f, 0.02f);
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = PfxVector3(-3, 1, 0);
  ray.m_direction = PfxVector3(6, 0, 0);
  PfxRayOutput hit;
  ASSERT_EQ(world.castRay(ray, hit), PFX_OK);
  ASSERT_TRUE(hit.m_contactFlag);
  EXPECT_EQ(hit.m_objectId, body);
  EXPECT_NEAR(hit.m_contactPoint.x(), -0.3f, 1e-3f);
}

// Twenty characters walking into each other, over a step and into loose boxes: after the
// first update (the world's query hierarchy is sized then) the controller allocates nothing.
// The world's own step may, while it meets more pairs than before.
TEST(CharacterController, UpdateAllocatesNothing) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  addBox(world, PfxVector3(0, 0.1f, 0), PfxVector3(1, 0.1f, 4));
  for (int i = 0; i < 5; ++i) {
    addBox(world, PfxVector3(2, 0.25f, PfxFloat(i) - 2), PfxVector3(0.25f, 0.25f, 0.25f), 10);
  }
  PfxCharacterController controller(world);
  for (int i = 0; i < 20; ++i) {
    const PfxFloat side = i % 2 == 0 ? -1 : 1;
    PfxUInt32 id = 0;
    ASSERT_EQ(controller.addCharacter(PfxCharacterParam(),
                                      PfxVector3(4 * side, 0, PfxFloat(i / 2) * 0.7f - 3), &id),
              PFX_OK);
    ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(-side, 0, 0)), PFX_OK);
  }
  ASSERT_EQ(controller.update(), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  long allocations = 0;
  for (int i = 0; i < 240; ++i) {
    const long before = pfx_test::pfxAllocationCount();
    ASSERT_EQ(controller.update(), PFX_OK);
    allocations += pfx_test::pfxAllocationCount() - before;
    ASSERT_EQ(world.step(), PFX_OK);
  }
  EXPECT_EQ(allocations, 0);
}

TEST(CharacterController, RemovedCharactersVanishWithTheirBodies) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxUInt32 first = 0, second = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(0, 0, 0), &first), PFX_OK);
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(2, 0, 0), &second), PFX_OK);
  run(world, controller, 0.2f);
  const PfxUInt32 body = statusOf(controller, first).rigidBodyId;
  ASSERT_EQ(controller.removeCharacter(first), PFX_OK);
  EXPECT_FALSE(controller.isCharacter(first));
  EXPECT_EQ(controller.getNumCharacters(), 1u);
  PfxCharacterStatus status;
  EXPECT_EQ(controller.getStatus(first, status), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(controller.removeCharacter(first), PFX_ERR_OUT_OF_RANGE);
  // The second walks through where the first stood.
  ASSERT_EQ(controller.setDesiredVelocity(second, PfxVector3(-2, 0, 0)), PFX_OK);
  run(world, controller, 2);
  EXPECT_LT(statusOf(controller, second).footPosition.x(), -1.0f);
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = PfxVector3(0, 5, 0);
  ray.m_direction = PfxVector3(0, -10, 0);
  PfxRayOutput hit;
  ASSERT_EQ(world.castRay(ray, hit), PFX_OK);
  EXPECT_EQ(hit.m_objectId, 0u);  // the floor, not the removed body
  EXPECT_FALSE(world.hasRigidBody(body));
  // The next character takes the free id and a new body.
  PfxUInt32 third = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(3, 0, 3), &third), PFX_OK);
  EXPECT_EQ(third, first);
  EXPECT_NE(statusOf(controller, third).rigidBodyId, body);
  EXPECT_TRUE(world.hasRigidBody(statusOf(controller, third).rigidBodyId));
  run(world, controller, 0.5f);
  EXPECT_NEAR(statusOf(controller, third).footPosition.x(), 3, 1e-3f);
  EXPECT_EQ(statusOf(controller, third).state, kPfxCharacterStanding);
}

TEST(CharacterController, RejectsBadInputAndChangesNothing) {
  PfxWorld world;
  initWorld(world);
  addFloor(world);
  PfxCharacterController controller(world);
  PfxUInt32 id = 0;
  ASSERT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3::Zero(), &id), PFX_OK);
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(1, 0, 0)), PFX_OK);
  const PfxUInt32 numBodies = world.getNumRigidBodies();

  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  const PfxFloat inf = std::numeric_limits<PfxFloat>::infinity();
  EXPECT_EQ(controller.setDesiredVelocity(id, PfxVector3(nan, 0, 0)), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(controller.setDesiredVelocity(id, PfxVector3(0, 0, inf)), PFX_ERR_INVALID_VALUE);

  const auto rejected = [&](void (*spoil)(PfxCharacterParam&)) {
    PfxCharacterParam param;
    spoil(param);
    PfxUInt32 newId = 99;
    const PfxInt32 err = controller.addCharacter(param, PfxVector3(3, 0, 0), &newId);
    EXPECT_EQ(newId, 99u);
    return err;
  };
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.radius = -0.3f; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.height = -1; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.height = 0.5f; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.mass = 0; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.maxStepHeight = -0.1f; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.maxStepHeight = 1.5f; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.maxSlope = PFX_PI / 2; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.maxForce = std::nanf(""); }),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.airControl = 1.5f; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(rejected([](PfxCharacterParam& p) { p.groundProbe = 0; }), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(controller.addCharacter(PfxCharacterParam(), PfxVector3(nan, 0, 0)),
            PFX_ERR_INVALID_VALUE);

  const PfxUInt32 unknown = id + 1;
  PfxCharacterStatus status;
  status.numSteps = 42;
  EXPECT_EQ(controller.setDesiredVelocity(unknown, PfxVector3(1, 0, 0)), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(controller.requestJump(unknown), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(controller.removeCharacter(unknown), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(controller.getStatus(unknown, status), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(status.numSteps, 42u);
  PfxCharacterParam param;
  param.mass = 1;
  EXPECT_EQ(controller.getParam(unknown, param), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(param.mass, 1);

  EXPECT_EQ(world.getNumRigidBodies(), numBodies);
  EXPECT_EQ(controller.getNumCharacters(), 1u);
  // The rejected velocities left the last good one in force.
  run(world, controller, 2);
  EXPECT_NEAR(statusOf(controller, id).velocity.x(), 1, 0.02f);
  // A finite velocity, however large, is accepted and cut to maxSpeed.
  ASSERT_EQ(controller.setDesiredVelocity(id, PfxVector3(-3e38f, 0, 3e38f)), PFX_OK);
  run(world, controller, 2);
  const PfxFloat maxSpeed = PfxCharacterParam().maxSpeed;
  EXPECT_NEAR(statusOf(controller, id).velocity.x(), -maxSpeed / std::sqrt(PfxFloat(2)), 0.05f);
  EXPECT_NEAR(statusOf(controller, id).velocity.z(), maxSpeed / std::sqrt(PfxFloat(2)), 0.05f);
}
