"""Places a two-finger gripper on an object given by its signed distance field so that both
fingertips touch the surface on opposite sides (a grasp-like placement), by gradient descent on
the gripper's pose and opening with the field's distance and gradient (tumble.Sdf).

The gripper: a palm at its origin (a ball of radius 0.04 m that must stay clear of the object)
and two fingertips (balls of radius 0.015 m) at +-w along its y axis, 0.12 m ahead along its z
axis. The loss, for fingertip centres f1, f2 with field values phi_i and unit normals n_i:

    sum_i (phi_i - r)^2                    both tips on the surface
  + a |n_1 + n_2|^2                        opposite normals: the tips squeeze, not slide off
  + b max(0, R + c - phi(palm))^2          the palm clear of the object by c

Its gradient comes from grad phi through the chain rule: d/d position = the tips' pulls summed,
d/d turn = sum (R o_i) x pull_i, d/d w = the pulls along the gripper's y axis; the normals'
term uses central differences of grad phi (the field's second derivative is not exposed). Ten
random starts, the best kept; prints each start's final loss and the contact errors.

    PYTHONPATH=build/release/python python3 examples/python/sdf_grasp.py --plot docs/sdf/grasp.png
"""
import argparse

import numpy as np

import tumble

TIP = 0.015  # fingertip radius [m]
PALM = 0.04  # palm radius [m]
REACH = 0.12  # fingertips ahead of the palm along the gripper's z [m]
CLEAR = 0.01  # palm clearance [m]
A_NORMALS = 0.05
B_PALM = 10.0

# The object: a nut-like CSG solid (a hexagonal prism 0.16 m across the flats with a hole),
# standing on edge, which only a few placements grip well.
OBJECT = {
    "difference": [
        {"intersection": [
            {"box": {"half_extents": [0.08, 0.1, 0.03]}},
            {"box": {"half_extents": [0.08, 0.1, 0.03]},
             "orientation": [0.8660254037844387, 0, 0, 0.5]},
            {"box": {"half_extents": [0.08, 0.1, 0.03]},
             "orientation": [0.5, 0, 0, 0.8660254037844386]}]},
        {"cylinder": {"radius": 0.04, "half_length": 0.1}}],
    "orientation": [0.7071067811865476, 0.7071067811865476, 0, 0],
}


def rotation(v):
    """The rotation matrix of the rotation vector v (Rodrigues)."""
    angle = np.linalg.norm(v)
    if angle < 1e-12:
        return np.eye(3)
    k = v / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def points(pose):
    """Palm and fingertip centres of a pose (position, rotation matrix, opening)."""
    p, r, w = pose
    offsets = np.array([[0, 0, 0], [0, w, REACH], [0, -w, REACH]])
    return p + offsets @ r.T, offsets


def loss_and_gradient(sdf, pose):
    p, r, w = pose
    centres, offsets = points(pose)
    phi, grad = sdf.sample(centres)
    norms = np.linalg.norm(grad, axis=1, keepdims=True)
    normals = grad / np.maximum(norms, 1e-12)
    pulls = np.zeros((3, 3))  # d loss / d centre, per point
    loss = 0.0
    for i in (1, 2):
        e = phi[i] - TIP
        loss += e * e
        pulls[i] += 2 * e * grad[i]
    s = normals[1] + normals[2]
    loss += A_NORMALS * s @ s
    # d |n1 + n2|^2 / d tip: 2 s^T (d n_i / d x), d n / d x by central differences of the normal.
    h = 1e-5
    for i in (1, 2):
        for k in range(3):
            step = np.zeros(3)
            step[k] = h
            up = sdf.sample(centres[i] + step)[1]
            down = sdf.sample(centres[i] - step)[1]
            dn = (up / np.linalg.norm(up) - down / np.linalg.norm(down)) / (2 * h)
            pulls[i][k] += A_NORMALS * 2 * s @ dn
    gap = PALM + CLEAR - phi[0]
    if gap > 0:
        loss += B_PALM * gap * gap
        pulls[0] += -2 * B_PALM * gap * grad[0]
    d_position = pulls.sum(axis=0)
    d_turn = sum(np.cross(r @ offsets[i], pulls[i]) for i in range(3))
    d_opening = (pulls[1] - pulls[2]) @ (r @ np.array([0, 1, 0]))
    return loss, d_position, d_turn, d_opening, phi


