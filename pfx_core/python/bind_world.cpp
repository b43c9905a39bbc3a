// The world: its parameters, stepping, statistics, and the bodies' states as numpy arrays.
#include <cstddef>

#include "pfx_python.h"

namespace pfx::python {

namespace {

// Keeps the world alive and its state buffer in place while a zero-copy array reads it.
struct StateViewLease {
  explicit StateViewLease(py::object worldObject) : world(std::move(worldObject)) {
    ++world.cast<PyWorld&>().liveStateViews;
  }
  ~StateViewLease() { --world.cast<PyWorld&>().liveStateViews; }
  StateViewLease(const StateViewLease&) = delete;
  StateViewLease& operator=(const StateViewLease&) = delete;
  py::object world;
};

// Byte offsets of the fields in PfxRigidState (their members are private, so measured).
struct StateLayout {
  std::size_t position, orientation, linearVelocity, angularVelocity;
};

StateLayout measureStateLayout() {
  PfxRigidState state;
  const char* base = reinterpret_cast<const char*>(&state);
  auto offset = [base](const void* field) {
    return std::size_t(reinterpret_cast<const char*>(field) - base);
  };
  return {offset(state.getPosition().data()), offset(state.getOrientation().coeffs().data()),
          offset(state.getLinearVelocity().data()), offset(state.getAngularVelocity().data())};
}

const StateLayout kStateLayout = measureStateLayout();

// A read-only (n, columns) array over one field of every body's state, without a copy.
py::array stateView(const py::object& self, std::size_t offset, py::ssize_t columns) {
  PyWorld& w = self.cast<PyWorld&>();
  const char* data = reinterpret_cast<const char*>(w.world.getRigidStates()) + offset;
  return worldMemoryView(self, data, w.world.getNumRigidBodies(), columns,
                         sizeof(PfxRigidState));
}

const char* const kViewDoc =
    " of every body, a read-only view of the world's own memory (no copy) that always shows\n"
    "the current state: take .copy() to keep a snapshot. While such a view is alive, calls\n"
    "that add or remove bodies (add_body, loaders, initialize, load, truncate) raise\n"
    "pfx.Error instead of leaving it dangling; delete the view or copy it first.";

const PfxRigidState& stateOf(const PyWorld& w, PfxUInt32 id) {
  if (id >= w.world.getNumRigidBodies()) {
    raiseIfError(PFX_ERR_OUT_OF_RANGE, "body " + std::to_string(id) + " of " +
                                           std::to_string(w.world.getNumRigidBodies()));
  }
  return w.world.getRigidState(id);
}

void bindWorldParam(py::module_& m) {
  py::enum_<PfxPipelineType>(m, "Pipeline", "The pipelines of seed chapter 4.")
      .value("SIMPLE", kPfxPipelineSimple, "Nothing kept between frames (seed 1_simple).")
      .value("STABLE", kPfxPipelineStable, "Contacts and impulses carried over (seed 2_stable).");

  py::class_<PfxWorldParam> param(m, "WorldParam",
                                  "PfxWorldParam: bounds, gravity, step, solver and sleep "
                                  "settings of a world.");
  defKeywordInit(param, "Any field as a keyword; the rest keep pfx's defaults.");
  defVector3(param, "world_center", &PfxWorldParam::worldCenter, "Centre of the world's bounds (m).");
  defVector3(param, "world_extent", &PfxWorldParam::worldExtent, "Half size of the bounds (m).");
  defVector3(param, "gravity", &PfxWorldParam::gravity, "m/s^2; default (0, -9.80665, 0).");
  param.def_readwrite("time_step", &PfxWorldParam::timeStep, "Seconds per step (default 1/60).")
      .def_readwrite("sub_step", &PfxWorldParam::subStep, "Solver and integrator runs per step.")
      .def_readwrite("iteration", &PfxWorldParam::iteration, "Solver iterations per sub-step.")
      .def_readwrite("pipeline", &PfxWorldParam::pipeline, "Pipeline.STABLE or Pipeline.SIMPLE.")
      .def_readwrite("separate_bias", &PfxWorldParam::separateBias,
                     "Share of an overlap pushed out per step.")
      .def_readwrite("contact_slop", &PfxWorldParam::contactSlop, "Overlap left uncorrected (m).")
      .def_readwrite("contact_margin", &PfxWorldParam::contactMargin,
                     "Distance at which speculative contacts start (m).")
      .def_readwrite("restitution_threshold", &PfxWorldParam::restitutionThreshold,
                     "Approach speed below which nothing bounces (m/s).")
      .def_readwrite("enable_shock_propagation", &PfxWorldParam::enableShockPropagation,
                     "After the iterations, stop bodies sinking into those under them (off by default).")
      .def_readwrite("measure_conservation", &PfxWorldParam::measureConservation,
                     "Report energy and momentum changes in the statistics.")
      .def_readwrite("measure_stages", &PfxWorldParam::measureStages,
                     "Time each stage of the step into the statistics' stage_seconds.")
      .def_readwrite("out_of_world_behavior", &PfxWorldParam::outOfWorldBehavior,
                     "What happens to a body leaving the bounds: OUT_OF_WORLD_* flags.")
      .def_readwrite("enable_sleep", &PfxWorldParam::enableSleep, "Let islands at rest sleep.")
      .def_readwrite("sleep_linear_velocity", &PfxWorldParam::sleepLinearVelocity,
                     "Below this speed (m/s) a body counts as still.")
      .def_readwrite("sleep_angular_velocity", &PfxWorldParam::sleepAngularVelocity,
                     "Below this turn rate (rad/s) a body counts as still.")
      .def_readwrite("sleep_time", &PfxWorldParam::sleepTime,
                     "Seconds an island must stay still to sleep.")
      .def_readwrite("num_threads", &PfxWorldParam::numThreads,
                     "Threads of a step (0: every core); results are the same bits with any.");
}

void bindOutOfWorldFlags(py::module_& m) {
  m.attr("OUT_OF_WORLD_FIX_MOTION") = PfxUInt32(PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION);
  m.attr("OUT_OF_WORLD_REMOVE_PROXY") = PfxUInt32(PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY);
}

void bindStats(py::module_& m) {
  py::class_<PfxWorldStats>(m, "WorldStats", "PfxWorldStats: what the last step did and cost.")
      .def_property_readonly(
          "stage_seconds",
          [](const PfxWorldStats& s) {
            py::dict stages;
            for (int i = 0; i < kPfxStageCount; ++i) {
              stages[pfxStageName(PfxStage(i))] = s.stageSeconds[i];
            }
            return stages;
          },
          "Wall seconds of each stage by its seed name.")
      .def_readonly("step_seconds", &PfxWorldStats::stepSeconds, "Wall seconds of the step.")
      .def_readonly("num_pairs", &PfxWorldStats::numPairs, "Broad-phase pairs worked on.")
      .def_readonly("num_contact_pairs", &PfxWorldStats::numContactPairs, "Pairs with points.")
      .def_readonly("num_contact_points", &PfxWorldStats::numContactPoints, "Contact points.")
      .def_readonly("num_out_of_world", &PfxWorldStats::numOutOfWorld, "Bodies out of bounds.")
      .def_readonly("num_proxies_updated", &PfxWorldStats::numProxiesUpdated,
                    "Broadphase proxies built and sorted in the last step.")
      .def_readonly("max_penetration", &PfxWorldStats::maxPenetration, "Deepest overlap (m).")
      .def_readonly("max_joint_gap", &PfxWorldStats::maxJointGap, "Widest joint anchor gap (m).")
      .def_readonly("energy_change", &PfxWorldStats::energyChange, "J (measure_conservation).")
      .def_readonly("linear_momentum_change", &PfxWorldStats::linearMomentumChange, "kg m/s.")
      .def_readonly("angular_momentum_change", &PfxWorldStats::angularMomentumChange, "kg m^2/s.")
      .def_readonly("num_islands", &PfxWorldStats::numIslands, "Simulation islands.")
      .def_readonly("num_sleeping_islands", &PfxWorldStats::numSleepingIslands, "Asleep.")
      .def_readonly("num_awake_bodies", &PfxWorldStats::numAwakeBodies, "Moving bodies awake.")
      .def_readonly("num_sleeping_bodies", &PfxWorldStats::numSleepingBodies, "Bodies asleep.")
      .def_readonly("num_sleeping_pairs", &PfxWorldStats::numSleepingPairs, "Pairs set aside.")
      .def_readonly("num_island_groups", &PfxWorldStats::numIslandGroups,
                    "Groups of islands solved one a task (0: the world as a whole).")
      .def_readonly("num_particles", &PfxWorldStats::numParticles, "Particles in all groups.");
}

}  // namespace

py::array worldMemoryView(const py::object& worldObject, const void* data, py::ssize_t rows,
                          py::ssize_t columns, std::size_t rowBytes) {
  if (rows == 0) return newArray<PfxFloat>(0, columns);
  py::object lease =
      py::cast(new StateViewLease(worldObject), py::return_value_policy::take_ownership);
  py::array array(py::dtype::of<PfxFloat>(), {rows, columns},
                  {py::ssize_t(rowBytes), py::ssize_t(sizeof(PfxFloat))},
                  static_cast<const PfxFloat*>(data), lease);
  // Writing through the view would bypass the world's checks and the waking of its setters.
  py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return array;
}

void bindWorld(py::module_& m) {
  bindWorldParam(m);
  bindOutOfWorldFlags(m);
  bindStats(m);
  py::class_<StateViewLease>(m, "_StateViewLease",
                             "Holds a world while a zero-copy state array reads it.");

  py::class_<PyWorld>(m, "World",
                      "PfxWorld: bodies, joints and contacts, stepped by the pipeline of its\n"
                      "WorldParam. Body, joint and coupling ids count from 0 in the order added.")
      .def(py::init([](const PfxWorldParam& param) {
             auto w = std::make_unique<PyWorld>();
             raiseIfError(w->world.initialize(param), "WorldParam");
             return w;
           }),
           py::arg("param") = PfxWorldParam(), "A world initialized with param.")
      .def(
          "initialize",
          [](PyWorld& w, const PfxWorldParam& param) {
            w.requireNoStateViews("initialize");
            raiseIfError(w.world.initialize(param), "WorldParam");
            w.startGeneration(true);
          },
          py::arg("param"), "Takes new parameters and removes every body, joint and coupling.")
      .def_property_readonly(
          "param", [](const PyWorld& w) { return w.world.getParam(); },
          "A copy of the world's parameters.")
      .def(
          "set_step_param",
          [](PyWorld& w, PfxFloat timeStep, PfxUInt32 subStep, PfxUInt32 iteration,
             py::handle gravity) {
            raiseIfError(w.world.setStepParam(timeStep, subStep, iteration,
                                              toVector3(gravity, "gravity")));
          },
          py::arg("time_step"), py::arg("sub_step"), py::arg("iteration"), py::arg("gravity"),
          "Between steps: a new step, sub-steps, iterations and gravity; bodies and contacts kept.")
      .def(
          "step",
          [](PyWorld& w, long count) {
            const PfxInt32 err = stepWithoutGil(count, [&](long n) {
              PfxInt32 stepErr = PFX_OK;
              for (long i = 0; i < n && stepErr == PFX_OK; ++i) stepErr = w.world.step();
              return stepErr;
            });
            raiseIfError(err, "step");
          },
          py::arg("count") = 1, "Steps count times by param.time_step (the GIL is released).")
      .def_property(
          "simulated_time", [](const PyWorld& w) { return w.world.getSimulatedTime(); },
          [](PyWorld& w, double seconds) {
            raiseIfError(w.world.setSimulatedTime(seconds),
                         "simulated_time must be finite and not negative");
          },
          "Seconds simulated since initialize (a loaded world goes on from its saved time). "
          "Settable, for a world rebuilt to continue another's clock; a negative, NaN or "
          "infinite time raises pfx.Error and changes nothing.")
      .def_property_readonly(
          "stats", [](const PyWorld& w) { return w.world.getStats(); },
          "WorldStats of the last step (a copy).")
      .def_property_readonly(
          "num_bodies", [](const PyWorld& w) { return w.world.getNumRigidBodies(); },
          "Bodies in the world.")
      .def_property_readonly(
          "positions",
          [](const py::object& self) { return stateView(self, kStateLayout.position, 3); },
          (std::string("Positions (n, 3)") + kViewDoc).c_str())
      .def_property_readonly(
          "orientations",
          [](const py::object& self) { return stateView(self, kStateLayout.orientation, 4); },
          (std::string("Orientations (n, 4) as (x, y, z, w)") + kViewDoc).c_str())
      .def_property_readonly(
          "linear_velocities",
          [](const py::object& self) { return stateView(self, kStateLayout.linearVelocity, 3); },
          (std::string("Linear velocities (n, 3)") + kViewDoc).c_str())
      .def_property_readonly(
          "angular_velocities",
          [](const py::object& self) { return stateView(self, kStateLayout.angularVelocity, 3); },
          (std::string("Angular velocities (n, 3)") + kViewDoc).c_str())
      .def_property_readonly(
          "asleep",
          [](const PyWorld& w) {
            py::array_t<bool> out(w.world.getNumRigidBodies());
            for (PfxUInt32 i = 0; i < w.world.getNumRigidBodies(); ++i) {
              out.mutable_at(i) = w.world.getRigidState(i).isAsleep();
            }
            return out;
          },
          "Whether each body sleeps (a copy).")
      .def_property_readonly(
          "motion_types",
          [](const PyWorld& w) {
            py::array_t<PfxUInt8> out(w.world.getNumRigidBodies());
            for (PfxUInt32 i = 0; i < w.world.getNumRigidBodies(); ++i) {
              out.mutable_at(i) = w.world.getRigidState(i).getMotionType();
            }
            return out;
          },
          "MotionType of each body as integers (a copy).")
      .def(
          "set_state",
          [](PyWorld& w, PfxUInt32 id, py::handle position, py::handle orientation,
             py::handle linearVelocity, py::handle angularVelocity) {
            PfxRigidState state = stateOf(w, id);
            if (!position.is_none()) state.setPosition(toVector3(position, "position"));
            if (!orientation.is_none()) state.setOrientation(toQuat(orientation, "orientation"));
            if (!linearVelocity.is_none()) {
              state.setLinearVelocity(toVector3(linearVelocity, "linear_velocity"));
            }
            if (!angularVelocity.is_none()) {
              state.setAngularVelocity(toVector3(angularVelocity, "angular_velocity"));
            }
            raiseIfError(w.world.setRigidState(id, state), "body " + std::to_string(id));
          },
          py::arg("body"), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
          py::arg("linear_velocity") = py::none(), py::arg("angular_velocity") = py::none(),
          "Replaces what is given of a body's state (setRigidState: checked, wakes its island).")
      .def(
          "apply_force",
          [](PyWorld& w, PfxUInt32 id, py::handle force, py::handle torque) {
            raiseIfError(w.world.applyForce(id, toVector3(force, "force"),
                                            toVector3(torque, "torque")),
                         "body " + std::to_string(id));
          },
          py::arg("body"), py::arg("force"), py::arg("torque") = py::make_tuple(0, 0, 0),
          "A force (N) and torque (N m, world frame, about the centre of mass) for the next step.")
      .def(
          "set_keyframe_target",
          [](PyWorld& w, PfxUInt32 id, py::handle position, py::handle orientation) {
            raiseIfError(w.world.setKeyframeTarget(id, toVector3(position, "position"),
                                                   toQuat(orientation, "orientation")),
                         "body " + std::to_string(id));
          },
          py::arg("body"), py::arg("position"), py::arg("orientation"),
          "Moves a keyframe body to this pose over the next step.")
      .def(
          "exclude_collision",
          [](PyWorld& w, PfxUInt32 a, PfxUInt32 b) { raiseIfError(w.world.excludeCollision(a, b)); },
          py::arg("body_a"), py::arg("body_b"), "Bodies a and b never collide from now on.")
      .def(
          "truncate",
          [](PyWorld& w, PfxUInt32 numBodies, PfxUInt32 numJoints, PfxUInt32 numCouplings) {
            w.requireNoStateViews("truncate");
            raiseIfError(w.world.truncate(numBodies, numJoints, numCouplings));
            w.startGeneration(false);
          },
          py::arg("num_bodies"), py::arg("num_joints"), py::arg("num_couplings"),
          "Keeps the first bodies, joints and couplings and removes the rest.")
      .def(
          "conserved_quantities",
          [](const PyWorld& w) {
            const PfxConservedQuantities q = w.world.measureConservedQuantities();
            py::dict out;
            out["energy"] = q.energy;
            out["linear_momentum"] = fromVector3(q.linearMomentum);
            out["angular_momentum"] = fromVector3(q.angularMomentum);
            return out;
          },
          "Total energy (J), linear and angular momentum of the bodies forces move.");
}

}  // namespace pfx::python
