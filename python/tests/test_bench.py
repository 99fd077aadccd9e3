"""tumble.bench: the batch benchmark from Python returns one sane row per world and thread
count, and runs as a module."""
import os
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR
from tumble.bench import bench_batch

SCENE = os.path.join(SOURCE_DIR, "scenes", "rl", "boxes20.yaml")


def test_rows_for_every_count():
    rows = bench_batch(SCENE, worlds=(1, 4), threads=(1, 2), steps=3, repetitions=2)
    assert [(r["worlds"], r["threads"]) for r in rows] == [(1, 1), (1, 2), (4, 1), (4, 2)]
    for r in rows:
        assert 0 < r["rate_min"] <= r["rate_median"] <= r["rate_max"]
        assert 0 < r["p50_ms"] <= r["p99_ms"]
    with pytest.raises(ValueError):
        bench_batch(SCENE, steps=0)


def test_runs_as_a_module():
    out = subprocess.run([sys.executable, "-m", "tumble.bench", SCENE, "--worlds", "2",
                          "--threads", "1", "--steps", "2", "--repetitions", "1"],
                         capture_output=True, text=True, timeout=120, env=os.environ.copy())
    assert out.returncode == 0, out.stderr
    assert "| 2 | 1 |" in out.stdout
