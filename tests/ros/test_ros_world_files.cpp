// rostest (world_files.test): the ragdoll beside the obstacles of tests/ros/data/obstacles.xml,
// loaded through ~world_file. Rays name the scene file's bodies. ~save_world writes the
// running world; after it has run on, ~load_world brings it back: the clock returns to the
// saved time, /joint_states to the saved positions, and stepping goes on from there. Empty
// paths, missing, foreign and damaged files are refused with a reason, and the world, its
// clock and its state stay as they were.
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <mutex>

#include "pfx/WorldFile.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

const std::string kNode = "/pfx_node/";
pfx_test::RosClient* client = nullptr;  // made in main, once: it spins the callbacks

// The latest /joint_states message.
class JointStateWatcher {
 public:
  explicit JointStateWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/joint_states", 100, &JointStateWatcher::onState, this)) {}
  sensor_msgs::JointState latest() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_latest;
  }
  // Waits for a message stamped `seconds`; false after `wallSeconds`.
  bool waitForStamp(double seconds, double wallSeconds) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (latest().header.stamp.toSec() != seconds) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.01).sleep();
    }
    return true;
  }

 private:
  void onState(const sensor_msgs::JointState& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_latest = msg;
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  sensor_msgs::JointState m_latest;
};

pfx::WorldFile::Response worldFile(const std::string& service, const std::string& path) {
  pfx::WorldFile srv;
  srv.request.path = path;
  return call(kNode + service, srv).response;
}

bool trigger(const std::string& service) {
  std_srvs::Trigger srv;
  return call(kNode + service, srv).response.success;
}

// Pauses the node and waits until its last step's state is out: the clock then holds still.
double pauseAndSettle(const pfx_test::ClockWatcher& clock) {
  EXPECT_TRUE(trigger("pause"));
  ros::WallDuration(0.5).sleep();
  return clock.now();
}

std::string scratchPath(const std::string& name) {
  return "/tmp/pfx_world_files_" + std::to_string(::getpid()) + "_" + name;
}

}  // namespace

TEST(WorldFiles, SceneFileBodiesAreInTheWorldAndNamed) {
  const auto hit = pfx_test::raycast(kNode + "raycast", 0, 1.2, 0.5, 0, 5, 0);
  ASSERT_TRUE(hit.success) << hit.message;
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.link, "wall");
  EXPECT_NEAR(hit.point.y, 1.9, 1e-4) << "the wall's near face";
}

TEST(WorldFiles, SavedWorldComesBackWithItsClockAndState) {
  pfx_test::ClockWatcher clock(client->nh);
  JointStateWatcher joints(client->nh);
  ASSERT_TRUE(clock.waitUntil(0.3, 30)) << "the ragdoll is falling";
  const double savedTime = pauseAndSettle(clock);
  ASSERT_TRUE(joints.waitForStamp(savedTime, 10));
  const sensor_msgs::JointState saved = joints.latest();
  ASSERT_FALSE(saved.position.empty());

  const std::string path = scratchPath("ragdoll.pfxw");
  const auto save = worldFile("save_world", path);
  ASSERT_TRUE(save.success) << save.message;
  EXPECT_NE(save.message.find(path), std::string::npos) << save.message;

  ASSERT_TRUE(trigger("unpause"));
  ASSERT_TRUE(clock.waitUntil(savedTime + 0.5, 30));
  const double laterTime = pauseAndSettle(clock);
  ASSERT_TRUE(joints.waitForStamp(laterTime, 10));
  EXPECT_NE(joints.latest().position, saved.position) << "the ragdoll moved on";

  // Bad requests: refused with a reason, and the world stays at laterTime.
  const std::string garbage = scratchPath("garbage.pfxw");
  std::ofstream(garbage) << "a text file, longer than the 32 bytes of a world file's header";
  const std::string cut = scratchPath("cut.pfxw");
  {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 7);
  }
  const std::string foreign = scratchPath("foreign.pfxw");
  {
    pfx::PfxWorld world;
    pfx::pfxAddBody(world, pfx::pfxMakeShape(pfx::PfxBox(1, 1, 1)), pfx::PfxBodyInit());
    ASSERT_EQ(pfx::pfxSaveWorld(world, foreign.c_str()), pfx::PFX_OK);
  }
  struct Bad {
    std::string service, path, reason;
  };
  for (const Bad& bad :
       {Bad{"load_world", "", "no path"}, Bad{"save_world", "", "no path"},
        Bad{"load_world", scratchPath("missing.pfxw"), "missing.pfxw"},
        Bad{"load_world", garbage, "not a pfx world file"}, Bad{"load_world", cut, "cut.pfxw"},
        Bad{"load_world", foreign, "was not saved from this robot and scene"},
        Bad{"save_world", "/nonexistent-folder/world.pfxw", "nonexistent"}}) {
    const auto res = worldFile(bad.service, bad.path);
    EXPECT_FALSE(res.success) << bad.service << " " << bad.path;
    EXPECT_NE(res.message.find(bad.reason), std::string::npos)
        << bad.service << " " << bad.path << ": " << res.message;
  }
  ros::WallDuration(0.3).sleep();
  EXPECT_EQ(clock.now(), laterTime) << "refused loads leave the clock";
  EXPECT_EQ(joints.latest().header.stamp.toSec(), laterTime);

  // The saved world back: the clock and the joints return to the saved ones.
  const auto load = worldFile("load_world", path);
  ASSERT_TRUE(load.success) << load.message;
  ASSERT_TRUE(joints.waitForStamp(savedTime, 10)) << "the state at the saved time is published";
  EXPECT_EQ(joints.latest().name, saved.name);
  EXPECT_EQ(joints.latest().position, saved.position) << "the very positions that were saved";
  EXPECT_EQ(clock.now(), savedTime);

  // And it goes on from there.
  ASSERT_TRUE(trigger("unpause"));
  ASSERT_TRUE(clock.waitUntil(savedTime + 0.2, 30));
  for (const std::string& file : {path, garbage, cut, foreign}) std::remove(file.c_str());
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_world_files");
  pfx_test::RosClient rosClient;
  client = &rosClient;
  if (!pfx_test::waitForServices({kNode + "save_world", kNode + "load_world", kNode + "raycast"},
                                 60)) {
    ADD_FAILURE() << "pfx_node's services did not come up";
    return 1;
  }
  return RUN_ALL_TESTS();
}
