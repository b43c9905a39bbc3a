// Characters (pfx_character_controller.h): a controller over a world, its characters added,
// steered, jumped and removed by id, their statuses one at a time or all as numpy arrays.
#include <algorithm>

#include <pybind11/stl.h>

#include "pfx_python.h"

namespace pfx::python {

namespace {

// A controller and the world it drives, which the Python object keeps alive. It belongs to
// the world's generation it was made in: once the world is initialized, loaded or
// truncated, its characters' bodies are gone and every call raises.
class PyCharacterController {
 public:
  explicit PyCharacterController(py::object worldObject)
      : m_worldObject(std::move(worldObject)),
        m_world(m_worldObject.cast<PyWorld&>()),
        m_generation(m_world.generation),
        m_controller(m_world.world) {
    m_world.characterControllers.push_back(&m_controller);
  }
  ~PyCharacterController() {
    auto& registered = m_world.characterControllers;
    registered.erase(std::remove(registered.begin(), registered.end(), &m_controller),
                     registered.end());
  }
  PyCharacterController(const PyCharacterController&) = delete;
  PyCharacterController& operator=(const PyCharacterController&) = delete;

  PyWorld& world() { return m_world; }
  // The controller, or pfx.Error when its world changed generation.
  PfxCharacterController& current() {
    if (m_generation != m_world.generation) {
      raiseIfError(PFX_ERR_OUT_OF_RANGE,
                   "the world was initialized, loaded or truncated after this character "
                   "controller was made; its characters' bodies are gone");
    }
    return m_controller;
  }

