// Broad phase: proxies from bodies, sort and sweep for pairs, and the split of pairs into
// new, kept and removed against the last frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <vector>

#include "pfx/low_level/broadphase/pfx_decompose_pairs.h"
#include "pfx/low_level/broadphase/pfx_find_pairs.h"
#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"
#include "pfx/base_level/task/pfx_tbb_task_manager.h"

namespace pfx {
namespace {

constexpr PfxFloat kNaN = std::numeric_limits<PfxFloat>::quiet_NaN();

struct Scene {
  std::vector<PfxRigidState> states;
  std::vector<PfxCollidable> collidables;
};

struct BodyDesc {
  PfxUInt32 id = 0;
  PfxVector3 position = PfxVector3::Zero();
  PfxVector3 half = PfxVector3::Constant(0.5f);
  PfxMotionType type = kPfxMotionTypeActive;
  bool asleep = false;
  PfxUInt32 self = 0xffffffffu;
  PfxUInt32 target = 0xffffffffu;
  PfxQuat orientation = PfxQuat::Identity();
  PfxVector3 velocity = PfxVector3::Zero();
};

void addBody(Scene& scene, const BodyDesc& d) {
  PfxRigidState state;
  state.reset();
  state.setPosition(d.position);
  state.setOrientation(d.orientation);
  state.setLinearVelocity(d.velocity);
  state.setRigidBodyId(d.id);
  state.setMotionType(d.type);
  state.setContactFilterSelf(d.self);
  state.setContactFilterTarget(d.target);
  if (d.asleep) state.sleep();
  PfxCollidable collidable;
  collidable.reset();
  PfxShape shape;
  shape.reset();
  shape.setBox(PfxBox(d.half));
  EXPECT_EQ(PFX_OK, collidable.addShape(shape));
  EXPECT_EQ(PFX_OK, collidable.finish());
  scene.states.push_back(state);
  scene.collidables.push_back(collidable);
}

template <class T>
bool sameBytes(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

template <class T>
void fillPattern(std::vector<T>& v) {
  std::memset(static_cast<void*>(v.data()), 0xab, v.size() * sizeof(T));
}

// Field by field: a rejected call must not touch any of them (padding is not compared).
bool sameStates(const std::vector<PfxRigidState>& a, const std::vector<PfxRigidState>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const PfxRigidState& x = a[i];
    const PfxRigidState& y = b[i];
    const bool same =
        sameBytes(x.getPosition(), y.getPosition()) &&
        sameBytes(x.getOrientation().coeffs(), y.getOrientation().coeffs()) &&
        sameBytes(x.getLinearVelocity(), y.getLinearVelocity()) &&
        sameBytes(x.getAngularVelocity(), y.getAngularVelocity()) &&
        x.getMotionType() == y.getMotionType() && x.getRigidBodyId() == y.getRigidBodyId() &&
        x.getContactFilterSelf() == y.getContactFilterSelf() &&
        x.getContactFilterTarget() == y.getContactFilterTarget() &&
        x.isAsleep() == y.isAsleep() && x.getSleepCount() == y.getSleepCount();
    if (!same) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// pfxUpdateBroadphaseProxy

// World [-10, 10] on every axis: one quantization step is 20 / 65535 m, so a coordinate x
// maps to (x + 10) * 3276.75 cells.
const PfxVector3 kSmallWorldCenter = PfxVector3::Zero();
const PfxVector3 kSmallWorldExtent = PfxVector3::Constant(10);

TEST(UpdateBroadphaseProxy, KnownAnswerForAxisAlignedBox) {
  Scene scene;
  BodyDesc d;
  d.id = 77;
  d.position = PfxVector3(1, 2, 3);
  d.type = kPfxMotionTypeKeyframe;
  d.asleep = true;
  d.self = 0x5;
  d.target = 0x9;
  addBody(scene, d);
  PfxBroadphaseProxy proxy;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxy(proxy, scene.states[0], scene.collidables[0],
                                             kSmallWorldCenter, kSmallWorldExtent, 1));
  // x in [0.5, 1.5]: 10.5 * 3276.75 = 34405.875 -> floor 34405; 11.5 * 3276.75 = 37682.625
  // -> ceil 37683. y in [1.5, 2.5]: 37682.625 -> 37682; 12.5 * 3276.75 = 40959.375 -> 40960.
  // z in [2.5, 3.5]: 40959.375 -> 40959; 13.5 * 3276.75 = 44236.125 -> 44237.
  EXPECT_EQ(34405, pfxGetXMin(proxy, 0));
  EXPECT_EQ(37683, pfxGetXMax(proxy, 0));
  EXPECT_EQ(37682, pfxGetXMin(proxy, 1));
  EXPECT_EQ(40960, pfxGetXMax(proxy, 1));
  EXPECT_EQ(40959, pfxGetXMin(proxy, 2));
  EXPECT_EQ(44237, pfxGetXMax(proxy, 2));
  EXPECT_EQ(37682, pfxGetSortValue(proxy));  // minimum along the requested axis (Y)
  EXPECT_EQ(77u, pfxGetObjectId(proxy));
  EXPECT_EQ(kPfxMotionTypeKeyframe, pfxGetMotionType(proxy));
  EXPECT_TRUE(pfxGetSleeping(proxy));
  EXPECT_EQ(0x5u, pfxGetSelf(proxy));
  EXPECT_EQ(0x9u, pfxGetTarget(proxy));
}

TEST(UpdateBroadphaseProxy, QuantizationIsConservativeAndTight) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<PfxFloat> pos(-70, 70);  // boxes stay inside the world
  std::uniform_real_distribution<PfxFloat> size(0.01f, 6);
  std::uniform_real_distribution<PfxFloat> unit(-1, 1);
  const PfxVector3 worldCenter(5, -3, 2);
  const PfxVector3 worldExtent(100, 120, 90);
  for (int trial = 0; trial < 2000; ++trial) {
    Scene scene;
    BodyDesc d;
    d.position = PfxVector3{pos(rng), pos(rng), pos(rng)};
    d.half = PfxVector3{size(rng), size(rng), size(rng)};
    d.orientation = PfxQuat{unit(rng), unit(rng), unit(rng), unit(rng)}.normalized();
    addBody(scene, d);
    PfxBroadphaseProxy proxy;
    ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxy(proxy, scene.states[0], scene.collidables[0],
                                               worldCenter, worldExtent, 0));
    PfxVector3 center, half;
    scene.collidables[0].getWorldAabb(scene.states[0].getTransform(), center, half);
    for (int a = 0; a < 3; ++a) {
      const double origin = double(worldCenter[a]) - worldExtent[a];
      const double cell = 2.0 * worldExtent[a] / 65535.0;
      const double lo = double(center[a]) - half[a];
      const double hi = double(center[a]) + half[a];
      const double qlo = origin + pfxGetXMin(proxy, a) * cell;
      const double qhi = origin + pfxGetXMax(proxy, a) * cell;
      EXPECT_LE(qlo, lo) << "trial " << trial << " axis " << a;
      EXPECT_GE(qhi, hi) << "trial " << trial << " axis " << a;
      // And no wider than one step on each side.
      EXPECT_GT(qlo + cell, lo) << "trial " << trial << " axis " << a;
      EXPECT_LT(qhi - cell, hi) << "trial " << trial << " axis " << a;
    }
  }
}

TEST(UpdateBroadphaseProxy, SweepExtendsTheSideTheBodyMovesTo) {
  Scene scene;
  BodyDesc d;
  d.velocity = PfxVector3(10, -5, 0);
  addBody(scene, d);
  PfxBroadphaseProxy still, swept;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxy(still, scene.states[0], scene.collidables[0],
                                             kSmallWorldCenter, kSmallWorldExtent, 0, 0));
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxy(swept, scene.states[0], scene.collidables[0],
                                             kSmallWorldCenter, kSmallWorldExtent, 0, 0.1f));
  // Unswept: [-0.5, 0.5] on each axis: 9.5 * 3276.75 = 31129.125 -> 31129 and
  // 10.5 * 3276.75 = 34405.875 -> 34406.
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(31129, pfxGetXMin(still, a));
    EXPECT_EQ(34406, pfxGetXMax(still, a));
  }
  // Travel (1, -0.5, 0): x grows to 1.5 (11.5 * 3276.75 = 37682.625 -> 37683), y down to
  // -1 (9 * 3276.75 = 29490.75 -> 29490), z stays.
  EXPECT_EQ(31129, pfxGetXMin(swept, 0));
  EXPECT_EQ(37683, pfxGetXMax(swept, 0));
  EXPECT_EQ(29490, pfxGetXMin(swept, 1));
  EXPECT_EQ(34406, pfxGetXMax(swept, 1));
  EXPECT_EQ(31129, pfxGetXMin(swept, 2));
  EXPECT_EQ(34406, pfxGetXMax(swept, 2));
}

