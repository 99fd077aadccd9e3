"""`tumble sweep` and examples/python/mpi_rollout.py over MPI ranks (docs/scale-out.md), against
the same work in one process: byte-identical outputs, a restart after a killed rank, errors that
name the rank and the file, and the same worlds on any number of ranks.

Run by ctest with TUMBLE_CLI (the tumble binary), MPIEXEC, TUMBLE_SOURCE_DIR and, for the Python
part, PYTHONPATH set to the build's python directory.
"""
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

import pytest

CLI = str(pathlib.Path(os.environ["TUMBLE_CLI"]).resolve())
MPIEXEC = os.environ.get("MPIEXEC", "mpirun")
SOURCE = pathlib.Path(os.environ["TUMBLE_SOURCE_DIR"])
# Open MPI refuses root unless told, and two ranks plus a coordinator oversubscribe two cores.
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")

SCENE = """world: {dt: 0.01, duration: 0.5}
randomize: {friction: [0.3, 0.9], position_noise: 0.01, size_noise: 0.02}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - {name: base, shape: {type: box, half_extents: [0.5, 0.5, 0.5]}, position: [0, 0, 0.5], mass: 1}
  - {name: ball, shape: {type: sphere, radius: 0.3}, position: [0.2, 0, 1.8], mass: 1}
  - {name: top, shape: {type: box, half_extents: [0.3, 0.2, 0.3]}, position: [-0.1, 0, 2.6], mass: 2}
"""

SPEC = """scene: scene.yaml
vary:
  world.dt: [0.01, 0.005]
  world.solver: [impulse, penalty]
  materials.default.restitution: {from: 0, to: 0.5, count: 2}
seeds: 2
reference: {world.dt: 0.0025, world.solver: impulse}
"""


def mpirun(ranks, *args, cwd=None):
    return [MPIEXEC, "-n", str(ranks), *args]


def run(command, cwd=None, check=True):
    result = subprocess.run(command, cwd=cwd, env=MPI_ENV, capture_output=True, text=True,
                            timeout=600)
    if check and result.returncode != 0:
        raise AssertionError(f"{command} exited {result.returncode}:\n{result.stdout}\n"
                             f"{result.stderr}")
    return result


def make_sweep(tmp_path, spec=SPEC, scene=SCENE):
    (tmp_path / "scene.yaml").write_text(scene)
    (tmp_path / "sweep.yaml").write_text(spec)
    return tmp_path / "sweep.yaml"


def outputs(directory):
    """Every output file but the wall times, by path."""
    files = {}
    for path in sorted(directory.rglob("*")):
        if path.is_file() and path.name not in ("timing.json", "timings.csv"):
            files[str(path.relative_to(directory))] = path.read_bytes()
    return files


def test_a_sweep_over_ranks_writes_the_bytes_of_one_process(tmp_path):
    spec = make_sweep(tmp_path)
    run([CLI, "sweep", str(spec), "-o", str(tmp_path / "one")])
    result = run(mpirun(3, CLI, "sweep", str(spec), "-o", str(tmp_path / "three")))
    assert "on 2 ranks" in result.stdout
    one, three = outputs(tmp_path / "one"), outputs(tmp_path / "three")
    assert len(one) == 1 + 2 * (16 + 4)  # sweep.csv; summary and checkpoints per run, reference
    assert one.keys() == three.keys()
    for name in one:
        assert one[name] == three[name], name
    rows = (tmp_path / "three" / "sweep.csv").read_text().splitlines()
    assert len(rows) == 17
    # Only the workers ran: rank 0 coordinates.
    timings = (tmp_path / "three" / "timings.csv").read_text().splitlines()[1:]
    ranks = {line.split(",")[1] for line in timings}
    assert ranks <= {"1", "2"} and ranks, ranks


def worker_pid(launcher_pid):
    """The process of rank 1 among the launcher's descendants (its environment says its rank)."""
    for entry in pathlib.Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            environ = (entry / "environ").read_bytes().split(b"\0")
            cmdline = (entry / "cmdline").read_bytes()
        except OSError:
            continue
        if b"OMPI_COMM_WORLD_RANK=1" in environ and b"sweep" in cmdline:
            return int(entry.name)
    return None


