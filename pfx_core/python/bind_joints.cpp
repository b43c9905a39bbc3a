// Joints (the six kinds and their pfxInitialize...Joint helpers, then each axis's lock,
// limits and drive) and couplings between two joints' axes.
#include <algorithm>

#include "pfx_python.h"

namespace pfx::python {

namespace {

template <typename Param>
using JointInitFunc = PfxInt32 (*)(PfxJoint&, const PfxRigidState&, const PfxRigidState&,
                                   const Param&);

template <typename Param>
py::class_<Param> bindInitParam(py::module_& m, const char* name, const char* doc) {
  py::class_<Param> cls(m, name, doc);
  defKeywordInit(cls, "Any field as a keyword; the rest keep pfx's defaults.");
  defVector3(cls, "anchor_point", &Param::anchorPoint, "The joint's origin, world frame (m).");
  cls.def_readwrite("damping", &Param::damping, "Share of relative velocity removed per step.")
      .def_readwrite("bias", &Param::bias, "Share of position error corrected per step.")
      .def_readwrite("enable_joint_frame", &Param::enableJointFrame,
                     "Take the frame from joint_frame instead of the axis fields.");
  cls.def_property(
      "joint_frame",
      [](const Param& p) {
        auto out = newArray<PfxFloat>(3, 3);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) out.mutable_at(r, c) = p.jointFrame(r, c);
        return out;
      },
      [](Param& p, py::handle value) {
        const auto rows = toRows(value, 3, "joint_frame");
        if (rows.shape(0) != 3) throw py::value_error("joint_frame must be 3 x 3");
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) p.jointFrame(r, c) = rows.at(r, c);
      },
      "World frame of the joint, columns X, Y, Z (3 x 3).");
  return cls;
}

template <typename Param>
void defAddJoint(py::class_<PyWorld>& world, const char* name, JointInitFunc<Param> initialize,
                 const char* doc) {
  world.def(
      name,
      [initialize, name](PyWorld& w, PfxUInt32 a, PfxUInt32 b, const Param& param) {
        const PfxUInt32 n = w.world.getNumRigidBodies();
        if (a >= n || b >= n) raiseIfError(PFX_ERR_OUT_OF_RANGE, "body id");
        PfxJoint joint;
        raiseIfError(initialize(joint, w.world.getRigidState(a), w.world.getRigidState(b), param),
                     name);
        PfxUInt32 id = 0;
        raiseIfError(w.world.addJoint(joint, &id), name);
        return id;
      },
      py::arg("body_a"), py::arg("body_b"), py::arg("param") = Param(), doc);
}

const PfxJoint& jointOf(const PyWorld& w, PfxUInt32 id) {
  if (id >= w.world.getNumJoints()) raiseIfError(PFX_ERR_OUT_OF_RANGE, "joint id");
  return w.world.getJoint(id);
}

void bindJointTypes(py::module_& m) {
  py::enum_<PfxJointLock>(m, "JointLock", "What an axis of a joint allows.")
      .value("FREE", kPfxJointLockFree)
      .value("LOCKED", kPfxJointLockLocked)
      .value("LIMIT", kPfxJointLockLimit, "Between lower_limit and upper_limit.");
  py::enum_<PfxJointDrive>(m, "JointDrive", "A motor on an axis.")
      .value("NONE", kPfxJointDriveNone)
      .value("VELOCITY", kPfxJointDriveVelocity, "drive_target is m/s or rad/s.")
      .value("POSITION", kPfxJointDrivePosition, "drive_target is m or rad.");

  py::class_<PfxJointConstraint>(m, "JointAxis",
                                 "One of a joint's six axes (X, Y, Z, twist, swing1, swing2).")
      .def_property(
          "lock", [](const PfxJointConstraint& c) { return PfxJointLock(c.m_lock); },
          [](PfxJointConstraint& c, PfxJointLock v) { c.m_lock = v; }, "JointLock.")
      .def_property(
          "drive", [](const PfxJointConstraint& c) { return PfxJointDrive(c.m_drive); },
          [](PfxJointConstraint& c, PfxJointDrive v) { c.m_drive = v; }, "JointDrive.")
      .def_readwrite("lower_limit", &PfxJointConstraint::m_movableLowerLimit, "m or rad.")
      .def_readwrite("upper_limit", &PfxJointConstraint::m_movableUpperLimit, "m or rad.")
      .def_readwrite("bias", &PfxJointConstraint::m_bias, "0..1.")
      .def_readwrite("weight", &PfxJointConstraint::m_weight, "0..1; below 1 the axis is soft.")
      .def_readwrite("damping", &PfxJointConstraint::m_damping, "0..1 per step.")
      .def_readwrite("friction", &PfxJointConstraint::m_friction, "N or N m.")
      .def_readwrite("drive_target", &PfxJointConstraint::m_driveTarget, "See JointDrive.")
      .def_readwrite("drive_max_force", &PfxJointConstraint::m_driveMaxForce, "N or N m.")
      .def_readonly("position", &PfxJointConstraint::m_position,
                    "The coordinate when last measured (m or rad).");

  py::class_<PfxJoint>(m, "Joint",
                       "PfxJoint: a copy of a world's joint (World.joint); change its axes and\n"
                       "give it back with World.set_joint.")
      .def_readonly("body_a", &PfxJoint::m_rigidBodyIdA, "Id of body A.")
      .def_readonly("body_b", &PfxJoint::m_rigidBodyIdB, "Id of body B.")
      .def_property_readonly("type", [](const PfxJoint& j) { return int(j.m_type); },
                             "JOINT_* kind it was made as.")
      .def(
          "axis",
          [](PfxJoint& j, PfxUInt32 i) -> PfxJointConstraint& {
            if (i >= 6) raiseIfError(PFX_ERR_OUT_OF_RANGE, "axis index (0..5)");
            return j.m_constraints[i];
          },
          py::arg("index"), py::return_value_policy::reference_internal,
          "Axis 0..5 (X, Y, Z, twist, swing1, swing2), editable in place.")
      .def("applied_force", &PfxJoint::getAppliedForce, py::arg("time_step"),
           "Force on body B in the last step (N, world).")
      .def("applied_torque", &PfxJoint::getAppliedTorque, py::arg("time_step"),
           "Torque on body B in the last step (N m, world).");
  m.attr("JOINT_BALL") = int(kPfxJointBall);
  m.attr("JOINT_SWING_TWIST") = int(kPfxJointSwingTwist);
  m.attr("JOINT_HINGE") = int(kPfxJointHinge);
  m.attr("JOINT_SLIDER") = int(kPfxJointSlider);
  m.attr("JOINT_FIXED") = int(kPfxJointFixed);
  m.attr("JOINT_UNIVERSAL") = int(kPfxJointUniversal);
}