TEST(UpdateBroadphaseProxy, OutOfWorldIsReportedAndStillWrittenClamped) {
  Scene scene;
  BodyDesc outside;
  outside.id = 4;
  outside.position = PfxVector3(50, 0, 0);
  addBody(scene, outside);
  BodyDesc straddling;
  straddling.position = PfxVector3(-9.8f, 0, 0);  // x in [-10.3, -9.3]: pokes out only
  addBody(scene, straddling);

  PfxBroadphaseProxy proxy;
  EXPECT_EQ(PFX_ERR_OUT_OF_WORLD,
            pfxUpdateBroadphaseProxy(proxy, scene.states[0], scene.collidables[0],
                                     kSmallWorldCenter, kSmallWorldExtent, 0));
  EXPECT_EQ(65535, pfxGetXMin(proxy, 0));
  EXPECT_EQ(65535, pfxGetXMax(proxy, 0));
  EXPECT_EQ(4u, pfxGetObjectId(proxy));

  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxy(proxy, scene.states[1], scene.collidables[1],
                                             kSmallWorldCenter, kSmallWorldExtent, 0));
  // -9.3 -> 0.7 * 3276.75 = 2293.725 -> 2294.
  EXPECT_EQ(0, pfxGetXMin(proxy, 0));
  EXPECT_EQ(2294, pfxGetXMax(proxy, 0));
}

TEST(UpdateBroadphaseProxy, BadInputIsRejectedAndProxyUntouched) {
  Scene scene;
  addBody(scene, BodyDesc());
  PfxRigidState nanState = scene.states[0];
  nanState.setPosition(PfxVector3(kNaN, 0, 0));
  PfxRigidState badQuat = scene.states[0];
  badQuat.setOrientation(PfxQuat(2, 0, 0, 0));
  PfxCollidable empty;
  empty.reset();

  PfxBroadphaseProxy proxy;
  std::memset(&proxy, 0xab, sizeof(proxy));
  const PfxBroadphaseProxy before = proxy;
  const PfxRigidState& s = scene.states[0];
  const PfxCollidable& c = scene.collidables[0];
  const PfxVector3 center = kSmallWorldCenter;
  const PfxVector3 extent = kSmallWorldExtent;
  EXPECT_EQ(PFX_ERR_INVALID_VALUE, pfxUpdateBroadphaseProxy(proxy, s, c, center, extent, 3));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE, pfxUpdateBroadphaseProxy(proxy, s, c, center, extent, -1));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, s, c, center, PfxVector3(10, kNaN, 10), 0));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, s, c, center, PfxVector3(10, 0, 10), 0));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, s, c, center, PfxVector3(10, 10, -1), 0));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, s, c, PfxVector3(kNaN, 0, 0), extent, 0));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, s, c, center, extent, 0, -0.1f));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, s, c, center, extent, 0, kNaN));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, nanState, c, center, extent, 0));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE,
            pfxUpdateBroadphaseProxy(proxy, badQuat, c, center, extent, 0));
  EXPECT_EQ(PFX_ERR_INVALID_VALUE, pfxUpdateBroadphaseProxy(proxy, s, empty, center, extent, 0));
  EXPECT_TRUE(sameBytes(proxy, before));
}

// ---------------------------------------------------------------------------------------
// pfxUpdateBroadphaseProxies

// Bodies at random places; ids are a shuffled range so that id and index differ.
Scene randomScene(PfxUInt32 n, std::mt19937& rng, PfxFloat spread) {
  std::vector<PfxUInt32> ids(n);
  for (PfxUInt32 i = 0; i < n; ++i) ids[i] = 1000 + 3 * i;
  std::shuffle(ids.begin(), ids.end(), rng);
  std::uniform_real_distribution<PfxFloat> pos(-spread, spread);
  std::uniform_real_distribution<PfxFloat> size(0.2f, 3.0f);
  std::uniform_int_distribution<int> type(0, kPfxMotionTypeCount - 1);
  std::uniform_int_distribution<int> bit(0, 2);
  std::uniform_int_distribution<int> mask(1, 7);
  std::bernoulli_distribution asleep(0.3);
  Scene scene;
  for (PfxUInt32 i = 0; i < n; ++i) {
    BodyDesc d;
    d.id = ids[i];
    d.position = PfxVector3{pos(rng), pos(rng), pos(rng)};
    d.half = PfxVector3{size(rng), size(rng), size(rng)};
    d.type = static_cast<PfxMotionType>(type(rng));
    d.asleep = asleep(rng);
    d.self = 1u << bit(rng);
    d.target = static_cast<PfxUInt32>(mask(rng));
    addBody(scene, d);
  }
  return scene;
}

struct ProxyArrays {
  explicit ProxyArrays(std::size_t n) {
    for (auto& a : arrays) a.resize(n);
    work.resize(pfxGetWorkBytesOfUpdateBroadphaseProxies(static_cast<PfxUInt32>(n)) /
                    sizeof(PfxBroadphaseProxy) + 1);
  }
  PfxUpdateBroadphaseProxiesParam param(Scene& scene) {
    PfxUpdateBroadphaseProxiesParam p;
    p.workBuff = work.data();
    p.workBytes = pfxGetWorkBytesOfUpdateBroadphaseProxies(
        static_cast<PfxUInt32>(scene.states.size()));
    p.offsetRigidStates = scene.states.data();
    p.offsetCollidables = scene.collidables.data();
    p.numRigidBodies = static_cast<PfxUInt32>(scene.states.size());
    p.proxiesX = arrays[0].data();
    p.proxiesY = arrays[1].data();
    p.proxiesZ = arrays[2].data();
    p.proxiesXb = arrays[3].data();
    p.proxiesYb = arrays[4].data();
    p.proxiesZb = arrays[5].data();
    return p;
  }
  std::vector<PfxBroadphaseProxy> arrays[6];
  std::vector<PfxBroadphaseProxy> work;
};

TEST(UpdateBroadphaseProxies, SixArraysSortedAndMatchingSingleBodyProxies) {
  std::mt19937 rng(8);
  Scene scene = randomScene(300, rng, 40);
  ProxyArrays out(scene.states.size());
  PfxUpdateBroadphaseProxiesParam param = out.param(scene);
  param.worldExtent = PfxVector3::Constant(50);
  param.timeStep = 0.02f;
  for (auto& s : scene.states) s.setLinearVelocity(PfxVector3(3, -7, 1));
  PfxUpdateBroadphaseProxiesResult result;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(param, result));
  ASSERT_EQ(300u, result.numProxies);
  EXPECT_EQ(0u, result.numOutOfWorldProxies);

  // The expected proxy of every body, by id, from the single-body function.
  std::vector<PfxBroadphaseProxy> expected(scene.states.size());
  for (std::size_t i = 0; i < scene.states.size(); ++i) {
    ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxy(expected[i], scene.states[i],
                                               scene.collidables[i], param.worldCenter,
                                               param.worldExtent, 0, param.timeStep));
  }
  auto findExpected = [&](PfxUInt32 id) -> const PfxBroadphaseProxy* {
    for (std::size_t i = 0; i < scene.states.size(); ++i) {
      if (scene.states[i].getRigidBodyId() == id) return &expected[i];
    }
    return nullptr;
  };

  for (int a = 0; a < 6; ++a) {
    const std::vector<PfxBroadphaseProxy>& array = out.arrays[a];
    std::vector<PfxUInt32> ids;
    for (std::size_t i = 0; i < array.size(); ++i) {
      const PfxBroadphaseProxy& p = array[i];
      ids.push_back(pfxGetObjectId(p));
      const PfxBroadphaseProxy* e = findExpected(pfxGetObjectId(p));
      ASSERT_NE(nullptr, e);
      for (int w = 0; w < 6; ++w) EXPECT_EQ(e->data[w], p.data[w]) << "array " << a;
      EXPECT_EQ(e->key & 0xffffffffffffull, p.key & 0xffffffffffffull);
      const PfxUInt16 sortValue =
          a < 3 ? pfxGetXMin(p, a) : static_cast<PfxUInt16>(65535 - pfxGetXMax(p, a - 3));
      EXPECT_EQ(sortValue, pfxGetSortValue(p));
      if (i == 0) continue;
      const PfxBroadphaseProxy& prev = array[i - 1];
      EXPECT_LT(prev.key, p.key) << "array " << a << " index " << i;
      if (a < 3) {
        EXPECT_LE(pfxGetXMin(prev, a), pfxGetXMin(p, a));
      } else {
        EXPECT_GE(pfxGetXMax(prev, a - 3), pfxGetXMax(p, a - 3));
      }
    }
    std::sort(ids.begin(), ids.end());
    EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end()) << "array " << a;
  }
}

