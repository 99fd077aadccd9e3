"""The Python module's argument checks, fuzzed: thousands of calls of every function and method
with arguments drawn from fixed seeds, most of them valid and one or more replaced by a hostile
value (a wrong type, shape or dtype, NaN, infinity, a huge or negative number, an empty or
nested list, a strided or zero-dimensional array, a handle from another world). Each call must
return or raise one of the errors the module documents (ValueError, TypeError, IndexError,
OverflowError, MemoryError, tumble.Error), and after any call that returned, every state the
module shows is finite. The calls run in a child interpreter, so that a crash is a failed test
naming the seed and the call rather than the end of the test run."""
import os
import subprocess
import sys
import textwrap

import pytest

CASES_PER_SEED = 5000
SEEDS = (1, 2, 3, 4)

CHILD = textwrap.dedent(
    r'''
    import math
    import sys

    import numpy as np

    import tumble

    # A bigger world, whose body handles are out of range in the pile.
    ROW = "world: {dt: 0.01}\nbodies:\n" + "".join(
        "  - {name: r%d, shape: {type: sphere, radius: 0.1}, position: [%d, 0, 1]}\n" % (i, i)
        for i in range(9))

    ALLOWED = (ValueError, TypeError, IndexError, OverflowError, MemoryError, tumble.Error)

    seed = int(sys.argv[1])
    cases = int(sys.argv[2])
    pile_path = sys.argv[3]  # the pile of conftest.py, which every test steps
    with open(pile_path) as f:
        PILE = f.read()
    rng = np.random.default_rng(seed)
    scene = tumble.load_scene(pile_path)
    row = tumble.World(tumble.load_scene_text(ROW, "row.yaml"))
    foreign = row.body("r8")

    class BadFloat:
        # A number whose conversion fails (its error propagates, as any Python call's would).
        def __float__(self):
            raise TypeError("no float here")

        def __index__(self):
            raise TypeError("no index here")

    nan, inf = float("nan"), float("inf")
    hostile = [
        None, True, 0, -1, 2**31, 2**63, -2**63, 2**200, 1.5, nan, inf, -inf, 1e308, -0.0,
        "", "a", "\x00", "\udcff", b"bytes", [], [1], [1, 2], [nan] * 3, [inf] * 3, [1e308] * 3,
        [[1, 2, 3]], ["x", "y", "z"], [None] * 3, [0.0] * 7, [nan] * 7, {}, {"type": "box"},
        {"type": "sdf", "sdf": {}}, {"type": "sphere", "radius": -1}, (1, 2, 3, 4, 5),
        np.zeros(0), np.zeros(3, dtype=np.float32), np.zeros(3, dtype=np.int64),
        np.full(3, nan), np.zeros((3, 1)), np.float64(nan), np.array(1.0), np.zeros((2, 5, 3)),
        np.zeros((2, 5, 3), dtype=np.float32), np.zeros((2, 5, 3), order="F"),
        np.zeros((2, 5, 6))[:, :, ::2], np.full((2, 5, 3), inf), np.zeros((2, 5, 7)),
        np.zeros((5, 2, 3)), np.zeros((2, 5, 3), dtype=complex), np.zeros((2, 5, 3), dtype=object),
        np.broadcast_to(np.zeros(3), (2, 5, 3)), np.array([0, 1, 2]), np.array([-1]),
        np.array([[0]]), np.array([0.5]), np.zeros((1, 4)), np.zeros((4, 3)), foreign, object(),
        BadFloat(), [BadFloat()] * 3, [[[0.0] * 3] * 5] * 2, np.zeros((2, 5, 3))[::-1],
        np.zeros((2, 5, 3))[:, ::-1, :], memoryview(b"abc"), np.float32(1.5), np.int8(-1),
        np.uint64(2**64 - 1), [1] * 100000, {"sphere": {"radius": 1}}, "{sphere: {radius: 1}}",
        {"torus": {"major_radius": 1, "minor_radius": 2}}, {"box": {"half_extents": [1, 1]}},
        "[" * 300 + "]" * 300, "&a [*a]", "\t\n", "scenes/../../../etc/passwd",
    ]

    def pick(values):
        return values[int(rng.integers(len(values)))]

    def real(low=-10.0, high=10.0):
        return float(rng.uniform(low, high))

    def vec(n=3, low=-10.0, high=10.0):
        return [real(low, high) for _ in range(n)]

    def quat():
        q = rng.normal(size=4)
        return list(q / np.linalg.norm(q))

    def pose():
        return vec(3, -1, 1) + (quat() if rng.random() < 0.5 else [])

    def shape():
        return pick([
            {"type": "box", "half_extents": vec(3, 0.1, 1)},
            {"type": "sphere", "radius": real(0.1, 1)},
            {"type": "capsule", "radius": real(0.1, 0.5), "half_length": real(0, 1)},
            {"type": "cylinder", "radius": real(0.1, 0.5), "half_length": real(0.1, 1)},
            {"type": "plane"},
            {"type": "sdf", "resolution": 8,
             "sdf": {"torus": {"major_radius": 0.5, "minor_radius": 0.2}}},
        ])

    def forces(batch, width=3):
        return rng.uniform(-50, 50, size=(batch.num_worlds, batch.body_count, width))

    def targets(batch):
        t = np.zeros((batch.num_worlds, batch.body_count, 7))
        t[:, :, :3] = rng.uniform(-1, 1, size=(batch.num_worlds, batch.body_count, 3))
        t[:, :, 3] = 1.0
        return t

    def body(world):
        return world.body(pick(["ground", "a", "b", "c", "pusher"]))

    world = tumble.World(scene)
    batch = tumble.BatchWorld(scene, 2, threads=int(rng.integers(1, 3)))

    # Each entry: a name and a function of nothing giving (callable, valid arguments).
    calls = [
        ("World.body", lambda: (world.body, [pick(["a", "b", "ground", "nobody"])])),
        ("World.step", lambda: (world.step, [int(rng.integers(1, 3))])),
        ("World.reset", lambda: (world.reset, [])),
        ("World.add_force", lambda: (world.add_force, [body(world), vec()])),
        ("World.add_torque", lambda: (world.add_torque, [body(world), vec()])),
        ("World.apply_impulse", lambda: (world.apply_impulse, [body(world), vec(), vec()])),
        ("World.set_velocity", lambda: (world.set_velocity, [body(world), vec(), vec()])),
        ("World.set_kinematic_target",
         lambda: (world.set_kinematic_target, [world.body("pusher"), vec(3, -2, 2), quat()])),
        ("World.body_state", lambda: (world.body_state, [body(world)])),
        ("World.ray_cast", lambda: (world.ray_cast, [vec(), vec(), real(0, 100)])),
        ("World.contact_reports", lambda: (world.contact_reports, [])),
        ("BatchWorld.set_forces", lambda: (batch.set_forces, [forces(batch)])),
        ("BatchWorld.set_torques", lambda: (batch.set_torques, [forces(batch)])),
        ("BatchWorld.set_kinematic_targets",
         lambda: (batch.set_kinematic_targets, [targets(batch)])),
        ("BatchWorld.step", lambda: (batch.step, [int(rng.integers(1, 3))])),
        ("BatchWorld.reset", lambda: (batch.reset, [[int(rng.integers(0, 2))]])),
        ("BatchWorld.state_hash", lambda: (batch.state_hash, [int(rng.integers(0, 2))])),
        ("BatchWorld.contact_forces", lambda: (batch.contact_forces, [])),
        ("BatchWorld.contact_counts", lambda: (batch.contact_counts, [])),
        ("BatchWorld", lambda: (tumble.BatchWorld, [scene, int(rng.integers(1, 4))])),
        ("World", lambda: (tumble.World, [scene])),
        ("distance", lambda: (tumble.distance, [shape(), pose(), shape(), pose()])),
        ("contact_potential",
         lambda: (tumble.contact_potential,
                  [tumble.distance(shape(), pose(), {"type": "sphere", "radius": 0.5},
                                   [0.0, 0.0, 0.0]), real(0, 1e4), real(0, 1e3)])),
        ("randomized", lambda: (tumble.randomized, [scene, int(rng.integers(0, 1000))])),
        ("load_scene_text", lambda: (tumble.load_scene_text, [PILE, "pile.yaml"])),
        ("Sdf", lambda: (tumble.Sdf, [{"sphere": {"radius": real(0.1, 2)}}])),
        ("Sdf.sample",
         lambda: (tumble.Sdf({"torus": {"major_radius": 1, "minor_radius": 0.25}}).sample,
                  [rng.uniform(-2, 2, size=(int(rng.integers(0, 5)), 3))])),
    ]
    # Values that are valid but would run long are not drawn: step(n) takes whatever n it is
    # given up to a billion, as the command line does.
    long_running = {"World.step", "BatchWorld.step", "BatchWorld"}

    def finite_state():
        for name in ("ground", "a", "b", "c", "pusher"):
            s = world.body_state(world.body(name))
            assert np.all(np.isfinite(s)), (name, s)
        assert np.all(np.isfinite(batch.observe())), batch.observe()

    succeeded = {}
    for case in range(cases):
        name, make = calls[int(rng.integers(len(calls)))]
        function, args = make()
        args = list(args)
        for k in range(len(args)):
            if rng.random() < 0.35:
                value = pick(hostile)
                if name in long_running and isinstance(value, int) and value > 3:
                    value = -value
                args[k] = value
        if args and rng.random() < 0.05:
            args = args[:-1]  # a missing argument
        elif rng.random() < 0.05:
            args = args + [pick(hostile)]  # one too many
        print(f"case {case}: {name}({', '.join(repr(a)[:60] for a in args)})", flush=True)
        try:
            function(*args)
        except ALLOWED as error:
            # A clear message, never an empty one or pybind11's internal wording.
            message = str(error)
            assert message and "Unable to cast" not in message, (name, type(error), message)
            if isinstance(error, tumble.Error) and "non-finite" in message:
                # A world that stopped on a non-finite state (NonFiniteStateError): a new one.
                world = tumble.World(scene)
                batch = tumble.BatchWorld(scene, 2, threads=1)
        else:
            succeeded[name] = succeeded.get(name, 0) + 1
        finite_state()
    # Every function was also called in ways it takes: a check that refused everything would
    # pass the loop above.
    never = sorted(name for name, _ in calls if succeeded.get(name, 0) == 0)
    assert not never, f"never returned: {never}"
    print("done", flush=True)
    '''
)


