// Cables and cloths of the real node (cables.test): a cable hung between the post and the
// world sags as the analytic catenary of its length, rays and ray batches hit cables and the
// cloth by name, the cloth lying on the pad is listed by get_contacts, the 1 kg cable hanging
// from the pendulum loads its hinge, a cloth fallen onto a cable lies on it, listed by
// get_contacts, the markers draw them, and a node given bad cables and cloths refuses each
// with its reason and starts with the rest.
#include <geometry_msgs/WrenchStamped.h>
#include <visualization_msgs/MarkerArray.h>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "pfx/DeleteModel.h"
#include "pfx/GetContacts.h"
#include "pfx/RaycastBatch.h"
#include "pfx_ros_test_util.h"

namespace {

const std::string kNode = "/pfx_node/";
const double kG = 9.80665;
const double kCableRadius = 0.01;
pfx_test::RosClient* client = nullptr;

// The latest message of a topic.
template <typename Msg>
class Latest {
 public:
  explicit Latest(const std::string& topic)
      : m_sub(client->nh.subscribe(topic, 10, &Latest::onMessage, this)) {}
  bool waitFor(int count, double wallSeconds) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (received() < count) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.01).sleep();
    }
    return true;
  }
  Msg latest() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_latest;
  }
  int received() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_count;
  }

 private:
  void onMessage(const Msg& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_latest = msg;
    ++m_count;
  }
  mutable std::mutex m_mutex;
  Msg m_latest;
  int m_count = 0;
  ros::Subscriber m_sub;
};

const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& array,
                                             const std::string& ns, int id) {
  for (const visualization_msgs::Marker& m : array.markers) {
    if (m.ns == ns && m.id == id) return &m;
  }
  return nullptr;
}

// The sag (m) below its ends of a catenary of `length` hanging between two points at the
// same height `span` apart: length = 2 a sinh(span / 2a), sag = a (cosh(span / 2a) - 1).
double catenarySag(double length, double span) {
  double lo = 1e-3, hi = 1e3;  // a: the length above decreases as a grows
  for (int i = 0; i < 200; ++i) {
    const double a = std::sqrt(lo * hi);
    (2 * a * std::sinh(span / (2 * a)) > length ? lo : hi) = a;
  }
  const double a = std::sqrt(lo * hi);
  return a * (std::cosh(span / (2 * a)) - 1);
}

// The node's answer to ~get_contacts for one link.
pfx::GetContacts::Response contactsOf(const std::string& link) {
  pfx::GetContacts contacts;
  contacts.request.link = link;
  return pfx_test::call(kNode + "get_contacts", contacts).response;
}

}  // namespace

// Runs first: the cables and the cloth settle while the simulation runs.
TEST(Cables, ACableBetweenTheFixedPostAndTheWorldSagsAsTheCatenary) {
  pfx_test::ClockWatcher clock(client->nh);
  ASSERT_TRUE(clock.waitUntil(8.0, 90));  // swings damped out, cloth at rest
  Latest<visualization_msgs::MarkerArray> markers(kNode + "markers");
  ASSERT_TRUE(markers.waitFor(1, 10));
  const visualization_msgs::MarkerArray array = markers.latest();
  const visualization_msgs::Marker* cable = findMarker(array, "cables", 0);
  ASSERT_NE(cable, nullptr);
  EXPECT_EQ(cable->type, visualization_msgs::Marker::LINE_STRIP);
  ASSERT_EQ(cable->points.size(), 41u);
  EXPECT_NEAR(cable->scale.x, 2 * kCableRadius, 1e-9);
  // Its ends stay where they are tied: the post's point (0, 0.5, 0) at 1 m, and the world's.
  EXPECT_NEAR(cable->points.front().x, 0, 1e-3);
  EXPECT_NEAR(cable->points.front().z, 1, 1e-3);
  EXPECT_NEAR(cable->points.back().x, 1.6, 1e-3);
  EXPECT_NEAR(cable->points.back().z, 1, 1e-3);
  geometry_msgs::Point lowest = cable->points.front();
  for (const geometry_msgs::Point& p : cable->points) {
    if (p.z < lowest.z) lowest = p;
    EXPECT_NEAR(p.y, 0.5, 1e-3);
  }
  const double sag = 1 - lowest.z;
  const double expected = catenarySag(2.0, 1.6);
  std::printf("catenary: lowest point %.5f m below the ends (analytic %.5f m), at x = %.4f\n",
              sag, expected, lowest.x);
  EXPECT_NEAR(sag, expected, 0.005);
  EXPECT_NEAR(lowest.x, 0.8, 0.05);

  // A ray straight down through the lowest particle's centre meets its top.
  const pfx::Raycast::Response hit =
      pfx_test::raycast(kNode + "raycast", lowest.x, lowest.y, 2, 0, 0, -2);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.link, "catenary");
  EXPECT_NEAR(hit.point.z, lowest.z + kCableRadius, 2e-3);  // it moves a little between calls
  EXPECT_NEAR(hit.normal.z, 1, 1e-2);
}