TEST(UpdateBroadphaseProxies, OnlyRequestedArraysAreWritten) {
  std::mt19937 rng(10);
  Scene scene = randomScene(50, rng, 20);
  ProxyArrays out(scene.states.size());
  for (auto& a : out.arrays) fillPattern(a);
  const std::vector<PfxBroadphaseProxy> untouched = out.arrays[0];
  PfxUpdateBroadphaseProxiesParam param = out.param(scene);
  param.proxiesX = nullptr;
  param.proxiesY = nullptr;
  param.proxiesXb = nullptr;
  param.proxiesYb = nullptr;
  param.proxiesZb = nullptr;
  PfxUpdateBroadphaseProxiesResult result;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(param, result));
  EXPECT_EQ(50u, result.numProxies);
  for (int a : {0, 1, 3, 4, 5}) EXPECT_TRUE(sameBytes(out.arrays[a], untouched));
  for (std::size_t i = 1; i < 50; ++i) {
    EXPECT_LE(pfxGetXMin(out.arrays[2][i - 1], 2), pfxGetXMin(out.arrays[2][i], 2));
  }
}

// Three bodies in world [-10, 10]: id 10 inside, id 11 far outside along +x, id 12 inside.
Scene outOfWorldScene() {
  Scene scene;
  BodyDesc d;
  d.id = 10;
  addBody(scene, d);
  d.id = 11;
  d.position = PfxVector3(40, 0, 0);
  addBody(scene, d);
  d.id = 12;
  d.position = PfxVector3(0, 5, 0);
  addBody(scene, d);
  return scene;
}

PfxInt32 updateOutOfWorldScene(Scene& scene, PfxUInt32 behavior, ProxyArrays& out,
                               PfxUpdateBroadphaseProxiesResult& result,
                               const PfxUInt8* skipBodies = nullptr) {
  PfxUpdateBroadphaseProxiesParam param = out.param(scene);
  param.worldCenter = kSmallWorldCenter;
  param.worldExtent = kSmallWorldExtent;
  param.outOfWorldBehavior = behavior;
  param.skipBodies = skipBodies;
  return pfxUpdateBroadphaseProxies(param, result);
}

bool hasProxyOf(const std::vector<PfxBroadphaseProxy>& array, PfxUInt32 n, PfxUInt32 id,
                PfxMotionType* type) {
  for (PfxUInt32 i = 0; i < n; ++i) {
    if (pfxGetObjectId(array[i]) == id) {
      *type = pfxGetMotionType(array[i]);
      return true;
    }
  }
  return false;
}

TEST(UpdateBroadphaseProxies, OutOfWorldBehaviours) {
  struct Case {
    PfxUInt32 behavior;
    PfxUInt32 numProxies;
    PfxMotionType stateType;
  };
  const Case cases[] = {
      {0, 3, kPfxMotionTypeActive},
      {PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION, 3, kPfxMotionTypeFixed},
      {PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY, 2, kPfxMotionTypeActive},
      {PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION | PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY, 2,
       kPfxMotionTypeFixed},
  };
  for (const Case& c : cases) {
    Scene scene = outOfWorldScene();
    ProxyArrays out(scene.states.size());
    PfxUpdateBroadphaseProxiesResult result;
    ASSERT_EQ(PFX_OK, updateOutOfWorldScene(scene, c.behavior, out, result));
    EXPECT_EQ(c.numProxies, result.numProxies) << "behaviour " << c.behavior;
    EXPECT_EQ(1u, result.numOutOfWorldProxies) << "behaviour " << c.behavior;
    EXPECT_EQ(c.stateType, scene.states[1].getMotionType()) << "behaviour " << c.behavior;
    EXPECT_EQ(kPfxMotionTypeActive, scene.states[0].getMotionType());
    EXPECT_EQ(kPfxMotionTypeActive, scene.states[2].getMotionType());
    for (int a = 0; a < 6; ++a) {
      PfxMotionType type = kPfxMotionTypeCount;
      const bool present = hasProxyOf(out.arrays[a], result.numProxies, 11, &type);
      EXPECT_EQ(c.numProxies == 3, present) << "behaviour " << c.behavior;
      if (present) {
        EXPECT_EQ(c.stateType, type);
      }
      EXPECT_TRUE(hasProxyOf(out.arrays[a], result.numProxies, 10, &type));
      EXPECT_TRUE(hasProxyOf(out.arrays[a], result.numProxies, 12, &type));
    }
  }
}

TEST(UpdateBroadphaseProxies, SkippedBodiesGetNoProxyAndAreNotChecked) {
  Scene scene = outOfWorldScene();
  // The skipped body lies outside the world and holds NaN: neither is looked at.
  scene.states[1].setPosition(PfxVector3(kNaN, 0, 0));
  const PfxUInt8 skip[3] = {0, 1, 0};
  ProxyArrays out(scene.states.size());
  PfxUpdateBroadphaseProxiesResult result;
  ASSERT_EQ(PFX_OK,
            updateOutOfWorldScene(scene, PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION, out, result, skip));
  EXPECT_EQ(2u, result.numProxies);
  EXPECT_EQ(0u, result.numOutOfWorldProxies);
  EXPECT_EQ(kPfxMotionTypeActive, scene.states[1].getMotionType());
  for (int a = 0; a < 6; ++a) {
    PfxMotionType type = kPfxMotionTypeCount;
    EXPECT_FALSE(hasProxyOf(out.arrays[a], result.numProxies, 11, &type));
    EXPECT_TRUE(hasProxyOf(out.arrays[a], result.numProxies, 10, &type));
    EXPECT_TRUE(hasProxyOf(out.arrays[a], result.numProxies, 12, &type));
  }
}

TEST(UpdateBroadphaseProxies, EmptySceneGivesNoProxies) {
  Scene scene;
  ProxyArrays out(1);
  PfxUpdateBroadphaseProxiesParam param = out.param(scene);
  PfxUpdateBroadphaseProxiesResult result;
  result.numProxies = 99;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(param, result));
  EXPECT_EQ(0u, result.numProxies);
  EXPECT_EQ(0u, result.numOutOfWorldProxies);
}

