// The node under load: two pfx_nodes simulate the ragdoll paused, /quiet and /loaded (each
// with its own /tf and /diagnostics), markers on. While ~clients threads call every service
// of /loaded as fast as it answers for ~load_seconds, mixing read-only requests and bad
// ones (NaN, unknown names, a batch beyond ~max_batch_rays, ...), this program drives
// /loaded with joint commands, wrenches and ~step; then it drives /quiet the same way
// without load. Service calls are answered between steps, so both must end in the same
// state, bit for bit (joint_states and TF). Then /loaded runs at real-time factor 1 under
// the same load for ~running_seconds. Checked throughout: no call goes unanswered, every
// bad request gets success false and its reason, every good one success true, and the
// node's resident memory stays flat. Figures (calls per second, the real-time factor the
// node reached, RSS at start and end) go to the test's output and to ~report_file.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/network.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <trajectory_msgs/JointTrajectory.h>
#include <unistd.h>
#include <visualization_msgs/MarkerArray.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "pfx/ApplyBodyWrench.h"
#include "pfx/DeleteAgent.h"
#include "pfx/GetContacts.h"
#include "pfx/GetPhysics.h"
#include "pfx/Raycast.h"
#include "pfx/RaycastBatch.h"
#include "pfx/SetBodyState.h"
#include "pfx/SetJointCommand.h"
#include "pfx/SetPhysics.h"
#include "pfx/SpawnAgent.h"
#include "pfx/Step.h"
#include "pfx/WorldFile.h"
#include "pfx_ros_test_util.h"

namespace {

pfx_test::RosClient* client = nullptr;  // made in main, once: it spins the callbacks
double loadSeconds = 6;                 // ~load_seconds: the paused phase, driven by ~step
double runningSeconds = 5;              // ~running_seconds: the running phase, real-time factor 1
int numClients = 4;                     // ~clients: threads calling the services
std::string reportFile;  // ~report_file: where the figures go too (none: output only)
const double kNan = std::numeric_limits<double>::quiet_NaN();
// The RSS the node may gain between the first second of load and the end: buffers that
// grow to the largest request have grown by then, so what comes after is a leak.
const double kMaxRssGrowthMb = 16;

// The latest message of a topic.
template <typename Msg>
class Latest {
 public:
  explicit Latest(const std::string& topic)
      : m_sub(client->nh.subscribe(topic, 100, &Latest::onMessage, this)) {}
  Msg get() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_latest;
  }
  long count() const { return m_count.load(); }

 private:
  void onMessage(const Msg& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_latest = msg;
    ++m_count;
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  Msg m_latest;
  std::atomic<long> m_count{0};
};

// Every link's latest transform on one node's /tf.
class TfRecord {
 public:
  explicit TfRecord(const std::string& topic)
      : m_sub(client->nh.subscribe(topic, 1000, &TfRecord::onMessage, this)) {}
  std::map<std::string, geometry_msgs::Transform> get() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_frames;
  }

 private:
  void onMessage(const tf2_msgs::TFMessage& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (const auto& t : msg.transforms) m_frames[t.child_frame_id] = t.transform;
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  std::map<std::string, geometry_msgs::Transform> m_frames;
};

bool sameTransform(const geometry_msgs::Transform& a, const geometry_msgs::Transform& b) {
  return a.translation.x == b.translation.x && a.translation.y == b.translation.y &&
         a.translation.z == b.translation.z && a.rotation.x == b.rotation.x &&
         a.rotation.y == b.rotation.y && a.rotation.z == b.rotation.z &&
         a.rotation.w == b.rotation.w;
}

// The process id of a node, from its own XML-RPC server.
int pidOf(const std::string& node) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return -1;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return -1;
  XmlRpc::XmlRpcClient rpc(host.c_str(), int(port), "/");
  XmlRpc::XmlRpcValue pidArgs, pidResult;
  pidArgs[0] = ros::this_node::getName();
  if (!rpc.execute("getPid", pidArgs, pidResult) || pidResult.size() < 3) return -1;
  return static_cast<int>(pidResult[2]);
}

// Resident memory of a process (MB), from /proc; negative when it is gone.
double rssMb(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return -1;
}

// Processor seconds (user and system) a process has used so far, from /proc.
double cpuSeconds(int pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  // The fields after the command's name, which ends with the last ')'.
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) utime = std::stod(field);
    if (i == 15) stime = std::stod(field);
  }
  return (utime + stime) / double(::sysconf(_SC_CLK_TCK));
}

