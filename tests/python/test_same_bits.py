"""The module steps a scene to the same bits as the C++ API (pfx_python_reference)."""
import os
import tempfile

import pfx
from pfx_scenes import ARM_URDF, build_arm, build_pyramid, state_lines

ARM_STEPS = 240
PYRAMID_STEPS = 60


def test_arm_matches_cpp(reference):
    world, _ = build_arm()
    world.step(ARM_STEPS)
    expected = reference("arm", ARM_URDF, ARM_STEPS)
    assert len(expected) == world.num_bodies
    assert state_lines(world) == expected


def test_pyramid_matches_cpp(reference):
    world = build_pyramid()
    assert world.num_bodies == 211
    for _ in range(PYRAMID_STEPS):
        world.step()
    assert state_lines(world) == reference("pyramid", PYRAMID_STEPS)


def test_arm_moves(reference):
    # The comparison above would pass on a world that never moved; the arm must swing.
    world, model = build_arm()
    start = world.positions.copy()
    world.step(ARM_STEPS)
    assert abs(world.positions - start).max() > 0.01
    positions, _ = model.joint_states()
    assert abs(positions).max() > 0.01


def test_saved_world_continues_with_the_same_bits():
    world, _ = build_arm()
    world.step(60)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "arm.pfx")
        world.save(path)
        loaded = pfx.World()
        loaded.load(path)
    world.step(60)
    loaded.step(60)
    assert loaded.simulated_time == world.simulated_time
    assert state_lines(loaded) == state_lines(world)


def test_islands_on_two_threads_give_the_bits_of_one():
    """The arm and 40 loose boxes dropped apart on one floor: on two threads the world
    solves its islands a group at a time (stats.num_island_groups), to the bits of one."""
    def run(threads):
        arm, _ = build_arm()
        world = pfx.World.from_bytes(arm.to_bytes(), num_threads=threads)
        box = pfx.Shape.box((0.1, 0.1, 0.1))
        for i in range(40):
            world.add_body(box, pfx.BodyInit(position=(0.6 * (i % 8) - 2.1, 0.6 * (i // 8) + 1,
                                                      0.2 + 0.03 * (i % 5))))
        groups = 0
        for _ in range(120):
            world.step()
            groups = max(groups, world.stats.num_island_groups)
        return state_lines(world), groups

    one, groups_on_one = run(1)
    two, groups_on_two = run(2)
    assert groups_on_one == 0
    assert groups_on_two >= 2
    assert two == one