TEST(Cables, RaysAndBatchesHitTheCablesAndTheClothByName) {
  const pfx::Raycast::Response onCloth =
      pfx_test::raycast(kNode + "raycast", 1.0, 0.02, 1.0, 0, 0, -2);
  ASSERT_TRUE(onCloth.success) << onCloth.message;
  ASSERT_TRUE(onCloth.hit);
  EXPECT_EQ(onCloth.link, "drape");
  // The cloth's surface runs through its particles' centres, one radius above the pad's top.
  EXPECT_NEAR(onCloth.point.z, 0.1 + kCableRadius, 0.005);

  pfx::RaycastBatch batch;
  auto add = [&](double x, double y, double z, double dz) {
    geometry_msgs::Point origin;
    origin.x = x;
    origin.y = y;
    origin.z = z;
    geometry_msgs::Vector3 direction;
    direction.z = dz;
    batch.request.origins.push_back(origin);
    batch.request.directions.push_back(direction);
  };
  add(1.0, 0.02, 1.0, -2);   // the cloth on the pad
  add(0.0, 0.0, 0.35, -0.3);  // inside the payload cable's column, from above its end
  add(0.0, 0.0, 0.12, 0.03);  // up toward the payload cable's end, stopping short of it
  add(0.3, 0.5, 2.0, -3);     // down onto the catenary
  add(3.0, 3.0, 1.0, -0.5);   // nothing
  batch = pfx_test::call(kNode + "raycast_batch", batch);
  ASSERT_TRUE(batch.response.success) << batch.response.message;
  ASSERT_EQ(batch.response.links.size(), 5u);
  EXPECT_EQ(batch.response.links[0], "drape");
  EXPECT_EQ(batch.response.links[1], "payload");
  EXPECT_FALSE(batch.response.hit[2]);
  EXPECT_EQ(batch.response.links[3], "catenary");
  EXPECT_FALSE(batch.response.hit[4]);
  EXPECT_EQ(batch.response.links[4], "");
}

TEST(Cables, GetContactsListsTheClothLyingOnThePad) {
  const pfx::GetContacts::Response onPad = contactsOf("pad");
  ASSERT_TRUE(onPad.success) << onPad.message;
  int clothPoints = 0;
  for (const pfx::Contact& c : onPad.contacts) {
    EXPECT_EQ(c.link_a, "pad");
    if (c.link_b != "drape") continue;
    ++clothPoints;
    // On the pad's top (0.1 m), the normal from the pad up to the cloth.
    if (c.normal.z > 0.9) {
      EXPECT_NEAR(c.position.z, 0.1, 0.006);
    }
    EXPECT_LT(std::abs(c.depth), 0.006);
    EXPECT_GE(c.impulse, 0);
  }
  // The 7 x 7 particles over the pad's 0.2 m square, at least, rest on it.
  std::printf("cloth on the pad: %d contact points\n", clothPoints);
  EXPECT_GE(clothPoints, 25);

  const pfx::GetContacts::Response ofCloth = contactsOf("drape");
  ASSERT_TRUE(ofCloth.success) << ofCloth.message;
  int onPadFromCloth = 0;
  for (const pfx::Contact& c : ofCloth.contacts) {
    EXPECT_EQ(c.link_a, "drape");
    onPadFromCloth += c.link_b == "pad" ? 1 : 0;
  }
  EXPECT_EQ(onPadFromCloth, clothPoints);
}

TEST(Cables, TheCableHangingFromThePendulumLoadsItsHinge) {
  // The hinge's force-torque sensor (parent on child, child frame) carries the 2 kg pendulum
  // and the 1 kg cable: 3 g up.
  Latest<geometry_msgs::WrenchStamped> wrench("/hinge_wrench");
  double sum = 0;
  int samples = 0;
  for (int last = 0; samples < 20;) {
    ASSERT_TRUE(wrench.waitFor(last + 1, 10));
    last = wrench.received();
    sum += wrench.latest().wrench.force.z;
    ++samples;
  }
  const double mean = sum / samples;
  std::printf("hinge: %.4f N up over %d readings (pendulum and cable: %.4f N)\n", mean, samples,
              3 * kG);
  EXPECT_NEAR(mean, 3 * kG, 0.03 * 3 * kG);
}

