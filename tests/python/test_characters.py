"""Characters from Python: one walks to a target on the ground, over a step on the way, and
bad input raises with the world, the controller and the characters unchanged."""
import math

import numpy as np
import pytest

import pfx

STEP_HEIGHT = 0.3
STEP_NEAR_EDGE = 1.5  # x of the riser


def course():
    """A floor (top at z = 0) and a fixed step STEP_HEIGHT high from x = STEP_NEAR_EDGE on."""
    world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.80665), time_step=1 / 60))
    floor = world.add_body(pfx.Shape.box((20, 20, 0.5)), pfx.BodyInit(mass=0, position=(0, 0, -0.5)))
    step = world.add_body(pfx.Shape.box((2, 2, STEP_HEIGHT / 2)),
                          pfx.BodyInit(mass=0, position=(STEP_NEAR_EDGE + 2, 0, STEP_HEIGHT / 2)))
    return world, floor, step


def walk_to(characters, character, target, seconds, speed=1.5):
    """Heads for target at speed, stopping within 5 cm of it; returns the statuses seen."""
    seen = []
    for _ in range(round(seconds * 60)):
        status = characters.status(character)
        seen.append(status)
        to_target = np.asarray(target, dtype=float) - status.foot_position
        to_target[2] = 0
        distance = np.linalg.norm(to_target)
        velocity = to_target / distance * min(speed, 2 * distance) if distance > 0.05 else (0, 0, 0)
        characters.set_desired_velocity(character, velocity)
        characters.step()
    return seen


def test_walks_to_a_target_on_the_ground():
    world, floor, _ = course()
    characters = pfx.CharacterController(world)
    walker = characters.add((0, -1, 0))
    seen = walk_to(characters, walker, (1.0, 0.5, 0), seconds=3)
    status = characters.status(walker)
    assert np.linalg.norm(status.foot_position[:2] - (1.0, 0.5)) < 0.08
    assert abs(status.foot_position[2]) < 0.02
    assert status.state in (pfx.CharacterState.STANDING, pfx.CharacterState.WALKING)
    assert status.ground_body == floor and status.on_ground
    assert np.allclose(status.ground_normal, (0, 0, 1), atol=1e-3)
    assert pfx.CharacterState.WALKING in {s.state for s in seen}
    assert status.num_steps == 0


def test_climbs_a_step_on_the_way_to_its_target():
    world, _, step = course()
    characters = pfx.CharacterController(world)
    climber = characters.add((0, 0, 0))
    seen = walk_to(characters, climber, (STEP_NEAR_EDGE + 1, 0, 0), seconds=4)
    status = characters.status(climber)
    assert status.num_steps == 1
    assert status.ground_body == step
    assert abs(status.foot_position[2] - STEP_HEIGHT) < 0.02
    assert abs(status.foot_position[0] - (STEP_NEAR_EDGE + 1)) < 0.08
    # Never inside the step: before the riser the foot stays on the floor.
    assert all(s.foot_position[0] < STEP_NEAR_EDGE or s.foot_position[2] > STEP_HEIGHT - 0.02
               for s in seen)


def test_states_are_arrays_of_every_character_in_id_order():
    world, floor, _ = course()
    characters = pfx.CharacterController(world)
    ids = [characters.add((x, 3, 0)) for x in (0, 1, 2)]
    characters.set_desired_velocity(ids[1], (0, 1, 0))
    characters.jump(ids[2])
    characters.step(3)
    states = characters.states()
    assert list(states["id"]) == ids == characters.ids and len(characters) == 3
    assert states["foot_position"].shape == (3, 3) and states["velocity"].shape == (3, 3)
    for row, character in enumerate(ids):
        status = characters.status(character)
        assert np.array_equal(states["foot_position"][row], status.foot_position)
        assert np.array_equal(states["velocity"][row], status.velocity)
        assert states["state"][row] == int(status.state)
        assert states["ground_body"][row] == status.ground_body
        assert states["body"][row] == status.body
        assert np.allclose(world.positions[status.body] - (0, 0, 0.9), status.foot_position, atol=1e-5)
    assert states["state"][2] == int(pfx.CharacterState.JUMPING)
    assert states["ground_body"][2] == pfx.CHARACTER_NO_GROUND
    assert states["velocity"][1][1] > 0.1
    assert states["ground_body"][0] == floor