// What the load clients saw: calls answered, calls that failed (no answer), and answers
// that were wrong (a bad request accepted, a good one refused, a refusal without its reason).
struct Tally {
  std::atomic<long> answered{0}, unanswered{0}, wrong{0};
  std::mutex mutex;
  std::vector<std::string> firstProblems;
  void problem(const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex);
    if (firstProblems.size() < 10) firstProblems.push_back(what);
  }
};

// One client: its own connections to every service, called in turn.
class LoadClient {
 public:
  // `node` is the node's private namespace, `robot` the namespace of its joint topics.
  LoadClient(const std::string& node, const std::string& robot, int index, Tally& tally)
      : m_node(node),
        m_index(index),
        m_tally(tally),
        m_trajectories(
            m_nh.advertise<trajectory_msgs::JointTrajectory>(node + "joint_trajectory", 10)),
        m_kneeCommands(m_nh.advertise<std_msgs::Float64>(robot + "knee_l/command", 10)) {}

  // One request of each kind, in an order of its own; `running` says whether the node is
  // stepping by itself (then ~step is refused as running, and ~pause is not sent). Then a
  // bad trajectory and a NaN joint command on the topics, which the node drops.
  void round(bool running) {
    for (int k = 0; k < kKinds; ++k) request((k + m_index * 5) % kKinds, running);
    trajectory_msgs::JointTrajectory trajectory;
    trajectory.joint_names = {"knee_l", "no_such_joint"};
    trajectory.points.resize(1);
    trajectory.points[0].positions = {0.5, 0.5};
    trajectory.points[0].time_from_start = ros::Duration(0.1);
    m_trajectories.publish(trajectory);
    std_msgs::Float64 command;
    command.data = kNan;
    m_kneeCommands.publish(command);
  }

 private:
  static constexpr int kKinds = 24;

  template <typename Srv>
  bool send(const std::string& service, Srv& srv) {
    ros::ServiceClient& c = m_clients[service];
    if (!c.isValid()) c = m_nh.serviceClient<Srv>(m_node + service, true);
    if (c.call(srv)) {
      ++m_tally.answered;
      return true;
    }
    ++m_tally.unanswered;
    m_tally.problem(service + ": no answer");
    c.shutdown();
    return false;
  }
  template <typename Srv>
  void expectRefused(const std::string& service, Srv srv, const std::string& reason) {
    if (!send(service, srv)) return;
    if (srv.response.success || srv.response.message.find(reason) == std::string::npos) {
      ++m_tally.wrong;
      m_tally.problem(service + ": expected refused with '" + reason + "', got " +
                      (srv.response.success ? "success" : "'" + srv.response.message + "'"));
    }
  }
  template <typename Srv>
  void expectAccepted(const std::string& service, Srv srv) {
    if (!send(service, srv)) return;
    if (!srv.response.success) {
      ++m_tally.wrong;
      m_tally.problem(service + ": refused a good request: " + srv.response.message);
    }
  }

  static pfx::RaycastBatch batch(std::size_t rays) {
    pfx::RaycastBatch srv;
    srv.request.origins.resize(rays);
    srv.request.directions.resize(rays);
    for (std::size_t i = 0; i < rays; ++i) {
      srv.request.origins[i].x = -1 + 2.0 * double(i % 40) / 40;
      srv.request.origins[i].y = -1 + 2.0 * double(i / 40 % 40) / 40;
      srv.request.origins[i].z = 3;
      srv.request.directions[i].z = -5;
    }
    return srv;
  }
  static pfx::SetJointCommand jointCommand(const std::string& joint, double target) {
    pfx::SetJointCommand srv;
    srv.request.names = {joint};
    srv.request.mode = pfx::SetJointCommand::Request::POSITION;
    srv.request.targets = {target};
    return srv;
  }
  pfx::WorldFile worldFile(const std::string& path) const {
    pfx::WorldFile srv;
    srv.request.path = path;
    return srv;
  }

