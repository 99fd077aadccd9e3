"""tumble.envs.PushBoxEnv against the Gymnasium vector protocol (checked here, since Gymnasium is
not packaged): spaces, reset and step signatures, same-step autoreset, determinism per seed, the
documented reward, bad actions, and a scripted pusher that reaches the goal."""
import numpy as np
import pytest

from tumble.envs import PushBoxEnv
from tumble.spaces import Box


def steer(obs):
    """Pushes along +x, steering the pusher's y towards the box's."""
    a = np.zeros((obs.shape[0], 2))
    a[:, 0] = 1.0
    a[:, 1] = np.clip(3.0 * (obs[:, 3] - obs[:, 1]), -1, 1)
    return a


def test_spaces_and_signatures():
    env = PushBoxEnv(num_envs=4, threads=1, seed=3)
    assert env.num_envs == 4
    assert isinstance(env.single_observation_space, Box)
    assert env.single_observation_space.shape == (10,)
    assert env.observation_space.shape == (4, 10)
    assert env.single_action_space.shape == (2,)
    assert env.action_space.shape == (4, 2)
    assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)
    assert env.observation_space.dtype == np.float64
    obs, info = env.reset(seed=1)
    assert isinstance(info, dict)
    assert env.observation_space.contains(obs)
    sample = env.action_space.sample()
    assert env.action_space.contains(sample)
    obs, reward, terminated, truncated, info = env.step(sample)
    assert obs.shape == (4, 10) and obs.dtype == np.float64
    assert reward.shape == (4,) and reward.dtype == np.float64
    assert terminated.shape == (4,) and terminated.dtype == bool
    assert truncated.shape == (4,) and truncated.dtype == bool
    assert info["success"].shape == (4,)
    assert env.metadata["autoreset_mode"] == "SameStep"
    env.close()
    assert env.closed


def test_reward_is_the_documented_one():
    env = PushBoxEnv(num_envs=6, threads=1, seed=0, randomize=False)
    obs, _ = env.reset(seed=0)
    for _ in range(5):
        obs, reward, terminated, truncated, _ = env.step(steer(obs))
    assert not np.any(terminated | truncated)
    to_goal = np.linalg.norm(obs[:, 8:10], axis=1)
    to_box = np.linalg.norm(obs[:, 0:2] - obs[:, 2:4], axis=1)
    np.testing.assert_allclose(reward, -to_goal - 0.2 * to_box, rtol=0, atol=1e-12)


def test_same_seed_same_episodes_and_seeds_give_each_world_its_own_draw():
    def rollout(seed):
        env = PushBoxEnv(num_envs=5, threads=2, seed=9)
        obs, _ = env.reset(seed=seed)
        trace = [obs]
        rng = np.random.default_rng(4)
        for _ in range(30):
            obs, *_ = env.step(rng.uniform(-1, 1, size=(5, 2)))
            trace.append(obs)
        return np.array(trace)

    a, b, c = rollout(11), rollout(11), rollout(12)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    # docs/rl.md, "Seeds": reset with s gives world i the draw s + i, so world 1 after s = 11
    # is world 0 after s = 12.
    env = PushBoxEnv(num_envs=2, threads=1)
    first, _ = env.reset(seed=11)
    second, _ = env.reset(seed=12)
    np.testing.assert_array_equal(first[1], second[0])


def test_finished_worlds_reset_in_the_same_step():
    env = PushBoxEnv(num_envs=3, threads=1, seed=2, max_steps=4)
    obs, _ = env.reset(seed=5)
    for step in range(4):
        obs, reward, terminated, truncated, info = env.step(np.zeros((3, 2)))
    assert np.all(truncated) and not np.any(terminated)
    assert np.all(info["_final_obs"])
    # The final observation is the end of the episode (the pusher never moved); the returned one
    # is the start of the next, whose box stands where a fresh draw puts it.
    np.testing.assert_array_equal(info["final_obs"][:, 0:2], obs[:, 0:2])
    assert not np.array_equal(info["final_obs"][:, 2:4], obs[:, 2:4])
    obs, reward, terminated, truncated, info = env.step(np.zeros((3, 2)))
    assert not np.any(truncated)  # the step counters restarted


def test_bad_actions_raise_value_errors():
    env = PushBoxEnv(num_envs=2, threads=1)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"expected shape \(2, 2\)"):
        env.step(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([[0.0, np.nan], [0.0, 0.0]]))
    with pytest.raises(ValueError):
        PushBoxEnv(num_envs=0)


def test_a_steering_pusher_reaches_the_goal_in_randomized_worlds():
    env = PushBoxEnv(num_envs=32, threads=2, seed=7)
    obs, _ = env.reset(seed=100)
    reached = np.zeros(32, dtype=bool)
    for _ in range(60):
        obs, reward, terminated, truncated, info = env.step(steer(obs))
        reached |= info["success"]
    assert reached.mean() >= 0.9, f"only {reached.mean():.2f} of the worlds reached the goal"
    # Standing still reaches nothing.
    obs, _ = env.reset(seed=100)
    for _ in range(20):
        obs, reward, terminated, truncated, info = env.step(np.zeros((32, 2)))
        assert not np.any(info["success"])


def test_shards_step_the_worlds_of_the_whole_env():
    # 7 worlds as one env, and as shards of 3 and 4 (first_env 0 and 3): the same observations
    # and rewards, through resets with a seed and the automatic resets of short episodes.
    whole = PushBoxEnv(num_envs=7, seed=5, max_steps=4)
    head = PushBoxEnv(num_envs=3, seed=5, max_steps=4)
    tail = PushBoxEnv(num_envs=4, seed=5, max_steps=4, first_env=3)
    obs = [env.reset(seed=11)[0] for env in (whole, head, tail)]
    np.testing.assert_array_equal(obs[0], np.concatenate(obs[1:]))
    rng = np.random.default_rng(0)
    for _ in range(10):
        actions = rng.uniform(-1, 1, size=(7, 2))
        w = whole.step(actions)
        h = head.step(actions[:3])
        t = tail.step(actions[3:])
        for k in (0, 1, 2, 3):  # observation, reward, terminated, truncated
            np.testing.assert_array_equal(w[k], np.concatenate([h[k], t[k]]))
    with pytest.raises(ValueError):
        PushBoxEnv(num_envs=2, first_env=-1)


def test_the_reset_benchmarks_scene_is_the_environments_world():
    # tests/benchmarks/bench_reset times PushBoxEnv's resets on a copy of its world in
    # tests/data/scenes/push_box.yaml: the same bodies and the same draws, step for step.
    import os

    import tumble
    from tumble import envs

    here = os.path.dirname(os.path.abspath(__file__))
    copy = tumble.load_scene(os.path.join(here, "..", "..", "tests", "data", "scenes",
                                          "push_box.yaml"))
    env_scene = tumble.load_scene_text(envs._SCENE.format(randomize=envs._RANDOMIZE), "env.yaml")
    for seed in (0, 1, 17):
        worlds = [tumble.World(tumble.randomized(s, seed)) for s in (copy, env_scene)]
        for w in worlds:
            w.step(30)
        assert worlds[0].state_hash() == worlds[1].state_hash()
