"""The batch benchmark from Python: env-steps per second and batch-step latency of
tumble.BatchWorld over world and thread counts, measured as `tumble bench-batch` measures tumble
(the same scene from its initial state, only the steps timed, min/median/max over repetitions;
docs/rl.md). The peers (MuJoCo, Bullet) are the command line's.

    python3 -m tumble.bench scenes/rl/boxes20.yaml --worlds 1,256,1024 --threads 1,2
"""
import argparse
import time

import numpy as np

from tumble import BatchWorld, load_scene


def bench_batch(scene, worlds=(1, 16, 256, 1024), threads=(1, 2), steps=60, repetitions=3):
    """One row per (worlds, threads): a dict with worlds, threads, rate_min, rate_median,
    rate_max (env-steps/s over the repetitions), p50_ms and p99_ms (one batch step)."""
    if isinstance(scene, str):
        scene = load_scene(scene)
    if steps < 1 or repetitions < 1:
        raise ValueError("steps and repetitions must be at least 1")
    rows = []
    for n in worlds:
        for t in threads:
            batch = BatchWorld(scene, int(n), threads=int(t))
            rates, latencies = [], []
            for _ in range(repetitions):
                batch.reset()
                total = 0.0
                for _ in range(steps):
                    start = time.perf_counter()
                    batch.step()
                    elapsed = time.perf_counter() - start
                    total += elapsed
                    latencies.append(elapsed)
                rates.append(n * steps / total)
            rows.append({
                "worlds": int(n),
                "threads": batch.threads,
                "rate_min": float(np.min(rates)),
                "rate_median": float(np.median(rates)),
                "rate_max": float(np.max(rates)),
                "p50_ms": float(np.percentile(latencies, 50) * 1e3),
                "p99_ms": float(np.percentile(latencies, 99) * 1e3),
            })
    return rows


def _counts(text):
    return [int(x) for x in text.split(",") if x]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--worlds", type=_counts, default=[1, 16, 256, 1024])
    parser.add_argument("--threads", type=_counts, default=[1, 2])
    parser.add_argument("--steps", type=int, default=60)
    parser.add_argument("--repetitions", type=int, default=3)
    args = parser.parse_args()
    rows = bench_batch(args.scene, args.worlds, args.threads, args.steps, args.repetitions)
    print("| worlds | threads | env-steps/s median (min / max) | p50 batch step ms | p99 ms |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['worlds']} | {r['threads']} | {r['rate_median']:,.0f} "
              f"({r['rate_min']:,.0f} / {r['rate_max']:,.0f}) | {r['p50_ms']:.3f} | "
              f"{r['p99_ms']:.3f} |")


if __name__ == "__main__":
    main()