  void request(int kind, bool running) {
    switch (kind) {
      case 0:
        expectAccepted("raycast", pfx_test::rayRequest(0, 0, 3, 0, 0, -5));
        break;
      case 1:
        expectRefused("raycast", pfx_test::rayRequest(kNan, 0, 3, 0, 0, -5),
                      "origin is not finite");
        break;
      case 2:
        expectRefused("raycast", pfx_test::rayRequest(0, 0, 3, 0, 0, 0), "zero length");
        break;
      case 3:
        expectAccepted("raycast_batch", batch(1000));
        break;
      case 4: {
        // One ray beyond ~max_batch_rays: 4.8 MB that must be read and refused.
        expectRefused("raycast_batch", batch(100001), "at most 100000");
        break;
      }
      case 5: {
        pfx::RaycastBatch srv = batch(10);
        srv.request.directions.pop_back();
        expectRefused("raycast_batch", srv, "one of each per ray");
        break;
      }
      case 6:
        expectAccepted("get_contacts", pfx::GetContacts());
        break;
      case 7: {
        pfx::GetContacts srv;
        srv.request.link = "no_such_link";
        expectRefused("get_contacts", srv, "unknown link 'no_such_link'");
        break;
      }
      case 8: {
        pfx::ApplyBodyWrench srv;
        srv.request.link = "pelvis";
        srv.request.force.x = kNan;
        expectRefused("apply_body_wrench", srv, "force is not finite");
        break;
      }
      case 9: {
        pfx::ApplyBodyWrench srv;
        srv.request.link = "tail";
        expectRefused("apply_body_wrench", srv, "unknown link 'tail'");
        break;
      }
      case 10: {
        pfx::SetBodyState srv;
        srv.request.link = "pelvis";
        srv.request.pose.orientation.w = 2;  // not unit
        expectRefused("set_body_state", srv, "unit");
        break;
      }
      case 11: {
        pfx::SetBodyState srv;
        srv.request.link = "pelvis";
        srv.request.pose.position.z = std::numeric_limits<double>::infinity();
        srv.request.pose.orientation.w = 1;
        expectRefused("set_body_state", srv, "position is not finite");
        break;
      }
      case 12:
        expectRefused("set_joint_command", jointCommand("no_such_joint", 0.1),
                      "unknown joint 'no_such_joint'");
        break;
      case 13:
        expectRefused("set_joint_command", jointCommand("knee_l", kNan),
                      "target of joint 'knee_l' is not finite");
        break;
      case 14: {
        pfx::GetPhysics srv;
        if (send("get_physics", srv) && srv.response.physics.dt != 0.004f) {
          ++m_tally.wrong;
          m_tally.problem("get_physics: dt is not 0.004 s");
        }
        break;
      }
      case 15: {
        pfx::SetPhysics srv;
        srv.request.physics.dt = kNan;
        srv.request.physics.substeps = 1;
        srv.request.physics.iterations = 10;
        srv.request.physics.gravity.z = -9.81;
        srv.request.physics.real_time_factor = 1;
        expectRefused("set_physics", srv, "dt nan");
        break;
      }
      case 16:
        expectAccepted("save_world", worldFile("/tmp/pfx_node_load_" + std::to_string(::getpid()) +
                                               "_" + std::to_string(m_index) + ".pfxw"));
        break;
      case 17:
        expectRefused("load_world", worldFile("/nonexistent-pfx-folder/world.pfxw"),
                      "/nonexistent-pfx-folder/world.pfxw");
        break;
      case 18:
        expectRefused("save_world", worldFile(""), "no path given");
        break;
      case 19: {
        pfx::SpawnAgent srv;
        srv.request.name = "9lives";  // a digit first
        srv.request.radius = 0.3;
        srv.request.height = 1.8;
        expectRefused("spawn_agent", srv, "9lives");
        break;
      }
      case 20: {
        pfx::SpawnAgent srv;
        srv.request.name = "nan_radius";
        srv.request.radius = kNan;
        srv.request.height = 1.8;
        expectRefused("spawn_agent", srv, "radius");
        break;
      }
      case 21: {
        pfx::DeleteAgent srv;
        srv.request.name = "nobody";
        expectRefused("delete_agent", srv, "nobody");
        break;
      }
      case 22: {
        pfx::Step srv;
        srv.request.steps = running ? 1 : 10001;
        expectRefused("step", srv, running ? "running" : "must be 1 .. 10000");
        break;
      }
      case 23:
        // Pausing a paused node changes nothing; a running one is left running.
        if (!running) expectAccepted("pause", std_srvs::Trigger());
        break;
    }
  }

  std::string m_node;
  int m_index;
  Tally& m_tally;
  ros::NodeHandle m_nh;
  std::map<std::string, ros::ServiceClient> m_clients;
  ros::Publisher m_trajectories, m_kneeCommands;
};