def test_a_sweep_whose_rank_was_killed_finishes_when_run_again(tmp_path):
    # Runs long enough (about 0.1 s each) to kill the worker in the middle.
    spec = make_sweep(tmp_path, spec="""scene: scene.yaml
duration: 5
vary:
  world.dt: [0.004, 0.005]
  materials.default.friction: {from: 0.2, to: 0.8, count: 6}
seeds: 2
""")
    run([CLI, "sweep", str(spec), "-o", str(tmp_path / "whole")])
    out = tmp_path / "killed"
    command = mpirun(2, CLI, "sweep", str(spec), "-o", str(out))
    job = subprocess.Popen(command, env=MPI_ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True)
    deadline = time.time() + 120
    done = 0
    while time.time() < deadline and done < 3:
        done = len(list(out.glob("runs/*/summary.json")))
        time.sleep(0.01)
    pid = worker_pid(job.pid)
    assert pid is not None and done >= 3
    os.kill(pid, signal.SIGKILL)
    job.communicate(timeout=120)
    assert job.returncode != 0
    complete = len(list(out.glob("runs/*/summary.json")))
    assert 3 <= complete < 24, complete
    # The same command again does the rest, and the sweep ends as an unbroken one does.
    again = run(command)
    assert f"{complete} already complete, {24 - complete} to run" in again.stdout, again.stdout
    assert not list(out.glob("runs/*/*.tmp.*"))
    assert outputs(out) == outputs(tmp_path / "whole")


def test_bad_sweeps_are_refused_once_before_any_rank_works(tmp_path):
    spec = make_sweep(tmp_path, spec="scene: scene.yaml\nvary:\n  world.dtt: [0.01]\n")
    result = run(mpirun(2, CLI, "sweep", str(spec), "-o", str(tmp_path / "out")), check=False)
    assert result.returncode != 0
    assert result.stderr.count("sweep.yaml:3:15: field 'vary.world.dtt'") == 1, result.stderr
    assert not (tmp_path / "out" / "runs").exists()
    empty = make_sweep(tmp_path, spec="scene: scene.yaml\nvary:\n  world.dt: []\n")
    result = run(mpirun(2, CLI, "sweep", str(empty), "-o", str(tmp_path / "out")), check=False)
    assert result.returncode != 0 and "an empty list" in result.stderr
    good = make_sweep(tmp_path, spec="scene: scene.yaml\nvary:\n  world.dt: [0.01]\n")
    blocked = tmp_path / "blocked"
    blocked.write_text("a file, not a directory")
    result = run(mpirun(2, CLI, "sweep", str(good), "-o", str(blocked / "out")), check=False)
    assert result.returncode != 0 and "cannot create the output directory" in result.stderr


def test_a_rank_that_cannot_read_the_scene_names_itself_and_the_file(tmp_path):
    # Rank 0 runs in a folder with the scene, rank 1 in one without (as on a node that does not
    # see the file): rank 1 reports itself and the file.
    here, there = tmp_path / "here", tmp_path / "there"
    here.mkdir()
    there.mkdir()
    spec = "scene: scene.yaml\nduration: 0.1\nvary:\n  world.dt: [0.01, 0.005]\n"
    make_sweep(here, spec=spec)
    (there / "sweep.yaml").write_text(spec)
    command = [MPIEXEC, "-n", "1", "-wdir", str(here), CLI, "sweep", "sweep.yaml", "-o",
               str(tmp_path / "out"), ":", "-n", "1", "-wdir", str(there), CLI, "sweep",
               "sweep.yaml", "-o", str(tmp_path / "out")]
    result = run(command, check=False)
    assert result.returncode != 0
    assert "rank 1: task" in result.stderr, result.stderr
    assert "scene.yaml: cannot open scene file" in result.stderr, result.stderr


def rollout(prefix):
    script = SOURCE / "examples" / "python" / "mpi_rollout.py"
    result = run([*prefix, sys.executable, str(script), "--envs", "7", "--steps", "25",
                  "--max-steps", "6", "--hash"])
    digest = [line for line in result.stdout.splitlines() if line.startswith("digest ")]
    assert len(digest) == 1, result.stdout
    return digest[0], result.stdout


def test_an_rl_batch_spread_over_ranks_steps_the_same_worlds():
    pytest.importorskip("mpi4py")
    pytest.importorskip("tumble")
    alone, _ = rollout([])
    shared, text = rollout([MPIEXEC, "-n", "2"])
    assert alone == shared
    assert "rank 1: 3 worlds" in text and "rank 0: 4 worlds" in text
    assert "env-steps/s in total" in text
    three, _ = rollout([MPIEXEC, "-n", "3"])
    assert three == alone


def test_a_report_over_ranks_measures_the_same_errors(tmp_path):
    scene = SOURCE / "scenes" / "stack10.yaml"
    common = ["report", str(scene), "--duration", "0.3", "--no-plot"]
    run([CLI, *common, "-o", str(tmp_path / "one")])
    run(mpirun(3, CLI, *common, "-o", str(tmp_path / "three")))

    def without_wall_times(path):
        rows = [line.split(",") for line in path.read_text().splitlines()]
        wall = rows[0].index("wall_per_simulated_second")
        return [row[:wall] + row[wall + 1:] for row in rows]

    one = without_wall_times(tmp_path / "one" / "report.csv")
    assert len(one) > 40
    assert one == without_wall_times(tmp_path / "three" / "report.csv")
