"""Vectorised environments on tumble.BatchWorld, with the Gymnasium vector API.

`PushBoxEnv(num_envs)` follows gymnasium.vector.VectorEnv: `reset(seed=, options=)` returns
`(obs, info)`, `step(actions)` returns `(obs, reward, terminated, truncated, info)`, and
`observation_space`, `action_space`, `single_observation_space`, `single_action_space`,
`num_envs`, `metadata`, `render_mode` and `close()` are there. Sub-environments that end are reset
in the same step (Gymnasium's "SameStep" autoreset): the returned observation is the new
episode's first, and `info["final_obs"]` holds the last one where `info["_final_obs"]` is True.
docs/rl.md describes the task, its reward and termination.
"""
import math

import numpy as np

from tumble import BatchWorld, load_scene_text
from tumble.spaces import Box, batch_space

# The task's world: a table, two static obstacles, a box to push and a kinematic pusher.
# Bodies, in order: table 0, obstacles 1 and 2, box 3, pusher 4.
_SCENE = """
world:
  dt: 0.016666666666666666
  gravity: [0, 0, -9.81]
materials:
  table: {{friction: 0.6}}
bodies:
  - {{name: table, static: true, material: table,
     shape: {{type: box, half_extents: [1.0, 1.0, 0.05]}}, position: [0, 0, -0.05]}}
  - {{name: obstacle_left, static: true,
     shape: {{type: box, half_extents: [0.1, 0.1, 0.1]}}, position: [0.35, 0.4, 0.1]}}
  - {{name: obstacle_right, static: true,
     shape: {{type: box, half_extents: [0.1, 0.1, 0.1]}}, position: [0.35, -0.4, 0.1]}}
  - {{name: box, density: 250, shape: {{type: box, half_extents: [0.1, 0.1, 0.1]}},
     position: [0, 0, 0.13]}}
  - {{name: pusher, kinematic: true,
     shape: {{type: box, half_extents: [0.05, 0.15, 0.08]}}, position: [-0.3, 0, 0.09]}}
{randomize}
"""

_RANDOMIZE = """
randomize:
  friction: [0.4, 0.9]
  mass_scale: [0.7, 1.4]
  size_noise: 0.02
  position_noise: 0.01
  orientation_noise: 0.05
"""

_BOX, _PUSHER = 3, 4


