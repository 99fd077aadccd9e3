"""tumble: rigid-body physics centred on collision detection, from Python (docs/python.md).

The engine is the compiled module tumble._tumble; this package re-exports it and adds the pure
Python parts: tumble.spaces (Gymnasium-style space descriptions) and tumble.envs (vectorised
environments).
"""
from tumble._tumble import (  # noqa: F401  (the public names of the compiled module)
    BatchWorld,
    BodyId,
    Error,
    NeuralSdf,
    Scene,
    SceneError,
    Sdf,
    World,
    __version__,
    contact_potential,
    distance,
    load_scene,
    load_scene_text,
    randomized,
)

__all__ = [
    "BatchWorld",
    "BodyId",
    "Error",
    "NeuralSdf",
    "Scene",
    "SceneError",
    "Sdf",
    "World",
    "__version__",
    "contact_potential",
    "distance",
    "load_scene",
    "load_scene_text",
    "randomized",
]
