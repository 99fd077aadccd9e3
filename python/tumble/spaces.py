"""Space descriptions with the attributes of gymnasium.spaces.Box (shape, dtype, low, high,
sample, contains, seed), so that tumble's environments describe their observations and actions as
Gymnasium expects without depending on it (Debian does not package Gymnasium). A Box converts to
the real one with gymnasium.spaces.Box(box.low, box.high, box.shape, box.dtype).
"""
import numpy as np


class Box:
    """A box in R^shape: every component between its low and high bound (which may be infinite)."""

    def __init__(self, low, high, shape=None, dtype=np.float64, seed=None):
        self.dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low)
        self.shape = tuple(int(n) for n in shape)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        if np.any(np.isnan(self.low)) or np.any(np.isnan(self.high)):
            raise ValueError("Box: bounds must not be NaN")
        if np.any(self.low > self.high):
            raise ValueError("Box: every low bound must be at most its high bound")
        self._rng = np.random.default_rng(seed)

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        """Uniform where both bounds are finite; normal where neither is; else one-sided."""
        low, high = self.low, self.high
        out = self._rng.normal(size=self.shape)
        bounded = np.isfinite(low) & np.isfinite(high)
        out[bounded] = self._rng.uniform(low[bounded], high[bounded])
        below = np.isfinite(low) & ~np.isfinite(high)
        out[below] = low[below] + self._rng.exponential(size=int(below.sum()))
        above = ~np.isfinite(low) & np.isfinite(high)
        out[above] = high[above] - self._rng.exponential(size=int(above.sum()))
        return out.astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return (
            x.shape == self.shape
            and np.can_cast(x.dtype, self.dtype)
            and bool(np.all(x >= self.low))
            and bool(np.all(x <= self.high))
        )

    def __contains__(self, x):
        return self.contains(x)

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"

    def __eq__(self, other):
        return (
            isinstance(other, Box)
            and self.shape == other.shape
            and self.dtype == other.dtype
            and np.array_equal(self.low, other.low)
            and np.array_equal(self.high, other.high)
        )


def batch_space(space, n):
    """The space of n stacked samples of `space` (gymnasium.vector.utils.batch_space for a Box)."""
    return Box(
        np.broadcast_to(space.low, (n,) + space.shape),
        np.broadcast_to(space.high, (n,) + space.shape),
        (n,) + space.shape,
        space.dtype,
    )