class PushBoxEnv:
    """Push a box into a goal region with a kinematic pusher, in `num_envs` worlds at once.

    Observation (10 float64 per world): pusher x, y; box x, y; cos and sin of the box's yaw;
    box velocity x, y; goal minus box x, y. Action (2 per world, in [-1, 1]): the pusher's
    velocity in x and y as a fraction of `max_speed` (m/s), held for `frame_skip` steps of 1/60 s.

    Reward per step: minus the box's distance to the goal, minus 0.2 times the pusher's distance
    to the box, plus 10 on reaching the goal (box centre within `goal_radius`). An episode
    terminates when the box reaches the goal or leaves the table, and is truncated after
    `max_steps` steps. With `randomize` (the default) every episode draws the box's friction,
    mass, size and starting pose (docs/scene-format.md, "randomize").
    """

    metadata = {"render_modes": [], "autoreset_mode": "SameStep"}
    render_mode = None

    def __init__(self, num_envs=16, threads=0, seed=0, max_steps=100, frame_skip=3,
                 max_speed=0.5, goal=(0.7, 0.0), goal_radius=0.12, randomize=True, first_env=0):
        if int(num_envs) < 1:
            raise ValueError(f"num_envs must be at least 1, got {num_envs}")
        if int(max_steps) < 1 or int(frame_skip) < 1:
            raise ValueError("max_steps and frame_skip must be at least 1")
        if not (math.isfinite(max_speed) and max_speed > 0):
            raise ValueError(f"max_speed must be positive and finite, got {max_speed}")
        if int(first_env) < 0:
            raise ValueError(f"first_env must be at least 0, got {first_env}")
        self.num_envs = int(num_envs)
        # A shard of a larger vector env (one MPI rank's part): world i here is world
        # first_env + i there, in its draws and its reset seeds.
        self.first_env = int(first_env)
        self.max_steps = int(max_steps)
        self.frame_skip = int(frame_skip)
        self.max_speed = float(max_speed)
        self.goal = np.asarray(goal, dtype=np.float64)
        self.goal_radius = float(goal_radius)
        text = _SCENE.format(randomize=_RANDOMIZE if randomize else "")
        self.scene = load_scene_text(text, "PushBoxEnv")
        self.batch = BatchWorld(self.scene, self.num_envs, threads=threads, seed=seed,
                                first_world=self.first_env)
        self.dt = self.scene.dt
        self.single_observation_space = Box(-np.inf, np.inf, (10,), np.float64)
        self.single_action_space = Box(-1.0, 1.0, (2,), np.float64)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.closed = False
        self._elapsed = np.zeros(self.num_envs, dtype=np.int64)
        self._targets = np.zeros((self.num_envs, self.batch.body_count, 7))
        self._targets[:, :, 3] = 1.0  # identity orientation in every row

    # -- Gymnasium vector API ------------------------------------------------------------------

    def reset(self, seed=None, options=None):
        """Resets every world. An int seed gives world i the draw of seed + first_env + i
        (Gymnasium's rule for vector environments, counted over the whole env when this one is
        a shard); a list gives one seed per world; None draws the next episode."""
        ids = list(range(self.num_envs))
        if seed is None:
            self.batch.reset(ids)
        elif isinstance(seed, (list, tuple, np.ndarray)):
            self.batch.reset(ids, seeds=[int(s) for s in seed])
        else:
            self.batch.reset(ids, seeds=[int(seed) + self.first_env + i for i in ids])
        self._elapsed[:] = 0
        return self._observe(), {}

    def step(self, actions):
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape != (self.num_envs, 2):
            raise ValueError(
                f"actions: expected shape ({self.num_envs}, 2), got {actions.shape}")
        if not np.all(np.isfinite(actions)):
            raise ValueError("actions: every value must be finite")
        velocity = np.clip(actions, -1.0, 1.0) * self.max_speed
        for _ in range(self.frame_skip):
            obs = self.batch.observe()
            target = obs[:, _PUSHER, 0:2] + velocity * self.dt
            self._targets[:, _PUSHER, 0:2] = np.clip(target, -0.95, 0.95)
            self._targets[:, _PUSHER, 2] = 0.09
            self.batch.set_kinematic_targets(self._targets)
            self.batch.step()
        self._elapsed += 1
        observation = self._observe()
        raw = self.batch.observe()
        box = raw[:, _BOX, 0:3]
        to_goal = np.linalg.norm(box[:, 0:2] - self.goal, axis=1)
        to_box = np.linalg.norm(raw[:, _PUSHER, 0:2] - box[:, 0:2], axis=1)
        success = to_goal < self.goal_radius
        fell = (box[:, 2] < -0.05) | np.any(np.abs(box[:, 0:2]) > 1.0, axis=1)
        reward = -to_goal - 0.2 * to_box + 10.0 * success
        terminated = success | fell
        truncated = (self._elapsed >= self.max_steps) & ~terminated
        info = {"success": success.copy()}
        done = terminated | truncated
        if np.any(done):
            ids = np.flatnonzero(done)
            info["final_obs"] = observation.copy()
            info["_final_obs"] = done.copy()
            self.batch.reset(ids.tolist())
            self._elapsed[ids] = 0
            observation = self._observe()
        return observation, reward, terminated, truncated, info

    def close(self):
        self.closed = True

    # -- helpers ---------------------------------------------------------------------------------

    def _observe(self):
        raw = self.batch.observe()
        box = raw[:, _BOX]
        w, x, y, z = box[:, 3], box[:, 4], box[:, 5], box[:, 6]
        yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
        out = np.empty((self.num_envs, 10))
        out[:, 0:2] = raw[:, _PUSHER, 0:2]
        out[:, 2:4] = box[:, 0:2]
        out[:, 4] = np.cos(yaw)
        out[:, 5] = np.sin(yaw)
        out[:, 6:8] = box[:, 7:9]
        out[:, 8:10] = self.goal - box[:, 0:2]
        return out
