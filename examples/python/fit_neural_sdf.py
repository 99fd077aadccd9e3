"""Fits a neural signed distance field to a shape with PyTorch and writes it in tumble's weights
format (docs/sdf.md, "Neural SDFs"), which tumble.NeuralSdf and `{neural: {file: ...}}` read.

    PYTHONPATH=build/release/python python3 examples/python/fit_neural_sdf.py \
        --shape torus --out torus_sdf.json
    PYTHONPATH=build/release/python python3 examples/python/fit_neural_sdf.py \
        --mesh scenes/sdf/meshes/bowl_closed.obj --cell 0.02 --out bowl_sdf.json

The target is the SDF of the shape, evaluated by tumble.Sdf: exact for the analytic shapes, and
for a closed OBJ mesh (--mesh) a grid SDF of it (`{grid: {file, cell}}`, exact within three cells
of the surface, docs/sdf.md "Grids"): points are drawn uniformly in
the shape's bounds grown by a margin and, half of them, near the surface (where contacts are
decided, so where the fit must be best). The loss is the squared error plus an Eikonal term
(|grad phi| - 1)^2 (Gropp et al., "Implicit geometric regularization", ICML 2020). Prints the
mean and largest error on held-out points near the surface.
"""
import argparse
import json
import math

import numpy as np
import torch

import tumble

SHAPES = {
    "torus": {"torus": {"major_radius": 0.6, "minor_radius": 0.2}},
    "bowl": {"difference": [{"box": {"half_extents": [0.6, 0.6, 0.3]}},
                            {"sphere": {"radius": 0.5}, "position": [0, 0, 0.35]}]},
}


class Network(torch.nn.Module):
    def __init__(self, frequencies, width, depth, beta):
        super().__init__()
        self.frequencies = frequencies
        self.beta = beta
        sizes = [3 + 6 * frequencies] + [width] * depth + [1]
        self.layers = torch.nn.ModuleList(
            torch.nn.Linear(a, b, dtype=torch.float64) for a, b in zip(sizes[:-1], sizes[1:]))

    def encode(self, x):
        # Per band k and coordinate c: sin then cos of 2^k pi x_c, after the coordinates: the
        # order tumble's NeuralSdf reads.
        parts = [x]
        for k in range(self.frequencies):
            w = (2.0 ** k) * math.pi
            both = torch.stack([torch.sin(w * x), torch.cos(w * x)], dim=-1)  # [N, 3, 2]
            parts.append(both.reshape(x.shape[0], 6))
        return torch.cat(parts, dim=1)

    def forward(self, x):
        h = self.encode(x)
        for layer in self.layers[:-1]:
            h = torch.nn.functional.softplus(layer(h), beta=self.beta)
        return self.layers[-1](h).squeeze(-1)


def samples(sdf, low, high, count, rng):
    uniform = rng.uniform(low, high, size=(count // 2, 3))
    near = rng.uniform(low, high, size=(count - count // 2, 3))
    phi, grad = sdf.sample(near)
    near = near - phi[:, None] * grad + rng.normal(0, 0.02, size=(near.shape[0], 1)) * grad
    points = np.vstack([uniform, near])
    return points, sdf.sample(points)[0]


def export(net, offset, scale, low, high):
    layers = []
    for i, layer in enumerate(net.layers):
        last = i == len(net.layers) - 1
        layers.append({
            "weights": layer.weight.detach().numpy().tolist(),
            "bias": layer.bias.detach().numpy().tolist(),
            "activation": "none" if last else "softplus",
            **({} if last else {"beta": net.beta}),
        })
    return {"format": "tumble-neural-sdf", "version": 1, "frequencies": net.frequencies,
            "offset": list(offset), "scale": scale,
            "bounds": {"min": list(low), "max": list(high)}, "layers": layers}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--shape", choices=sorted(SHAPES), default="torus")
    parser.add_argument("--mesh", help="fit a closed OBJ mesh instead of --shape")
    parser.add_argument("--cell", type=float, default=0.02,
                        help="the grid's cell for --mesh [m] (default 0.02)")
    parser.add_argument("--out", required=True)
    parser.add_argument("--width", type=int, default=32)
    parser.add_argument("--depth", type=int, default=3)
    parser.add_argument("--frequencies", type=int, default=2)
    parser.add_argument("--iterations", type=int, default=1500)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    torch.manual_seed(args.seed)
    rng = np.random.default_rng(args.seed)
    if args.mesh:
        import os

        sdf = tumble.Sdf({"grid": {"file": os.path.abspath(args.mesh), "cell": args.cell}})
        name = os.path.basename(args.mesh)
    else:
        sdf = tumble.Sdf(SHAPES[args.shape])
        name = args.shape
    low = np.asarray(sdf.bounds[0]) - 0.2
    high = np.asarray(sdf.bounds[1]) + 0.2
    offset = (low + high) / 2
    scale = float(np.max(high - low) / 2)
    net = Network(args.frequencies, args.width, args.depth, beta=20.0)
    optimiser = torch.optim.Adam(net.parameters(), lr=3e-3)
    for it in range(args.iterations):
        points, target = samples(sdf, low, high, 2048, rng)
        x = torch.tensor((points - offset) / scale, requires_grad=True)
        y = torch.tensor(target / scale)
        phi = net(x)
        (grad,) = torch.autograd.grad(phi.sum(), x, create_graph=True)
        loss = torch.mean((phi - y) ** 2) + 0.01 * torch.mean((grad.norm(dim=1) - 1) ** 2)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
    points, target = samples(sdf, low, high, 4000, np.random.default_rng(args.seed + 1))
    near = np.abs(target) < 0.05
    with torch.no_grad():
        fitted = net(torch.tensor((points - offset) / scale)).numpy() * scale
    error = np.abs(fitted - target)[near]
    with open(args.out, "w") as f:
        json.dump(export(net, offset, scale, low, high), f)
    print(f"{name}: {sum(p.numel() for p in net.parameters())} weights; error near the "
          f"surface mean {error.mean():.4f} m, largest {error.max():.4f} m; wrote {args.out}")


if __name__ == "__main__":
    main()
