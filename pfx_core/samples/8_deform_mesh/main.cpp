// Sample 8_deform_mesh: a large mesh whose vertices move after every step. A 40 x 40 grid
// of 0.5 m cells (3,200 triangles) carries a travelling wave, y = A sin(k x - w t) cos(k z),
// and a mix of boxes, spheres, capsules and cylinders rests on it. After each step the
// application writes the new vertices through PfxWorld::updateLargeTriMesh, which refits
// the mesh, carries the contact points on it by their corner weights, and puts any body the
// wave pushed deeper back onto the surface. Prints what it measured: the deepest overlap
// the solver saw, the lowest point of any body relative to the surface under it, and
// whether any body fell through.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"

using namespace pfx;

namespace {

constexpr int kCells = 40;
constexpr PfxFloat kCell = 0.5f;
constexpr PfxFloat kAmplitude = 0.4f;
constexpr PfxFloat kWaveNumber = 0.6f;  // rad/m
constexpr PfxFloat kAngularSpeed = 1.5f;  // rad/s

PfxFloat waveHeight(PfxFloat x, PfxFloat z, PfxFloat t) {
  return kAmplitude * std::sin(kWaveNumber * x - kAngularSpeed * t) * std::cos(kWaveNumber * z);
}

void writeVertices(std::vector<PfxFloat>& vertices, PfxFloat t) {
  const PfxFloat origin = -kCells * kCell / 2;
  std::size_t k = 0;
  for (int j = 0; j <= kCells; ++j) {
    for (int i = 0; i <= kCells; ++i) {
      const PfxFloat x = origin + PfxFloat(i) * kCell;
      const PfxFloat z = origin + PfxFloat(j) * kCell;
      vertices[k++] = x;
      vertices[k++] = waveHeight(x, z, t);
      vertices[k++] = z;
    }
  }
}

// Height of the triangulated surface (not the smooth wave) under (x, z).
PfxFloat surfaceHeight(const PfxLargeTriMesh& mesh, PfxFloat x, PfxFloat z) {
  PfxFloat fraction;
  PfxVector3 normal;
  PfxUInt32 triangle;
  if (!pfxRayCastLargeTriMesh(mesh, PfxVector3(x, 10, z), PfxVector3(0, -20, 0), fraction, normal,
                              triangle)) {
    return -1e9f;
  }
  return 10 - 20 * fraction;
}

}  // namespace

int main() {
  std::vector<PfxFloat> vertices(3 * (kCells + 1) * (kCells + 1));
  std::vector<PfxUInt32> triangles;
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      const PfxUInt32 a = j * (kCells + 1) + i, b = a + 1, d = a + kCells + 1, c = d + 1;
      triangles.insert(triangles.end(), {a, d, c, a, c, b});
    }
  }
  writeVertices(vertices, 0);
  PfxCreateLargeTriMeshParam meshParam;
  meshParam.m_vertices = vertices.data();
  meshParam.m_numVertices = static_cast<PfxUInt32>(vertices.size() / 3);
  meshParam.m_triangles = triangles.data();
  meshParam.m_numTriangles = static_cast<PfxUInt32>(triangles.size() / 3);
  meshParam.m_flags = PFX_MESH_FLAG_USE_BVH;
  // The seed's "largish thickness": a body the wave overtakes within a step is still
  // inside the prism below the face, and goes back up rather than through.
  meshParam.m_thickness = 0.5f;
  PfxLargeTriMesh mesh;
  if (pfxCreateLargeTriMesh(mesh, meshParam) != PFX_OK) return 1;

  PfxWorld world;
  PfxWorldParam param;
  param.worldExtent = PfxVector3::Constant(40);
  world.initialize(param);
  PfxShape groundShape;
  groundShape.reset();
  groundShape.setLargeTriMesh(&mesh);
  PfxBodyInit groundInit;
  groundInit.mass = 0;
  PfxUInt32 ground = 0;
  pfxAddBody(world, groundShape, groundInit, &ground);

  const PfxShape shapes[4] = {pfxMakeShape(PfxBox(0.3f, 0.2f, 0.25f)), pfxMakeShape(PfxSphere(0.25f)),
                              pfxMakeShape(PfxCapsule(0.3f, 0.15f)),
                              pfxMakeShape(PfxCylinder(0.2f, 0.25f))};
  const PfxUInt32 firstBody = world.getNumRigidBodies();
  for (int i = 0; i < 36; ++i) {
    PfxBodyInit init;
    const PfxFloat x = -7.5f + 3 * PfxFloat(i % 6), z = -7.5f + 3 * PfxFloat(i / 6);
    init.position = PfxVector3(x, waveHeight(x, z, 0) + 0.6f, z);
    pfxAddBody(world, shapes[i % 4], init);
  }

  const PfxFloat dt = param.timeStep;
  const int steps = 600;  // 10 s
  PfxFloat deepest = 0;
  PfxFloat lowestGap = 1e9f;
  int fellThrough = 0;
  for (int s = 1; s <= steps; ++s) {
    world.step();
    deepest = std::max(deepest, world.getStats().maxPenetration);
    writeVertices(vertices, PfxFloat(s) * dt);
    world.updateLargeTriMesh(ground, mesh, vertices.data(), meshParam.m_numVertices);
    if (s < 60) continue;  // settling
    for (PfxUInt32 id = firstBody; id < world.getNumRigidBodies(); ++id) {
      const PfxRigidState& state = world.getRigidState(id);
      const PfxShape& shape = world.getCollidable(id).getShape(0);
      const PfxVector3 lowest =
          pfxGetSupportPoint(shape, state.getTransform() * shape.getOffsetTransform(),
                             PfxVector3(0, -1, 0));
      const PfxFloat surface = surfaceHeight(mesh, lowest.x(), lowest.z());
      if (surface < -1e8f) continue;  // rolled off the edge
      const PfxFloat gap = lowest.y() - surface;
      lowestGap = std::min(lowestGap, gap);
      if (gap < -meshParam.m_thickness) ++fellThrough;
    }
  }
  int onMesh = 0;
  for (PfxUInt32 id = firstBody; id < world.getNumRigidBodies(); ++id) {
    const PfxVector3 p = world.getRigidState(id).getPosition();
    if (surfaceHeight(mesh, p.x(), p.z()) > -1e8f) ++onMesh;
  }
  std::printf("8_deform_mesh: %u triangles waving %.1f m high for %.0f s, %d bodies\n",
              mesh.m_numTriangles, 2 * kAmplitude, steps * dt,
              int(world.getNumRigidBodies() - firstBody));
  std::printf("deepest penetration seen by the solver: %.4f m\n", deepest);
  std::printf("lowest body point relative to the surface under it: %+.4f m\n", lowestGap);
  std::printf("bodies still over the mesh at the end: %d\n", onMesh);
  std::printf("fell through: %s\n", fellThrough ? "yes" : "no");
  pfxReleaseLargeTriMesh(mesh);
  return fellThrough ? 1 : 0;
}
