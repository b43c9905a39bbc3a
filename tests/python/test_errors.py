"""Bad input raises pfx.Error carrying pfx's own message, and the world stays as it was."""
import math
import os

import numpy as np
import pytest

import pfx
from pfx_scenes import ARM_URDF, state_lines


def small_world():
    world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.80665), enable_sleep=False))
    world.add_body(pfx.Shape.box((5, 5, 0.5)), pfx.BodyInit(mass=0, position=(0, 0, -0.5)))
    world.add_body(pfx.Shape.sphere(0.2), pfx.BodyInit(position=(0, 0, 1)))
    world.step(5)
    return world


def assert_unchanged(world, before, bodies=2, joints=0):
    assert world.num_bodies == bodies
    assert world.num_joints == joints
    assert state_lines(world) == before


def test_nan_position_is_rejected():
    world = small_world()
    before = state_lines(world)
    with pytest.raises(pfx.InvalidValueError) as error:
        world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(position=(math.nan, 0, 1)))
    assert error.value.code == pfx.ERR_INVALID_VALUE
    assert str(error.value).startswith(pfx.error_string(pfx.ERR_INVALID_VALUE))
    assert isinstance(error.value, ValueError) and isinstance(error.value, RuntimeError)
    with pytest.raises(pfx.Error):
        world.set_state(1, position=(0, np.nan, 1))
    assert_unchanged(world, before)


def test_negative_mass_is_rejected():
    world = small_world()
    before = state_lines(world)
    with pytest.raises(pfx.InvalidValueError, match="invalid value"):
        world.add_body(pfx.Shape.box((0.1, 0.1, 0.1)), pfx.BodyInit(mass=-1))
    assert_unchanged(world, before)


def test_bad_shape_and_bad_ids_are_rejected():
    world = small_world()
    before = state_lines(world)
    with pytest.raises(pfx.Error):
        world.add_body(pfx.Shape.sphere(-1))
    with pytest.raises(pfx.Error) as error:
        world.set_state(7, position=(0, 0, 0))
    assert error.value.code == pfx.ERR_OUT_OF_RANGE
    with pytest.raises(pfx.Error):
        world.add_hinge_joint(1, 1)
    with pytest.raises(pfx.Error):
        world.add_joint_coupling(pfx.JointCoupling(0, 3, 1, 3))
    assert_unchanged(world, before)


def test_bad_world_param_is_rejected():
    world = small_world()
    before = state_lines(world)
    with pytest.raises(pfx.InvalidValueError):
        world.initialize(pfx.WorldParam(time_step=-1))
    with pytest.raises(pfx.InvalidValueError):
        world.set_step_param(0, 1, 10, (0, 0, -9.8))
    assert world.param.time_step == pytest.approx(1 / 60)
    assert_unchanged(world, before)


def test_missing_urdf_names_the_file():
    world = small_world()
    before = state_lines(world)
    missing = os.path.join(os.path.dirname(ARM_URDF), "no_such_robot.urdf")
    with pytest.raises(pfx.Error, match="no_such_robot.urdf"):
        world.load_urdf(missing)
    with pytest.raises(pfx.Error, match="no_such_mesh.stl"):
        pfx.load_mesh("no_such_mesh.stl")
    with pytest.raises(pfx.Error, match="no_such_world.pfx"):
        world.load("no_such_world.pfx")
    assert_unchanged(world, before)


def test_malformed_urdf_text_is_rejected():
    world = small_world()
    before = state_lines(world)
    with pytest.raises(pfx.Error, match="<urdf string>"):
        world.load_urdf_string("<robot name='r'><link name='a'></robot>")
    # Well-formed XML with a physically impossible link: the loader names link and reason.
    bad_inertia = """<robot name="r"><link name="base">
      <inertial><mass value="1"/><inertia ixx="-1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/>
      </inertial><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
      </link></robot>"""
    with pytest.raises(pfx.Error, match="base"):
        world.load_urdf_string(bad_inertia)
    assert_unchanged(world, before)


def test_stale_model_raises_after_initialize():
    world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.80665)))
    model = world.load_urdf(ARM_URDF, pfx.UrdfLoadParam(fixed_base=True))
    assert len(model.joint_states()[0]) == len(model.joints)
    world.initialize(pfx.WorldParam())
    with pytest.raises(pfx.Error, match="bodies are gone"):
        model.joint_states()


def test_bad_array_shapes_raise_value_error():
    world = small_world()
    with pytest.raises(ValueError):
        world.cast_rays(np.zeros((3, 2)), np.zeros((3, 3)))
    with pytest.raises(ValueError):
        world.cast_rays(np.zeros((3, 3)), np.zeros((2, 3)))
    with pytest.raises(TypeError):
        pfx.WorldParam(no_such_field=1)


def test_nan_ray_is_rejected():
    world = small_world()
    before = state_lines(world)
    with pytest.raises(pfx.InvalidValueError):
        world.cast_rays([[0, 0, 2], [0, 0, np.nan]], [[0, 0, -3], [0, 0, -3]])
    with pytest.raises(pfx.InvalidValueError):
        world.cast_ray((0, 0, 2), (np.inf, 0, -3))
    assert_unchanged(world, before)


def test_corrupt_saved_world_is_rejected(tmp_path):
    world = small_world()
    path = tmp_path / "small.pfx"
    world.save(str(path))
    path.write_bytes(path.read_bytes()[:100])
    before = state_lines(world)
    with pytest.raises(pfx.Error, match="small.pfx"):
        world.load(str(path))
    assert_unchanged(world, before)


def test_simulated_time_is_set_and_bad_times_are_refused():
    world = small_world()
    world.simulated_time = 12.5
    assert world.simulated_time == 12.5
    world.step()
    assert world.simulated_time == pytest.approx(12.5 + world.param.time_step)
    now = world.simulated_time
    before = state_lines(world)
    for bad in (-1.0, math.nan, math.inf):
        with pytest.raises(pfx.InvalidValueError) as error:
            world.simulated_time = bad
        assert "simulated_time" in str(error.value)
        assert world.simulated_time == now
    assert_unchanged(world, before)