def test_removal_takes_the_body_and_frees_the_id():
    world, _, _ = course()
    characters = pfx.CharacterController(world)
    first, second = characters.add((0, 0, 0)), characters.add((2, 0, 0))
    body = characters.status(first).body
    characters.remove(first)
    assert first not in characters and second in characters and len(characters) == 1
    assert not world.has_body(body)
    with pytest.raises(pfx.Error, match="character 0"):
        characters.remove(first)
    with pytest.raises(pfx.Error, match="character 0"):
        characters.status(first)
    assert characters.add((0, 0, 0)) == first


def test_bad_input_raises_and_changes_nothing():
    world, _, _ = course()
    characters = pfx.CharacterController(world)
    walker = characters.add((0, 0, 0))
    characters.set_desired_velocity(walker, (1, 0, 0))
    characters.step(10)
    body = characters.status(walker).body
    before = (world.num_bodies, world.state_hash(), characters.ids)

    def unchanged():
        return (world.num_bodies, world.state_hash(), characters.ids) == before

    with pytest.raises(pfx.InvalidValueError, match="foot_position"):
        characters.add((math.nan, 0, 0))
    with pytest.raises(pfx.InvalidValueError, match="foot_position"):
        characters.add((0, math.inf, 0))
    for bad in ({"radius": -0.3}, {"height": 0.5}, {"max_slope": 2.0}, {"air_control": 1.5},
                {"mass": math.nan}, {"max_step_height": 1.5}):
        with pytest.raises(pfx.InvalidValueError, match="CharacterParam out of range"):
            characters.add((3, 3, 0), pfx.CharacterParam(**bad))
    with pytest.raises(TypeError):
        pfx.CharacterParam(no_such_field=1)
    with pytest.raises(ValueError, match="velocity must be 3 numbers"):
        characters.set_desired_velocity(walker, (1, 0))
    with pytest.raises(pfx.InvalidValueError):
        characters.set_desired_velocity(walker, (math.nan, 0, 0))
    with pytest.raises(pfx.Error, match="character 7"):
        characters.set_desired_velocity(7, (1, 0, 0))
    with pytest.raises(pfx.Error, match="character 7"):
        characters.jump(7)
    with pytest.raises(pfx.Error, match="CharacterController.remove"):
        world.remove_body(body)
    with pytest.raises(pfx.Error, match="negative"):
        characters.step(-1)
    view = world.positions
    with pytest.raises(pfx.Error, match="CharacterController.add"):
        characters.add((3, 3, 0))
    del view
    with pytest.raises(TypeError, match="needs a pfx.World, not a str"):
        pfx.CharacterController("not a world")
    assert unchanged()
    # The refused NaN velocity left the desired one in place: the walker goes on at 1 m/s.
    characters.step(30)
    assert characters.status(walker).velocity[0] == pytest.approx(1, abs=0.02)


def test_a_controller_goes_stale_with_its_world():
    world, _, _ = course()
    characters = pfx.CharacterController(world)
    walker = characters.add((0, 0, 0))
    body = characters.status(walker).body
    world.initialize(world.param)
    with pytest.raises(pfx.Error, match="initialized, loaded or truncated"):
        characters.status(walker)
    with pytest.raises(pfx.Error, match="initialized, loaded or truncated"):
        characters.step()
    world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(mass=0))
    world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(mass=0, position=(1, 0, 0)))
    world.add_body(pfx.Shape.sphere(0.1), pfx.BodyInit(mass=0, position=(2, 0, 0)))
    world.remove_body(body)  # a new body with the old character's id is the world's own
