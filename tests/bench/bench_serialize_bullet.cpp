// The serialize scene on Bullet: the bodies in a btDiscreteDynamicsWorld sharing one sphere
// and one box shape, written with btDefaultSerializer and read back into a fresh world with
// btBulletWorldImporter (Debian's libbullet-extras-dev).
#include <BulletWorldImporter/btBulletWorldImporter.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>

#include "bench_rays.h"
#include "bench_serialize.h"

namespace pfxbench {

namespace {

// A dynamics world and everything it refers to, released in the right order.
struct BulletWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motionStates;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  BulletWorld() { world.setGravity(btVector3(0, btScalar(-9.80665), 0)); }
  ~BulletWorld() {
    for (auto& body : bodies) world.removeRigidBody(body.get());
  }

  void add(btCollisionShape* shape, btScalar mass, const btVector3& position) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    motionStates.push_back(
        std::make_unique<btDefaultMotionState>(btTransform(btQuaternion::getIdentity(), position)));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motionStates.back().get(), shape, inertia);
    bodies.push_back(std::make_unique<btRigidBody>(info));
    world.addRigidBody(bodies.back().get());
  }
};

btVector3 bodyPosition(const btCollisionObject* object) {
  return object->getWorldTransform().getOrigin();
}

}  // namespace

bool runBulletSerialize(const std::vector<SerializeBody>& bodies, SerializeFigures& figures,
                        std::string& error) {
  BulletWorld original;
  double extent = 1;
  for (const SerializeBody& body : bodies) {
    extent = std::max({extent, std::abs(body.x) + 1, std::abs(body.z) + 1});
  }
  original.shapes.push_back(std::make_unique<btBoxShape>(
      btVector3(btScalar(extent), btScalar(kSerializeGroundHalfHeight), btScalar(extent))));
  original.add(original.shapes.back().get(), 0,
               btVector3(0, btScalar(-kSerializeGroundHalfHeight), 0));
  const btScalar half = btScalar(kSerializeBodyHalfSize);
  original.shapes.push_back(std::make_unique<btSphereShape>(half));
  btCollisionShape* sphere = original.shapes.back().get();
  original.shapes.push_back(std::make_unique<btBoxShape>(btVector3(half, half, half)));
  btCollisionShape* cube = original.shapes.back().get();
  for (const SerializeBody& body : bodies) {
    original.add(body.sphere ? sphere : cube, 1,
                 btVector3(btScalar(body.x), btScalar(body.y), btScalar(body.z)));
  }
  for (int i = 0; i < kSerializeSteps; ++i) original.world.stepSimulation(btScalar(1.0 / 60), 0);

  const TemporaryFile file("pfx_bench_serialize_bullet");
  figures.writeSeconds = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < kSerializeTimedPasses; ++pass) {
    const double start = processCpuSeconds();
    btDefaultSerializer serializer;
    original.world.serialize(&serializer);
    std::FILE* out = std::fopen(file.path().c_str(), "wb");
    if (!out) {
      error = "cannot write " + file.path();
      return false;
    }
    const std::size_t size = std::size_t(serializer.getCurrentBufferSize());
    const bool written = std::fwrite(serializer.getBufferPointer(), 1, size, out) == size;
    std::fclose(out);
    figures.writeSeconds = std::min(figures.writeSeconds, processCpuSeconds() - start);
    if (!written) {
      error = "cannot write " + file.path();
      return false;
    }
    figures.fileBytes = double(size);
  }

  figures.readSeconds = std::numeric_limits<double>::infinity();
  figures.restored = true;
  for (int pass = 0; pass < kSerializeTimedPasses; ++pass) {
    BulletWorld copy;
    const double start = processCpuSeconds();
    std::ifstream in(file.path(), std::ios::binary);
    std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    btBulletWorldImporter importer(&copy.world);
    const bool loaded = importer.loadFileFromMemory(data.data(), int(data.size()));
    figures.readSeconds = std::min(figures.readSeconds, processCpuSeconds() - start);
    if (!loaded) {
      error = "btBulletWorldImporter could not read " + file.path();
      return false;
    }
    const btCollisionObjectArray& before = original.world.getCollisionObjectArray();
    const btCollisionObjectArray& after = copy.world.getCollisionObjectArray();
    if (after.size() != before.size()) {
      figures.restored = false;
    } else {
      for (int i = 0; i < before.size(); ++i) {
        if (bodyPosition(before[i]) != bodyPosition(after[i])) figures.restored = false;
      }
    }
    importer.deleteAllData();
  }
  return true;
}

}  // namespace pfxbench
