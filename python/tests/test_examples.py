"""The Python examples run at a small size: the rollout prints its throughput, and the
cross-entropy search learns to reach the goal and writes its plot."""
import os
import re
import subprocess
import sys

from conftest import SOURCE_DIR

EXAMPLES = os.path.join(SOURCE_DIR, "examples", "python")


def run(script, *args):
    result = subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args],
                            capture_output=True, text=True, timeout=300, env=os.environ.copy())
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_rollout_prints_env_steps_per_second():
    out = run("rollout.py", "--envs", "8", "--steps", "20", "--threads", "1")
    rate = float(re.search(r"(\d+) env-steps/s", out).group(1))
    assert rate > 0
    assert "8 worlds x 20 steps" in out


def test_cem_learns_to_push_and_plots(tmp_path):
    plot = tmp_path / "cem.png"
    out = run("cem_push.py", "--iterations", "4", "--population", "10",
              "--worlds-per-candidate", "2", "--steps", "60", "--threads", "1",
              "--plot", str(plot))
    rates = [float(x) for x in re.findall(r"mean policy success ([0-9.]+)", out)]
    assert len(rates) == 6  # the initial policy, four iterations and the final line
    # The initial policy (all zeros) never reaches the goal; four iterations learn to.
    assert rates[0] == 0.0, out
    assert rates[-1] >= 0.75, out
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [p for p in os.listdir(tmp_path) if p != "cem.png"]  # no temporary left behind