@pytest.mark.parametrize("seed", SEEDS)
def test_every_call_returns_or_raises_a_documented_error(seed, pile_scene):
    result = subprocess.run(
        [sys.executable, "-c", CHILD, str(seed), str(CASES_PER_SEED), pile_scene],
        capture_output=True,
        text=True,
        env=dict(os.environ),
        timeout=600,
    )
    tail = "\n".join(result.stdout.splitlines()[-3:])
    assert result.returncode == 0, f"seed {seed}: exit {result.returncode}\n{tail}\n{result.stderr[-3000:]}"
    assert result.stdout.rstrip().endswith("done"), tail


def test_what_the_fuzz_found():
    """Each defect the fuzz above found, as a call of its own."""
    import tumble

    # None as a scene was cast to an empty scene and dereferenced: a crash.
    for make in (lambda: tumble.randomized(None, 1), lambda: tumble.World(None),
                 lambda: tumble.BatchWorld(None, 2)):
        with pytest.raises(TypeError, match="expected a path"):
            make()
    # A NUL byte ended the name the system opened, and the message at it.
    with pytest.raises(tumble.SceneError, match=r"a\\x00b: cannot open scene file \(the file name "
                                                r"holds a NUL byte\)"):
        tumble.World("a\x00b")
    # A name that is not UTF-8 (os.fsdecode gives it lone surrogates) is the file of those bytes,
    # and the message shows them rather than being empty.
    with pytest.raises(tumble.SceneError, match=r"\\xff\.yaml: cannot open scene file"):
        tumble.World(os.fsdecode(b"\xff.yaml"))
    with pytest.raises(ValueError, match="UTF-8"):
        tumble.Sdf("\udcff")
    # A description nested past Python's recursion limit (found in review): a ValueError.
    deep = {"sphere": {"radius": 1}}
    for _ in range(100000):
        deep = {"union": [deep, deep]}
    with pytest.raises(ValueError, match="nested too deeply"):
        tumble.Sdf(deep)
