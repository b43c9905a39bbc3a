// pfx_sim as a user runs it: a robot dropped onto the ground simulates to the end, prints a
// TSV row per step with sane figures, and writes a picture in which the robot shows; bad
// arguments and files that cannot be loaded fail with a message and a non-zero status.
#include <cairo.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct SimRun {
  int status = -1;
  std::string out;
  std::string err;
};

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string scratch(const std::string& name) {
  return std::string(PFX_TEST_SCRATCH_DIR) + "/pfx_sim_check_" + name;
}

SimRun runSim(const std::string& arguments, const std::string& name) {
  const std::string out = scratch(name + ".tsv"), err = scratch(name + ".err");
  const std::string command =
      std::string("\"") + PFX_SIM + "\" " + arguments + " >\"" + out + "\" 2>\"" + err + "\"";
  SimRun run;
  const int raw = std::system(command.c_str());
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  run.out = readFile(out);
  run.err = readFile(err);
  return run;
}

std::vector<std::vector<std::string>> tsvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, '\t')) fields.push_back(cell);
    rows.push_back(fields);
  }
  return rows;
}

// Share of the picture's pixels in a saturated colour: bodies that move are drawn in
// colours, the ground, the grid and the sky in greys and pale blue.
double colouredShare(const std::string& png, int expectedWidth, int expectedHeight) {
  cairo_surface_t* image = cairo_image_surface_create_from_png(png.c_str());
  EXPECT_EQ(cairo_surface_status(image), CAIRO_STATUS_SUCCESS) << png;
  if (cairo_surface_status(image) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(image);
    return 0;
  }
  const int width = cairo_image_surface_get_width(image);
  const int height = cairo_image_surface_get_height(image);
  EXPECT_EQ(width, expectedWidth);
  EXPECT_EQ(height, expectedHeight);
  const int stride = cairo_image_surface_get_stride(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  long coloured = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const unsigned char* px = data + y * stride + 4 * x;
      const int hi = std::max({px[0], px[1], px[2]}), lo = std::min({px[0], px[1], px[2]});
      if (hi - lo > 80) ++coloured;
    }
  }
  cairo_surface_destroy(image);
  return double(coloured) / (double(width) * height);
}

void checkDrop(const std::string& urdf, const std::string& name, double maxJointGap) {
  const std::string png = scratch(name + ".png");
  std::remove(png.c_str());
  const SimRun run = runSim(
      "\"" + urdf + "\" --ground --seconds 1.5 --dt 0.004 --png \"" + png + "\" --png-size 640x480",
      name);
  ASSERT_EQ(run.status, 0) << run.err;
  const auto rows = tsvRows(run.out);
  ASSERT_EQ(rows.size(), 376u);  // the header and 375 steps
  ASSERT_EQ(rows[0].size(), 10u);
  EXPECT_EQ(rows[0][0], "step");
  EXPECT_EQ(rows[0][6], "max_joint_gap");
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 10u) << i;
    EXPECT_EQ(std::stol(rows[i][0]), long(i));
    for (const std::string& cell : rows[i]) ASSERT_TRUE(std::isfinite(std::stod(cell))) << i;
  }
  const auto& last = rows.back();
  EXPECT_NEAR(std::stod(last[1]), 1.5, 1e-6);
  EXPECT_GT(std::stol(last[4]), 0) << "the robot lies on the ground";
  EXPECT_LT(std::stod(last[5]), 0.02) << "deepest overlap";
  EXPECT_LT(std::stod(last[6]), maxJointGap);
  EXPECT_GT(colouredShare(png, 640, 480), 0.005) << "the robot shows in " << png;
}

}  // namespace