TEST(UpdateBroadphaseProxies, BadInputIsRejectedAndNothingWritten) {
  std::mt19937 rng(12);
  Scene scene = randomScene(20, rng, 5);
  scene.states[7].setPosition(PfxVector3(400, 0, 0));  // out of world: would be fixed
  ProxyArrays out(scene.states.size());
  for (auto& a : out.arrays) fillPattern(a);
  const ProxyArrays arraysBefore = out;
  const std::vector<PfxRigidState> statesBefore = scene.states;
  const std::vector<PfxRigidState>* expectedStates = &statesBefore;

  PfxUpdateBroadphaseProxiesResult result;
  result.numProxies = 1234;
  result.numOutOfWorldProxies = 5678;
  auto expectRejected = [&](PfxInt32 code, const PfxUpdateBroadphaseProxiesParam& param,
                            const char* what) {
    EXPECT_EQ(code, pfxUpdateBroadphaseProxies(param, result)) << what;
    EXPECT_EQ(1234u, result.numProxies) << what;
    EXPECT_EQ(5678u, result.numOutOfWorldProxies) << what;
    for (int a = 0; a < 6; ++a) EXPECT_TRUE(sameBytes(out.arrays[a], arraysBefore.arrays[a]));
    EXPECT_TRUE(sameStates(scene.states, *expectedStates)) << what;
  };
  const PfxUpdateBroadphaseProxiesParam good = [&] {
    PfxUpdateBroadphaseProxiesParam p = out.param(scene);
    p.outOfWorldBehavior = PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION;
    p.worldExtent = PfxVector3::Constant(100);
    return p;
  }();

  PfxUpdateBroadphaseProxiesParam p = good;
  p.offsetRigidStates = nullptr;
  expectRejected(PFX_ERR_NULL_POINTER, p, "null states");
  p = good;
  p.offsetCollidables = nullptr;
  expectRejected(PFX_ERR_NULL_POINTER, p, "null collidables");
  p = good;
  p.proxiesX = p.proxiesY = p.proxiesZ = p.proxiesXb = p.proxiesYb = p.proxiesZb = nullptr;
  expectRejected(PFX_ERR_NULL_POINTER, p, "all arrays null");
  p = good;
  p.proxiesYb = reinterpret_cast<PfxBroadphaseProxy*>(reinterpret_cast<char*>(p.proxiesYb) + 4);
  expectRejected(PFX_ERR_INVALID_ALIGNMENT, p, "misaligned array");
  p = good;
  p.proxiesZb = p.proxiesY;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "one array passed twice");
  p = good;
  p.workBuff = p.proxiesZ + 1;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "work buffer inside an array");
  p = good;
  p.outOfWorldBehavior = 1u << 5;
  expectRejected(PFX_ERR_INVALID_FLAG, p, "unknown behaviour");
  p = good;
  p.worldExtent = PfxVector3(100, kNaN, 100);
  expectRejected(PFX_ERR_INVALID_VALUE, p, "NaN extent");
  p = good;
  p.worldExtent = PfxVector3(100, 100, 0);
  expectRejected(PFX_ERR_INVALID_VALUE, p, "zero extent");
  p = good;
  p.worldExtent = PfxVector3(-100, 100, 100);
  expectRejected(PFX_ERR_INVALID_VALUE, p, "negative extent");
  p = good;
  p.worldCenter = PfxVector3(0, 0, std::numeric_limits<PfxFloat>::infinity());
  expectRejected(PFX_ERR_INVALID_VALUE, p, "infinite centre");
  p = good;
  p.timeStep = -0.01f;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "negative time step");
  p = good;
  p.workBuff = nullptr;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "null work buffer");
  p = good;
  p.workBuff = reinterpret_cast<char*>(p.workBuff) + 8;
  expectRejected(PFX_ERR_INVALID_ALIGNMENT, p, "misaligned work buffer");
  p = good;
  p.workBytes -= 1;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "small work buffer");

  // A NaN in the last body: the bodies before it must not have been written.
  scene.states.back().setLinearVelocity(PfxVector3(0, kNaN, 0));
  const std::vector<PfxRigidState> nanStates = scene.states;
  expectedStates = &nanStates;
  expectRejected(PFX_ERR_INVALID_VALUE, good, "NaN state");
}

TEST(ChooseSweepAxis, PicksTheAxisOfLargestSpread) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<PfxFloat> narrow(-1, 1);
  std::uniform_real_distribution<PfxFloat> wide(-30, 30);
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<PfxRigidState> states(100);
    for (auto& s : states) {
      s.reset();
      PfxVector3 p{narrow(rng), narrow(rng), narrow(rng)};
      p[axis] = wide(rng) + 1000;  // far from the origin: the spread is what counts
      s.setPosition(p);
    }
    EXPECT_EQ(axis, pfxChooseSweepAxis(states.data(), 100));
  }
  EXPECT_EQ(0, pfxChooseSweepAxis(nullptr, 0));
  // Two bodies: (0,0,0) and (1,3,2): spreads 0.5, 4.5, 2 -> Y.
  std::vector<PfxRigidState> two(2);
  two[0].reset();
  two[1].reset();
  two[1].setPosition(PfxVector3(1, 3, 2));
  EXPECT_EQ(1, pfxChooseSweepAxis(two.data(), 2));
}

// ---------------------------------------------------------------------------------------
// pfxFindPairs

// The brute-force answer: every two proxies tested against each other.
std::vector<PfxBroadphasePair> referencePairs(const PfxBroadphaseProxy* proxies, PfxUInt32 n) {
  std::vector<PfxBroadphasePair> pairs;
  for (PfxUInt32 i = 0; i < n; ++i) {
    for (PfxUInt32 j = i + 1; j < n; ++j) {
      const PfxBroadphaseProxy& a = proxies[i];
      const PfxBroadphaseProxy& b = proxies[j];
      if (!pfxProxiesOverlap(a, b)) continue;
      const PfxMotionType ta = pfxGetMotionType(a);
      const PfxMotionType tb = pfxGetMotionType(b);
      if (!pfxMotionTypesCollide(ta, tb)) continue;
      if ((pfxGetSelf(a) & pfxGetTarget(b)) == 0 || (pfxGetSelf(b) & pfxGetTarget(a)) == 0) {
        continue;
      }
      const bool sa = pfxGetSleeping(a);
      const bool sb = pfxGetSleeping(b);
      if (sa && sb) continue;
      if ((sa && tb == kPfxMotionTypeFixed) || (sb && ta == kPfxMotionTypeFixed)) continue;
      PfxBroadphasePair pair;
      pfxInitializePair(pair, pfxGetObjectId(a), ta, pfxGetObjectId(b), tb);
      pairs.push_back(pair);
    }
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const PfxBroadphasePair& x, const PfxBroadphasePair& y) { return x.key < y.key; });
  return pairs;
}

struct PairBuffers {
  explicit PairBuffers(PfxUInt32 maxPairs)
      : pairs(pfxGetPairBytesOfFindPairs(maxPairs) / sizeof(PfxBroadphasePair) + 1),
        work(pfxGetWorkBytesOfFindPairs(maxPairs) / sizeof(PfxBroadphasePair) + 1) {}
  PfxFindPairsParam param(const std::vector<PfxBroadphaseProxy>& proxies, PfxUInt32 numProxies,
                          PfxUInt32 maxPairs, int axis) {
    PfxFindPairsParam p;
    p.workBuff = work.data();
    p.workBytes = pfxGetWorkBytesOfFindPairs(maxPairs);
    p.pairBuff = pairs.data();
    p.pairBytes = pfxGetPairBytesOfFindPairs(maxPairs);
    p.proxies = proxies.data();
    p.numProxies = numProxies;
    p.maxPairs = maxPairs;
    p.axis = axis;
    return p;
  }
  std::vector<PfxBroadphasePair> pairs;
  std::vector<PfxBroadphasePair> work;
};

std::vector<PfxBroadphasePair> resultPairs(const PfxFindPairsResult& result) {
  return std::vector<PfxBroadphasePair>(result.pairs, result.pairs + result.numPairs);
}

// A random scene's proxies, sorted along each axis, and the pairs brute force finds in them.
struct RandomProxies {
  explicit RandomProxies(std::size_t n) : out(n) {}
  ProxyArrays out;
  PfxUInt32 numProxies = 0;
  std::vector<PfxBroadphasePair> expected;
};

RandomProxies randomProxies(unsigned seed, PfxUInt32 n, PfxFloat spread) {
  std::mt19937 rng(seed);
  Scene scene = randomScene(n, rng, spread);
  RandomProxies r(scene.states.size());
  PfxUpdateBroadphaseProxiesParam up = r.out.param(scene);
  up.worldExtent = PfxVector3::Constant(40);
  PfxUpdateBroadphaseProxiesResult upResult;
  EXPECT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(up, upResult));
  r.numProxies = upResult.numProxies;
  r.expected = referencePairs(r.out.arrays[0].data(), r.numProxies);
  return r;
}

