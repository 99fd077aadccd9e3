"""Steps tumble.envs.PushBoxEnv with random actions and prints the env-steps per second.

    PYTHONPATH=build/release/python python3 examples/python/rollout.py --envs 256 --steps 200

A large batch runs 5-10% faster with malloc on huge pages: start Python with
GLIBC_TUNABLES=glibc.malloc.hugetlb=1 (docs/rl.md, "Memory").
"""
import argparse
import time

import numpy as np

from tumble.envs import PushBoxEnv


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--envs", type=int, default=256)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--threads", type=int, default=0, help="0: the machine's cores")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    env = PushBoxEnv(num_envs=args.envs, threads=args.threads, seed=args.seed)
    obs, _ = env.reset(seed=args.seed)
    rng = np.random.default_rng(args.seed)
    episodes = 0
    start = time.perf_counter()
    for _ in range(args.steps):
        obs, reward, terminated, truncated, info = env.step(
            rng.uniform(-1, 1, size=env.action_space.shape))
        episodes += int(np.count_nonzero(terminated | truncated))
    seconds = time.perf_counter() - start
    env_steps = args.envs * args.steps
    print(f"{args.envs} worlds x {args.steps} steps ({env.frame_skip} physics steps each) on "
          f"{env.batch.threads} threads: {seconds:.3f} s, {env_steps / seconds:.0f} env-steps/s, "
          f"{episodes} episodes ended")


if __name__ == "__main__":
    main()