// Threads calling the services of `node` until stop(); `running` as LoadClient::round has it.
class Load {
 public:
  Load(const std::string& node, const std::string& robot, Tally& tally, bool running) {
    for (int i = 0; i < numClients; ++i) {
      m_threads.emplace_back([this, node, robot, i, &tally, running] {
        LoadClient c(node, robot, i, tally);
        while (!m_stop) c.round(running);
      });
    }
  }
  ~Load() { stop(); }
  void stop() {
    m_stop = true;
    for (std::thread& t : m_threads) {
      if (t.joinable()) t.join();
    }
  }

 private:
  std::atomic<bool> m_stop{false};
  std::vector<std::thread> m_threads;
};

// One round of driving: joint targets, a push on the pelvis, ten steps. The same round
// number gives the same requests on either node. Returns the clock after the steps.
double drive(const std::string& node, int round) {
  pfx::SetJointCommand command;
  command.request.names = {"hip_l_flexion", "knee_r", "elbow_l", "spine_pitch"};
  command.request.mode = pfx::SetJointCommand::Request::POSITION;
  command.request.targets = {0.4 * std::sin(0.7 * round), -0.5 - 0.4 * std::cos(0.3 * round),
                             0.6 * std::sin(0.2 * round), 0.2 * std::cos(0.5 * round)};
  command = pfx_test::call(node + "set_joint_command", command);
  EXPECT_TRUE(command.response.success) << command.response.message;
  pfx::ApplyBodyWrench wrench;
  wrench.request.link = "pelvis";
  wrench.request.force.x = 40 * std::sin(0.9 * round);
  wrench.request.force.y = 40 * std::cos(1.3 * round);
  wrench.request.force.z = 150;
  wrench.request.duration = 0.02;
  wrench = pfx_test::call(node + "apply_body_wrench", wrench);
  EXPECT_TRUE(wrench.response.success) << wrench.response.message;
  pfx::Step step;
  step.request.steps = 10;
  step = pfx_test::call(node + "step", step);
  EXPECT_TRUE(step.response.success) << step.response.message;
  return step.response.time;
}

// "real-time factor" of the node's latest /diagnostics report, NaN before one.
double reportedRealTimeFactor(const diagnostic_msgs::DiagnosticArray& report) {
  for (const auto& status : report.status) {
    for (const auto& kv : status.values) {
      if (kv.key == "real-time factor") return std::stod(kv.value);
    }
  }
  return kNan;
}

}  // namespace