TEST(FindPairs, MatchesBruteForceOnRandomScenes) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const RandomProxies r = randomProxies(seed, 400, seed % 2 ? 15.0f : 8.0f);
    const std::vector<PfxBroadphasePair>& expected = r.expected;
    ASSERT_GT(expected.size(), 50u) << "scene too sparse to test anything";

    for (int axis = 0; axis < 3; ++axis) {
      const PfxUInt32 maxPairs = 20000;
      PairBuffers buffers(maxPairs);
      PfxFindPairsParam param = buffers.param(r.out.arrays[axis], r.numProxies, maxPairs, axis);
      PfxFindPairsResult result;
      ASSERT_EQ(PFX_OK, pfxFindPairs(param, result));
      EXPECT_EQ(static_cast<void*>(buffers.pairs.data()), static_cast<void*>(result.pairs));
      EXPECT_EQ(expected.size(), result.numPairs) << "seed " << seed << " axis " << axis;
      EXPECT_EQ(result.numPairs, result.numPairsFound);
      EXPECT_TRUE(sameBytes(resultPairs(result), expected)) << "seed " << seed << " axis "
                                                            << axis;
    }
  }
}

// The sleeping bodies' proxies kept apart, as a world keeps them while they sleep, give the
// same pairs as every proxy in one array, on one thread and in parallel chunks.
TEST(FindPairs, SleepingProxiesApartGiveThePairsOfOneArray) {
  PfxTbbTaskManager threads;
  ASSERT_EQ(PFX_OK, threads.initialize(4));
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const RandomProxies r = randomProxies(seed, 1200, seed % 2 ? 25.0f : 12.0f);
    const std::vector<PfxBroadphasePair>& expected = r.expected;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<PfxBroadphaseProxy> awake, sleeping;
      for (PfxUInt32 i = 0; i < r.numProxies; ++i) {
        const PfxBroadphaseProxy& proxy = r.out.arrays[axis][i];
        (pfxGetSleeping(proxy) ? sleeping : awake).push_back(proxy);
      }
      ASSERT_GT(sleeping.size(), 200u);
      const PfxUInt32 maxPairs = 40000;
      for (PfxTaskManager* taskManager : {static_cast<PfxTaskManager*>(nullptr),
                                          static_cast<PfxTaskManager*>(&threads)}) {
        PairBuffers buffers(maxPairs);
        PfxFindPairsParam param =
            buffers.param(awake, static_cast<PfxUInt32>(awake.size()), maxPairs, axis);
        param.sleepingProxies = sleeping.data();
        param.numSleepingProxies = static_cast<PfxUInt32>(sleeping.size());
        PfxFindPairsResult result;
        ASSERT_EQ(PFX_OK, pfxFindPairs(param, result, taskManager));
        EXPECT_EQ(expected.size(), result.numPairs) << "seed " << seed << " axis " << axis;
        EXPECT_TRUE(sameBytes(resultPairs(result), expected)) << "seed " << seed << " axis "
                                                              << axis;
      }
      // Refused, with nothing written: a sleeping proxy not marked asleep, and sleeping
      // proxies out of order.
      PairBuffers buffers(maxPairs);
      fillPattern(buffers.pairs);
      const std::vector<PfxBroadphasePair> untouched = buffers.pairs;
      PfxFindPairsParam param =
          buffers.param(awake, static_cast<PfxUInt32>(awake.size()), maxPairs, axis);
      std::vector<PfxBroadphaseProxy> bad = sleeping;
      bad[7] = awake[0];
      param.sleepingProxies = bad.data();
      param.numSleepingProxies = static_cast<PfxUInt32>(bad.size());
      PfxFindPairsResult result;
      EXPECT_EQ(PFX_ERR_INVALID_VALUE, pfxFindPairs(param, result));
      bad = sleeping;
      std::reverse(bad.begin(), bad.end());
      param.sleepingProxies = bad.data();
      EXPECT_EQ(PFX_ERR_INVALID_VALUE, pfxFindPairs(param, result));
      param.sleepingProxies = nullptr;
      EXPECT_EQ(PFX_ERR_NULL_POINTER, pfxFindPairs(param, result));
      EXPECT_TRUE(sameBytes(buffers.pairs, untouched));
    }
  }
}

// Two overlapping awake boxes, ids 3 and 8.
std::vector<PfxBroadphaseProxy> twoBodyProxies(const BodyDesc& a, const BodyDesc& b) {
  Scene scene;
  addBody(scene, a);
  addBody(scene, b);
  ProxyArrays out(2);
  PfxUpdateBroadphaseProxiesParam param = out.param(scene);
  PfxUpdateBroadphaseProxiesResult result;
  EXPECT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(param, result));
  return out.arrays[0];
}

PfxFindPairsResult findTwoBodyPairs(const BodyDesc& a, const BodyDesc& b,
                                    std::vector<PfxBroadphasePair>& pairs) {
  const std::vector<PfxBroadphaseProxy> proxies = twoBodyProxies(a, b);
  PairBuffers buffers(4);
  PfxFindPairsParam param = buffers.param(proxies, 2, 4, 0);
  PfxFindPairsResult result;
  EXPECT_EQ(PFX_OK, pfxFindPairs(param, result));
  pairs = resultPairs(result);
  return result;
}

TEST(FindPairs, MotionTypeCombinationsFollowTheSeedTables) {
  // Seed chapter 10, "A List of the Behavior Change by Type", upper triangles mirrored.
  // Order: fixed, active, keyframe, one-way, trigger.
  const bool collides[5][5] = {
      {false, true, false, true, true},
      {true, true, true, true, true},
      {false, true, false, true, true},
      {true, true, true, false, true},
      {true, true, true, true, false},
  };
  const bool responds[5][5] = {
      {false, true, false, true, false},
      {true, true, true, true, false},
      {false, true, false, true, false},
      {true, true, true, false, false},
      {false, false, false, false, false},
  };
  for (int ta = 0; ta < 5; ++ta) {
    for (int tb = 0; tb < 5; ++tb) {
      BodyDesc a, b;
      a.id = 8;  // the larger id first in the array: the pair must still put 3 as A
      a.type = static_cast<PfxMotionType>(ta);
      b.id = 3;
      b.type = static_cast<PfxMotionType>(tb);
      b.position = PfxVector3(0.6f, 0.2f, -0.3f);
      std::vector<PfxBroadphasePair> pairs;
      findTwoBodyPairs(a, b, pairs);
      ASSERT_EQ(collides[ta][tb] ? 1u : 0u, pairs.size()) << "types " << ta << ", " << tb;
      if (pairs.empty()) continue;
      EXPECT_EQ(3u, pfxGetObjectIdA(pairs[0]));
      EXPECT_EQ(8u, pfxGetObjectIdB(pairs[0]));
      EXPECT_EQ(tb, pfxGetMotionTypeA(pairs[0]));
      EXPECT_EQ(ta, pfxGetMotionTypeB(pairs[0]));
      EXPECT_EQ(responds[ta][tb], pfxGetActive(pairs[0])) << "types " << ta << ", " << tb;
      EXPECT_EQ(0u, pfxGetContactId(pairs[0]));
      EXPECT_EQ(0u, pfxGetNumConstraints(pairs[0]));
    }
  }
}

TEST(FindPairs, SleepingBodiesAgainstFixedOrSleepingAreSkipped) {
  struct Case {
    PfxMotionType typeA;
    bool asleepA;
    PfxMotionType typeB;
    bool asleepB;
    bool expectPair;
  };
  const Case cases[] = {
      {kPfxMotionTypeActive, true, kPfxMotionTypeActive, true, false},
      {kPfxMotionTypeActive, true, kPfxMotionTypeFixed, false, false},
      {kPfxMotionTypeFixed, false, kPfxMotionTypeActive, true, false},
      {kPfxMotionTypeActive, true, kPfxMotionTypeActive, false, true},
      {kPfxMotionTypeActive, false, kPfxMotionTypeActive, true, true},
      {kPfxMotionTypeKeyframe, false, kPfxMotionTypeActive, true, true},
      {kPfxMotionTypeActive, false, kPfxMotionTypeFixed, false, true},
  };
  for (const Case& c : cases) {
    BodyDesc a, b;
    a.id = 0;
    a.type = c.typeA;
    a.asleep = c.asleepA;
    b.id = 1;
    b.type = c.typeB;
    b.asleep = c.asleepB;
    b.position = PfxVector3(0.5f, 0.5f, 0.5f);
    std::vector<PfxBroadphasePair> pairs;
    findTwoBodyPairs(a, b, pairs);
    EXPECT_EQ(c.expectPair ? 1u : 0u, pairs.size())
        << int(c.typeA) << c.asleepA << " " << int(c.typeB) << c.asleepB;
  }
}

