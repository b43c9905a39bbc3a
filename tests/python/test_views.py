"""Zero-copy state arrays: they show the current state, cannot be written, keep their world
alive, and calls that would move or drop the memory under them raise instead."""
import numpy as np
import pytest

import pfx


def falling_box():
    world = pfx.World(pfx.WorldParam(enable_sleep=False))
    world.add_body(pfx.Shape.box((10, 1, 10)), pfx.BodyInit(mass=0, position=(0, -1, 0)))
    world.add_body(pfx.Shape.box((0.5, 0.5, 0.5)), pfx.BodyInit(position=(0, 3, 0)))
    return world


def test_view_shows_each_step_without_copy():
    world = falling_box()
    positions = world.positions
    assert positions.shape == (2, 3) and positions.dtype == pfx.FLOAT_DTYPE
    assert not positions.flags.owndata
    heights = []
    for _ in range(10):
        world.step()
        heights.append(float(positions[1, 1]))
    assert heights == sorted(heights, reverse=True) and heights[-1] < 3
    np.testing.assert_array_equal(positions, world.positions)


def test_every_field_is_viewed_in_place():
    world = falling_box()
    world.set_state(1, orientation=(0, 0, np.sin(0.25), np.cos(0.25)),
                    linear_velocity=(1, 2, 3), angular_velocity=(4, 5, 6))
    np.testing.assert_allclose(world.orientations[1], (0, 0, np.sin(0.25), np.cos(0.25)),
                               rtol=1e-6)
    np.testing.assert_array_equal(world.linear_velocities[1], (1, 2, 3))
    np.testing.assert_array_equal(world.angular_velocities[1], (4, 5, 6))
    np.testing.assert_array_equal(world.positions[1], (0, 3, 0))


def test_view_is_read_only():
    world = falling_box()
    with pytest.raises(ValueError):
        world.positions[1, 1] = 10
    assert world.positions[1, 1] == 3


def test_adding_bodies_under_a_live_view_raises_and_changes_nothing():
    world = falling_box()
    view = world.orientations
    with pytest.raises(pfx.Error, match="live zero-copy"):
        world.add_body(pfx.Shape.sphere(0.5), pfx.BodyInit(position=(3, 1, 0)))
    with pytest.raises(pfx.Error, match="live zero-copy"):
        world.truncate(1, 0, 0)
    with pytest.raises(pfx.Error, match="live zero-copy"):
        world.initialize(pfx.WorldParam())
    assert world.num_bodies == 2
    snapshot = view.copy()
    del view
    assert world.add_body(pfx.Shape.sphere(0.5), pfx.BodyInit(position=(3, 1, 0))) == 2
    assert world.num_bodies == 3
    np.testing.assert_array_equal(world.orientations[:2], snapshot)


def test_slices_of_a_view_hold_the_lease():
    world = falling_box()
    column = world.positions[:, 1]
    with pytest.raises(pfx.Error):
        world.add_body(pfx.Shape.sphere(0.5))
    del column
    world.add_body(pfx.Shape.sphere(0.5), pfx.BodyInit(position=(3, 1, 0)))


def test_view_keeps_its_world_alive():
    world = falling_box()
    positions = world.positions
    del world
    assert positions[1, 1] == 3


def test_empty_world_gives_empty_arrays():
    world = pfx.World()
    assert world.positions.shape == (0, 3)
    assert world.orientations.shape == (0, 4)
    world.add_body(pfx.Shape.sphere(1))
