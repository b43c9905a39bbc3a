// The rigid-body scenes: stacks, a free spinning box, a rain of bodies into a container,
// and fast spheres at a thin wall. Stacks are built where their boxes rest in the
// undisturbed structure (faces touching, no drop), so that `stack_drift` measures from
// the built positions.
#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "bench_scene.h"

namespace pfxbench {

namespace {

constexpr double kCubeHalf = 0.5;  // stacks are made of 1 m cubes of 1 kg
constexpr double kCubeMass = 1;

void addGround(Scene& scene) {
  scene.bodies.push_back(makeFixedBody(ShapeDesc::box(Vec3(50, 0.5, 50)), Vec3(0, -0.5, 0)));
}

void addCube(Scene& scene, double x, int layer) {
  scene.bodies.push_back(makeDynamicBody(ShapeDesc::box(Vec3::Constant(kCubeHalf)), kCubeMass,
                                         Vec3(x, kCubeHalf + layer * 2 * kCubeHalf, 0)));
}

// Uniform in [0, 1) from the generator's raw output, so that the scene is the same with
// every standard library (std::uniform_real_distribution is not specified bit for bit).
double uniform(std::mt19937& rng) { return rng() / 4294967296.0; }

// Uniformly distributed rotation (Shoemake's method).
Quat randomRotation(std::mt19937& rng) {
  const double u1 = uniform(rng), u2 = 2 * kPi * uniform(rng), u3 = 2 * kPi * uniform(rng);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return Quat(a * std::cos(u2), a * std::sin(u2), b * std::sin(u3), b * std::cos(u3));
}

}  // namespace

// 210 cubes in 20 layers, 20 at the base, each resting on the two below it; rows are
// spaced 2 cm apart so that neighbours in a layer do not touch.
void buildPyramidScene(std::vector<Scene>& variants) {
  Scene scene;
  scene.name = "pyramid";
  scene.duration = 5;
  scene.metrics = {Metric::StackDrift, Metric::PenetrationMax};
  addGround(scene);
  const int base = 20;
  const double pitch = 2 * kCubeHalf + 0.02;
  for (int layer = 0; layer < base; ++layer) {
    const int count = base - layer;
    for (int i = 0; i < count; ++i) addCube(scene, (i - 0.5 * (count - 1)) * pitch, layer);
  }
  variants.push_back(scene);
}

void buildTowerScene(std::vector<Scene>& variants) {
  Scene scene;
  scene.name = "tower";
  scene.duration = 5;
  scene.metrics = {Metric::StackDrift, Metric::PenetrationMax, Metric::PositionError};
  addGround(scene);
  for (int layer = 0; layer < 30; ++layer) addCube(scene, 0, layer);
  variants.push_back(scene);
}

// A 1 x 0.5 x 0.25 m box of 1 kg spun at 10 rad/s about its intermediate axis (Y), with
// 0.02 rad/s about X to seed the Dzhanibekov flip, which comes after about a second.
void buildSpinnerScene(std::vector<Scene>& variants) {
  Scene scene;
  scene.name = "spinner";
  scene.gravity = Vec3::Zero();
  scene.duration = 10;
  scene.metrics = {Metric::EnergyDrift, Metric::MomentumDrift, Metric::PositionError};
  BodyDesc box = makeDynamicBody(ShapeDesc::box(Vec3(0.5, 0.25, 0.125)), 1, Vec3::Zero());
  box.angularVelocity = Vec3(0.02, 10, 0);
  scene.bodies.push_back(box);
  variants.push_back(scene);
}

// 4,000 bodies, spheres of 10 cm radius and cubes of 16 cm side alternating, on a
// 20 x 20 x 10 grid with a little jitter and random orientation, dropped into a 6 x 6 m
// container with 2.5 m walls. Density 1000 kg/m^3. The grid leaves every pair of
// neighbours, and the walls, apart whatever the orientation (a cube's corners reach
// 0.139 m from its centre).
void buildRainScene(std::vector<Scene>& variants) {
  Scene scene;
  scene.name = "rain";
  scene.duration = 5;
  scene.metrics = {Metric::PenetrationMax, Metric::Escaped};

  const double inner = 3, wallHalf = 0.25, wallHeight = 2.5;
  scene.bodies.push_back(makeFixedBody(ShapeDesc::box(Vec3(inner + 2 * wallHalf, wallHalf,
                                                           inner + 2 * wallHalf)),
                                       Vec3(0, -wallHalf, 0)));
  const double wallY = 0.5 * wallHeight;
  const ShapeDesc wallX = ShapeDesc::box(Vec3(wallHalf, 0.5 * wallHeight, inner + 2 * wallHalf));
  const ShapeDesc wallZ = ShapeDesc::box(Vec3(inner, 0.5 * wallHeight, wallHalf));
  scene.bodies.push_back(makeFixedBody(wallX, Vec3(inner + wallHalf, wallY, 0)));
  scene.bodies.push_back(makeFixedBody(wallX, Vec3(-inner - wallHalf, wallY, 0)));
  scene.bodies.push_back(makeFixedBody(wallZ, Vec3(0, wallY, inner + wallHalf)));
  scene.bodies.push_back(makeFixedBody(wallZ, Vec3(0, wallY, -inner - wallHalf)));
  scene.keepInside.min = Vec3(-inner, 0, -inner);
  scene.keepInside.max = Vec3(inner, std::numeric_limits<double>::infinity(), inner);

  const double density = 1000, pitch = 0.29, jitter = 0.005;
  const ShapeDesc sphere = ShapeDesc::sphere(0.1);
  const ShapeDesc cube = ShapeDesc::box(Vec3::Constant(0.08));
  std::mt19937 rng(20240601u);
  for (int layer = 0; layer < 10; ++layer) {
    for (int i = 0; i < 20; ++i) {
      for (int k = 0; k < 20; ++k) {
        const Vec3 position(pitch * (i - 9.5) + jitter * (2 * uniform(rng) - 1),
                            1.0 + 0.3 * layer,
                            pitch * (k - 9.5) + jitter * (2 * uniform(rng) - 1));
        const ShapeDesc& shape = ((i + k + layer) % 2 == 0) ? sphere : cube;
        const Quat orientation = randomRotation(rng);
        scene.bodies.push_back(
            makeDynamicBody(shape, density * shape.volume(), position, orientation));
      }
    }
  }
  variants.push_back(scene);
}

// Scaling: n spheres of 10 cm radius, 1,000 kg/m^3, resting on a fixed ground box on a
// square grid 25 cm apart, each touching the ground and none its neighbours, for n =
// 1,000, 10,000 and 100,000. Nothing should move; the step time shows how the cost grows
// with n, and bytes_per_body what the engine holds per body.
void buildSpheresScene(std::vector<Scene>& variants) {
  const double radius = 0.1, pitch = 0.25;
  for (const int n : {1000, 10000, 100000}) {
    Scene scene;
    scene.name = "spheres";
    scene.variant = std::to_string(n / 1000) + "k";
    scene.duration = 1;
    scene.metrics = {Metric::StackDrift, Metric::PenetrationMax, Metric::BytesPerBody};
    const int side = static_cast<int>(std::ceil(std::sqrt(double(n))));
    const double half = 0.5 * side * pitch + 1;
    scene.bodies.push_back(makeFixedBody(ShapeDesc::box(Vec3(half, 0.5, half)), Vec3(0, -0.5, 0)));
    const ShapeDesc sphere = ShapeDesc::sphere(radius);
    for (int i = 0; i < n; ++i) {
      const Vec3 position(pitch * (i % side - 0.5 * (side - 1)), radius,
                          pitch * (i / side - 0.5 * (side - 1)));
      scene.bodies.push_back(makeDynamicBody(sphere, 1000 * sphere.volume(), position));
    }
    variants.push_back(scene);
  }
}

// Ten steel spheres of 2 cm diameter at 100 m/s toward a fixed wall 1 cm thick, without
// gravity. They start at staggered distances so that they meet the wall at different
// phases of the time step, on parallel paths 10 cm apart so that they never touch.
void buildBulletScene(std::vector<Scene>& variants) {
  Scene scene;
  scene.name = "bullet";
  scene.gravity = Vec3::Zero();
  scene.duration = 1;
  scene.metrics = {Metric::Escaped};
  const double wallHalfThickness = 0.005;
  scene.bodies.push_back(
      makeFixedBody(ShapeDesc::box(Vec3(wallHalfThickness, 0.5, 0.5)), Vec3::Zero()));
  scene.keepInside.max.x() = wallHalfThickness;

  const ShapeDesc sphere = ShapeDesc::sphere(0.01);
  const double mass = 7800 * sphere.volume();
  for (int i = 0; i < 10; ++i) {
    const Vec3 start(-1 - 0.1371 * i, 0.1 * (i % 5) - 0.2, 0.1 * (i / 5) - 0.05);
    BodyDesc body = makeDynamicBody(sphere, mass, start);
    body.linearVelocity = Vec3(100, 0, 0);
    scene.bodies.push_back(body);
  }
  variants.push_back(scene);
}

}  // namespace pfxbench