TEST(FindPairs, ContactFiltersExcludePairs) {
  // (selfA & targetB) && (targetA & selfB) decides.
  struct Case {
    PfxUInt32 selfA, targetA, selfB, targetB;
    bool expectPair;
  };
  const Case cases[] = {
      {0x1, 0x2, 0x2, 0x1, true},   // each targets the other's group
      {0x1, 0x2, 0x2, 0x2, false},  // B does not target A's group
      {0x1, 0x1, 0x2, 0x1, false},  // A does not target B's group
      {0x0, 0xf, 0xf, 0xf, false},  // A belongs to no group
      {0x6, 0x4, 0x4, 0x2, true},   // overlap in one bit each way
  };
  for (const Case& c : cases) {
    BodyDesc a, b;
    a.id = 0;
    a.self = c.selfA;
    a.target = c.targetA;
    b.id = 1;
    b.self = c.selfB;
    b.target = c.targetB;
    b.position = PfxVector3(0, 0.9f, 0);
    std::vector<PfxBroadphasePair> pairs;
    findTwoBodyPairs(a, b, pairs);
    EXPECT_EQ(c.expectPair ? 1u : 0u, pairs.size()) << c.selfA << " " << c.targetA << " "
                                                     << c.selfB << " " << c.targetB;
  }
}

TEST(FindPairs, KnownAnswerAlongX) {
  // Unit boxes (half 0.5) at x = 0, 0.9, 2.5 and one at x = 0.2 but 3 m up: only the first
  // two overlap ([-0.5, 0.5] and [0.4, 1.4]); the third starts at 2.0, past 1.4; the
  // fourth overlaps the first two along x only.
  Scene scene;
  const PfxVector3 positions[4] = {PfxVector3(0, 0, 0), PfxVector3(0.9f, 0, 0),
                                   PfxVector3(2.5f, 0, 0), PfxVector3(0.2f, 3, 0)};
  for (PfxUInt32 i = 0; i < 4; ++i) {
    BodyDesc d;
    d.id = 20 - i;
    d.position = positions[i];
    addBody(scene, d);
  }
  ProxyArrays out(4);
  PfxUpdateBroadphaseProxiesParam up = out.param(scene);
  PfxUpdateBroadphaseProxiesResult upResult;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(up, upResult));
  PairBuffers buffers(8);
  PfxFindPairsParam param = buffers.param(out.arrays[0], 4, 8, 0);
  PfxFindPairsResult result;
  ASSERT_EQ(PFX_OK, pfxFindPairs(param, result));
  ASSERT_EQ(1u, result.numPairs);
  EXPECT_EQ(pfxCreatePairKey(19, 20), result.pairs[0].key);
}

TEST(FindPairs, OutOfMaxPairsThenRetryWithFoundCount) {
  std::mt19937 rng(21);
  Scene scene = randomScene(300, rng, 10);
  ProxyArrays out(scene.states.size());
  PfxUpdateBroadphaseProxiesParam up = out.param(scene);
  PfxUpdateBroadphaseProxiesResult upResult;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(up, upResult));
  const std::vector<PfxBroadphasePair> expected =
      referencePairs(out.arrays[1].data(), upResult.numProxies);
  ASSERT_GT(expected.size(), 100u);

  const PfxUInt32 tooFew = static_cast<PfxUInt32>(expected.size() / 2);
  PairBuffers small(tooFew);
  PfxFindPairsParam param = small.param(out.arrays[1], upResult.numProxies, tooFew, 1);
  PfxFindPairsResult result;
  ASSERT_EQ(PFX_ERR_OUT_OF_MAX_PAIRS, pfxFindPairs(param, result));
  EXPECT_EQ(expected.size(), result.numPairsFound);
  EXPECT_EQ(tooFew, result.numPairs);
  // What did fit is a sorted subset of the answer.
  for (PfxUInt32 i = 0; i < result.numPairs; ++i) {
    if (i > 0) {
      EXPECT_LT(result.pairs[i - 1].key, result.pairs[i].key);
    }
    EXPECT_TRUE(std::any_of(expected.begin(), expected.end(), [&](const PfxBroadphasePair& e) {
      return sameBytes(e, result.pairs[i]);
    }));
  }

  const PfxUInt32 enough = result.numPairsFound;
  PairBuffers large(enough);
  param = large.param(out.arrays[1], upResult.numProxies, enough, 1);
  ASSERT_EQ(PFX_OK, pfxFindPairs(param, result));
  EXPECT_TRUE(sameBytes(resultPairs(result), expected));

  // Counting only: no room at all still reports how many there are.
  PairBuffers none(0);
  param = none.param(out.arrays[1], upResult.numProxies, 0, 1);
  ASSERT_EQ(PFX_ERR_OUT_OF_MAX_PAIRS, pfxFindPairs(param, result));
  EXPECT_EQ(expected.size(), result.numPairsFound);
  EXPECT_EQ(0u, result.numPairs);
}

TEST(FindPairs, NoProxiesNoPairs) {
  std::vector<PfxBroadphaseProxy> proxies;
  PairBuffers buffers(4);
  PfxFindPairsParam param = buffers.param(proxies, 0, 4, 2);
  param.proxies = nullptr;
  PfxFindPairsResult result;
  ASSERT_EQ(PFX_OK, pfxFindPairs(param, result));
  EXPECT_EQ(0u, result.numPairs);
  EXPECT_EQ(0u, result.numPairsFound);
}

TEST(FindPairs, BadInputIsRejectedAndNothingWritten) {
  std::mt19937 rng(30);
  Scene scene = randomScene(40, rng, 4);
  ProxyArrays out(scene.states.size());
  PfxUpdateBroadphaseProxiesParam up = out.param(scene);
  PfxUpdateBroadphaseProxiesResult upResult;
  ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(up, upResult));

  const PfxUInt32 maxPairs = 1000;
  PairBuffers buffers(maxPairs);
  fillPattern(buffers.pairs);
  fillPattern(buffers.work);
  const std::vector<PfxBroadphasePair> pairsBefore = buffers.pairs;
  const PfxFindPairsParam good = buffers.param(out.arrays[0], 40, maxPairs, 0);
  PfxFindPairsResult result;
  result.pairs = nullptr;
  result.numPairs = 11;
  result.numPairsFound = 22;
  auto expectRejected = [&](PfxInt32 code, const PfxFindPairsParam& param, const char* what) {
    EXPECT_EQ(code, pfxFindPairs(param, result)) << what;
    EXPECT_EQ(nullptr, result.pairs) << what;
    EXPECT_EQ(11u, result.numPairs) << what;
    EXPECT_EQ(22u, result.numPairsFound) << what;
    EXPECT_TRUE(sameBytes(buffers.pairs, pairsBefore)) << what;
  };

  PfxFindPairsParam p = good;
  p.axis = 3;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "axis 3");
  p = good;
  p.axis = -1;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "axis -1");
  p = good;
  p.axis = 1;  // the X array is not sorted along Y
  expectRejected(PFX_ERR_INVALID_VALUE, p, "array of another axis");
  p = good;
  p.proxies = out.arrays[3].data();  // sorted by descending maximum
  expectRejected(PFX_ERR_INVALID_VALUE, p, "backward array");
  p = good;
  p.proxies = nullptr;
  expectRejected(PFX_ERR_NULL_POINTER, p, "null proxies");
  p = good;
  p.pairBuff = nullptr;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "null pair buffer");
  p = good;
  p.pairBuff = reinterpret_cast<char*>(p.pairBuff) + 4;
  expectRejected(PFX_ERR_INVALID_ALIGNMENT, p, "misaligned pair buffer");
  p = good;
  p.pairBytes -= 1;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "small pair buffer");
  p = good;
  p.workBuff = nullptr;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "null work buffer");
  p = good;
  p.workBuff = reinterpret_cast<char*>(p.workBuff) + 8;
  expectRejected(PFX_ERR_INVALID_ALIGNMENT, p, "misaligned work buffer");
  p = good;
  p.workBytes -= 16;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "small work buffer");
  p = good;
  p.workBuff = p.pairBuff;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "work buffer is the pair buffer");
}

// ---------------------------------------------------------------------------------------
// pfxDecomposePairs

