"""tumble.BatchWorld from Python: numpy views without copies, the same bits on any thread count
and as a lone World, exact replays after reset, and bad calls that raise Python errors."""
import numpy as np
import pytest

import tumble


def pushes(num_worlds, body_count, step):
    """A fixed, per-world push on the three dynamic bodies (bodies 1 to 3)."""
    rng = np.random.default_rng(1000 + step)
    f = np.zeros((num_worlds, body_count, 3))
    f[:, 1:4, :] = rng.uniform(-30, 30, size=(num_worlds, 3, 3))
    return f


def run(scene, threads, steps=30, num_worlds=6):
    batch = tumble.BatchWorld(scene, num_worlds, threads=threads)
    for s in range(steps):
        batch.set_forces(pushes(num_worlds, batch.body_count, s))
        batch.step()
    return [batch.state_hash(i) for i in range(num_worlds)], batch


def test_observations_are_a_view_updated_in_place(pile_scene):
    batch = tumble.BatchWorld(pile_scene, 3, threads=2)
    obs = batch.observe()
    assert obs.shape == (3, 5, 13) and obs.dtype == np.float64
    assert not obs.flags.writeable
    before = obs[:, 3, 2].copy()  # the sphere's height
    batch.step(10)
    assert np.all(obs[:, 3, 2] < before), "the view did not follow the step"
    assert np.shares_memory(obs, batch.observe())
    # Positions and unit quaternions where the scene put them.
    world = tumble.World(pile_scene)
    world.step(10)
    np.testing.assert_array_equal(obs[0, 3], world.body_state(world.body("c")))


def test_same_bits_on_any_thread_count_and_as_a_lone_world(pile_scene):
    one, _ = run(pile_scene, 1)
    assert one == run(pile_scene, 2)[0]
    assert one == run(pile_scene, 4)[0]
    world = tumble.World(pile_scene)
    for s in range(30):
        f = pushes(6, 5, s)
        for b in range(1, 4):
            world.add_force(world.body("abc"[b - 1]), f[2, b])
        world.step()
    assert world.state_hash() == one[2]
    assert len(set(one)) == 6, "differently pushed worlds should differ"


def test_reset_replays_exactly(pile_scene):
    hashes, batch = run(pile_scene, 2, steps=20)
    batch.reset([1, 4])
    assert batch.state_hash(1) == tumble.World(pile_scene).state_hash()
    for s in range(20):
        batch.set_forces(pushes(6, batch.body_count, s))
        batch.step()
    assert batch.state_hash(1) == hashes[1]
    assert batch.state_hash(4) == hashes[4]
    assert batch.state_hash(0) != hashes[0], "world 0 was not reset and kept stepping"


def test_kinematic_targets_and_contact_forces(pile_scene):
    batch = tumble.BatchWorld(pile_scene, 2, threads=2)
    batch.step(60)
    weight = batch.contact_forces()[:, 1, 2]
    assert np.all(weight > 0), "box a rests on the ground"
    assert batch.contact_counts().shape == (2, 5)
    targets = np.zeros((2, 5, 7))
    targets[:, :, 3] = 1.0
    targets[:, 4, :3] = [[-1.9, 0, 0.9], [-1.8, 0, 0.9]]
    batch.set_kinematic_targets(targets)
    batch.step()
    np.testing.assert_allclose(batch.observe()[:, 4, 0], [-1.9, -1.8], rtol=0, atol=1e-12)


def test_bad_calls_raise_python_errors(pile_scene):
    batch = tumble.BatchWorld(pile_scene, 2, threads=1)
    with pytest.raises(ValueError, match=r"expected shape \(2, 5, 3\), got \(2, 4, 3\)"):
        batch.set_forces(np.zeros((2, 4, 3)))
    with pytest.raises(ValueError, match="float64"):
        batch.set_forces(np.zeros((2, 5, 3), dtype=np.float32))
    bad = np.zeros((2, 5, 3))
    bad[1, 2, 0] = np.nan
    with pytest.raises(ValueError, match=r"forces\[1, 2, 0\]"):
        batch.set_forces(bad)
    static_push = np.zeros((2, 5, 3))
    static_push[0, 0, 2] = 10.0  # the ground is static
    batch.set_forces(static_push)
    with pytest.raises(tumble.Error, match="world 0, body 0 'ground'"):
        batch.step()
    batch.set_forces(np.zeros((2, 5, 3)))
    with pytest.raises(ValueError, match="float64"):
        batch.set_forces([[[1, 2, 3]] * 5] * 2)  # a nested list of ints: int64
    batch.set_forces([[[0.0, 0.0, 0.0]] * 5] * 2)  # a nested list of floats is fine
    with pytest.raises(TypeError, match="integers"):
        batch.reset(["a"])
    with pytest.raises(IndexError):
        batch.reset([2])
    with pytest.raises(IndexError):
        batch.reset([2**40])
    with pytest.raises(TypeError):
        batch.reset([True])
    batch.reset(np.array([0, 1]))  # numpy integers, as np.nonzero(done)[0] gives
    with pytest.raises(IndexError):
        batch.state_hash(-1)
    with pytest.raises(tumble.SceneError):
        tumble.BatchWorld("/nonexistent/scene.yaml", 2)
    with pytest.raises(tumble.Error):
        tumble.BatchWorld(pile_scene, 0)
    batch.step()  # still usable


def test_world_api_from_python(pile_scene):
    world = tumble.World(pile_scene)
    a = world.body("a")
    world.add_force(a, [0.0, 0.0, 20000.0])  # four times its weight (512 kg)
    world.step(2)
    assert world.body_state(a)[9] > 0, "the push did not lift box a"
    hit = world.ray_cast([5.0, 5.0, 5.0], [0.0, 0.0, -1.0], 10.0)
    assert hit is not None and abs(hit["distance"] - 4.5) < 1e-9
    with pytest.raises(tumble.Error, match="'nope'"):
        world.body("nope")
    with pytest.raises(tumble.Error, match="nan"):
        world.add_force(a, [float("nan"), 0.0, 0.0])
    with pytest.raises(ValueError):
        world.add_force(a, [1.0, 2.0])
    world.step(60)
    reports = world.contact_reports()
    assert reports and all("points" in r for r in reports)


def test_scene_files_outside_the_scene_folder_need_the_option(tmp_path):
    # A scene may name only files in its folder or below it, unless allowed (SceneLoadOptions).
    (tmp_path / "outside.obj").write_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    folder = tmp_path / "scene"
    folder.mkdir()
    scene = folder / "scene.yaml"
    scene.write_text("bodies:\n  - {name: m, static: true, shape: {type: mesh, "
                     "file: ../outside.obj}}\n")
    with pytest.raises(tumble.SceneError, match="lies outside the scene's folder"):
        tumble.load_scene(str(scene))
    assert tumble.load_scene(str(scene), allow_outside_files=True).body_names == ["m"]
    text = f"bodies:\n  - {{name: m, static: true, shape: {{type: mesh, file: '{tmp_path}/outside.obj'}}}}\n"
    with pytest.raises(tumble.SceneError, match="lies outside"):
        tumble.load_scene_text(text)
    assert tumble.load_scene_text(text, allow_outside_files=True).body_names == ["m"]
