// The `serialize` scene: how long a world takes to be written to a file and read back into
// a fresh world, and how many bytes it takes per body, for pfx (pfxSaveWorld and
// pfxLoadWorld, pfx_serialize.h) beside Bullet's own serializer (btDefaultSerializer, and
// btBulletWorldImporter to read) on the same bodies.
//
// The bodies: 4,000 and then 100,000 spheres and cubes (edge and diameter 0.5 m, 1 kg) in
// a square grid 1 m apart, resting on a fixed ground box, stepped a few times at 1/60 s so
// that each engine's world holds what a running simulation holds: pairs and contact
// manifolds. Bullet shares one sphere and one box shape among its bodies, as a Bullet user
// would; a pfx body holds its shapes by value.
//
// What each engine's file holds differs, and this is the comparison's point: pfx's holds
// everything the next step reads (contact manifolds with their impulses, sleep timers, the
// pending forces), so that a world read back continues bit for bit; Bullet's holds bodies,
// shapes and constraints but no contacts, so a world read back starts its solver cold.
// Both read back all bodies; the scene checks the count and every body's position (pfx:
// its whole state, bit for bit).
//
// Time is the process's CPU time, as in the rays scene: write = serializing the world into
// a file in the system's temporary folder (Bullet: into its buffer, then the buffer to the
// file); read = reading that file into a fresh world (Bullet: the file into memory, then
// the importer). Each figure is the fastest of three passes.
//
// TSV rows (scene `serialize`, variant the body count; dt, substeps and iterations read 0,
// 1, 1; engine pfx or bullet):
//   write_s         seconds to write (wall_s_per_sim_s too)
//   read_s          seconds to read (wall_s_per_sim_s too)
//   bytes_per_body  the file's size over the bodies (the ground included)
//   restored        1 when every body came back where it was (pfx: bit for bit), else 0
#pragma once

#include <string>
#include <vector>

#include "bench_report.h"

namespace pfxbench {

constexpr const char* kSerializeSceneName = "serialize";

struct SerializeBody {
  bool sphere = false;         // else a cube
  double x = 0, y = 0, z = 0;  // centre, Y up
};

// The grid of `count` bodies, resting on the ground's top at y = 0.
std::vector<SerializeBody> makeSerializeBodies(int count);

struct SerializeFigures {
  double writeSeconds = 0;
  double readSeconds = 0;
  double fileBytes = 0;
  bool restored = false;
};

// Each engine's side; false with `error` when something failed.
bool runPfxSerialize(const std::vector<SerializeBody>& bodies, SerializeFigures& figures,
                     std::string& error);
bool runBulletSerialize(const std::vector<SerializeBody>& bodies, SerializeFigures& figures,
                        std::string& error);

// A file in the system's temporary folder that is removed when this goes.
class TemporaryFile {
 public:
  explicit TemporaryFile(const std::string& stem);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
};

constexpr double kSerializeGroundHalfHeight = 0.5;
constexpr double kSerializeBodyHalfSize = 0.25;
constexpr int kSerializeSteps = 3;
constexpr int kSerializeTimedPasses = 3;

// Runs the scene for 4,000 and 100,000 bodies and appends its rows; returns the number of
// failures.
int runSerializeScene(std::vector<ResultRow>& rows);

}  // namespace pfxbench