PfxBroadphasePair makePair(PfxUInt32 idA, PfxUInt32 idB, PfxMotionType ta, PfxMotionType tb,
                           PfxUInt32 contactId, PfxUInt32 numConstraints) {
  PfxBroadphasePair pair;
  pfxInitializePair(pair, idA, ta, idB, tb);
  pfxSetContactId(pair, contactId);
  pfxSetNumConstraints(pair, numConstraints);
  return pair;
}

struct DecomposeBuffers {
  DecomposeBuffers(PfxUInt32 numPrevious, PfxUInt32 numCurrent)
      : pairs(pfxGetPairBytesOfDecomposePairs(numPrevious, numCurrent) /
                  sizeof(PfxBroadphasePair) + 1) {}
  PfxDecomposePairsParam param(const std::vector<PfxBroadphasePair>& previous,
                               const std::vector<PfxBroadphasePair>& current) {
    const PfxUInt32 np = static_cast<PfxUInt32>(previous.size());
    const PfxUInt32 nc = static_cast<PfxUInt32>(current.size());
    PfxDecomposePairsParam p;
    p.workBuff = work;
    p.workBytes = pfxGetWorkBytesOfDecomposePairs(np, nc);
    p.pairBuff = pairs.data();
    p.pairBytes = pfxGetPairBytesOfDecomposePairs(np, nc);
    p.previousPairs = previous.data();
    p.numPreviousPairs = np;
    p.currentPairs = current.data();
    p.numCurrentPairs = nc;
    return p;
  }
  std::vector<PfxBroadphasePair> pairs;
  alignas(16) PfxUInt8 work[16] = {};
};

TEST(DecomposePairs, KnownAnswer) {
  // Previous {(0,1) contact 5, (1,2) contact 6 with 3 constraints}; current {(1,2) with new
  // motion types, (2,3)}: (2,3) is new, (1,2) kept with contact 6 and 3 constraints but
  // the current motion types, (0,1) removed with its contact 5.
  const std::vector<PfxBroadphasePair> previous = {
      makePair(0, 1, kPfxMotionTypeActive, kPfxMotionTypeActive, 5, 2),
      makePair(1, 2, kPfxMotionTypeActive, kPfxMotionTypeActive, 6, 3)};
  const std::vector<PfxBroadphasePair> current = {
      makePair(1, 2, kPfxMotionTypeFixed, kPfxMotionTypeOneWay, 0, 0),
      makePair(2, 3, kPfxMotionTypeActive, kPfxMotionTypeTrigger, 0, 0)};
  DecomposeBuffers buffers(2, 2);
  PfxDecomposePairsResult result;
  ASSERT_EQ(PFX_OK, pfxDecomposePairs(buffers.param(previous, current), result));
  ASSERT_EQ(1u, result.numOutNewPairs);
  ASSERT_EQ(1u, result.numOutKeepPairs);
  ASSERT_EQ(1u, result.numOutRemovePairs);
  EXPECT_TRUE(sameBytes(current[1], result.outNewPairs[0]));
  const PfxBroadphasePair& kept = result.outKeepPairs[0];
  EXPECT_EQ(pfxCreatePairKey(1, 2), kept.key);
  EXPECT_EQ(6u, pfxGetContactId(kept));
  EXPECT_EQ(3u, pfxGetNumConstraints(kept));
  EXPECT_EQ(kPfxMotionTypeFixed, pfxGetMotionTypeA(kept));
  EXPECT_EQ(kPfxMotionTypeOneWay, pfxGetMotionTypeB(kept));
  EXPECT_EQ(pfxGetActive(current[0]), pfxGetActive(kept));
  EXPECT_EQ(pfxGetReceivesA(current[0]), pfxGetReceivesA(kept));
  EXPECT_EQ(pfxGetReceivesB(current[0]), pfxGetReceivesB(kept));
  EXPECT_TRUE(sameBytes(previous[0], result.outRemovePairs[0]));
  // New and kept pairs lie side by side at the start of the pair buffer.
  EXPECT_EQ(static_cast<void*>(buffers.pairs.data()), static_cast<void*>(result.outNewPairs));
  EXPECT_EQ(result.outNewPairs + 1, result.outKeepPairs);
}

std::vector<PfxBroadphasePair> randomPairSet(std::mt19937& rng, double density,
                                             bool withContacts) {
  std::bernoulli_distribution take(density);
  std::uniform_int_distribution<int> type(0, kPfxMotionTypeCount - 1);
  std::uniform_int_distribution<PfxUInt32> contact(0, 100000);
  std::uniform_int_distribution<PfxUInt32> constraints(0, 4);
  std::vector<PfxBroadphasePair> pairs;
  for (PfxUInt32 a = 0; a < 40; ++a) {
    for (PfxUInt32 b = a + 1; b < 40; ++b) {
      if (!take(rng)) continue;
      // One draw a statement: a call's arguments are taken in no fixed order.
      const auto typeA = static_cast<PfxMotionType>(type(rng));
      const auto typeB = static_cast<PfxMotionType>(type(rng));
      const PfxUInt32 contactId = withContacts ? contact(rng) : 0;
      const PfxUInt32 numConstraints = withContacts ? constraints(rng) : 0;
      pairs.push_back(makePair(a, b, typeA, typeB, contactId, numConstraints));
    }
  }
  return pairs;
}

TEST(DecomposePairs, RandomSetsGiveTheSetDifferences) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    const std::vector<PfxBroadphasePair> previous = randomPairSet(rng, 0.3, true);
    const std::vector<PfxBroadphasePair> current = randomPairSet(rng, 0.3, false);
    DecomposeBuffers buffers(static_cast<PfxUInt32>(previous.size()),
                             static_cast<PfxUInt32>(current.size()));
    PfxDecomposePairsResult result;
    ASSERT_EQ(PFX_OK, pfxDecomposePairs(buffers.param(previous, current), result));

    auto byKey = [](const PfxBroadphasePair& x, const PfxBroadphasePair& y) {
      return x.key < y.key;
    };
    std::vector<PfxBroadphasePair> expectNew, expectRemove, keptFromPrevious, keptFromCurrent;
    std::set_difference(current.begin(), current.end(), previous.begin(), previous.end(),
                        std::back_inserter(expectNew), byKey);
    std::set_difference(previous.begin(), previous.end(), current.begin(), current.end(),
                        std::back_inserter(expectRemove), byKey);
    std::set_intersection(previous.begin(), previous.end(), current.begin(), current.end(),
                          std::back_inserter(keptFromPrevious), byKey);
    std::set_intersection(current.begin(), current.end(), previous.begin(), previous.end(),
                          std::back_inserter(keptFromCurrent), byKey);

    EXPECT_TRUE(sameBytes(std::vector<PfxBroadphasePair>(
                              result.outNewPairs, result.outNewPairs + result.numOutNewPairs),
                          expectNew));
    EXPECT_TRUE(sameBytes(std::vector<PfxBroadphasePair>(
                              result.outRemovePairs,
                              result.outRemovePairs + result.numOutRemovePairs),
                          expectRemove));
    ASSERT_EQ(keptFromPrevious.size(), result.numOutKeepPairs);
    for (PfxUInt32 i = 0; i < result.numOutKeepPairs; ++i) {
      const PfxBroadphasePair& kept = result.outKeepPairs[i];
      EXPECT_EQ(keptFromCurrent[i].key, kept.key);
      EXPECT_EQ(pfxGetContactId(keptFromPrevious[i]), pfxGetContactId(kept));
      EXPECT_EQ(pfxGetNumConstraints(keptFromPrevious[i]), pfxGetNumConstraints(kept));
      EXPECT_EQ(keptFromCurrent[i].data[1] & 0xffffu, kept.data[1] & 0xffffu);
    }
    EXPECT_EQ(current.size(), result.numOutNewPairs + result.numOutKeepPairs);
  }
}

