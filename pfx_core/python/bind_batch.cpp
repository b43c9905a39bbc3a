// Many worlds stepped together (PfxWorldBatch) and worlds as bytes: copies for a batch, or
// a world sent to another process or machine (pfx.sweep).
#include <cstring>
#include <vector>

#include "pfx_python.h"

namespace pfx::python {

namespace {

// The worlds a batch steps, held by their Python objects so that none goes away or is
// re-initialized from under a step. The C++ batch only borrows their PfxWorld.
struct PyWorldBatch {
  std::vector<py::object> worlds;
  PfxWorldBatch batch;
};

py::bytes worldToBytes(const PyWorld& w) {
  std::vector<PfxUInt8> bytes;
  std::string message;
  raiseIfError(pfxSaveWorldToBytes(w.world, bytes, &message), message);
  return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

std::unique_ptr<PyWorld> worldFromBytes(const py::bytes& data, const py::object& numThreads) {
  PfxLoadWorldOptions options;
  if (!numThreads.is_none()) {
    options.keepSavedNumThreads = false;
    options.numThreads = numThreads.cast<PfxUInt32>();
  }
  const std::string_view view = data;
  auto w = std::make_unique<PyWorld>();
  auto meshes = std::make_shared<PfxSerializedMeshes>();
  std::string message;
  raiseIfError(pfxLoadWorldFromBytes(w->world, reinterpret_cast<const PfxUInt8*>(view.data()),
                                     view.size(), *meshes, &message, options),
               message);
  w->resources.push_back(std::move(meshes));
  return w;
}

std::unique_ptr<PyWorldBatch> makeBatch(const py::iterable& worlds, PfxUInt32 numThreads) {
  auto b = std::make_unique<PyWorldBatch>();
  raiseIfError(b->batch.setNumThreads(numThreads), "num_threads");
  for (const py::handle item : worlds) {
    if (!py::isinstance<PyWorld>(item)) {
      raiseIfError(PFX_ERR_INVALID_VALUE, "world " + std::to_string(b->worlds.size()) +
                                              " of the batch is a " +
                                              std::string(py::str(item.get_type().attr("__name__"))) +
                                              ", not a pfx.World");
    }
    ErrorDetailWatch watch;
    watch.raiseIfError(b->batch.addWorld(item.cast<PyWorld&>().world));
    b->worlds.push_back(py::reinterpret_borrow<py::object>(item));
  }
  return b;
}

// Every world's bodies as rows of 13 numbers, world after world.
py::array_t<PfxFloat> gatherStates(PyWorldBatch& b) {
  auto out = newArray<PfxFloat>(b.batch.getNumRigidBodies(), PFX_BATCH_STATE_FLOATS);
  raiseIfError(b.batch.gatherStates(out.mutable_data(), PfxUInt64(out.size())), "states");
  return out;
}

}  // namespace

void bindBatch(py::module_& m) {
  py::class_<PyWorld>(m.attr("World"))
      .def("to_bytes", &worldToBytes,
           "The whole world as save() writes it, in memory: to copy it (World.from_bytes) or\n"
           "send it to another process or machine.")
      .def_static("from_bytes", &worldFromBytes, py::arg("data"),
                  py::arg("num_threads") = py::none(),
                  "A new world from to_bytes() (or a saved file's bytes), which steps exactly as\n"
                  "the saved one would have. num_threads, when given, replaces the saved count.")
      .def(
          "state_hash", [](const PyWorld& w) { return pfxHashRigidStates(w.world); },
          "pfxHashRigidStates: FNV-1a (64 bits) of every body's 13 state values (as\n"
          "WorldBatch.states() lays them out, little-endian): equal hashes, equal bits. pfx_sim\n"
          "prints the same number in hex.");

  m.attr("BATCH_STATE_COLUMNS") = PFX_BATCH_STATE_FLOATS;
  py::class_<PyWorldBatch>(
      m, "WorldBatch",
      "PfxWorldBatch: independent worlds stepped together, each world on one of the batch's\n"
      "threads. Each world steps exactly as alone: the batch gives, world for world, the bits\n"
      "of stepping them one by one. Give the worlds num_threads=1 (copies() does): the\n"
      "batch's threads go to whole worlds.")
      .def(py::init(&makeBatch), py::arg("worlds"), py::arg("num_threads") = 1,
           "A batch of these pfx.World objects (kept alive by it), stepped on num_threads\n"
           "threads (0: every core). A world given twice raises.")
      .def_static(
          "copies",
          [](const PyWorld& source, PfxUInt32 count, PfxUInt32 numThreads) {
            const py::bytes data = worldToBytes(source);
            py::list worlds;
            for (PfxUInt32 i = 0; i < count; ++i) worlds.append(py::cast(worldFromBytes(data, py::int_(1))));
            return makeBatch(worlds, numThreads);
          },
          py::arg("world"), py::arg("count"), py::arg("num_threads") = 1,
          "A batch of count copies of world (through to_bytes), each continuing exactly as\n"
          "world would; change each through batch.worlds[i] (set_state, apply_force, ...).")
      .def_property_readonly(
          "worlds",
          [](const PyWorldBatch& b) {
            py::list worlds;
            for (const py::object& world : b.worlds) worlds.append(world);
            return worlds;
          },
          "The batch's pfx.World objects, in order (a new list of the same objects).")
      .def_property_readonly(
          "num_worlds", [](const PyWorldBatch& b) { return b.batch.getNumWorlds(); },
          "Worlds in the batch.")
      .def_property_readonly(
          "num_threads", [](const PyWorldBatch& b) { return b.batch.getNumThreads(); },
          "Threads that step the worlds.")
      .def(
          "step",
          [](PyWorldBatch& b, long count) {
            const PfxInt32 err = stepWithoutGil(
                count, [&](long n) { return b.batch.step(static_cast<PfxUInt32>(n)); });
            raiseIfError(err, pfxGetLastErrorDetail());
          },
          py::arg("count") = 1,
          "Steps every world count times (the GIL is released). A world that fails stops, the\n"
          "others go on, and the error names the first failed world.")
      .def("states", &gatherStates,
           "Every world's body states in one new array (bodies of all worlds, 13): position\n"
           "(3), orientation x, y, z, w (4), linear (3) and angular velocity (3), world after\n"
           "world; first_bodies says where each world starts. Worlds of equal size reshape to\n"
           "(num_worlds, bodies, 13).")
      .def_property_readonly(
          "first_bodies",
          [](const PyWorldBatch& b) {
            py::array_t<PfxInt64> out(b.batch.getNumWorlds() + 1);
            for (PfxUInt32 i = 0; i <= b.batch.getNumWorlds(); ++i) out.mutable_at(i) = b.batch.getFirstBody(i);
            return out;
          },
          "The row of states() where each world's bodies start, then the total (num_worlds + 1).");
}

}  // namespace pfx::python
