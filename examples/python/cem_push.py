"""Learns to push a box into the goal (tumble.envs.PushBoxEnv) by the cross-entropy method, in
numpy alone, and plots the success rate against the iteration.

The policy is linear: action = tanh(W f + b), f the 10 observations, 22 parameters. Each iteration
draws a population of parameter vectors from a Gaussian, runs each on `--worlds-per-candidate`
randomized worlds (all candidates in one batch, each world with its own candidate), keeps the
best fifth by return and refits the Gaussian to them (Rubinstein and Kroese, "The Cross-Entropy
Method", 2004; for policies, Szita and Lorincz, "Learning Tetris using the noisy cross-entropy
method", 2006, whose added noise keeps the search from collapsing early).

    PYTHONPATH=build/release/python python3 examples/python/cem_push.py --plot cem.png
"""
import argparse
import os
import tempfile

import numpy as np

from tumble.envs import PushBoxEnv

OBS, ACT = 10, 2
PARAMS = ACT * OBS + ACT


def act(params, obs):
    """params [worlds, PARAMS], obs [worlds, OBS] -> actions [worlds, ACT]."""
    w = params[:, : ACT * OBS].reshape(-1, ACT, OBS)
    b = params[:, ACT * OBS:]
    return np.tanh(np.einsum("wij,wj->wi", w, obs) + b)


def evaluate(env, params, seed):
    """One episode in every world; returns each world's return and whether it reached the goal."""
    obs, _ = env.reset(seed=seed)
    total = np.zeros(env.num_envs)
    success = np.zeros(env.num_envs, dtype=bool)
    running = np.ones(env.num_envs, dtype=bool)
    for _ in range(env.max_steps):
        obs, reward, terminated, truncated, info = env.step(act(params, obs))
        total += np.where(running, reward, 0.0)
        success |= running & info["success"]
        running &= ~(terminated | truncated)
        if not running.any():
            break
    return total, success


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--iterations", type=int, default=15)
    parser.add_argument("--population", type=int, default=40)
    parser.add_argument("--worlds-per-candidate", type=int, default=4)
    parser.add_argument("--steps", type=int, default=80, help="episode length (env steps)")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--plot", default="cem_push.png", help="where to write the plot (PNG)")
    args = parser.parse_args()

    rng = np.random.default_rng(args.seed)
    k = args.worlds_per_candidate
    env = PushBoxEnv(num_envs=args.population * k, threads=args.threads, seed=args.seed,
                     max_steps=args.steps)
    elite = max(2, args.population // 5)
    mean = np.zeros(PARAMS)
    std = np.full(PARAMS, 1.0)
    # Iteration 0: the initial mean policy (all zeros: the pusher stands still).
    _, mean_success = evaluate(env, np.tile(mean, (env.num_envs, 1)), seed=10**6 - 1)
    rates, mean_rates = [float("nan")], [float(mean_success.mean())]
    print(f"iteration   0  mean policy success {mean_rates[-1]:.3f}", flush=True)
    for it in range(args.iterations):
        candidates = mean + std * rng.standard_normal((args.population, PARAMS))
        returns, success = evaluate(env, np.repeat(candidates, k, axis=0), seed=1000 * it)
        score = returns.reshape(args.population, k).mean(axis=1)
        best = candidates[np.argsort(score)[-elite:]]
        mean = best.mean(axis=0)
        # The extra noise decays with the iterations (Szita and Lorincz).
        std = best.std(axis=0) + 0.5 / (1 + it)
        # The new mean policy on held-out draws (seeds no iteration trains on).
        _, mean_success = evaluate(env, np.tile(mean, (env.num_envs, 1)), seed=10**6 + it)
        rates.append(float(success.mean()))
        mean_rates.append(float(mean_success.mean()))
        print(f"iteration {it + 1:3d}  population success {rates[-1]:.3f}  "
              f"mean policy success {mean_rates[-1]:.3f}  best return {score.max():.2f}",
              flush=True)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    x = np.arange(0, args.iterations + 1)
    ax.plot(x, rates, "o-", label="population")
    ax.plot(x, mean_rates, "s-", label="mean policy (held-out draws)")
    ax.set_xlabel("CEM iteration")
    ax.set_ylabel("success rate")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title(f"PushBoxEnv, {args.population} x {k} randomized worlds per iteration")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    # Written beside the target and renamed onto it, so a reader never sees half a file.
    folder = os.path.dirname(os.path.abspath(args.plot))
    with tempfile.NamedTemporaryFile(dir=folder, suffix=".png", delete=False) as tmp:
        fig.savefig(tmp.name, dpi=100)
    os.replace(tmp.name, args.plot)
    print(f"final mean policy success {mean_rates[-1]:.3f}; plot {args.plot}")


if __name__ == "__main__":
    main()