 private:
  py::object m_worldObject;
  PyWorld& m_world;
  PfxUInt64 m_generation;
  PfxCharacterController m_controller;
};

std::string characterName(PfxUInt32 id) { return "character " + std::to_string(id); }

PfxCharacterStatus statusOf(const PfxCharacterController& controller, PfxUInt32 id) {
  PfxCharacterStatus status;
  raiseIfError(controller.getStatus(id, status), characterName(id) + ": no such character");
  return status;
}

std::vector<PfxUInt32> liveIds(const PfxCharacterController& controller) {
  std::vector<PfxUInt32> ids;
  for (PfxUInt32 id = 0; id < controller.getIdLimit(); ++id) {
    if (controller.isCharacter(id)) ids.push_back(id);
  }
  return ids;
}

const char* const kParamRanges =
    "radius > 0, height > 2 radius, mass > 0, max_step_height in [0, height - 2 radius], "
    "max_slope in [0, 89 degrees], max_force > 0, air_control in [0, 1], jump_speed >= 0, "
    "max_speed > 0, max_fall_speed > 0, landing_time >= 0, ground_probe > 0, all finite";

void bindParam(py::module_& m) {
  py::class_<PfxCharacterParam> param(
      m, "CharacterParam",
      "PfxCharacterParam: a character's capsule, mass and limits (see the README's\n"
      "\"Character controller\" for what each does).");
  defKeywordInit(param, "Any field as a keyword; the rest keep pfx's defaults.");
  param.def_readwrite("radius", &PfxCharacterParam::radius, "Capsule radius (m), > 0.")
      .def_readwrite("height", &PfxCharacterParam::height, "Foot to head (m), > 2 radius.")
      .def_readwrite("mass", &PfxCharacterParam::mass, "kg, > 0.")
      .def_readwrite("max_step_height", &PfxCharacterParam::maxStepHeight,
                     "Highest step it climbs (m), in [0, height - 2 radius].")
      .def_readwrite("max_slope", &PfxCharacterParam::maxSlope,
                     "Steepest slope it stands and walks on (rad), in [0, 89 degrees].")
      .def_readwrite("max_force", &PfxCharacterParam::maxForce,
                     "Largest force with which it changes its own velocity (N), > 0; the most\n"
                     "it pushes with.")
      .def_readwrite("air_control", &PfxCharacterParam::airControl,
                     "Share of max_force it steers with in the air, in [0, 1].")
      .def_readwrite("jump_speed", &PfxCharacterParam::jumpSpeed, "Upward m/s of a jump, >= 0.")
      .def_readwrite("max_speed", &PfxCharacterParam::maxSpeed,
                     "Fastest it walks (m/s), > 0; faster desired velocities are cut to it.")
      .def_readwrite("max_fall_speed", &PfxCharacterParam::maxFallSpeed,
                     "Fastest it falls (m/s), > 0.")
      .def_readwrite("landing_time", &PfxCharacterParam::landingTime,
                     "Seconds in the landing state, >= 0.")
      .def_readwrite("ground_probe", &PfxCharacterParam::groundProbe,
                     "How far below the capsule a surface still counts as ground (m), > 0.")
      .def_readwrite("contact_filter_self", &PfxCharacterParam::contactFilterSelf,
                     "The body's contact filter bits; its queries use the same.")
      .def_readwrite("contact_filter_target", &PfxCharacterParam::contactFilterTarget,
                     "Contact filter bits it touches.");
}

void bindStatus(py::module_& m) {
  py::enum_<PfxCharacterState>(m, "CharacterState", "The character's state machine.")
      .value("STANDING", kPfxCharacterStanding, "On the ground, no desired velocity.")
      .value("WALKING", kPfxCharacterWalking, "On the ground with a desired velocity.")
      .value("JUMPING", kPfxCharacterJumping, "After a jump, while it rises.")
      .value("FALLING", kPfxCharacterFalling, "In the air.")
      .value("SLIDING", kPfxCharacterSliding, "In the air against a surface too steep to stand on.")
      .value("LANDING", kPfxCharacterLanding, "On the ground after the air, for landing_time.");
  m.attr("CHARACTER_NO_GROUND") = PFX_CHARACTER_NO_GROUND;

  py::class_<PfxCharacterStatus> status(m, "CharacterStatus",
                                        "PfxCharacterStatus: where a character is and what it\n"
                                        "stands on, when it was read (a copy).");
  status
      .def_property_readonly(
          "foot_position", [](const PfxCharacterStatus& s) { return fromVector3(s.footPosition); },
          "The capsule's lowest point (m).")
      .def_property_readonly(
          "velocity", [](const PfxCharacterStatus& s) { return fromVector3(s.velocity); },
          "The body's velocity (m/s, world frame).")
      .def_readonly("state", &PfxCharacterStatus::state, "CharacterState.")
      .def_readonly("time_in_state", &PfxCharacterStatus::timeInState,
                    "Seconds since the last transition.")
      .def_property_readonly(
          "on_ground",
          [](const PfxCharacterStatus& s) { return s.groundBodyId != PFX_CHARACTER_NO_GROUND; },
          "Whether it stands on something.")
      .def_readonly("ground_body", &PfxCharacterStatus::groundBodyId,
                    "The body it stands on; CHARACTER_NO_GROUND in the air.")
      .def_property_readonly(
          "ground_normal", [](const PfxCharacterStatus& s) { return fromVector3(s.groundNormal); },
          "The normal of the surface it stands on (zero in the air).")
      .def_readonly("body", &PfxCharacterStatus::rigidBodyId, "The character's body in the world.")
      .def_readonly("num_steps", &PfxCharacterStatus::numSteps, "Steps climbed so far.")
      .def("__repr__", [](const PfxCharacterStatus& s) {
        return py::str("CharacterStatus(state={}, foot_position={}, ground_body={})")
            .format(pfxGetCharacterStateName(s.state), fromVector3(s.footPosition),
                    s.groundBodyId == PFX_CHARACTER_NO_GROUND ? py::object(py::none())
                                                               : py::cast(s.groundBodyId));
      });
}

// Every live character's status as arrays, one row per character, in the order of their ids.
py::dict statusArrays(const PfxCharacterController& controller) {
  const std::vector<PfxUInt32> ids = liveIds(controller);
  const py::ssize_t n = py::ssize_t(ids.size());
  auto footPositions = newArray<PfxFloat>(n, 3);
  auto velocities = newArray<PfxFloat>(n, 3);
  auto groundNormals = newArray<PfxFloat>(n, 3);
  py::array_t<PfxUInt8> states(n);
  py::array_t<PfxFloat> timesInState(n);
  py::array_t<PfxUInt32> groundBodies(n), bodies(n), numSteps(n);
  for (py::ssize_t row = 0; row < n; ++row) {
    const PfxCharacterStatus s = statusOf(controller, ids[row]);
    for (int axis = 0; axis < 3; ++axis) {
      footPositions.mutable_at(row, axis) = s.footPosition[axis];
      velocities.mutable_at(row, axis) = s.velocity[axis];
      groundNormals.mutable_at(row, axis) = s.groundNormal[axis];
    }
    states.mutable_at(row) = s.state;
    timesInState.mutable_at(row) = s.timeInState;
    groundBodies.mutable_at(row) = s.groundBodyId;
    bodies.mutable_at(row) = s.rigidBodyId;
    numSteps.mutable_at(row) = s.numSteps;
  }
  py::dict out;
  out["id"] = py::array_t<PfxUInt32>(n, ids.data());
  out["foot_position"] = footPositions;
  out["velocity"] = velocities;
  out["state"] = states;
  out["time_in_state"] = timesInState;
  out["ground_body"] = groundBodies;
  out["ground_normal"] = groundNormals;
  out["body"] = bodies;
  out["num_steps"] = numSteps;
  return out;
}

}  // namespace

void PyWorld::requireNotCharacterBody(PfxUInt32 body) const {
  for (const PfxCharacterController* controller : characterControllers) {
    for (const PfxUInt32 id : liveIds(*controller)) {
      if (statusOf(*controller, id).rigidBodyId == body) {
        raiseIfError(PFX_ERR_INVALID_VALUE,
                     "body " + std::to_string(body) + " is " + characterName(id) +
                         "'s; remove it with CharacterController.remove");
      }
    }
  }
}

void bindCharacters(py::module_& m) {
  bindParam(m);
  bindStatus(m);
  py::class_<PyCharacterController>(
      m, "CharacterController",
      "PfxCharacterController: upright capsules that walk at a desired velocity, climb steps\n"
      "and walkable slopes, jump, push and are pushed. Each character is a body of the world;\n"
      "the controller steers them once per step (update() before World.step(), or step()).\n"
      "Up is against gravity. The controller keeps its world alive; once the world is\n"
      "initialized, loaded or truncated every call raises pfx.Error.")
      .def(py::init([](const py::object& world) {
             if (!py::isinstance<PyWorld>(world)) {
               throw py::type_error(py::str("CharacterController needs a pfx.World, not a {}")
                                        .format(py::type::of(world).attr("__name__")));
             }
             return std::make_unique<PyCharacterController>(world);
           }),
           py::arg("world"), "A controller driving characters in world.")
      .def(
          "add",
          [](PyCharacterController& c, py::handle footPosition, const PfxCharacterParam& param) {
            PfxCharacterController& controller = c.current();
            const PfxVector3 foot = toVector3(footPosition, "foot_position");
            if (pfxCheckCharacterParam(param) != PFX_OK) {
              raiseIfError(PFX_ERR_INVALID_VALUE,
                           std::string("CharacterParam out of range (") + kParamRanges + ")");
            }
            c.world().requireNoStateViews("CharacterController.add");
            PfxUInt32 id = 0;
            raiseIfError(controller.addCharacter(param, foot, &id),
                         std::string("foot_position ") + py::repr(footPosition).cast<std::string>());
            return id;
          },
          py::arg("foot_position"), py::arg("param") = PfxCharacterParam(),
          "Adds a character standing with its foot at foot_position; returns its id, the lowest\n"
          "free one (a removed character's id is given out again). Raises\n"
          "pfx.InvalidValueError for a non-finite position or a param out of range.")
      .def(
          "remove",
          [](PyCharacterController& c, PfxUInt32 id) {
            raiseIfError(c.current().removeCharacter(id), characterName(id));
          },
          py::arg("character"),
          "Removes a character and its body from the world (World.remove_body refuses it).")
      .def(
          "set_desired_velocity",
          [](PyCharacterController& c, PfxUInt32 id, py::handle velocity) {
            raiseIfError(c.current().setDesiredVelocity(id, toVector3(velocity, "velocity")),
                         characterName(id));
          },
          py::arg("character"), py::arg("velocity"),
          "The velocity to walk at (m/s, world frame), kept until changed; its part along up\n"
          "is ignored and a faster one is cut to max_speed. Raises for NaN or infinity.")
      .def(
          "jump",
          [](PyCharacterController& c, PfxUInt32 id) {
            raiseIfError(c.current().requestJump(id), characterName(id));
          },
          py::arg("character"),
          "Jumps at the next update if the character is then on the ground; forgotten otherwise.")
      .def(
          "status",
          [](PyCharacterController& c, PfxUInt32 id) { return statusOf(c.current(), id); },
          py::arg("character"), "CharacterStatus of one character (a copy).")
      .def(
          "param",
          [](PyCharacterController& c, PfxUInt32 id) {
            PfxCharacterParam param;
            raiseIfError(c.current().getParam(id, param), characterName(id));
            return param;
          },
          py::arg("character"), "A copy of the character's CharacterParam.")
      .def(
          "states", [](PyCharacterController& c) { return statusArrays(c.current()); },
          "Every character's status as a dict of arrays, one row per character in the order\n"
          "of their ids (copies): id, foot_position (n, 3), velocity (n, 3), state (uint8,\n"
          "CharacterState values), time_in_state, ground_body (CHARACTER_NO_GROUND in the\n"
          "air), ground_normal (n, 3), body, num_steps.")
      .def_property_readonly(
          "ids", [](PyCharacterController& c) { return liveIds(c.current()); },
          "The characters' ids, ascending.")
      .def(
          "__contains__",
          [](PyCharacterController& c, PfxUInt32 id) { return c.current().isCharacter(id); },
          py::arg("character"), "Whether id names a character.")
      .def(
          "__len__", [](PyCharacterController& c) { return c.current().getNumCharacters(); },
          "How many characters there are.")
      .def(
          "update",
          [](PyCharacterController& c) { raiseIfError(c.current().update(), "update"); },
          "Senses and steers every character for the next World.step(); call once before each.")
      .def(
          "step",
          [](PyCharacterController& c, long count) {
            PfxCharacterController& controller = c.current();
            PfxWorld& world = c.world().world;
            const PfxInt32 err = stepWithoutGil(count, [&](long n) {
              PfxInt32 stepErr = PFX_OK;
              for (long i = 0; i < n && stepErr == PFX_OK; ++i) {
                stepErr = controller.update();
                if (stepErr == PFX_OK) stepErr = world.step();
              }
              return stepErr;
            });
            raiseIfError(err, "step");
          },
          py::arg("count") = 1,
          "update() then World.step(), count times (the GIL is released).");
}

}  // namespace pfx::python