def optimise(sdf, start, iterations, step):
    p, v, w = start
    history = []
    for _ in range(iterations):
        r = rotation(v)
        loss, dp, dturn, dw, phi = loss_and_gradient(sdf, (p, r, w))
        history.append(loss)
        p = p - step * dp
        # A turn of the world axes dturn applied on the left: R <- exp(-step dturn) R.
        r = rotation(-step * dturn) @ r
        angle = np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1))
        if angle < 1e-9:
            v = np.zeros(3)
        else:
            axis = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
            v = axis / (2 * np.sin(angle)) * angle
        w = float(np.clip(w - step * dw, 0.02, 0.15))
    return (p, v, w), history


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--starts", type=int, default=10)
    parser.add_argument("--iterations", type=int, default=600)
    parser.add_argument("--step", type=float, default=0.05)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--plot", help="write a figure of the best placement here")
    args = parser.parse_args()
    sdf = tumble.Sdf(OBJECT)
    rng = np.random.default_rng(args.seed)
    results = []
    for k in range(args.starts):
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        # Start 0.25 m out along a random direction, the gripper's z pointing roughly inward.
        p = 0.25 * direction
        z = -direction + 0.3 * rng.normal(size=3)
        z /= np.linalg.norm(z)
        axis = np.cross([0, 0, 1], z)
        angle = np.arccos(np.clip(z[2], -1, 1))
        v = axis / max(np.linalg.norm(axis), 1e-12) * angle
        start = (p, v, 0.1)
        final, history = optimise(sdf, start, args.iterations, args.step)
        centres, _ = points((final[0], rotation(final[1]), final[2]))
        phi, grad = sdf.sample(centres)
        n = grad / np.linalg.norm(grad, axis=1, keepdims=True)
        results.append((history[-1], k, start, final, history, phi, n))
        print("start %d: loss %.3e -> %.3e, tip gaps %+.2e %+.2e m, normals' angle %.1f deg, "
              "palm clearance %.3f m" % (
                  k, history[0], history[-1], phi[1] - TIP, phi[2] - TIP,
                  np.degrees(np.arccos(np.clip(-n[1] @ n[2], -1, 1))), phi[0] - PALM))
    best = min(results, key=lambda x: x[0])
    loss, k, start, final, history, phi, n = best
    print("best: start %d, loss %.3e, tips %+.2e and %+.2e m from the surface, normals %.1f deg "
          "from opposite, opening %.3f m" % (
              k, loss, phi[1] - TIP, phi[2] - TIP,
              np.degrees(np.arccos(np.clip(-n[1] @ n[2], -1, 1))), final[2]))
    if args.plot:
        plot(sdf, best, results, args.plot)


def plot(sdf, best, results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    loss, k, start, final, history, phi, n = best
    centres, _ = points((final[0], rotation(final[1]), final[2]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8))
    # The object's section through the plane of the three points (palm and tips).
    origin = centres.mean(axis=0)
    e1 = centres[1] - centres[2]
    e1 /= np.linalg.norm(e1)
    e2 = centres[0] - origin
    e2 -= (e2 @ e1) * e1
    e2 /= np.linalg.norm(e2)
    s = np.linspace(-0.2, 0.2, 241)
    uu, vv = np.meshgrid(s, s)
    grid = origin + uu[..., None] * e1 + vv[..., None] * e2
    values = sdf.sample(grid.reshape(-1, 3))[0].reshape(uu.shape)
    ax = axes[0]
    ax.contourf(uu, vv, values, levels=[-1, 0], colors=["#bbbbbb"])
    ax.contour(uu, vv, values, levels=[0], colors="k", linewidths=1)
    for i, (centre, radius) in enumerate(zip(centres, (PALM, TIP, TIP))):
        c = centre - origin
        ax.add_patch(plt.Circle((c @ e1, c @ e2), radius, color="C1" if i == 0 else "C0"))
    ax.set_aspect("equal")
    ax.set_title("best placement: section through palm (orange) and tips (blue)")
    ax.set_xlabel("along the opening [m]")
    ax.set_ylabel("towards the palm [m]")
    ax = axes[1]
    for result in results:
        ax.semilogy(np.maximum(result[4], 1e-20), color="C0" if result is best else "0.7",
                    linewidth=2 if result is best else 1)
    ax.set_xlabel("iteration")
    ax.set_ylabel("loss (floored at 1e-20)")
    ax.set_title("loss of the %d starts (best in blue)" % len(results))
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print("figure:", path)


if __name__ == "__main__":
    main()
