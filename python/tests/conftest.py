"""Shared fixtures of the Python tests: the scenes they step, written to a temporary folder."""
import os

import pytest

SOURCE_DIR = os.environ.get(
    "TUMBLE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..")
)

PILE = """
world: {dt: 0.016666666666666666}
bodies:
  - {name: ground, static: true, shape: {type: box, half_extents: [10, 10, 0.5]}}
  - {name: a, shape: {type: box, half_extents: [0.4, 0.4, 0.4]}, position: [0, 0, 1.0]}
  - {name: b, shape: {type: box, half_extents: [0.3, 0.3, 0.3]}, position: [0.2, 0.1, 2.2]}
  - {name: c, shape: {type: sphere, radius: 0.3}, position: [-0.3, 0.2, 3.4]}
  - {name: pusher, kinematic: true, shape: {type: box, half_extents: [0.1, 0.5, 0.3]},
     position: [-2, 0, 0.9]}
"""


@pytest.fixture()
def pile_scene(tmp_path):
    path = tmp_path / "pile.yaml"
    path.write_text(PILE)
    return str(path)
