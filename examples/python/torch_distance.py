"""tumble.distance as a PyTorch function: the signed distance of two shapes, differentiable with
respect to both poses (positions and turns) through the gradients tumble computes (not through
PyTorch's own arithmetic), checked by torch.autograd.gradcheck on convex shapes and fields and
then used to push two overlapping boxes apart by gradient descent on the contact potential
k/2 d^2.

    PYTHONPATH=build/release/python python3 examples/python/torch_distance.py
"""
import numpy as np
import torch

import tumble


def _rotation(w, base):
    """The quaternion (w, x, y, z) of exp(w) applied to `base`: a turn by the rotation vector w
    about world axes, after base."""
    theta = float(np.linalg.norm(w))
    if theta < 1e-300:
        turn = np.array([1.0, 0.0, 0.0, 0.0])
    else:
        turn = np.concatenate([[np.cos(theta / 2)], np.sin(theta / 2) * np.asarray(w) / theta])
    a, b = turn, np.asarray(base, dtype=float)
    return [a[0] * b[0] - a[1:] @ b[1:], *(a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:]))]


def _left_jacobian(w):
    """J with exp(w + e) = exp(J e) exp(w) to first order (the left Jacobian of SO(3)): a change
    e of the rotation vector turns the body by J e about world axes."""
    theta = float(np.linalg.norm(w))
    cross = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    if theta < 1e-8:
        return np.eye(3) + 0.5 * cross
    return (np.eye(3) + (1 - np.cos(theta)) / theta**2 * cross +
            (theta - np.sin(theta)) / theta**3 * cross @ cross)


class SignedDistance(torch.autograd.Function):
    """d(pose_a, pose_b) for fixed shapes, each pose 6 numbers: the position, then a rotation
    vector w turning the body from its base orientation (w, x, y, z) by exp(w) about world axes.
    tumble's rotation gradients are about world axes at the current orientation; the chain rule
    through exp takes them to w by the transposed left Jacobian."""

    @staticmethod
    def forward(ctx, pose_a, pose_b, shape_a, shape_b, base_a, base_b):
        values_a = pose_a.detach().numpy()
        values_b = pose_b.detach().numpy()
        d = tumble.distance(shape_a, [*values_a[:3], *_rotation(values_a[3:], base_a)],
                            shape_b, [*values_b[:3], *_rotation(values_b[3:], base_b)])
        gradients = []
        for values, gradient in ((values_a, d["gradient_a"]), (values_b, d["gradient_b"])):
            turn = _left_jacobian(values[3:]).T @ gradient[3:]
            gradients.append(torch.as_tensor(np.concatenate([gradient[:3], turn]),
                                             dtype=pose_a.dtype))
        ctx.save_for_backward(*gradients)
        return pose_a.new_tensor(d["distance"])

    @staticmethod
    def backward(ctx, grad_output):
        gradient_a, gradient_b = ctx.saved_tensors
        return grad_output * gradient_a, grad_output * gradient_b, None, None, None, None


def signed_distance(pose_a, pose_b, shape_a, shape_b, base_a=(1, 0, 0, 0), base_b=(1, 0, 0, 0)):
    return SignedDistance.apply(pose_a, pose_b, shape_a, shape_b, list(base_a), list(base_b))


def _random_pose(rng, spread):
    return torch.tensor(np.concatenate([rng.uniform(-spread, spread, size=3),
                                        rng.uniform(-1, 1, size=3)]),
                        dtype=torch.float64, requires_grad=True)


def check_gradients(trials=21, seed=0):
    """gradcheck of all 12 pose numbers on random placements, apart and overlapping, of a box and
    a hull, of a ball and a torus given as a field, and of two tori given as fields."""
    rng = np.random.default_rng(seed)
    box = {"type": "box", "half_extents": [0.5, 0.3, 0.2]}
    torus = {"type": "sdf", "sdf": {"torus": {"major_radius": 0.6, "minor_radius": 0.2}}}
    ring = {"type": "sdf", "sdf": {"torus": {"major_radius": 0.4, "minor_radius": 0.1}}}
    ball = {"type": "sphere", "radius": 0.15}
    for trial in range(trials):
        hull = {"type": "hull", "points": rng.uniform(-0.4, 0.4, size=(10, 3)).tolist()}
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        pair = [(box, hull), (ball, torus), (ring, torus)][trial % 3]
        a = _random_pose(rng, 0.2)
        b = _random_pose(rng, 1.0)
        # The field pairs' descents stop within about 1e-11 m of their least value: differences
        # of 1e-5 (docs/sdf.md, "Gradients").
        eps, atol = (1e-6, 1e-5) if trial % 3 == 0 else (1e-5, 1e-4)
        ok = torch.autograd.gradcheck(
            lambda x, y: signed_distance(x, y, pair[0], pair[1], base_a=q), (a, b), eps=eps,
            atol=atol)
        if not ok:
            return False
    return True


def separate(steps=200, stiffness=50.0, rate=0.05):
    """Two overlapping boxes pushed apart by descending the contact potential; returns the
    distances before and after."""
    box = {"type": "box", "half_extents": [0.5, 0.5, 0.5]}
    a = torch.tensor([0.0] * 6, dtype=torch.float64, requires_grad=True)
    b = torch.tensor([0.6, 0.3, 0.1, 0.0, 0.0, 0.0], dtype=torch.float64, requires_grad=True)
    optimiser = torch.optim.SGD([a, b], lr=rate)
    before = float(signed_distance(a, b, box, box))
    for _ in range(steps):
        optimiser.zero_grad()
        d = signed_distance(a, b, box, box)
        potential = 0.5 * stiffness * torch.clamp(d, max=0.0) ** 2
        potential.backward()
        optimiser.step()
    return before, float(signed_distance(a, b, box, box))


def main():
    verdict = "passed" if check_gradients() else "FAILED"
    print(f"gradcheck of positions and turns on 21 random placements (box-hull, ball-torus field, "
          f"torus field-torus field): {verdict}")
    before, after = separate()
    print(f"two boxes overlapping by {-before:.3f} m pushed apart: distance now {after:+.2e} m")


if __name__ == "__main__":
    main()
