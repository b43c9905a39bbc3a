// The golden state: a fixed scene (a pile of every convex shape, a convex mesh among them,
// and a chain of capsules on hinges swinging into it) stepped for a fixed simulated time
// hashes to a constant kept here, on 1, 2 and 4 threads. The other tests accept any result
// within their tolerances, so a change that moves a bit (an operation reordered, a constant
// rounded differently, a stage's order changed) passes them unseen; this test makes such a
// change visible, so that it is made on purpose and the constant updated with it.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx_test_meshes.h"

using namespace pfx;

namespace {

// The hash of the state after kSteps, one constant per precision. To update one: run this
// test in that build (build/bin/test_golden_state, and build-double for PFX_DOUBLE), check
// that the change that moved the bits was meant to, and paste the hash the failure prints.
#ifdef PFX_DOUBLE
constexpr std::uint64_t kGoldenHash = 0x0b3778b635aa631dull;
#else
constexpr std::uint64_t kGoldenHash = 0x085bfa025446a2deull;
#endif
constexpr int kSteps = 90;  // 1.5 s at 1/60 s: the pile lands and the chain swings into it

// FNV-1a over bytes: simple, fixed by its definition, the same on every platform.
class StateHash {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
      m_hash = (m_hash ^ p[i]) * 0x100000001b3ull;
    }
  }
  // The bit patterns of the coefficients, not the object's bytes, so that padding inside
  // Eigen's types can never enter the hash.
  template <typename Vector>
  void addCoefficients(const Vector& v) {
    for (int i = 0; i < v.size(); ++i) {
      const PfxFloat x = v[i];
      add(&x, sizeof x);
    }
  }
  std::uint64_t value() const { return m_hash; }

 private:
  std::uint64_t m_hash = 0xcbf29ce484222325ull;
};

// Uniform in [0, 1) from the generator's raw output, the same with every standard library.
PfxFloat uniform(std::mt19937& rng) { return PfxFloat(rng() / 4294967296.0); }

void addBody(PfxWorld& world, const PfxShape& shape, PfxFloat mass, const PfxVector3& position,
             const PfxQuat& orientation = PfxQuat::Identity()) {
  PfxBodyInit init;
  init.mass = mass;
  init.position = position;
  init.orientation = orientation;
  ASSERT_EQ(pfxAddBody(world, shape, init), PFX_OK);
}

