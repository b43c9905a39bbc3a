"""Every shape becomes a body, joints hold bodies together, couplings make one axis follow
another."""
import math

import numpy as np
import pytest

import pfx

CUBE_VERTICES = [[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
CUBE_TRIANGLES = [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]


def ground_world():
    world = pfx.World(pfx.WorldParam(enable_sleep=False))
    world.add_body(pfx.Shape.box((20, 0.5, 20)), pfx.BodyInit(mass=0, position=(0, -0.5, 0)))
    return world


def test_every_shape_comes_to_rest_on_the_ground():
    world = ground_world()
    mesh = pfx.ConvexMesh(CUBE_VERTICES, CUBE_TRIANGLES)
    assert mesh.vertices.shape == (8, 3) and mesh.num_faces == 6
    shapes = {
        "sphere": (pfx.Shape.sphere(0.5), 0.5),
        "box": (pfx.Shape.box((0.5, 0.5, 0.5)), 0.5),
        "capsule": (pfx.Shape.capsule(0.5, 0.5), 0.5),
        "cylinder": (pfx.Shape.cylinder(0.5, 0.5), 0.5),
        "convex_mesh": (pfx.Shape.convex_mesh(mesh), 0.5),
    }
    ids = {}
    for i, (name, (shape, _)) in enumerate(shapes.items()):
        assert shape.type == name
        ids[name] = world.add_body(shape, pfx.BodyInit(position=(3 * i - 6, 1.5, 0)))
    del mesh  # the body keeps the mesh alive
    world.step(180)
    for name, (_, rest_height) in shapes.items():
        assert world.positions[ids[name], 1] == pytest.approx(rest_height, abs=0.02), name
    assert world.body_mass(ids["box"]) == pytest.approx(1)


def test_compound_body_with_offsets():
    world = ground_world()
    parts = [pfx.Shape.box((0.5, 0.1, 0.1), offset_position=(0, 0, 0)),
             pfx.Shape.sphere(0.2, offset_position=(0.6, 0, 0)),
             pfx.Shape.sphere(0.2, offset_position=(-0.6, 0, 0))]
    body = world.add_body(parts, pfx.BodyInit(position=(0, 1, 0), mass=2))
    np.testing.assert_array_equal(parts[1].offset_position, np.float32([0.6, 0, 0]))
    world.step(120)
    assert world.positions[body, 1] == pytest.approx(0.2, abs=0.02)


def test_bad_convex_mesh_is_rejected():
    open_surface = CUBE_TRIANGLES[:-2]
    with pytest.raises(pfx.InvalidValueError):
        pfx.ConvexMesh(CUBE_VERTICES, open_surface)


def test_hinge_pendulum_swings_about_its_axis():
    world = pfx.World(pfx.WorldParam(enable_sleep=False, time_step=1 / 240))
    anchor = world.add_body(pfx.Shape.sphere(0.05), pfx.BodyInit(mass=0, position=(0, 2, 0)))
    bob = world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(position=(1, 2, 0)))
    joint = world.add_hinge_joint(anchor, bob, pfx.HingeJointInitParam(anchor_point=(0, 2, 0),
                                                                       axis=(0, 0, 1)))
    assert world.num_joints == 1 and world.joint(joint).body_b == bob
    lowest = 2.0
    for _ in range(240):
        world.step()
        lowest = min(lowest, float(world.positions[bob, 1]))
        assert np.linalg.norm(world.positions[bob] - (0, 2, 0)) == pytest.approx(1, abs=2e-3)
    assert lowest == pytest.approx(1, abs=0.01)  # it passed below the anchor
    assert abs(world.positions[bob, 2]) < 1e-3  # and stayed in its plane
    twist = world.joint_coordinates(joint)[3]
    assert abs(twist) > 0.1


def test_removing_a_joint_and_a_body():
    world = ground_world()
    anchor = world.add_body(pfx.Shape.sphere(0.05), pfx.BodyInit(mass=0, position=(0, 3, 0)))
    bob = world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(position=(1, 3, 0)))
    joint = world.add_hinge_joint(anchor, bob, pfx.HingeJointInitParam(anchor_point=(0, 3, 0),
                                                                       axis=(0, 0, 1)))
    box = world.add_body(pfx.Shape.box((0.2, 0.2, 0.2)), pfx.BodyInit(position=(3, 0.2, 0)))
    positions = world.positions  # a live view: removal keeps the state array where it is
    world.step(30)
    assert np.linalg.norm(positions[bob] - (0, 3, 0)) == pytest.approx(1, abs=2e-3)

    world.remove_joint(joint)
    assert not world.has_joint(joint)
    with pytest.raises(pfx.Error, match="remove_joint"):
        world.remove_joint(joint)
    world.step(60)  # the bob falls free, no longer held at 1 m from the anchor
    assert np.linalg.norm(positions[bob] - (0, 3, 0)) > 1.5

    resting = positions[box].copy()
    world.remove_body(box)
    assert not world.has_body(box) and world.has_body(bob)
    before = positions.copy()
    with pytest.raises(pfx.Error, match="remove_body"):
        world.remove_body(box)
    with pytest.raises(pfx.Error):
        world.remove_body(world.num_bodies + 5)
    assert np.array_equal(positions, before)
    hit = world.cast_ray((3, 2, 0), (0, -3, 0))  # straight down where the box rested
    assert hit["hit"][0] and hit["body"][0] != box
    assert float(hit["point"][0][1]) < resting[1] - 0.1  # the ground, not the box


