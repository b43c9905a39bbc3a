// Which URDF link a contact point or a ray hit lies on: a body that lumps several links (a
// massless helper between a joint and the link that carries the geometry, a massless pad
// fixed to it, a massless sensor leaf carried as a frame) holds the shapes of all of them,
// and PfxUrdfModel::shapeLinks names the link each shape's <collision> belongs to.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_urdf_loader.h"

using namespace pfx;

namespace {

// `link1_14` is a massless helper between joint1 and link1, which carries link1's mass and
// box; `link1_pad` (massless, a sphere) is fixed to link1; `sensor` is a massless leaf on a
// revolute joint of the base. Everything lies flat, 0.1 m thick, along +X.
const char* const kHelperRobot = R"(<robot name="helpers">
  <link name="base">
    <inertial><mass value="2"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
    <collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision>
  </link>
  <link name="link1_14"/>
  <link name="link1">
    <inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><origin xyz="0.2 0 0"/><geometry><box size="0.2 0.1 0.1"/></geometry></collision>
  </link>
  <link name="link1_pad">
    <collision><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <link name="sensor">
    <collision><geometry><sphere radius="0.03"/></geometry></collision>
  </link>
  <joint name="joint1" type="revolute">
    <parent link="base"/><child link="link1_14"/><origin xyz="0.2 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <joint name="link1_14_to_link1" type="fixed">
    <parent link="link1_14"/><child link="link1"/>
  </joint>
  <joint name="link1_to_pad" type="fixed">
    <parent link="link1"/><child link="link1_pad"/><origin xyz="0.4 0 0"/>
  </joint>
  <joint name="sensor_pan" type="revolute">
    <parent link="base"/><child link="sensor"/><origin xyz="-0.1 0 0.08"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>)";

void initZUpWorld(PfxWorld& world) {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.81));
  ASSERT_EQ(world.initialize(param), PFX_OK);
}

std::string linkOf(const PfxUrdfModel& model, PfxUInt32 bodyId, PfxUInt32 shapeIndex) {
  const PfxInt32 link = pfxFindUrdfShapeLink(model, bodyId, shapeIndex);
  return link < 0 ? "" : model.links[link].name;
}

// The link a vertical ray from above (x, y) hits first, "" on a miss or a body of no link.
std::string linkHitFromAbove(PfxWorld& world, const PfxUrdfModel& model, PfxFloat x, PfxFloat y) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = PfxVector3(x, y, 2);
  ray.m_direction = PfxVector3(0, 0, -4);
  PfxRayOutput hit;
  EXPECT_EQ(world.castRay(ray, hit), PFX_OK);
  if (!hit.m_contactFlag) return "";
  return linkOf(model, hit.m_objectId, hit.m_shapeId);
}

}  // namespace

TEST(UrdfShapeLinks, RayHitsNameTheLinkWhoseCollisionWasHit) {
  PfxWorld world;
  ASSERT_NO_FATAL_FAILURE(initZUpWorld(world));
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.rootPosition = PfxVector3(0, 0, 1);
  std::string message;
  ASSERT_EQ(pfxLoadUrdfString(world, kHelperRobot, ".", param, model, &message), PFX_OK) << message;
  ASSERT_EQ(model.numBodies, 2u);
  ASSERT_EQ(model.shapeLinks.size(), model.numBodies);

  const PfxUInt32 armBody = model.links[pfxFindUrdfLink(model, "link1")].bodyId;
  // The helper, link1 and the pad share one body; the sensor rides on the base's.
  EXPECT_EQ(model.links[pfxFindUrdfLink(model, "link1_14")].bodyId, armBody);
  EXPECT_EQ(world.getCollidable(armBody).getNumShapes(), 2u);
  EXPECT_EQ(linkHitFromAbove(world, model, 0, 0), "base");
  EXPECT_EQ(linkHitFromAbove(world, model, -0.1f, 0), "sensor");
  EXPECT_EQ(linkHitFromAbove(world, model, 0.4f, 0), "link1");
  EXPECT_EQ(linkHitFromAbove(world, model, 0.6f, 0), "link1_pad");
  // No shape of the helper: no index maps to it.
  for (const std::vector<PfxInt32>& links : model.shapeLinks) {
    for (const PfxInt32 link : links) {
      ASSERT_GE(link, 0);
      EXPECT_NE(model.links[link].name, "link1_14");
    }
  }
}

TEST(UrdfShapeLinks, ContactsOnTheGroundNameTheLinksThatTouchIt) {
  PfxWorld world;
  ASSERT_NO_FATAL_FAILURE(initZUpWorld(world));
  PfxBodyInit groundInit;
  groundInit.mass = 0;
  groundInit.position = PfxVector3(0, 0, -0.5f);
  PfxUInt32 ground = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(5, 5, 0.5f)), groundInit, &ground), PFX_OK);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.rootPosition = PfxVector3(0, 0, PfxFloat(0.1));
  std::string message;
  ASSERT_EQ(pfxLoadUrdfString(world, kHelperRobot, ".", param, model, &message), PFX_OK) << message;
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);

  std::set<std::string> touching;
  for (PfxUInt32 p = 0; p < world.getNumContactPairs(); ++p) {
    const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(p));
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      const PfxContactPoint& point = manifold.getContactPoint(i);
      const PfxUInt32 idA = manifold.getRigidBodyIdA();
      const PfxUInt32 idB = manifold.getRigidBodyIdB();
      ASSERT_TRUE(idA == ground || idB == ground);
      touching.insert(idA == ground ? linkOf(model, idB, point.m_shapeIdB)
                                    : linkOf(model, idA, point.m_shapeIdA));
    }
  }
  EXPECT_EQ(touching, (std::set<std::string>{"base", "link1", "link1_pad"}));
  // Bodies and shapes the model did not make name no link.
  EXPECT_EQ(pfxFindUrdfShapeLink(model, ground, 0), -1);
  EXPECT_EQ(pfxFindUrdfShapeLink(model, model.firstBodyId, 7), -1);
  EXPECT_EQ(pfxFindUrdfShapeLink(model, model.firstBodyId + model.numBodies, 0), -1);
}

TEST(UrdfShapeLinks, ABodyWithoutGeometryHasOnlyItsPlaceholder) {
  PfxWorld world;
  ASSERT_NO_FATAL_FAILURE(initZUpWorld(world));
  PfxUrdfModel model;
  const std::string xml = R"(<robot name="bare"><link name="lonely">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link></robot>)";
  std::string message;
  ASSERT_EQ(pfxLoadUrdfString(world, xml, ".", PfxUrdfLoadParam(), model, &message), PFX_OK)
      << message;
  ASSERT_EQ(model.shapeLinks.size(), 1u);
  EXPECT_EQ(model.shapeLinks[0], std::vector<PfxInt32>{-1});
  EXPECT_EQ(pfxFindUrdfShapeLink(model, model.firstBodyId, 0), -1);
}