// A floor with a wall, 48 bodies of five shapes dropped in a loose grid, and a chain of six
// capsules hinged to a fixed post, released horizontal so that it swings through the pile.
void buildScene(PfxWorld& world, const PfxConvexMesh& mesh, PfxUInt32 numThreads) {
  PfxWorldParam param;
  param.numThreads = numThreads;
  param.subStep = 2;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  addBody(world, pfxMakeShape(PfxBox(3, 0.25, 3)), 0, PfxVector3(0, -0.25, 0));
  addBody(world, pfxMakeShape(PfxBox(0.25, 1, 3)), 0, PfxVector3(-1.5, 1, 0));
  std::mt19937 rng(1903u);
  for (int layer = 0; layer < 3; ++layer) {
    for (int i = 0; i < 4; ++i) {
      for (int k = 0; k < 4; ++k) {
        // Each draw in a statement of its own: the order in which a call's arguments are
        // evaluated is unspecified, and clang's is the reverse of GCC's, in which the
        // constant was made (and which these follow).
        const PfxFloat jitterZ = uniform(rng);
        const PfxFloat jitterX = uniform(rng);
        const PfxFloat axisY = uniform(rng);
        const PfxFloat turn = uniform(rng);
        const PfxVector3 position(PfxFloat(0.4) * i - PfxFloat(0.9) + PfxFloat(0.02) * jitterX,
                                  PfxFloat(0.3) + PfxFloat(0.4) * layer,
                                  PfxFloat(0.4) * k - PfxFloat(0.6) + PfxFloat(0.02) * jitterZ);
        const PfxQuat orientation(Eigen::AngleAxis<PfxFloat>(
            PfxFloat(6.28) * turn, PfxVector3(1, axisY, 2).normalized()));
        PfxShape shape;
        switch ((i + k + layer) % 5) {
          case 0: shape = pfxMakeShape(PfxBox(0.15, 0.1, 0.12)); break;
          case 1: shape = pfxMakeShape(PfxSphere(0.14)); break;
          case 2: shape = pfxMakeShape(PfxCapsule(0.08, 0.08)); break;
          case 3: shape = pfxMakeShape(PfxCylinder(0.1, 0.12)); break;
          default: shape = pfxMakeShape(&mesh); break;
        }
        addBody(world, shape, PfxFloat(0.5) + uniform(rng), position, orientation);
      }
    }
  }
  const PfxUInt32 post = world.getNumRigidBodies();
  addBody(world, pfxMakeShape(PfxBox(0.1, 0.1, 0.1)), 0, PfxVector3(1.5, 1.6, 0));
  for (int link = 0; link < 6; ++link) {
    // Capsules lie along their X axis; each hangs from the previous one's far end.
    addBody(world, pfxMakeShape(PfxCapsule(0.1, 0.05)), 1,
            PfxVector3(PfxFloat(1.35) - PfxFloat(0.3) * link, 1.6, 0));
    PfxHingeJointInitParam hinge;
    hinge.anchorPoint = PfxVector3(PfxFloat(1.5) - PfxFloat(0.3) * link, 1.6, 0);
    hinge.axis = PfxVector3(0, PfxFloat(0.3), 1).normalized();
    PfxJoint joint;
    const PfxUInt32 child = post + 1 + link;
    ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(child - 1),
                                      world.getRigidState(child), hinge),
              PFX_OK);
    ASSERT_EQ(world.addJoint(joint), PFX_OK);
  }
}

std::uint64_t hashOfState(const PfxWorld& world) {
  StateHash hash;
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    const PfxRigidState& state = world.getRigidState(id);
    hash.addCoefficients(state.getPosition());
    hash.addCoefficients(state.getOrientation().coeffs());
    hash.addCoefficients(state.getLinearVelocity());
    hash.addCoefficients(state.getAngularVelocity());
  }
  return hash.value();
}

std::string hex(std::uint64_t value) {
  char text[32];
  std::snprintf(text, sizeof text, "0x%016llxull", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace

TEST(GoldenState, PileAndChainHashToTheConstantOnOneTwoAndFourThreads) {
  const pfx_test::TriangleList icosahedron = pfx_test::makeIcosahedronTriangles();
  std::vector<PfxFloat> vertices = icosahedron.vertices;
  for (PfxFloat& v : vertices) v *= PfxFloat(0.08);
  PfxConvexMesh mesh;
  ASSERT_EQ(pfxCreateConvexMesh(mesh, vertices.data(), icosahedron.numVertices(),
                                icosahedron.indices.data(), icosahedron.numIndices()),
            PFX_OK);
  for (PfxUInt32 threads : {1u, 2u, 4u}) {
    PfxWorld world;
    buildScene(world, mesh, threads);
    for (int i = 0; i < kSteps; ++i) ASSERT_EQ(world.step(), PFX_OK);
    // The scene did what it is there for: bodies touch, and nothing left the floor's area.
    EXPECT_GT(world.getStats().numContactPoints, 40u);
    for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
      ASSERT_TRUE(pfxIsFinite(world.getRigidState(id).getPosition())) << id;
    }
    EXPECT_EQ(hex(hashOfState(world)), hex(kGoldenHash))
        << "on " << threads << " threads: the bits of the golden scene changed. If the change "
        << "that moved them was meant to (a new operation order, a different solver step, a "
        << "new constant), set kGoldenHash in tests/core/test_golden_state.cpp to the hash "
        << "above for this precision (" << sizeof(PfxFloat) * 8 << "-bit PfxFloat) and say "
        << "why in the commit. If not, the change altered results it was not meant to.";
  }
}
