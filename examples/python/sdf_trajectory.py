"""Moves a sphere through CSG obstacles by gradient descent on the obstacles' signed distance
and its gradient (tumble.Sdf): a path of waypoints from start to goal, pulled straight by a
smoothness term and pushed out of the obstacles by the contact potential k/2 (phi - r - margin)^2
wherever phi - r < margin.

    PYTHONPATH=build/release/python python3 examples/python/sdf_trajectory.py --plot out.png

Prints the clearance of the straight path and of the optimised one (the smallest phi - r along
the path, sampled between waypoints too); a positive clearance is a path that touches nothing.
"""
import argparse

import numpy as np

import tumble

RADIUS = 0.15  # the sphere's [m]
MARGIN = 0.05  # clearance the potential asks for [m]

# Obstacles in the plane z = 0 (each extends 1 m up and down): a blob of two spheres blended
# together, a box with a bite taken out of it, and a capsule.
OBSTACLES = {"union": [
    {"smooth_union": {"k": 6, "of": [
        {"sphere": {"radius": 0.45}, "position": [-1.2, -0.55, 0]},
        {"sphere": {"radius": 0.35}, "position": [-0.8, -0.95, 0]}]}},
    {"difference": [{"box": {"half_extents": [0.35, 0.5, 1.0]}},
                    {"sphere": {"radius": 0.4}, "position": [0.35, 0.3, 0]}],
     "position": [0.2, 0.05, 0]},
    {"capsule": {"radius": 0.25, "half_length": 0.5}, "position": [1.3, 0.9, 0],
     "orientation": [0.7071067811865476, 0.7071067811865476, 0, 0]},
]}


def clearance(sdf, path, per_segment=20):
    """The smallest phi - RADIUS along the polyline, sampled densely between waypoints."""
    t = np.linspace(0, 1, per_segment, endpoint=False)[:, None, None]
    points = (path[:-1][None] * (1 - t) + path[1:][None] * t).reshape(-1, 3)
    points = np.vstack([points, path[-1:]])
    return float(np.min(sdf.sample(points)[0]) - RADIUS)


def optimise(sdf, start, goal, waypoints=80, iterations=3000, stiffness=1500.0, step=2e-3):
    path = np.linspace(start, goal, waypoints)
    history = [path.copy()]
    for it in range(iterations):
        inner = path[1:-1]
        # Smoothness: sum |x_{i+1} - x_i|^2, scaled by the waypoint count so that it measures
        # length whatever the spacing.
        smooth = 2 * (2 * inner - path[:-2] - path[2:]) * (waypoints - 1)
        phi, grad = sdf.sample(inner)
        gap = np.minimum(phi - RADIUS - MARGIN, 0.0)
        # The push is the gradient of k/2 gap^2 with its component along the path removed, as
        # CHOMP does (Ratliff et al., "CHOMP: Gradient optimization techniques for efficient
        # motion planning", ICRA 2009): a path through an obstacle's middle is then moved
        # sideways, around it, instead of being split into points pushed out both ways.
        tangent = path[2:] - path[:-2]
        tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
        across = grad - np.sum(grad * tangent, axis=1, keepdims=True) * tangent
        push = stiffness * gap[:, None] * across
        change = smooth + push
        change[:, 2] = 0  # stay in the plane
        path[1:-1] -= step * change
        if it % 500 == 0:
            history.append(path.copy())
    history.append(path.copy())
    return path, history


def plot(sdf, history, filename):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs, ys = np.meshgrid(np.linspace(-2.6, 2.6, 260), np.linspace(-1.8, 1.8, 180))
    grid = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    phi = sdf.sample(grid)[0].reshape(xs.shape)
    fig, ax = plt.subplots(figsize=(9, 6.2))
    ax.contourf(xs, ys, phi, levels=[-10, 0], colors=["#9aa5b1"])
    ax.contour(xs, ys, phi, levels=[RADIUS, RADIUS + MARGIN], colors=["#d62728", "#ff9896"],
               linestyles=["-", "--"], linewidths=1)
    for k, path in enumerate(history):
        last = k == len(history) - 1
        ax.plot(path[:, 0], path[:, 1], "-o" if last else "-", ms=2.5 if last else 0,
                color="#1f77b4" if last else "#aec7e8", lw=2 if last else 1,
                label="optimised" if last else ("straight start" if k == 0 else None))
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("a sphere's path through CSG obstacles by gradient descent on their SDF\n"
                 "(grey: obstacles; red: where the sphere's centre would touch them)")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(filename, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--iterations", type=int, default=3000)
    parser.add_argument("--plot", help="write the figure to this PNG file")
    args = parser.parse_args()
    sdf = tumble.Sdf(OBSTACLES)
    start, goal = np.array([-2.4, -1.5, 0.0]), np.array([2.4, 1.5, 0.0])
    straight = np.linspace(start, goal, 60)
    path, history = optimise(sdf, start, goal, iterations=args.iterations)
    length = float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))
    print(f"straight path: clearance {clearance(sdf, straight):+.3f} m, length "
          f"{np.linalg.norm(goal - start):.3f} m")
    print(f"optimised path: clearance {clearance(sdf, path):+.3f} m, length {length:.3f} m")
    if args.plot:
        plot(sdf, history, args.plot)
        print(f"figure: {args.plot}")


if __name__ == "__main__":
    main()