void bindInitParams(py::module_& m) {
  bindInitParam<PfxBallJointInitParam>(m, "BallJointInitParam", "A ball joint: rotations free.");
  bindInitParam<PfxFixedJointInitParam>(m, "FixedJointInitParam", "Every axis locked.");
  auto swing = bindInitParam<PfxSwingTwistJointInitParam>(
      m, "SwingTwistJointInitParam", "A twist range about twist_axis and a swing cone.");
  defVector3(swing, "twist_axis", &PfxSwingTwistJointInitParam::twistAxis, "World axis.");
  swing.def_readwrite("twist_lower_angle", &PfxSwingTwistJointInitParam::twistLowerAngle, "rad.")
      .def_readwrite("twist_upper_angle", &PfxSwingTwistJointInitParam::twistUpperAngle, "rad.")
      .def_readwrite("swing_upper_angle", &PfxSwingTwistJointInitParam::swingUpperAngle,
                     "Half angle of the cone (rad).");
  auto hinge = bindInitParam<PfxHingeJointInitParam>(m, "HingeJointInitParam",
                                                     "Turns about axis between two angles.");
  defVector3(hinge, "axis", &PfxHingeJointInitParam::axis, "World axis.");
  hinge.def_readwrite("lower_angle", &PfxHingeJointInitParam::lowerAngle, "rad (-pi: free).")
      .def_readwrite("upper_angle", &PfxHingeJointInitParam::upperAngle, "rad (pi: free).");
  auto slider = bindInitParam<PfxSliderJointInitParam>(m, "SliderJointInitParam",
                                                       "Slides along direction.");
  defVector3(slider, "direction", &PfxSliderJointInitParam::direction, "World direction.");
  slider.def_readwrite("lower_distance", &PfxSliderJointInitParam::lowerDistance, "m.")
      .def_readwrite("upper_distance", &PfxSliderJointInitParam::upperDistance, "m.");
  auto universal = bindInitParam<PfxUniversalJointInitParam>(
      m, "UniversalJointInitParam", "Twist about axis locked, two swings limited.");
  defVector3(universal, "axis", &PfxUniversalJointInitParam::axis, "The locked twist axis.");
  defVector3(universal, "up_vec", &PfxUniversalJointInitParam::upVec, "Fixes the frame's Y.");
  universal
      .def_readwrite("swing1_lower_angle", &PfxUniversalJointInitParam::swing1LowerAngle, "rad.")
      .def_readwrite("swing1_upper_angle", &PfxUniversalJointInitParam::swing1UpperAngle, "rad.")
      .def_readwrite("swing2_lower_angle", &PfxUniversalJointInitParam::swing2LowerAngle, "rad.")
      .def_readwrite("swing2_upper_angle", &PfxUniversalJointInitParam::swing2UpperAngle, "rad.");
}