def test_joint_drive_and_limits_through_set_joint():
    world = pfx.World(pfx.WorldParam(enable_sleep=False, gravity=(0, 0, 0)))
    base = world.add_body(pfx.Shape.box((0.1, 0.1, 0.1)), pfx.BodyInit(mass=0))
    wheel = world.add_body(pfx.Shape.cylinder(0.05, 0.3), pfx.BodyInit(position=(0.3, 0, 0)))
    joint_id = world.add_hinge_joint(base, wheel, pfx.HingeJointInitParam(
        anchor_point=(0.3, 0, 0), axis=(1, 0, 0)))
    joint = world.joint(joint_id)
    axis = joint.axis(3)
    axis.drive = pfx.JointDrive.VELOCITY
    axis.drive_target = 2.0
    axis.drive_max_force = 100
    world.set_joint(joint_id, joint)
    world.step(30)
    np.testing.assert_allclose(world.angular_velocities[wheel], (2, 0, 0), atol=1e-3)
    axis.drive_target = math.nan
    with pytest.raises(pfx.InvalidValueError):
        world.set_joint(joint_id, joint)
    assert world.joint(joint_id).axis(3).drive_target == 2.0


def test_every_joint_kind_can_be_added():
    world = pfx.World(pfx.WorldParam(enable_sleep=False))
    bodies = [world.add_body(pfx.Shape.box((0.1, 0.1, 0.1)), pfx.BodyInit(position=(i, 0, 0)))
              for i in range(7)]
    adders = [world.add_ball_joint, world.add_swing_twist_joint, world.add_hinge_joint,
              world.add_slider_joint, world.add_fixed_joint, world.add_universal_joint]
    params = [pfx.BallJointInitParam, pfx.SwingTwistJointInitParam, pfx.HingeJointInitParam,
              pfx.SliderJointInitParam, pfx.FixedJointInitParam, pfx.UniversalJointInitParam]
    for i, (add, param) in enumerate(zip(adders, params)):
        assert add(bodies[i], bodies[i + 1], param(anchor_point=(i + 0.5, 0, 0))) == i
    kinds = [world.joint(i).type for i in range(6)]
    assert kinds == [pfx.JOINT_BALL, pfx.JOINT_SWING_TWIST, pfx.JOINT_HINGE, pfx.JOINT_SLIDER,
                     pfx.JOINT_FIXED, pfx.JOINT_UNIVERSAL]
    world.step(10)
    assert world.stats.max_joint_gap < 1e-3


def test_coupling_makes_one_slider_follow_another():
    world = pfx.World(pfx.WorldParam(enable_sleep=False, gravity=(0, 0, 0)))
    base = world.add_body(pfx.Shape.box((1, 0.1, 0.1)), pfx.BodyInit(mass=0))
    left = world.add_body(pfx.Shape.box((0.05, 0.05, 0.05)), pfx.BodyInit(position=(-0.5, 0.2, 0)))
    right = world.add_body(pfx.Shape.box((0.05, 0.05, 0.05)), pfx.BodyInit(position=(0.5, 0.2, 0)))
    leader = world.add_slider_joint(base, left, pfx.SliderJointInitParam(
        anchor_point=(-0.5, 0.2, 0), direction=(0, 1, 0)))
    follower = world.add_slider_joint(base, right, pfx.SliderJointInitParam(
        anchor_point=(0.5, 0.2, 0), direction=(0, 1, 0)))
    coupling = world.add_joint_coupling(pfx.JointCoupling(leader, 0, follower, 0, multiplier=-1))
    assert world.num_joint_couplings == 1
    world.set_state(left, linear_velocity=(0, 0.5, 0))
    world.step(60)
    lead = world.joint_coordinates(leader)[0]
    follow = world.joint_coordinates(follower)[0]
    assert lead > 0.1
    assert follow == pytest.approx(-lead, abs=1e-3)
    assert abs(world.joint_coupling(coupling).error) < 1e-3