TEST(NodeLoad, AnswersEveryCallRightKeepsItsMemoryAndMovesAsWithoutLoad) {
  const std::string loaded = "/loaded/pfx_node/", quiet = "/quiet/pfx_node/";
  ASSERT_TRUE(pfx_test::waitForServices({loaded + "step", quiet + "step"}, 60));
  const int pid = pidOf("/loaded/pfx_node");
  ASSERT_GT(pid, 0) << "the node's process id";
  Latest<sensor_msgs::JointState> loadedJoints("/loaded/joint_states");
  Latest<sensor_msgs::JointState> quietJoints("/quiet/joint_states");
  TfRecord loadedTf("/loaded/tf"), quietTf("/quiet/tf");
  Latest<visualization_msgs::MarkerArray> loadedMarkers("/loaded/pfx_node/markers");
  Latest<visualization_msgs::MarkerArray> quietMarkers("/quiet/pfx_node/markers");
  Latest<diagnostic_msgs::DiagnosticArray> diagnostics("/loaded/diagnostics");

  // Paused, driven by ~step, under load.
  Tally tally;
  const ros::WallTime start = ros::WallTime::now();
  const double cpuStart = cpuSeconds(pid);
  auto load = std::make_unique<Load>(loaded, "/loaded/", tally, false);
  int rounds = 0;
  double loadedTime = 0, rssStart = -1;
  while ((ros::WallTime::now() - start).toSec() < loadSeconds) {
    loadedTime = drive(loaded, rounds++);
    if (rssStart < 0 && (ros::WallTime::now() - start).toSec() > 1) rssStart = rssMb(pid);
  }
  load->stop();
  const double pausedWall = (ros::WallTime::now() - start).toSec();
  const long pausedCalls = tally.answered.load();
  const double rssAfterPaused = rssMb(pid);
  const double pausedCpu = cpuSeconds(pid) - cpuStart;

  // The same rounds on the quiet node.
  double quietTime = 0;
  for (int r = 0; r < rounds; ++r) quietTime = drive(quiet, r);
  EXPECT_EQ(loadedTime, quietTime);
  ros::WallDuration(0.5).sleep();  // the state published after the last steps arrives
  const sensor_msgs::JointState a = loadedJoints.get(), b = quietJoints.get();
  ASSERT_FALSE(a.position.empty());
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.position, b.position) << "joint positions after " << rounds << " rounds";
  EXPECT_EQ(a.velocity, b.velocity) << "joint velocities after " << rounds << " rounds";
  const auto tfA = loadedTf.get(), tfB = quietTf.get();
  ASSERT_EQ(tfA.size(), tfB.size());
  ASSERT_GE(tfA.size(), 30u) << "every link of the ragdoll";
  for (const auto& [frame, transform] : tfA) {
    ASSERT_TRUE(tfB.count(frame)) << frame;
    EXPECT_TRUE(sameTransform(transform, tfB.at(frame))) << frame;
  }
  EXPECT_GT(loadedMarkers.count(), 0) << "markers were drawn under load";
  EXPECT_GT(quietMarkers.count(), 0);

  // Running at real-time factor 1, under the same load.
  std_srvs::Trigger unpause;
  ASSERT_TRUE(pfx_test::call(loaded + "unpause", unpause).response.success);
  const double runningCpuStart = cpuSeconds(pid);
  load = std::make_unique<Load>(loaded, "/loaded/", tally, true);
  const ros::WallTime runningStart = ros::WallTime::now();
  std::vector<double> factors;
  long lastReport = diagnostics.count();
  while ((ros::WallTime::now() - runningStart).toSec() < runningSeconds) {
    ros::WallDuration(0.05).sleep();
    if (diagnostics.count() == lastReport) continue;
    lastReport = diagnostics.count();
    // The first report after the unpause covers paused time too.
    if ((ros::WallTime::now() - runningStart).toSec() > 1.5) {
      factors.push_back(reportedRealTimeFactor(diagnostics.get()));
    }
  }
  const double runningWall = (ros::WallTime::now() - runningStart).toSec();
  const long runningCalls = tally.answered.load() - pausedCalls;
  load->stop();
  const double runningCpu = cpuSeconds(pid) - runningCpuStart;
  const double rssEnd = rssMb(pid);

  pfx_test::call(loaded + "get_physics", pfx::GetPhysics());  // still answering
  EXPECT_EQ(tally.unanswered.load(), 0);
  EXPECT_EQ(tally.wrong.load(), 0);
  for (const std::string& problem : tally.firstProblems) ADD_FAILURE() << problem;
  EXPECT_GT(rssStart, 0);
  EXPECT_GT(rssEnd, 0) << "the node is alive";
  EXPECT_LT(rssEnd - rssStart, kMaxRssGrowthMb) << "RSS " << rssStart << " -> " << rssEnd << " MB";
  EXPECT_FALSE(factors.empty()) << "diagnostics while running";
  double factorMean = 0, factorMin = std::numeric_limits<double>::infinity();
  for (double f : factors) {
    factorMean += f / double(factors.size());
    factorMin = std::min(factorMin, f);
  }

  std::ostringstream figures;
  figures << "clients\t" << numClients << "\n"
          << "paused_phase_wall_s\t" << pausedWall << "\n"
          << "paused_phase_calls_per_s\t" << double(pausedCalls) / pausedWall << "\n"
          << "paused_phase_node_core_share\t" << pausedCpu / pausedWall << "\n"
          << "paused_phase_rounds\t" << rounds << "\n"
          << "paused_phase_sim_s_per_wall_s\t" << loadedTime / pausedWall << "\n"
          << "running_phase_wall_s\t" << runningWall << "\n"
          << "running_phase_calls_per_s\t" << double(runningCalls) / runningWall << "\n"
          << "running_phase_node_core_share\t" << runningCpu / runningWall << "\n"
          << "running_real_time_factor_mean\t" << factorMean << "\n"
          << "running_real_time_factor_min\t" << factorMin << "\n"
          << "rss_start_mb\t" << rssStart << "\n"
          << "rss_after_paused_phase_mb\t" << rssAfterPaused << "\n"
          << "rss_end_mb\t" << rssEnd << "\n";
  std::cout << figures.str();
  if (!reportFile.empty()) std::ofstream(reportFile) << figures.str();
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_node_load");
  pfx_test::RosClient rosClient;
  client = &rosClient;
  ros::NodeHandle params("~");
  params.param("load_seconds", loadSeconds, loadSeconds);
  params.param("running_seconds", runningSeconds, runningSeconds);
  params.param("clients", numClients, numClients);
  params.param("report_file", reportFile, reportFile);
  return RUN_ALL_TESTS();
}