TEST(PfxSim, ArmDroppedOntoTheGround) {
  checkDrop(std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/pfx_sim_arm.urdf", "arm", 1e-3);
}

#ifdef PFX_RAGDOLL_URDF
TEST(PfxSim, RagdollDroppedOntoTheGround) { checkDrop(PFX_RAGDOLL_URDF, "ragdoll", 1e-3); }
#endif

// With --sleep the arm at rest on the ground falls asleep: no pair is solved any more,
// while without it every step solves its contacts.
TEST(PfxSim, SleepIsAnOption) {
  const std::string arm = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/pfx_sim_arm.urdf";
  for (const bool sleep : {false, true}) {
    const SimRun run =
        runSim("\"" + arm + "\" --ground --seconds 3 --dt 0.004" + (sleep ? " --sleep" : ""),
               sleep ? "sleep" : "awake");
    ASSERT_EQ(run.status, 0) << run.err;
    const auto rows = tsvRows(run.out);
    ASSERT_EQ(rows.size(), 751u);
    EXPECT_EQ(std::stol(rows.back()[3]) == 0, sleep) << "pairs solved in the last step";
  }
}

#ifdef PFX_RAGDOLL_URDF
// The ragdoll bolted by its root, whose URDF pose has its legs below z = 0, starts above the
// ground with --ground instead of inside it: no step finds a deep overlap. Without
// self-collision it runs too.
TEST(PfxSim, FixedBaseRobotStartsAboveTheGround) {
  for (const std::string extra : {"", " --no-self-collision"}) {
    const SimRun run = runSim(std::string("\"") + PFX_RAGDOLL_URDF +
                                  "\" --fixed-base --ground --seconds 0.5 --dt 0.004" + extra,
                              "fixed_base");
    ASSERT_EQ(run.status, 0) << run.err;
    const auto rows = tsvRows(run.out);
    ASSERT_EQ(rows.size(), 126u);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      ASSERT_LT(std::stod(rows[i][5]), 0.01) << "deepest overlap at step " << i << extra;
    }
  }
}
#endif

// bullet3's r2d2 names gripper meshes it does not ship: the load fails naming one, unless
// --allow-missing-meshes leaves them out with a warning.
TEST(PfxSim, MissingMeshesFailUnlessAllowed) {
  const std::string r2d2 = std::string("\"") + PFX_SOURCE_DIR + "/urdf/r2d2.urdf\"";
  SimRun run = runSim(r2d2 + " --ground --seconds 0.1", "r2d2");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("mesh 'l_finger.stl' not found"), std::string::npos) << run.err;
  run = runSim(r2d2 + " --ground --seconds 0.1 --allow-missing-meshes", "r2d2_allowed");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.err.find("warning: link 'left_gripper': mesh 'l_finger.stl' not found"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(tsvRows(run.out).size(), 25u);  // the header and 24 steps
}

TEST(PfxSim, HelpAndBadArgumentsAndFiles) {
  const std::string arm = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/pfx_sim_arm.urdf";
  SimRun run = runSim("--help", "help");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.out.find("--drop-height"), std::string::npos);

  for (const char* bad : {"", "--dt -1", "--dt abc", "--seconds", "--substeps 0",
                          "--iterations 2.5", "--threads -1", "--threads 257", "--threads",
                          "--png-size 10x10", "--bogus", "extra.urdf"}) {
    run = runSim((std::string(bad).empty() ? std::string() : "\"" + arm + "\" ") + bad, "bad");
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_NE(run.err.find("pfx_sim: "), std::string::npos) << bad;
    EXPECT_TRUE(run.out.empty()) << bad;
  }

  run = runSim("\"" + scratch("missing.urdf") + "\"", "missing");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("missing.urdf"), std::string::npos) << run.err;

  const std::string broken = scratch("broken.urdf");
  std::ofstream(broken) << "<robot name=\"r\"><link name=\"a\"><inertial><mass value=\"-1\"/>"
                           "<inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/>"
                           "</inertial></link></robot>";
  run = runSim("\"" + broken + "\"", "broken");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("broken.urdf"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("'a'"), std::string::npos) << run.err;

  run = runSim("\"" + arm + "\" --seconds 0.01 --png /nonexistent-folder/picture.png", "nopng");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("/nonexistent-folder/picture.png"), std::string::npos) << run.err;
}

// Every column of a TSV row but the step number and the step's wall time.
std::vector<std::string> simulatedFigures(const std::vector<std::string>& row) {
  std::vector<std::string> figures = row;
  figures.erase(figures.begin() + 2);  // step_s
  figures.erase(figures.begin());      // step
  return figures;
}