TEST(DecomposePairs, EmptySides) {
  std::mt19937 rng(4);
  const std::vector<PfxBroadphasePair> some = randomPairSet(rng, 0.1, true);
  const std::vector<PfxBroadphasePair> none;
  PfxDecomposePairsResult result;

  DecomposeBuffers allNew(0, static_cast<PfxUInt32>(some.size()));
  ASSERT_EQ(PFX_OK, pfxDecomposePairs(allNew.param(none, some), result));
  EXPECT_EQ(some.size(), result.numOutNewPairs);
  EXPECT_EQ(0u, result.numOutKeepPairs);
  EXPECT_EQ(0u, result.numOutRemovePairs);

  DecomposeBuffers allRemoved(static_cast<PfxUInt32>(some.size()), 0);
  ASSERT_EQ(PFX_OK, pfxDecomposePairs(allRemoved.param(some, none), result));
  EXPECT_EQ(0u, result.numOutNewPairs);
  EXPECT_EQ(0u, result.numOutKeepPairs);
  EXPECT_EQ(some.size(), result.numOutRemovePairs);
  EXPECT_TRUE(sameBytes(std::vector<PfxBroadphasePair>(
                            result.outRemovePairs, result.outRemovePairs + some.size()),
                        some));

  DecomposeBuffers nothing(0, 0);
  ASSERT_EQ(PFX_OK, pfxDecomposePairs(nothing.param(none, none), result));
  EXPECT_EQ(0u, result.numOutNewPairs + result.numOutKeepPairs + result.numOutRemovePairs);
}

TEST(DecomposePairs, BadInputIsRejectedAndNothingWritten) {
  std::mt19937 rng(6);
  std::vector<PfxBroadphasePair> previous = randomPairSet(rng, 0.2, true);
  std::vector<PfxBroadphasePair> current = randomPairSet(rng, 0.2, false);
  const PfxUInt32 np = static_cast<PfxUInt32>(previous.size());
  const PfxUInt32 nc = static_cast<PfxUInt32>(current.size());
  DecomposeBuffers buffers(np, nc);
  fillPattern(buffers.pairs);
  const std::vector<PfxBroadphasePair> pairsBefore = buffers.pairs;
  const PfxDecomposePairsParam good = buffers.param(previous, current);
  PfxDecomposePairsResult result;
  result.numOutNewPairs = 1;
  result.numOutKeepPairs = 2;
  result.numOutRemovePairs = 3;
  auto expectRejected = [&](PfxInt32 code, const PfxDecomposePairsParam& param,
                            const char* what) {
    EXPECT_EQ(code, pfxDecomposePairs(param, result)) << what;
    EXPECT_EQ(nullptr, result.outNewPairs) << what;
    EXPECT_EQ(1u, result.numOutNewPairs) << what;
    EXPECT_EQ(2u, result.numOutKeepPairs) << what;
    EXPECT_EQ(3u, result.numOutRemovePairs) << what;
    EXPECT_TRUE(sameBytes(buffers.pairs, pairsBefore)) << what;
  };

  PfxDecomposePairsParam p = good;
  p.previousPairs = nullptr;
  expectRejected(PFX_ERR_NULL_POINTER, p, "null previous");
  p = good;
  p.currentPairs = nullptr;
  expectRejected(PFX_ERR_NULL_POINTER, p, "null current");
  p = good;
  p.pairBuff = nullptr;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "null pair buffer");
  p = good;
  p.pairBuff = reinterpret_cast<char*>(p.pairBuff) + 4;
  expectRejected(PFX_ERR_INVALID_ALIGNMENT, p, "misaligned pair buffer");
  p = good;
  p.pairBytes = sizeof(PfxBroadphasePair) * (np + nc) - 1;
  expectRejected(PFX_ERR_OUT_OF_BUFFER, p, "small pair buffer");
  p = good;
  p.currentPairs = buffers.pairs.data() + 2;
  p.numCurrentPairs = 3;
  expectRejected(PFX_ERR_INVALID_VALUE, p, "pair buffer overlaps the current pairs");

  std::vector<PfxBroadphasePair> unsorted = previous;
  std::swap(unsorted[0], unsorted[1]);
  p = good;
  p.previousPairs = unsorted.data();
  expectRejected(PFX_ERR_INVALID_VALUE, p, "unsorted previous");
  std::vector<PfxBroadphasePair> repeated = current;
  repeated[1] = repeated[0];
  p = good;
  p.currentPairs = repeated.data();
  expectRejected(PFX_ERR_INVALID_VALUE, p, "repeated key in current");
}

// ---------------------------------------------------------------------------------------
// With a task manager: the same bytes as on one thread, whatever the number of threads.

TEST(BroadphaseThreads, ProxiesAndPairsAreTheSameWithAnyNumberOfThreads) {
  std::mt19937 rng(77);
  // Enough bodies for the proxies, the sorts and the sweep to split into chunks; some lie
  // outside the world.
  const Scene original = randomScene(20000, rng, 60);
  for (const PfxUInt32 behavior :
       {PfxUInt32(PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION), PfxUInt32(PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY)}) {
    Scene serialScene = original;
    ProxyArrays serial(original.states.size());
    PfxUpdateBroadphaseProxiesParam serialParam = serial.param(serialScene);
    serialParam.worldExtent = PfxVector3::Constant(50);
    serialParam.outOfWorldBehavior = behavior;
    PfxUpdateBroadphaseProxiesResult serialResult;
    ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(serialParam, serialResult));
    ASSERT_GT(serialResult.numOutOfWorldProxies, 0u);
    ASSERT_GT(serialResult.numProxies, 10000u);

    // Serial pairs, with room for all of them and with room for half.
    PairBuffers serialPairs(200000);
    PfxFindPairsParam findParam =
        serialPairs.param(serial.arrays[1], serialResult.numProxies, 200000, 1);
    PfxFindPairsResult found;
    ASSERT_EQ(PFX_OK, pfxFindPairs(findParam, found));
    const std::vector<PfxBroadphasePair> allPairs = resultPairs(found);
    ASSERT_GT(allPairs.size(), 2000u);
    const PfxUInt32 half = static_cast<PfxUInt32>(allPairs.size() / 2);
    PairBuffers serialHalf(half);
    findParam = serialHalf.param(serial.arrays[1], serialResult.numProxies, half, 1);
    ASSERT_EQ(PFX_ERR_OUT_OF_MAX_PAIRS, pfxFindPairs(findParam, found));
    const std::vector<PfxBroadphasePair> halfPairs = resultPairs(found);

    for (PfxUInt32 threads : {1u, 2u, 4u}) {
      PfxTbbTaskManager manager;
      ASSERT_EQ(PFX_OK, manager.initialize(threads));
      Scene scene = original;
      ProxyArrays out(original.states.size());
      PfxUpdateBroadphaseProxiesParam param = out.param(scene);
      param.worldExtent = serialParam.worldExtent;
      param.outOfWorldBehavior = behavior;
      PfxUpdateBroadphaseProxiesResult result;
      ASSERT_EQ(PFX_OK, pfxUpdateBroadphaseProxies(param, result, &manager));
      EXPECT_EQ(serialResult.numProxies, result.numProxies);
      EXPECT_EQ(serialResult.numOutOfWorldProxies, result.numOutOfWorldProxies);
      for (int a = 0; a < 6; ++a) {
        EXPECT_TRUE(sameBytes(serial.arrays[a], out.arrays[a])) << "array " << a << ", "
                                                                  << threads << " threads";
      }
      for (std::size_t i = 0; i < scene.states.size(); ++i) {
        ASSERT_EQ(serialScene.states[i].getMotionType(), scene.states[i].getMotionType());
      }

      // Exactly as many pairs as fit: chunks that found more than their share of the
      // work buffer sweep again into place.
      const PfxUInt32 exact = static_cast<PfxUInt32>(allPairs.size());
      for (const PfxUInt32 maxPairs : {PfxUInt32(200000), exact}) {
        PairBuffers buffers(maxPairs);
        PfxFindPairsParam p = buffers.param(out.arrays[1], result.numProxies, maxPairs, 1);
        PfxFindPairsResult pairs;
        ASSERT_EQ(PFX_OK, pfxFindPairs(p, pairs, &manager));
        EXPECT_TRUE(sameBytes(resultPairs(pairs), allPairs)) << threads << " threads";
      }
      PairBuffers halfBuffers(half);
      PfxFindPairsParam p = halfBuffers.param(out.arrays[1], result.numProxies, half, 1);
      PfxFindPairsResult pairs;
      ASSERT_EQ(PFX_ERR_OUT_OF_MAX_PAIRS, pfxFindPairs(p, pairs, &manager));
      EXPECT_EQ(exact, pairs.numPairsFound);
      EXPECT_TRUE(sameBytes(resultPairs(pairs), halfPairs)) << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace pfx
