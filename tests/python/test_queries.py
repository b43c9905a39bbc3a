"""Rays and contacts as numpy arrays: a batch gives what single C++ rays give, and contact
arrays describe the step's contact points."""
import numpy as np
import pytest

import pfx
from pfx_scenes import build_pyramid


@pytest.fixture(scope="module")
def pyramid():
    world = build_pyramid()
    world.step(30)
    return world


def test_batch_equals_single_rays(pyramid):
    rng = np.random.default_rng(7)
    count = 500  # above castRays' 64, so the batch runs in its Morton order
    starts = np.column_stack([rng.uniform(-12, 12, count), np.full(count, 25.0),
                              rng.uniform(-1, 1, count)])
    # Some rays point up or stop short of everything, so that misses are compared too.
    directions = np.column_stack([rng.uniform(-2, 2, count), rng.uniform(-30, 5, count),
                                  np.zeros(count)])
    batch = pyramid.cast_rays(starts, directions)
    assert batch["point"].shape == (count, 3)
    assert batch["hit"].sum() > 50 and (~batch["hit"]).sum() > 50
    for i in range(count):
        single = pyramid.cast_ray(starts[i], directions[i])
        for key in ("hit", "fraction", "point", "normal", "body", "shape", "triangle"):
            np.testing.assert_array_equal(batch[key][i], single[key][0], err_msg=key)


def test_ray_hits_the_top_cube(pyramid):
    top = pyramid.num_bodies - 1
    x, y, _ = pyramid.positions[top]
    hit = pyramid.cast_ray((x, 30, 0), (0, -30, 0))
    assert hit["body"][0] == top
    assert hit["point"][0, 1] == pytest.approx(y + 0.5, abs=2e-3)
    np.testing.assert_allclose(hit["normal"][0], (0, 1, 0), atol=1e-3)
    miss = pyramid.cast_ray((100, 30, 0), (0, 10, 0))
    assert not miss["hit"][0] and miss["body"][0] == -1 and miss["fraction"][0] == 1


def test_contacts_as_arrays(pyramid):
    contacts = pyramid.contacts()
    count = len(contacts["distance"])
    assert count == pyramid.stats.num_contact_points
    assert contacts["point_a"].shape == (count, 3) and contacts["normal"].shape == (count, 3)
    np.testing.assert_allclose(np.linalg.norm(contacts["normal"], axis=1), 1, atol=1e-5)
    assert (contacts["body_a"] != contacts["body_b"]).all()
    # Every cube on the ground touches it; the ground (body 0) holds the weight of all 210.
    on_ground = contacts["body_a"] == 0
    assert len(np.unique(contacts["body_b"][on_ground])) == 20
    weight_per_step = 210 * 9.80665 / 60
    assert contacts["impulse"][on_ground].sum() == pytest.approx(weight_per_step, rel=0.05)


def test_query_contacts_of_a_placed_shape(pyramid):
    top = pyramid.num_bodies - 1
    centre = pyramid.positions[top] + (0, 0.9, 0)
    found = pyramid.query_contacts(pfx.Shape.sphere(0.5), centre)
    assert top in found["body"]
    assert (found["distance"] < 0).any()
    far = pyramid.query_contacts(pfx.Shape.sphere(0.5), (0, 100, 0))
    assert len(far["body"]) == 0