// A run saved after 1 s and continued from the file for 0.5 s prints, step for step, the
// very figures of one run of 1.5 s: the world read back goes on bit for bit, its clock
// included. The saved world can be given to --world too.
TEST(PfxSim, SavedWorldContinuesExactly) {
  const std::string arm = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/pfx_sim_arm.urdf";
  const std::string saved = scratch("arm_1s.pfxw");
  std::remove(saved.c_str());
  const std::string physics = " --ground --dt 0.004 --iterations 12";
  const SimRun whole = runSim("\"" + arm + "\"" + physics + " --seconds 1.5", "whole");
  ASSERT_EQ(whole.status, 0) << whole.err;
  const SimRun first =
      runSim("\"" + arm + "\"" + physics + " --seconds 1 --save \"" + saved + "\"", "first");
  ASSERT_EQ(first.status, 0) << first.err;
  const auto wholeRows = tsvRows(whole.out);
  ASSERT_EQ(wholeRows.size(), 376u);
  for (const char* option : {"--load", "--world"}) {
    const SimRun rest = runSim(std::string(option) + " \"" + saved + "\" --seconds 0.5", option);
    ASSERT_EQ(rest.status, 0) << option << ": " << rest.err;
    const auto restRows = tsvRows(rest.out);
    ASSERT_EQ(restRows.size(), 126u) << option;
    EXPECT_NEAR(std::stod(restRows[1][1]), 1.004, 1e-9) << "the clock goes on from 1 s";
    for (std::size_t i = 1; i < restRows.size(); ++i) {
      EXPECT_EQ(simulatedFigures(restRows[i]), simulatedFigures(wholeRows[250 + i]))
          << option << ", step " << i << " after loading";
    }
  }
}

TEST(PfxSim, SavedWorldsAndScenesRefusedWithReasons) {
  const std::string arm = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/pfx_sim_arm.urdf";
  const std::string saved = scratch("arm_short.pfxw");
  SimRun run = runSim("\"" + arm + "\" --ground --seconds 0.1 --save \"" + saved + "\"", "short");
  ASSERT_EQ(run.status, 0) << run.err;

  // Options that a saved world cannot take.
  for (const std::string& bad :
       {"\"" + arm + "\" --load \"" + saved + "\"", "--load \"" + saved + "\" --dt 0.01",
        "--load \"" + saved + "\" --ground", "--load \"" + saved + "\" --world \"" + saved + "\"",
        "--world \"" + saved + "\" --iterations 3", std::string("--load"), std::string("--save")}) {
    run = runSim(bad, "bad_saved");
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_NE(run.err.find("pfx_sim: "), std::string::npos) << bad;
  }

  // Files that do not read: each named, with why.
  const std::string garbage = scratch("garbage.pfxw");
  std::ofstream(garbage) << "a text file, longer than the 32 bytes of a world file's header";
  const std::string cut = scratch("cut.pfxw");
  {
    const std::string bytes = readFile(saved);
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  struct Unreadable {
    std::string file, reason;
  };
  for (const Unreadable& bad :
       {Unreadable{scratch("missing.pfxw"), "cannot be opened"},
        Unreadable{garbage, "not a pfx world file"}, Unreadable{cut, "the file ends"}}) {
    run = runSim("--load \"" + bad.file + "\"", "unreadable");
    EXPECT_EQ(run.status, 1) << bad.file;
    EXPECT_NE(run.err.find(bad.file + ": "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(bad.reason), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty()) << bad.file;
  }
  run = runSim("--world \"" + scratch("missing.world") + "\"", "missing_world");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("missing.world"), std::string::npos) << run.err;
  run = runSim("\"" + arm + "\" --seconds 0.01 --save /nonexistent-folder/world.pfxw", "nosave");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("/nonexistent-folder/world.pfxw"), std::string::npos) << run.err;
}

