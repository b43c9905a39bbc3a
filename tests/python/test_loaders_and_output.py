"""The loaders (URDF, mesh files, OctoMaps, scene files), stepping statistics, and the
picture of a world."""
import os
import tempfile

import numpy as np
import pytest

import pfx
from pfx_scenes import ARM_URDF, SOURCE_DIR, build_arm

DATA = os.path.join(SOURCE_DIR, "tests", "loaders", "data")


def test_urdf_model_names_links_and_joints():
    world, model = build_arm()
    assert model.fixed_base and model.num_bodies > 1
    names = [joint.name for joint in model.joints]
    assert "joint_2" in names and "finger_left_joint" in names
    shoulder = model.joints[names.index("joint_2")]
    assert shoulder.joint_id is not None and shoulder.lower_limit < shoulder.upper_limit
    assert set(model.link_bodies) >= {"base_link", "tool0"}
    world.step(480)
    positions, velocities = model.joint_states()
    assert positions[names.index("joint_2")] == pytest.approx(0.8, abs=0.02)
    position, orientation = model.link_pose("tool0")
    assert position.shape == (3,) and np.linalg.norm(orientation) == pytest.approx(1, abs=1e-5)
    with pytest.raises(pfx.Error, match="no_such_link"):
        model.link_pose("no_such_link")


def test_stats_report_the_step():
    world, _ = build_arm()
    world.step()
    stats = world.stats
    assert stats.step_seconds > 0
    assert set(stats.stage_seconds) >= {"find_pairs", "solve_constraints"}
    assert set(stats.stage_seconds.values()) == {0.0}  # stages are timed when asked
    timed = pfx.World(pfx.WorldParam(measure_stages=True))
    timed.add_body(pfx.Shape.sphere(0.5), pfx.BodyInit(position=(0, 0, 1)))
    timed.step()
    assert timed.stats.stage_seconds["update_rigid_states"] > 0
    assert world.simulated_time == pytest.approx(1 / 240)


def test_mesh_file_becomes_a_hull_and_a_large_mesh():
    vertices, triangles = pfx.load_mesh(os.path.join(DATA, "cube.stl"), scale=(2, 2, 2))
    assert vertices.shape[1] == 3 and triangles.shape[1] == 3 and len(triangles) == 12
    hull = pfx.ConvexMesh.hull(vertices)
    world = pfx.World(pfx.WorldParam(enable_sleep=False))
    floor = pfx.LargeTriMesh([[-10, 0, -10], [10, 0, -10], [10, 0, 10], [-10, 0, 10]],
                             [[0, 2, 1], [0, 3, 2]])
    world.add_body(pfx.Shape.large_mesh(floor), pfx.BodyInit(mass=0))
    body = world.add_body(pfx.Shape.convex_mesh(hull), pfx.BodyInit(position=(0, 3, 0)))
    world.step(180)
    half_height = (vertices[:, 1].max() - vertices[:, 1].min()) / 2
    assert world.positions[body, 1] == pytest.approx(half_height, abs=0.02)


def test_octomap_is_one_fixed_body():
    world = pfx.World(pfx.WorldParam(gravity=(0, 0, -9.80665)))
    octomap = world.load_octomap(os.path.join(DATA, "small.bt"))
    assert octomap.body_id == 0 and octomap.num_occupied_voxels > 0 and octomap.resolution > 0
    assert world.motion_types[0] == int(pfx.MotionType.FIXED)
    with pytest.raises(pfx.Error, match="missing.bt"):
        world.load_octomap(os.path.join(DATA, "missing.bt"))
    assert world.num_bodies == 1


def test_scene_file_brings_its_bodies_and_physics():
    world = pfx.World()
    scene = world.load_scene(os.path.join(DATA, "scenes", "example.xml"))
    assert scene.num_bodies == world.num_bodies > 0
    assert all(0 <= body_id < world.num_bodies for body_id in scene.bodies.values())
    world.step(10)


def test_render_png_draws_the_robot():
    world, _ = build_arm()
    world.step(10)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "arm.png")
        triangles = world.render_png(path, width=320, height=240)
        with open(path, "rb") as png:
            assert png.read(8) == b"\x89PNG\r\n\x1a\n"
    assert triangles > 100
    with pytest.raises(pfx.Error):
        world.render_png(os.path.join("/no/such/folder", "x.png"))


def test_saving_into_a_missing_folder_names_it():
    world, _ = build_arm()
    with pytest.raises(pfx.Error, match="/no/such/folder"):
        world.save("/no/such/folder/arm.pfx")


def test_docstrings_everywhere():
    undocumented = []
    for name in dir(pfx):
        item = getattr(pfx, name)
        if name.startswith("_") or not callable(item):
            continue
        if not (item.__doc__ or "").strip():
            undocumented.append(name)
        if isinstance(item, type):
            for member, value in vars(item).items():
                if member.startswith("_") or not callable(getattr(value, "__get__", None)):
                    continue
                if member == "value" and hasattr(item, "__members__"):
                    continue  # pybind11's own enum property
                if not (getattr(value, "__doc__", None) or "").strip():
                    undocumented.append(name + "." + member)
    assert not undocumented
