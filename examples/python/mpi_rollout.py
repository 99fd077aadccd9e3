"""Steps one vectorised env spread over MPI ranks: each rank steps its shard of the worlds in its
own BatchWorld, and rank 0 gathers the observations and rewards of all of them every step.

    mpirun -n 2 python3 examples/python/mpi_rollout.py --envs 512 --steps 200

World i is the same world on any number of ranks: a rank's shard draws its worlds as the whole
env would (PushBoxEnv's first_env), and the actions are drawn for all worlds on every rank and
sliced, so `--hash` prints the same digest of everything rank 0 gathered for 1, 2 or 8 ranks.
Prints env-steps/s per rank and in total, and the time rank 0 spends gathering per step.
"""
import argparse
import hashlib
import json
import time

import numpy as np
from mpi4py import MPI

from tumble.envs import PushBoxEnv


def shard(total, ranks, rank):
    """The first world and the count of `rank`'s shard: as equal as can be, the first ranks
    taking one more."""
    base, extra = divmod(total, ranks)
    count = base + (1 if rank < extra else 0)
    first = rank * base + min(rank, extra)
    return first, count


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--envs", type=int, default=256, help="worlds over all ranks")
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--threads", type=int, default=1, help="threads per rank (0: cores)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-steps", type=int, default=100, help="steps per episode")
    parser.add_argument("--hash", action="store_true",
                        help="print a digest of every gathered observation and reward")
    parser.add_argument("--json", help="write the figures to this file (rank 0)")
    args = parser.parse_args()

    comm = MPI.COMM_WORLD
    rank, ranks = comm.Get_rank(), comm.Get_size()
    if args.envs < ranks:
        if rank == 0:
            print(f"mpi_rollout: {args.envs} worlds cannot be shared by {ranks} ranks")
        raise SystemExit(1)
    first, count = shard(args.envs, ranks, rank)
    env = PushBoxEnv(num_envs=count, threads=args.threads, seed=args.seed, first_env=first,
                     max_steps=args.max_steps)
    obs, _ = env.reset(seed=args.seed)
    width = obs.shape[1]
    counts = [shard(args.envs, ranks, r)[1] for r in range(ranks)]
    all_obs = np.empty((args.envs, width)) if rank == 0 else None
    all_reward = np.empty(args.envs) if rank == 0 else None
    digest = hashlib.sha256()

    def gather(local_obs, local_reward):
        comm.Gatherv(np.ascontiguousarray(local_obs),
                     [all_obs, [c * width for c in counts]] if rank == 0 else None, root=0)
        comm.Gatherv(np.ascontiguousarray(local_reward), [all_reward, counts] if rank == 0 else None,
                     root=0)
        if rank == 0 and args.hash:
            digest.update(all_obs.tobytes())
            digest.update(all_reward.tobytes())

    gather(obs, np.zeros(count))
    comm.Barrier()
    step_seconds = 0.0
    gather_seconds = 0.0
    start = time.perf_counter()
    for step in range(args.steps):
        # Every rank draws the actions of all worlds and takes its own: world i acts the same
        # whatever the ranks.
        actions = np.random.default_rng([args.seed, step]).uniform(-1, 1, size=(args.envs, 2))
        t0 = time.perf_counter()
        obs, reward, terminated, truncated, info = env.step(actions[first:first + count])
        t1 = time.perf_counter()
        gather(obs, reward)
        t2 = time.perf_counter()
        step_seconds += t1 - t0
        gather_seconds += t2 - t1
    comm.Barrier()
    seconds = time.perf_counter() - start
    per_rank = comm.gather({"rank": rank, "worlds": count, "step_seconds": step_seconds,
                            "gather_seconds": gather_seconds}, root=0)
    if rank != 0:
        return
    total = args.envs * args.steps / seconds
    figures = {"ranks": ranks, "worlds": args.envs, "steps": args.steps,
               "threads_per_rank": env.batch.threads, "seconds": seconds,
               "env_steps_per_second": total,
               "gather_seconds_per_step": per_rank[0]["gather_seconds"] / args.steps,
               "per_rank": [dict(r, env_steps_per_second=r["worlds"] * args.steps /
                                 max(r["step_seconds"], 1e-12)) for r in per_rank]}
    for r in figures["per_rank"]:
        print(f"rank {r['rank']}: {r['worlds']} worlds, {r['env_steps_per_second']:.0f} "
              f"env-steps/s stepping, {r['gather_seconds'] / args.steps * 1e6:.1f} us/step "
              f"in the gather")
    print(f"{ranks} ranks, {args.envs} worlds x {args.steps} steps: {seconds:.3f} s, "
          f"{total:.0f} env-steps/s in total")
    if args.hash:
        print(f"digest {digest.hexdigest()}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(figures, f, indent=2)


if __name__ == "__main__":
    main()