// A scene file alone runs with its own physics (Gazebo's shapes.world: the SDF default step
// of 1 ms), --dt overrides its step, and a robot loads beside a pfx scene.
TEST(PfxSim, SceneFilesAloneAndBesideARobot) {
  const std::string data = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/";
  const std::string shapes = "\"" + data + "sdf/worlds/shapes.world\"";
  SimRun run = runSim("--world " + shapes + " --seconds 0.5", "shapes");
  ASSERT_EQ(run.status, 0) << run.err;
  auto rows = tsvRows(run.out);
  ASSERT_EQ(rows.size(), 501u) << "0.5 s at the file's 1 ms";
  EXPECT_NEAR(std::stod(rows.back()[1]), 0.5, 1e-6);
  EXPECT_GT(std::stol(rows.back()[4]), 0) << "the shapes rest on the ground";
  EXPECT_LT(std::stod(rows.back()[5]), 0.01) << "deepest overlap";

  run = runSim("--world " + shapes + " --seconds 0.5 --dt 0.004", "shapes_dt");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(tsvRows(run.out).size(), 126u) << "0.5 s at --dt 0.004";

  const std::string arm = "\"" + data + "pfx_sim_arm.urdf\"";
  const std::string obstacles =
      "\"" + std::string(PFX_SOURCE_DIR) + "/tests/ros/data/obstacles.xml\"";
  run = runSim(arm + " --world " + obstacles + " --ground --seconds 0.5 --dt 0.004", "beside");
  ASSERT_EQ(run.status, 0) << run.err;
  rows = tsvRows(run.out);
  ASSERT_EQ(rows.size(), 126u);
  EXPECT_GT(std::stol(rows.back()[4]), 0);
  EXPECT_LT(std::stod(rows.back()[5]), 0.02) << "deepest overlap";
}

// A robot beside a scene of 48 crates and balls dropped apart, many islands on one floor,
// prints on 2 and 3 threads, step for step, the figures of one thread; so does a saved world
// continued on 2.
TEST(PfxSim, ThreadsGiveTheFiguresOfOneThread) {
  const std::string scene = scratch("islands.xml");
  {
    std::ofstream xml(scene);
    xml << "<pfx_scene version=\"1\" name=\"islands\">\n";
    for (int i = 0; i < 48; ++i) {
      xml << "<body name=\"b" << i << "\" mass=\"1\" position=\"" << 0.8 * (i % 8) - 2.8 << " "
          << 0.8 * (i / 8) + 1 << " " << 0.3 + 0.05 * (i % 5) << "\">"
          << (i % 3 ? "<box size=\"0.3 0.3 0.3\"/>" : "<sphere radius=\"0.15\"/>") << "</body>\n";
    }
    xml << "</pfx_scene>\n";
  }
  const std::string run = "\"" + std::string(PFX_SOURCE_DIR) +
                          "/tests/loaders/data/pfx_sim_arm.urdf\" --world \"" + scene +
                          "\" --ground --seconds 1 --dt 0.004";
  const std::string saved = scratch("threads.pfxw");
  std::remove(saved.c_str());
  const SimRun one = runSim(run + " --save \"" + saved + "\"", "threads_1");
  ASSERT_EQ(one.status, 0) << one.err;
  const auto oneRows = tsvRows(one.out);
  ASSERT_EQ(oneRows.size(), 251u);
  EXPECT_GT(std::stol(oneRows.back()[4]), 48) << "bodies rest on the ground";
  for (const char* threads : {"2", "3"}) {
    const SimRun many = runSim(run + " --threads " + threads, std::string("threads_") + threads);
    ASSERT_EQ(many.status, 0) << many.err;
    const auto manyRows = tsvRows(many.out);
    ASSERT_EQ(manyRows.size(), oneRows.size());
    for (std::size_t i = 1; i < oneRows.size(); ++i) {
      ASSERT_EQ(simulatedFigures(manyRows[i]), simulatedFigures(oneRows[i]))
          << threads << " threads, step " << i;
    }
  }
  const SimRun rest = runSim("--load \"" + saved + "\" --seconds 0.2", "threads_rest_1");
  const SimRun restOnTwo =
      runSim("--load \"" + saved + "\" --seconds 0.2 --threads 2", "threads_rest_2");
  ASSERT_EQ(rest.status, 0) << rest.err;
  ASSERT_EQ(restOnTwo.status, 0) << restOnTwo.err;
  const auto restRows = tsvRows(rest.out), restOnTwoRows = tsvRows(restOnTwo.out);
  ASSERT_EQ(restRows.size(), 51u);
  ASSERT_EQ(restOnTwoRows.size(), restRows.size());
  for (std::size_t i = 1; i < restRows.size(); ++i) {
    EXPECT_EQ(simulatedFigures(restOnTwoRows[i]), simulatedFigures(restRows[i])) << i;
  }
}
