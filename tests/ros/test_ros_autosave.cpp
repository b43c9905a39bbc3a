// ~autosave_period, ~autosave_file and ~resume: pfx_node, started here as a process of our
// own in the namespace /crash, saves the falling ragdoll every 0.5 s of simulated time, is
// killed with SIGKILL, and started again with ~resume: the world it resumes is the last
// save, body by body and bit for bit, and its clock goes on from the save's time. Bad
// values and files stop it at startup with the reason.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "pfx/Step.h"
#include "pfx/WorldFile.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx_ros_test_util.h"

using pfx_test::call;

namespace {

pfx_test::RosClient* client = nullptr;  // made in main, once: it spins the callbacks
std::string folder;                     // a fresh folder for this run's files

std::string privateParam(const std::string& ns, const std::string& name) {
  return ns + "/pfx_node/" + name;
}

// The node's private parameters: those of an earlier start are deleted first.
void setAutosaveParams(const std::string& ns, double period, const std::string& file, bool resume,
                       bool paused) {
  ros::param::set(ns + "/robot_description",
                  pfx_test::readText(std::string(PFX_SOURCE_DIR) + "/urdf/ragdoll.urdf"));
  ros::param::del(ns + "/pfx_node");
  ros::param::set(privateParam(ns, "autosave_period"), period);
  ros::param::set(privateParam(ns, "autosave_file"), file);
  ros::param::set(privateParam(ns, "resume"), resume);
  ros::param::set(privateParam(ns, "paused"), paused);
  ros::param::set(privateParam(ns, "real_time_factor"), 2.0);
}

// pfx_node in namespace `ns`, its output in `log`; killed by the caller.
pid_t startNode(const std::string& ns, const std::string& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    ::dup2(::fileno(stdout), 2);
    const std::string nsArg = "__ns:=" + ns;
    ::execl(PFX_NODE, PFX_NODE, nsArg.c_str(), "__name:=pfx_node", static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  return pid;
}

// Kills `pid` with `signal` and returns its wait status.
int stopNode(pid_t pid, int signal) {
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

// Runs pfx_node in `ns` to its end (it must refuse its parameters within 30 s) and returns
// what it logged.
std::string runRefusedNode(const std::string& ns, int& status) {
  return pfx_test::runCommand("timeout 30 " PFX_NODE " __ns:=" + ns + " __name:=pfx_node 2>&1",
                              status);
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// Every body's pose and velocity, bit for bit, and the simulated time.
void expectSameWorld(const pfx::PfxWorld& a, const pfx::PfxWorld& b) {
  EXPECT_EQ(a.getSimulatedTime(), b.getSimulatedTime());
  ASSERT_EQ(a.getNumRigidBodies(), b.getNumRigidBodies());
  for (pfx::PfxUInt32 id = 0; id < a.getNumRigidBodies(); ++id) {
    const pfx::PfxRigidState& sa = a.getRigidState(id);
    const pfx::PfxRigidState& sb = b.getRigidState(id);
    EXPECT_EQ(sa.getPosition(), sb.getPosition()) << "body " << id;
    EXPECT_EQ(sa.getOrientation().coeffs(), sb.getOrientation().coeffs()) << "body " << id;
    EXPECT_EQ(sa.getLinearVelocity(), sb.getLinearVelocity()) << "body " << id;
    EXPECT_EQ(sa.getAngularVelocity(), sb.getAngularVelocity()) << "body " << id;
  }
}

bool loadWorld(const std::string& path, pfx::PfxWorld& world, pfx::PfxSerializedMeshes& meshes) {
  std::string error;
  const bool loaded = pfx::pfxLoadWorld(world, path.c_str(), meshes, &error) == pfx::PFX_OK;
  EXPECT_TRUE(loaded) << path << ": " << error;
  return loaded;
}

}  // namespace

TEST(Autosave, AfterSigkillTheNodeResumesFromTheLastSaveClockIncluded) {
  const std::string ns = "/crash";
  const std::string file = folder + "/ragdoll.pfxw";
  const double period = 0.5;
  setAutosaveParams(ns, period, file, false, false);
  pfx_test::ClockWatcher clock(client->nh);
  const pid_t first = startNode(ns, folder + "/first.log");
  ASSERT_TRUE(clock.waitUntil(2.2, 60)) << pfx_test::readText(folder + "/first.log");
  const int status = stopNode(first, SIGKILL);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "it was running until killed";
  EXPECT_FALSE(std::ifstream(file + ".tmp").good()) << "every save renamed its temporary file";

  pfx::PfxWorld saved;
  pfx::PfxSerializedMeshes savedMeshes;
  ASSERT_TRUE(loadWorld(file, saved, savedMeshes));
  const double savedTime = saved.getSimulatedTime();
  const double dt = saved.getParam().timeStep;
  EXPECT_GE(savedTime, 2.0 - dt / 2) << "the clock passed 2.2 s: the save at 2.0 s was made";
  EXPECT_NEAR(savedTime / period, std::round(savedTime / period), dt / 2 / period)
      << "saves fall on multiples of the period";

  // A save cut short by the crash lies beside the last good one: it is not read.
  const std::string good = bytesOf(file);
  writeBytes(file + ".tmp", good.substr(0, good.size() / 2));

  setAutosaveParams(ns, period, file, true, true);
  const std::string log = folder + "/resumed.log";
  const pid_t second = startNode(ns, log);
  ASSERT_TRUE(pfx_test::waitForServices({ns + "/pfx_node/step"}, 60)) << pfx_test::readText(log);
  EXPECT_NE(pfx_test::readText(log).find("continuing from " + file), std::string::npos)
      << pfx_test::readText(log);

  // The resumed world, written out before any step, is the saved one.
  pfx::WorldFile save;
  save.request.path = folder + "/resumed.pfxw";
  save = call(ns + "/pfx_node/save_world", save);
  ASSERT_TRUE(save.response.success) << save.response.message;
  pfx::PfxWorld resumed;
  pfx::PfxSerializedMeshes resumedMeshes;
  ASSERT_TRUE(loadWorld(save.request.path, resumed, resumedMeshes));
  expectSameWorld(saved, resumed);

  // Its clock goes on from the save's time, one step at a time. /clock is not latched: a
  // step published before our subscription reached the node is not seen, so the steps go on
  // until one is; /clock then holds that step's time (in whole nanoseconds).
  pfx_test::ClockWatcher resumedClock(client->nh);
  pfx::Step step;
  step.request.steps = 1;
  for (int taken = 1; taken <= 20; ++taken) {
    step = call(ns + "/pfx_node/step", step);
    ASSERT_TRUE(step.response.success) << step.response.message;
    EXPECT_NEAR(step.response.time, savedTime + taken * dt, 1e-9) << taken << " steps";
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(0.5);
    while (resumedClock.now() < 0 && ros::WallTime::now() < deadline) {
      ros::WallDuration(0.01).sleep();
    }
    if (resumedClock.now() >= 0) break;
  }
  EXPECT_NEAR(resumedClock.now(), step.response.time, 1e-9) << "/clock after the last step";
  stopNode(second, SIGTERM);
}

TEST(Autosave, ResumeWithoutASavedFileStartsAfresh) {
  const std::string ns = "/fresh";
  setAutosaveParams(ns, 0.5, folder + "/never_saved.pfxw", true, true);
  const std::string log = folder + "/fresh.log";
  const pid_t node = startNode(ns, log);
  ASSERT_TRUE(pfx_test::waitForServices({ns + "/pfx_node/step"}, 60)) << pfx_test::readText(log);
  pfx::Step step;
  step.request.steps = 1;
  step = call(ns + "/pfx_node/step", step);
  ASSERT_TRUE(step.response.success) << step.response.message;
  EXPECT_NEAR(step.response.time, 0.004, 1e-9) << "the clock starts at 0";
  EXPECT_NE(pfx_test::readText(log).find("starting afresh"), std::string::npos)
      << pfx_test::readText(log);
  stopNode(node, SIGTERM);
}

TEST(Autosave, BadValuesAndFilesAreRefusedAtStartup) {
  // A file of the ragdoll with one byte changed, and a world of another scene.
  const std::string source = folder + "/ragdoll.pfxw";
  ASSERT_TRUE(std::ifstream(source).good()) << "the crash test ran first and left its save";
  std::string bytes = bytesOf(source);
  bytes[bytes.size() / 2] ^= 0x55;
  const std::string damaged = folder + "/damaged.pfxw";
  writeBytes(damaged, bytes);
  const std::string foreign = folder + "/foreign.pfxw";
  {
    pfx::PfxWorld world;
    pfx::pfxAddBody(world, pfx::pfxMakeShape(pfx::PfxBox(1, 1, 1)), pfx::PfxBodyInit());
    ASSERT_EQ(pfx::pfxSaveWorld(world, foreign.c_str()), pfx::PFX_OK);
  }
  const std::string notAFolder = folder + "/plain_file";
  writeBytes(notAFolder, "a file, not a folder");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Bad {
    double period;
    std::string file;
    bool resume;
    std::string reason;
    bool withCable = false;
  };
  const std::vector<Bad> bads = {
      {-0.5, folder + "/a.pfxw", false, "~autosave_period must be a finite number"},
      {nan, folder + "/a.pfxw", false, "~autosave_period must be a finite number"},
      {0.5, "", false, "~autosave_file is not"},
      {0, "", true, "there is nothing to resume from"},
      {0.5, "/nonexistent-pfx-folder/a.pfxw", false, "cannot write in the folder"},
      {0.5, notAFolder + "/a.pfxw", false, "cannot write in the folder"},
      {0.5, damaged, true, "~resume refused: " + damaged},
      {0.5, foreign, true, "was not saved from this robot and scene"},
      {0.5, source, true, "~resume cannot be used with ~cables or ~cloths", true},
  };
  for (std::size_t i = 0; i < bads.size(); ++i) {
    const Bad& bad = bads[i];
    const std::string ns = "/bad" + std::to_string(i);
    setAutosaveParams(ns, bad.period, bad.file, bad.resume, true);
    if (bad.withCable) {
      XmlRpc::XmlRpcValue cables;
      cables[0]["name"] = std::string("hose");
      cables[0]["start_link"] = std::string("pelvis");
      ros::param::set(privateParam(ns, "cables"), cables);
    }
    int status = 0;
    const std::string output = runRefusedNode(ns, status);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 124)
        << "case " << i << " exits by itself, refusing: " << output;
    EXPECT_NE(output.find(bad.reason), std::string::npos) << "case " << i << ": " << output;
  }
  EXPECT_EQ(bytesOf(damaged), bytes) << "a refused file is left as it was";
}

// Starts a node with ~`name` set to each of `values` in turn, and expects it to exit by
// itself, saying `reason`.
template <typename Value>
void expectRefusedByName(const std::string& name, const std::vector<Value>& values,
                         const std::string& reason) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::string ns = "/bad_" + name + std::to_string(i);
    setAutosaveParams(ns, 0, "", false, true);
    ros::param::set(privateParam(ns, name), values[i]);
    int status = 0;
    const std::string output = runRefusedNode(ns, status);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 124)
        << "~" << name << " " << values[i] << " exits by itself, refusing: " << output;
    EXPECT_NE(output.find(reason), std::string::npos)
        << "~" << name << " " << values[i] << ": " << output;
  }
}

// The time step's bound is the world's (PFX_MAX_TIME_STEP); the node names the parameter.
TEST(Startup, ATimeStepOutsideTheWorldsRangeIsRefusedByName) {
  expectRefusedByName<double>("dt", {1000.0, 0.0, std::numeric_limits<double>::quiet_NaN()},
                              "~dt must be a positive number of seconds, at most 100");
}

// So is a thread count out of the task manager's range (PFX_MAX_THREADS).
TEST(Startup, AThreadCountOutsideTheRangeIsRefusedByName) {
  expectRefusedByName<int>("threads", {-1, 257},
                           "~threads must be a whole number from 0 (every core) to 256");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_autosave");
  pfx_test::RosClient rosClient;
  client = &rosClient;
  char pattern[] = "/tmp/pfx_autosave_XXXXXX";
  if (!::mkdtemp(pattern)) return 1;
  folder = pattern;
  const int result = RUN_ALL_TESTS();
  int removed = 0;
  pfx_test::runCommand("rm -rf " + folder, removed);
  return result;
}
