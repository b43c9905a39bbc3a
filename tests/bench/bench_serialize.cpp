#include "bench_serialize.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace pfxbench {

std::vector<SerializeBody> makeSerializeBodies(int count) {
  const int side = static_cast<int>(std::ceil(std::sqrt(double(count))));
  std::vector<SerializeBody> bodies(count);
  for (int i = 0; i < count; ++i) {
    SerializeBody& body = bodies[i];
    body.sphere = (i % 2) == 1;
    body.x = double(i % side) - 0.5 * double(side - 1);
    body.z = double(i / side) - 0.5 * double(side - 1);
    body.y = kSerializeBodyHalfSize;
  }
  return bodies;
}

TemporaryFile::TemporaryFile(const std::string& stem) {
  m_path =
      (std::filesystem::temp_directory_path() / (stem + "." + std::to_string(::getpid()) + ".bin"))
          .string();
}

TemporaryFile::~TemporaryFile() {
  std::error_code ignored;
  std::filesystem::remove(m_path, ignored);
}

int runSerializeScene(std::vector<ResultRow>& rows) {
  struct EngineSide {
    const char* name;
    bool (*run)(const std::vector<SerializeBody>&, SerializeFigures&, std::string&);
  };
  std::vector<EngineSide> engines = {{"pfx", runPfxSerialize}};
#ifdef PFX_BENCH_HAVE_BULLET_IMPORTER
  engines.push_back({"bullet", runBulletSerialize});
#endif
  int failures = 0;
  for (const int count : {4000, 100000}) {
    const std::vector<SerializeBody> bodies = makeSerializeBodies(count);
    const std::string variant = std::to_string(count);
    for (const EngineSide& engine : engines) {
      SerializeFigures figures;
      std::string error;
      if (!engine.run(bodies, figures, error)) {
        std::fprintf(stderr, "serialize %s %s: FAILED: %s\n", engine.name, variant.c_str(),
                     error.c_str());
        ++failures;
        continue;
      }
      const double bytesPerBody = figures.fileBytes / double(count + 1);
      std::fprintf(stderr,
                   "serialize %s %d bodies: write %.4f s, read %.4f s, %.1f bytes per body, %s\n",
                   engine.name, count, figures.writeSeconds, figures.readSeconds, bytesPerBody,
                   figures.restored ? "every body restored" : "NOT RESTORED");
      if (!figures.restored) ++failures;
      auto row = [&](const char* metric, double seconds, double value) {
        rows.push_back(
            {kSerializeSceneName, engine.name, variant, 0, 1, 1, 1, seconds, metric, value});
      };
      row("write_s", figures.writeSeconds, figures.writeSeconds);
      row("read_s", figures.readSeconds, figures.readSeconds);
      row("bytes_per_body", 0, bytesPerBody);
      row("restored", 0, figures.restored ? 1 : 0);
    }
  }
  return failures;
}

}  // namespace pfxbench
