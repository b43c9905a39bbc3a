"""WorldBatch: worlds stepped together give, world for world, the bits of the same worlds
stepped one by one; worlds copy through bytes; bad input raises and changes nothing."""
import numpy as np
import pytest

import pfx
from pfx_scenes import build_arm

STEPS = 60


def own_states(world):
    """A world's rows as WorldBatch.states() lays them out, read through the world's views."""
    return np.concatenate([world.positions, world.orientations, world.linear_velocities,
                           world.angular_velocities], axis=1)


def pushed_copies(world, count):
    """count copies of world, copy i pushed sideways by i newtons on its last body: worlds
    that part ways, so that a batch stepping one world for all would be caught."""
    copies = [pfx.World.from_bytes(world.to_bytes(), num_threads=1) for _ in range(count)]
    for i, copy in enumerate(copies):
        copy.apply_force(copy.num_bodies - 1, (float(i), 0, 0))
    return copies


@pytest.mark.parametrize("threads", [1, 2])
def test_batch_equals_the_worlds_stepped_one_by_one(threads):
    arm, _ = build_arm()
    alone = pushed_copies(arm, 4)
    for world in alone:
        world.step(STEPS)
    batch = pfx.WorldBatch(pushed_copies(arm, 4), num_threads=threads)
    batch.step(STEPS // 2)
    batch.step(STEPS - STEPS // 2)

    expected = np.concatenate([own_states(world) for world in alone])
    assert batch.states().tobytes() == expected.tobytes()
    assert not np.array_equal(own_states(alone[0]), own_states(alone[3]))
    assert list(batch.first_bodies) == [i * arm.num_bodies for i in range(5)]
    assert [w.simulated_time for w in batch.worlds] == [w.simulated_time for w in alone]


def test_copies_continue_as_their_source():
    arm, _ = build_arm()
    arm.step(20)
    batch = pfx.WorldBatch.copies(arm, 3, num_threads=2)
    batch.step(STEPS)
    arm.step(STEPS)
    states = batch.states().reshape(batch.num_worlds, arm.num_bodies, pfx.BATCH_STATE_COLUMNS)
    for world_states in states:
        assert world_states.tobytes() == own_states(arm).tobytes()
    assert {w.state_hash() for w in batch.worlds} == {arm.state_hash()}


def test_state_hash_changes_with_the_state():
    arm, _ = build_arm()
    before = arm.state_hash()
    assert pfx.World.from_bytes(arm.to_bytes()).state_hash() == before
    arm.step()
    assert arm.state_hash() != before


def test_bad_input_raises_and_changes_nothing():
    arm, _ = build_arm()
    with pytest.raises(pfx.InvalidValueError, match="world 1 of the batch is a str"):
        pfx.WorldBatch([arm, "arm"])
    with pytest.raises(pfx.InvalidValueError, match="in the batch already"):
        pfx.WorldBatch([arm, arm])
    with pytest.raises(pfx.Error, match="num_threads"):
        pfx.WorldBatch([arm], num_threads=100000)

    batch = pfx.WorldBatch([arm])
    before = batch.states()
    with pytest.raises(pfx.InvalidValueError, match="negative"):
        batch.step(-1)
    assert batch.states().tobytes() == before.tobytes()
    assert arm.simulated_time == 0

    data = arm.to_bytes()
    with pytest.raises(pfx.Error, match="announces"):
        pfx.World.from_bytes(data + b"\0")
    with pytest.raises(pfx.Error, match="not a pfx world"):
        pfx.World.from_bytes(b"PFXWORLX" + data[8:])
    with pytest.raises(pfx.Error):
        pfx.World.from_bytes(data[:-1])