TEST(Cables, TheMarkersDrawEveryCableAndTheCloth) {
  Latest<visualization_msgs::MarkerArray> markers(kNode + "markers");
  ASSERT_TRUE(markers.waitFor(1, 10));
  const visualization_msgs::MarkerArray array = markers.latest();
  const visualization_msgs::Marker* payload = findMarker(array, "cables", 1);
  ASSERT_NE(payload, nullptr);
  EXPECT_EQ(payload->points.size(), 11u);
  // It hangs straight down from 2 cm below the pendulum's tip at (0, 0, 0.5).
  EXPECT_NEAR(payload->points.front().z, 0.48, 2e-3);
  EXPECT_NEAR(payload->points.back().z, 0.18, 0.01);
  const visualization_msgs::Marker* cloth = findMarker(array, "cloths", 0);
  ASSERT_NE(cloth, nullptr);
  EXPECT_EQ(cloth->type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_EQ(cloth->points.size(), 10u * 10u * 2u * 3u);
  const visualization_msgs::Marker* line = findMarker(array, "cables", 2);
  ASSERT_NE(line, nullptr);
  EXPECT_EQ(line->points.size(), 31u);
  ASSERT_NE(findMarker(array, "cloths", 1), nullptr);
  EXPECT_EQ(findMarker(array, "cables", 3), nullptr);
  EXPECT_EQ(findMarker(array, "cloths", 2), nullptr);
}

// The cloth 'sheet' fell 20 cm onto the cable 'line' (0.61 m between two points of the world
// 0.6 m apart, at 0.5 m) and hangs over it: get_contacts lists their contacts from either
// side, and no particle of the cloth is below the cable where the two meet.
TEST(Cables, AClothFallenOntoACableLiesOnIt) {
  pfx_test::ClockWatcher clock(client->nh);
  ASSERT_TRUE(clock.waitUntil(2.0, 60));
  const pfx::GetContacts::Response ofSheet = contactsOf("sheet");
  ASSERT_TRUE(ofSheet.success) << ofSheet.message;
  int onLine = 0;
  double pushed = 0;
  for (const pfx::Contact& c : ofSheet.contacts) {
    EXPECT_EQ(c.link_a, "sheet");
    if (c.link_b != "line") continue;
    ++onLine;
    // From the cloth down to the cable, near the cable's height, the spheres touching.
    EXPECT_LT(c.normal.z, 0);
    EXPECT_NEAR(c.position.y, -0.6, 0.03);
    EXPECT_NEAR(c.position.z, 0.5, 0.06);
    EXPECT_LT(std::abs(c.depth), 0.002);
    EXPECT_GE(c.impulse, 0);
    pushed += c.impulse;
  }
  std::printf("cloth on the cable: %d contact points, %.6f N s of impulse\n", onLine, pushed);
  // It rests on the cable at several points (6 when this was written); its other contacts
  // with it, within reach but neither touching nor pushing, are not listed.
  EXPECT_GE(onLine, 3);
  EXPECT_GT(pushed, 0);

  const pfx::GetContacts::Response ofLine = contactsOf("line");
  ASSERT_TRUE(ofLine.success) << ofLine.message;
  int fromLine = 0;
  for (const pfx::Contact& c : ofLine.contacts) {
    EXPECT_EQ(c.link_a, "line");
    if (c.link_b != "sheet") continue;
    ++fromLine;
    EXPECT_GT(c.normal.z, 0);
  }
  EXPECT_EQ(fromLine, onLine);

  // Where the cloth crosses the cable (within the two radii of it across), every corner of
  // its triangles is above the cable's particle nearest along it.
  Latest<visualization_msgs::MarkerArray> markers(kNode + "markers");
  ASSERT_TRUE(markers.waitFor(1, 10));
  const visualization_msgs::MarkerArray array = markers.latest();
  const visualization_msgs::Marker* line = findMarker(array, "cables", 2);
  const visualization_msgs::Marker* sheet = findMarker(array, "cloths", 1);
  ASSERT_NE(line, nullptr);
  ASSERT_NE(sheet, nullptr);
  int over = 0;
  double lowestGap = 1e9;
  for (const geometry_msgs::Point& p : sheet->points) {
    const geometry_msgs::Point* nearest = &line->points.front();
    for (const geometry_msgs::Point& q : line->points) {
      if (std::abs(q.x - p.x) < std::abs(nearest->x - p.x)) nearest = &q;
    }
    if (std::abs(p.y - nearest->y) > 0.03) continue;
    ++over;
    lowestGap = std::min(lowestGap, p.z - nearest->z);
  }
  std::printf("cloth over the cable: %d corners within 3 cm across, the lowest %.4f m above it\n",
              over, lowestGap);
  EXPECT_GT(over, 0);
  EXPECT_GT(lowestGap, 0) << "a particle of the cloth passed through the cable";
}

TEST(Cables, TheRobotACableHoldsOnToIsNotDeleted) {
  pfx::DeleteModel remove;
  remove.request.name = "ft_bumper";
  const pfx::DeleteModel::Response refused =
      pfx_test::call(kNode + "delete_model", remove).response;
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("cable 'catenary' holds on to it"), std::string::npos)
      << refused.message;
  // Nothing went: its links answer by name, its sensor publishes.
  const pfx::GetContacts::Response pad = contactsOf("pad");
  EXPECT_TRUE(pad.success) << pad.message;
  EXPECT_FALSE(pad.contacts.empty());
  Latest<geometry_msgs::WrenchStamped> wrench("/hinge_wrench");
  EXPECT_TRUE(wrench.waitFor(2, 10));
}

