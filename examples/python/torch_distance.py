"""tumble.distance as a PyTorch function: the signed distance of two shapes, differentiable with
respect to both positions through the gradients tumble computes (not through PyTorch's own
arithmetic), checked by torch.autograd.gradcheck and then used to push two overlapping boxes
apart by gradient descent on the contact potential k/2 d^2.

    PYTHONPATH=build/release/python python3 examples/python/torch_distance.py
"""
import numpy as np
import torch

import tumble


class SignedDistance(torch.autograd.Function):
    """d(position_a, position_b) for fixed shapes and orientations (w, x, y, z)."""

    @staticmethod
    def forward(ctx, position_a, position_b, shape_a, shape_b, orientation_a, orientation_b):
        pose_a = [*position_a.detach().tolist(), *orientation_a]
        pose_b = [*position_b.detach().tolist(), *orientation_b]
        d = tumble.distance(shape_a, pose_a, shape_b, pose_b)
        ctx.save_for_backward(torch.as_tensor(d["gradient_a"][:3], dtype=position_a.dtype),
                              torch.as_tensor(d["gradient_b"][:3], dtype=position_b.dtype))
        return position_a.new_tensor(d["distance"])

    @staticmethod
    def backward(ctx, grad_output):
        gradient_a, gradient_b = ctx.saved_tensors
        return grad_output * gradient_a, grad_output * gradient_b, None, None, None, None


def signed_distance(position_a, position_b, shape_a, shape_b, orientation_a=(1, 0, 0, 0),
                    orientation_b=(1, 0, 0, 0)):
    return SignedDistance.apply(position_a, position_b, shape_a, shape_b, list(orientation_a),
                                list(orientation_b))


def check_gradients(trials=20, seed=0):
    """gradcheck on random placements of a box and a hull, apart and overlapping."""
    rng = np.random.default_rng(seed)
    box = {"type": "box", "half_extents": [0.5, 0.3, 0.2]}
    for _ in range(trials):
        hull = {"type": "hull", "points": rng.uniform(-0.4, 0.4, size=(10, 3)).tolist()}
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        a = torch.tensor(rng.uniform(-0.2, 0.2, size=3), dtype=torch.float64, requires_grad=True)
        b = torch.tensor(rng.uniform(-1, 1, size=3), dtype=torch.float64, requires_grad=True)
        ok = torch.autograd.gradcheck(
            lambda x, y: signed_distance(x, y, box, hull, orientation_a=q), (a, b), eps=1e-6,
            atol=1e-5)
        if not ok:
            return False
    return True


def separate(steps=200, stiffness=50.0, rate=0.05):
    """Two overlapping boxes pushed apart by descending the contact potential; returns the
    distances before and after."""
    box = {"type": "box", "half_extents": [0.5, 0.5, 0.5]}
    a = torch.tensor([0.0, 0.0, 0.0], dtype=torch.float64, requires_grad=True)
    b = torch.tensor([0.6, 0.3, 0.1], dtype=torch.float64, requires_grad=True)
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
    print(f"gradcheck on 20 random box-hull placements: {'passed' if check_gradients() else 'FAILED'}")
    before, after = separate()
    print(f"two boxes overlapping by {-before:.3f} m pushed apart: distance now {after:+.2e} m")


if __name__ == "__main__":
    main()
