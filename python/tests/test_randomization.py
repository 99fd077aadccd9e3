"""Domain randomization from Python: each world of a randomized batch is tumble.randomized of its
seed, reset draws anew, a given seed replays, and bad seeds raise Python errors."""
import numpy as np
import pytest

import tumble

RANDOMIZED = """
world: {dt: 0.016666666666666666}
bodies:
  - {name: ground, static: true, shape: {type: box, half_extents: [10, 10, 0.5]}}
  - {name: a, shape: {type: box, half_extents: [0.4, 0.4, 0.4]}, position: [0, 0, 1.0]}
  - {name: b, shape: {type: box, half_extents: [0.3, 0.3, 0.3]}, position: [0.2, 0.1, 2.2]}
randomize:
  friction: [0.3, 1.0]
  mass_scale: [0.5, 2.0]
  size_noise: 0.02
  position_noise: 0.01
  orientation_noise: 0.02
  gravity: {low: [-0.5, -0.5, -10.3], high: [0.5, 0.5, -9.3]}
"""


@pytest.fixture()
def scene():
    return tumble.load_scene_text(RANDOMIZED, "randomized.yaml")


def test_each_world_is_the_lone_world_of_its_seed(scene):
    batch = tumble.BatchWorld(scene, 5, threads=2, seed=11)
    batch.step(25)
    hashes = [batch.state_hash(i) for i in range(5)]
    assert len(set(hashes)) == 5, "the worlds should draw differently"
    for i in range(5):
        lone = tumble.World(tumble.randomized(scene, batch.seed(i)))
        lone.step(25)
        assert lone.state_hash() == hashes[i]
    # The same batch seed gives the same batch; another seed another one.
    again = tumble.BatchWorld(scene, 5, threads=1, seed=11)
    again.step(25)
    assert [again.state_hash(i) for i in range(5)] == hashes
    other = tumble.BatchWorld(scene, 5, threads=1, seed=12)
    other.step(25)
    assert [other.state_hash(i) for i in range(5)] != hashes


def test_reset_draws_again_and_seeds_replay(scene):
    batch = tumble.BatchWorld(scene, 3, threads=1, seed=3)
    first = batch.seed(2)
    start = batch.observe()[2].copy()
    batch.reset([2])
    assert batch.seed(2) != first
    assert not np.array_equal(batch.observe()[2], start)
    batch.reset([2], seeds=[first])
    np.testing.assert_array_equal(batch.observe()[2], start)
    batch.reset(seeds=[7, 8, 9])
    assert [batch.seed(i) for i in range(3)] == [7, 8, 9]


def test_bad_seeds_raise(scene):
    batch = tumble.BatchWorld(scene, 2, threads=1)
    with pytest.raises(ValueError, match="one per world"):
        batch.reset([0, 1], seeds=[1])
    with pytest.raises(ValueError, match="2\\*\\*64"):
        batch.reset([0], seeds=[-1])
    with pytest.raises(ValueError, match="2\\*\\*64"):
        tumble.BatchWorld(scene, 2, seed=2**64)
    with pytest.raises(TypeError):
        batch.reset([0], seeds=[1.5])
    with pytest.raises(IndexError):
        batch.seed(2)
    bad = RANDOMIZED.replace("friction: [0.3, 1.0]", "friction: [1.0, 0.3]")
    with pytest.raises(tumble.SceneError, match="randomize.friction"):
        tumble.load_scene_text(bad, "bad.yaml")