// Last: the second node it starts publishes /clock while it runs.
TEST(Cables, BadCablesAndClothsAreRefusedAndTheNodeStartsWithTheRest) {
  const std::string ns = "/bad_cables";
  ros::param::set(ns + "/robot_description",
                  pfx_test::readText(PFX_SOURCE_DIR "/tests/ros/data/ft_bumper.urdf"));
  ros::param::set(ns + "/pfx_node/fixed_base", true);
  ros::param::set(ns + "/pfx_node/initial_height", 1.0);
  ros::param::set(ns + "/pfx_node/paused", true);
  const std::string cables =
      "[{name: nan_length, length: .nan},"
      " {name: negative_radius, radius: -0.01},"
      " {name: unknown_link, start_link: elbow},"
      " {name: no_segments, segments: 0},"
      " {name: huge_count, segments: 1000000},"
      " {name: too_short, start_point: [0, 0, 2], end_link: world, end_point: [5, 0, 2],"
      "  length: 1},"
      " {name: negative_mass, mass_per_metre: -1},"
      " {name: typo, lenght: 1},"
      " {name: pendulum, length: 1},"
      " {name: kept, start_point: [3, 3, 2], length: 0.5}]";
  const std::string cloths =
      "[{name: one_row, resolution: [1, 10]},"
      " {name: huge_cloth, resolution: [100000, 2]},"
      " {name: pinned_badly, pinned: [middle]},"
      " {name: kept, corner: [3, 3, 1]},"
      " {name: sheet, corner: [-3, 3, 1], pin_link: nowhere}]";
  for (const auto& [list, yaml] : {std::make_pair("cables", cables), std::make_pair("cloths", cloths)}) {
    const std::string command = "rosparam set " + ns + "/pfx_node/" + list + " '" + yaml + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  int status = 0;
  const std::string output = pfx_test::runCommand(
      "timeout 10 " PFX_NODE " __ns:=" + ns + " __name:=pfx_node 2>&1", status);
  // Still running when the timeout stopped it.
  EXPECT_EQ(WEXITSTATUS(status), 124) << output;
  const char* const expected[] = {
      "~cables[0] 'nan_length' refused, left out: length: nan m, must be above 0 to 100",
      "~cables[1] 'negative_radius' refused, left out: radius: -0.01 m, must be above 0 to 1",
      "~cables[2] 'unknown_link' refused, left out: start_link: no link or body named 'elbow'",
      "~cables[3] 'no_segments' refused, left out: segments: 0, must be a whole number from 1 "
      "to 1000",
      "~cables[4] 'huge_count' refused, left out: segments: 1000000",
      "~cables[5] 'too_short' refused, left out: length: 1 m, shorter than the 5 m between its "
      "two ends",
      "~cables[6] 'negative_mass' refused, left out: mass_per_metre: -1 kg/m",
      "~cables[7] 'typo' refused, left out: unknown key 'lenght'",
      "~cables[8] 'pendulum' refused, left out: name: 'pendulum' names a link",
      "~cables[9] 'kept' added",
      "~cloths[0] 'one_row' refused, left out: resolution[0]: 1, must be a whole number from 2",
      "~cloths[1] 'huge_cloth' refused, left out: resolution[0]: 100000",
      "~cloths[2] 'pinned_badly' refused, left out: pinned: 'middle' is none of",
      "~cloths[3] 'kept' refused, left out: name: 'kept' names a link, body, agent, cable or "
      "cloth already",
      "~cloths[4] 'sheet' refused, left out: pin_link: no link or body named 'nowhere'",
      "1 cables, 0 cloths",
  };
  for (const char* line : expected) {
    EXPECT_NE(output.find(line), std::string::npos) << "expected '" << line << "' in:\n"
                                                    << output;
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_cables");
  pfx_test::RosClient rosClient;
  client = &rosClient;
  if (!pfx_test::waitForServices({kNode + "raycast_batch", kNode + "get_contacts"}, 60)) {
    ADD_FAILURE() << "pfx_node's services did not come up";
    return 1;
  }
  return RUN_ALL_TESTS();
}