void bindCoupling(py::module_& m) {
  py::class_<PfxJointCoupling> coupling(
      m, "JointCoupling", "follower = multiplier * leader + offset between two joint axes.");
  coupling.def(py::init([](PfxUInt32 leader, PfxUInt32 leaderAxis, PfxUInt32 follower,
                           PfxUInt32 followerAxis, PfxFloat multiplier, PfxFloat offset) {
                 PfxJointCoupling c;
                 c.reset();
                 c.m_leaderJointId = leader;
                 c.m_followerJointId = follower;
                 // Out-of-range axes are kept out of range, for pfxCheckJointCoupling to reject.
                 c.m_leaderAxis = PfxUInt8(std::min<PfxUInt32>(leaderAxis, 255));
                 c.m_followerAxis = PfxUInt8(std::min<PfxUInt32>(followerAxis, 255));
                 c.m_multiplier = multiplier;
                 c.m_offset = offset;
                 return c;
               }),
               py::arg("leader_joint"), py::arg("leader_axis"), py::arg("follower_joint"),
               py::arg("follower_axis"), py::arg("multiplier") = 1, py::arg("offset") = 0,
               "A coupling of one axis (0..5) of each of two joints.")
      .def_readwrite("multiplier", &PfxJointCoupling::m_multiplier, "Follower per unit of leader.")
      .def_readwrite("offset", &PfxJointCoupling::m_offset, "m or rad.")
      .def_readwrite("bias", &PfxJointCoupling::m_bias, "Share of the error corrected per step.")
      .def_readwrite("max_impulse_force", &PfxJointCoupling::m_maxImpulseForce,
                     "Largest force or torque; <= 0: none.")
      .def_readonly("error", &PfxJointCoupling::m_error,
                    "follower - multiplier * leader - offset when last measured.");
}

}  // namespace

void bindJoints(py::module_& m) {
  bindJointTypes(m);
  bindInitParams(m);
  bindCoupling(m);
  py::class_<PyWorld> world(m.attr("World"));
  defAddJoint<PfxBallJointInitParam>(world, "add_ball_joint", &pfxInitializeBallJoint,
                                     "A ball joint between bodies a and b; returns its id.");
  defAddJoint<PfxSwingTwistJointInitParam>(world, "add_swing_twist_joint",
                                           &pfxInitializeSwingTwistJoint,
                                           "A swing-twist joint; returns its id.");
  defAddJoint<PfxHingeJointInitParam>(world, "add_hinge_joint", &pfxInitializeHingeJoint,
                                      "A hinge; returns its id.");
  defAddJoint<PfxSliderJointInitParam>(world, "add_slider_joint", &pfxInitializeSliderJoint,
                                       "A slider; returns its id.");
  defAddJoint<PfxFixedJointInitParam>(world, "add_fixed_joint", &pfxInitializeFixedJoint,
                                      "A fixed joint; returns its id.");
  defAddJoint<PfxUniversalJointInitParam>(world, "add_universal_joint",
                                          &pfxInitializeUniversalJoint,
                                          "A universal joint; returns its id.");
  world
      .def_property_readonly(
          "num_joints", [](const PyWorld& w) { return w.world.getNumJoints(); }, "Joints.")
      .def(
          "joint", [](const PyWorld& w, PfxUInt32 id) { return jointOf(w, id); }, py::arg("id"),
          "A copy of joint id.")
      .def(
          "set_joint",
          [](PyWorld& w, PfxUInt32 id, const PfxJoint& joint) {
            raiseIfError(w.world.setJoint(id, joint), "joint " + std::to_string(id));
          },
          py::arg("id"), py::arg("joint"), "Replaces joint id (limits, drives), checked.")
      .def(
          "remove_joint",
          [](PyWorld& w, PfxUInt32 id) {
            raiseIfError(w.world.removeJoint(id), "remove_joint " + std::to_string(id));
          },
          py::arg("id"),
          "Removes the joint and its couplings; its bodies may collide again. Raises\n"
          "pfx.Error for an unknown or removed id, with nothing changed.")
      .def(
          "has_joint", [](const PyWorld& w, PfxUInt32 id) { return w.world.hasJoint(id); },
          py::arg("id"), "False for a removed id and for one never given.")
      .def(
          "joint_coordinates",
          [](const PyWorld& w, PfxUInt32 id) {
            const PfxJoint& joint = jointOf(w, id);
            PfxFloat coordinates[6];
            pfxCalcJointCoordinates(joint, w.world.getRigidState(joint.m_rigidBodyIdA),
                                    w.world.getRigidState(joint.m_rigidBodyIdB), coordinates);
            py::array_t<PfxFloat> out(6);
            std::copy(coordinates, coordinates + 6, out.mutable_data());
            return out;
          },
          py::arg("id"), "The six coordinates now: B's anchor in A's frame (m), twist, swings (rad).")
      .def_property_readonly(
          "num_joint_couplings", [](const PyWorld& w) { return w.world.getNumJointCouplings(); },
          "Couplings.")
      .def(
          "add_joint_coupling",
          [](PyWorld& w, const PfxJointCoupling& coupling) {
            PfxUInt32 id = 0;
            raiseIfError(w.world.addJointCoupling(coupling, &id), "add_joint_coupling");
            return id;
          },
          py::arg("coupling"), "Adds a JointCoupling; returns its id.")
      .def(
          "joint_coupling",
          [](const PyWorld& w, PfxUInt32 id) {
            if (id >= w.world.getNumJointCouplings()) raiseIfError(PFX_ERR_OUT_OF_RANGE, "coupling id");
            return w.world.getJointCoupling(id);
          },
          py::arg("id"), "A copy of coupling id.");
}

}  // namespace pfx::python
