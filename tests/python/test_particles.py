"""Particle groups through the module: a cloth added, its positions a live view, a ray that
hits it names the group, particle and triangle and no body, and removal."""
import numpy as np
import pytest

import pfx


def world_with_cloth():
    world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.81), time_step=1 / 120, enable_sleep=False))
    cloth = pfx.ParticleGroupBuilder()
    first = cloth.add_cloth((-0.5, -0.5, 1.0), (1, 0, 0), (0, 1, 0), 8, 8,
                            pfx.ParticleMaterial(radius=0.02))
    assert first == 0 and cloth.num_particles == 64
    cloth.pin_to_world(0)
    cloth.pin_to_world(7)
    return world, world.add_particle_group(cloth)


def test_positions_are_a_live_view_that_follows_the_steps():
    world, group = world_with_cloth()
    assert world.particle_groups == [group]
    positions = world.particle_positions(group)
    assert positions.shape == (64, 3) and not positions.flags.writeable
    start = positions.copy()
    world.step(30)
    assert positions[63, 2] < start[63, 2] - 0.01          # the free corner fell
    assert np.array_equal(positions[0], start[0])          # the pinned one did not
    world.set_particle_position(group, 0, (-0.5, -0.5, 1.2))
    assert positions[0, 2] == pytest.approx(1.2)


def test_a_ray_onto_the_cloth_names_its_particle_and_no_body():
    world, group = world_with_cloth()
    world.add_body(pfx.Shape.box((1, 1, 0.1)), pfx.BodyInit(mass=0, position=(3, 0, 0)))
    hits = world.cast_rays(np.array([[0.0, 0.0, 2.0], [3.0, 0.0, 2.0]]),
                           np.array([[0.0, 0.0, -2.0], [0.0, 0.0, -2.0]]))
    assert list(hits["hit"]) == [True, True]
    assert hits["particle_group"][0] == group and hits["body"][0] == -1
    assert 0 <= hits["particle"][0] < 64 and hits["triangle"][0] >= 0
    assert hits["body"][1] == 0 and hits["particle_group"][1] == -1 and hits["particle"][1] == -1


def test_removal_and_bad_input():
    world, group = world_with_cloth()
    view = world.particle_positions(group)
    with pytest.raises(pfx.Error, match="remove_particle_group"):
        world.remove_particle_group(group)
    assert world.particle_groups == [group]
    del view
    world.remove_particle_group(group)
    assert world.particle_groups == []
    with pytest.raises(pfx.Error, match="no particle group 0"):
        world.particle_positions(0)
    with pytest.raises(pfx.InvalidValueError, match="2 particles or more"):
        pfx.ParticleGroupBuilder().add_rope((0, 0, 0), (1, 0, 0), 1)
    with pytest.raises(pfx.Error, match="particle 3 of 0"):
        pfx.ParticleGroupBuilder().pin_to_world(3)
