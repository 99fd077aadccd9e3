"""tumble.Sdf and tumble.distance from Python: values against closed forms, gradients against
central differences, and bad input refused with the library's errors."""
import math

import numpy as np
import pytest

import tumble


def test_a_torus_field_is_the_closed_form_with_its_gradient():
    sdf = tumble.Sdf({"torus": {"major_radius": 1.0, "minor_radius": 0.25}})
    assert sdf.exact
    rng = np.random.default_rng(1)
    points = rng.uniform(-2, 2, size=(2000, 3))
    phi, grad = sdf.sample(points)
    rho = np.hypot(points[:, 0], points[:, 1])
    expected = np.hypot(rho - 1.0, points[:, 2]) - 0.25
    np.testing.assert_allclose(phi, expected, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(grad, axis=1), 1.0, atol=1e-12)
    h = 1e-6
    for k in range(3):
        step = np.zeros(3)
        step[k] = h
        fd = (sdf.sample(points + step)[0] - sdf.sample(points - step)[0]) / (2 * h)
        np.testing.assert_allclose(grad[:, k], fd, atol=1e-6)
    one_phi, one_grad = sdf.sample([1.0, 0.0, 0.0])
    assert one_phi == pytest.approx(-0.25) and one_grad.shape == (3,)
    low, high = sdf.bounds
    np.testing.assert_allclose(high, [1.25, 1.25, 0.25])


def test_csg_from_yaml_text_and_its_errors():
    bowl = tumble.Sdf("difference: [{box: {half_extents: [1, 1, 0.5]}},"
                      " {sphere: {radius: 0.9}, position: [0, 0, 0.6]}]")
    assert not bowl.exact
    assert bowl.sample([0, 0, 0.3])[0] > 0  # the hollow
    assert bowl.sample([0, 0, -0.4])[0] < 0  # the bottom
    with pytest.raises(tumble.SceneError, match="sdf.sphere.radius"):
        tumble.Sdf({"sphere": {"radius": -1}})
    with pytest.raises(TypeError):
        tumble.Sdf(3)
    with pytest.raises(ValueError, match="points"):
        bowl.sample(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="finite"):
        bowl.sample([math.nan, 0, 0])


def test_distance_of_two_spheres_is_the_closed_form():
    d = tumble.distance({"type": "sphere", "radius": 0.5}, [0, 0, 0],
                        {"type": "sphere", "radius": 0.25}, [1, 2, 2])
    assert d["distance"] == pytest.approx(3 - 0.75, abs=1e-12)
    np.testing.assert_allclose(d["gradient_b"][:3], [1 / 3, 2 / 3, 2 / 3], atol=1e-12)
    np.testing.assert_allclose(d["normal"], [-1 / 3, -2 / 3, -2 / 3], atol=1e-12)
    assert d["converged"]


def test_distance_gradients_match_central_differences():
    rng = np.random.default_rng(2)
    box = {"type": "box", "half_extents": [0.5, 0.3, 0.2]}
    hull = {"type": "hull", "points": rng.uniform(-0.5, 0.5, size=(12, 3)).tolist()}
    h = 1e-6
    for _ in range(50):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        pose_a = [0.0, 0.0, 0.0, *q]
        pose_b = rng.uniform(-1, 1, size=3).tolist()
        d = tumble.distance(box, pose_a, hull, pose_b)
        for k in range(3):
            plus = list(pose_b)
            minus = list(pose_b)
            plus[k] += h
            minus[k] -= h
            fd = (tumble.distance(box, pose_a, hull, plus)["distance"] -
                  tumble.distance(box, pose_a, hull, minus)["distance"]) / (2 * h)
            assert d["gradient_b"][k] == pytest.approx(fd, abs=1e-5)


def test_distance_refuses_what_it_cannot_answer():
    sphere = {"type": "sphere", "radius": 1}
    with pytest.raises(tumble.Error, match="only convex"):
        tumble.distance({"type": "compound", "parts": [{"shape": sphere}, {"shape": sphere,
                         "position": [1, 0, 0]}]}, [0, 0, 0], sphere, [0, 0, 3])
    with pytest.raises(ValueError, match="pose_b"):
        tumble.distance(sphere, [0, 0, 0], sphere, [0, 0])
    with pytest.raises(ValueError, match="unit quaternion"):
        tumble.distance(sphere, [0, 0, 0, 2, 0, 0, 0], sphere, [0, 0, 3])
    with pytest.raises(ValueError, match="pose_a: every number must be finite"):
        tumble.distance(sphere, [0, float("nan"), 0], sphere, [0, 0, 3])
    for wrong in ("0 0 0", None, [0, "a", 0], {"x": 0}):
        with pytest.raises(TypeError, match="pose_a: expected a sequence of 3 or 7 numbers"):
            tumble.distance(sphere, wrong, sphere, [0, 0, 3])
    with pytest.raises(tumble.SceneError, match="shape_a"):
        tumble.distance({"type": "sphere", "radius": -1}, [0, 0, 0], sphere, [0, 0, 3])


def test_an_sdf_body_rests_on_its_tube_in_a_world():
    # type: sdf in a scene given as text: a torus (ring 0.4 m, tube 0.1 m) dropped onto the floor
    # settles with its centre a tube's radius up.
    scene = tumble.load_scene_text(
        """
world: {dt: 0.016666666666666666}
bodies:
  - {name: floor, shape: {type: plane}, static: true}
  - name: ring
    shape: {type: sdf, sdf: {torus: {major_radius: 0.4, minor_radius: 0.1}}}
    density: 500
    position: [0, 0, 0.12]
""",
        "torus.yaml",
    )
    world = tumble.World(scene)
    ring = world.body("ring")
    world.step(120)
    state = world.body_state(ring)
    assert abs(state[2] - 0.1) < 1e-3
    assert np.linalg.norm(state[7:10]) < 1e-3
    with pytest.raises(tumble.SceneError, match="bounded solid"):
        tumble.load_scene_text(
            "bodies:\n  - {name: g, mass: 1, shape: {type: sdf, sdf: {plane: {}}}}\n", "half.yaml"
        )


def test_distance_of_a_sphere_to_a_field_has_its_gradient():
    # A ball 0.35 m above the torus's tube centre circle: 0.35 - 0.2 - 0.1 = 0.05 m apart, the
    # normal straight up, and moving the ball along the normal changes the distance one for one.
    torus = {"type": "sdf", "sdf": {"torus": {"major_radius": 0.6, "minor_radius": 0.2}}}
    ball = {"type": "sphere", "radius": 0.1}
    d = tumble.distance(ball, [0.6, 0, 0.35], torus, [0, 0, 0])
    assert d["distance"] == pytest.approx(0.05, abs=1e-12)
    np.testing.assert_allclose(d["normal"], [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(d["gradient_a"], [0, 0, 1, 0, 0, 0], atol=1e-12)
    # A box of half extent 0.1 at the same place: its bottom face 0.05 m above the tube's top.
    box = tumble.distance({"type": "box", "half_extents": [0.1, 0.1, 0.1]}, [0.6, 0, 0.35], torus,
                          [0, 0, 0])
    assert box["distance"] == pytest.approx(0.05, abs=1e-9)
    np.testing.assert_allclose(box["gradient_a"][:3], [0, 0, 1], atol=1e-6)
    # The floor's half-space below z = -0.5: the tube's bottom is 0.3 m above it, and raising
    # the floor closes the gap one for one.
    floor = tumble.distance({"type": "plane"}, [0, 0, -0.5], torus, [0, 0, 0])
    assert floor["distance"] == pytest.approx(0.3, abs=1e-9)
    np.testing.assert_allclose(floor["normal"], [0, 0, -1], atol=1e-9)
    np.testing.assert_allclose(floor["gradient_a"][:3], [0, 0, -1], atol=1e-9)


def test_distance_of_two_fields_is_their_gap():
    # Two balls given as fields, 0.3 and 0.5 m, centres 1 m apart along (0, 0.6, 0.8): 0.2 m.
    ball = {"type": "sdf", "sdf": {"sphere": {"radius": 0.3}}}
    big = {"type": "sdf", "sdf": {"sphere": {"radius": 0.5}}}
    d = tumble.distance(ball, [0, 0.6, 0.8], big, [0, 0, 0])
    assert d["distance"] == pytest.approx(0.2, abs=1e-9)
    np.testing.assert_allclose(d["normal"], [0, 0.6, 0.8], atol=1e-6)
    np.testing.assert_allclose(d["gradient_a"], [0, 0.6, 0.8, 0, 0, 0], atol=1e-6)
    np.testing.assert_allclose(d["gradient_b"], [0, -0.6, -0.8, 0, 0, 0], atol=1e-6)


def test_contact_potential_is_the_clipped_spring_of_the_depth():
    ball = {"type": "sphere", "radius": 0.5}
    apart = tumble.distance(ball, [0, 0, 0], ball, [0, 0, 1.5])
    assert tumble.contact_potential(apart, 100.0, 1.0)["value"] == 0
    d = tumble.distance(ball, [0, 0, 0], ball, [0, 0, 0.9])  # 0.1 m deep
    p = tumble.contact_potential(d, 100.0, 1e6)
    assert p["value"] == pytest.approx(100 / 2 * 0.01, rel=1e-12)
    np.testing.assert_allclose(p["gradient_a"], 100 * d["distance"] * d["gradient_a"], rtol=1e-12)
    # k d dd/dz_a = 100 * -0.1 * -1 = 10: clipped to 2.
    clipped = tumble.contact_potential(d, 100.0, 2.0)
    assert clipped["gradient_a"][2] == pytest.approx(2.0)
    assert clipped["gradient_b"][2] == pytest.approx(-2.0)
    with pytest.raises(ValueError, match="max_gradient"):
        tumble.contact_potential(d, 100.0, 0.0)
    with pytest.raises(ValueError, match="gradient_a"):
        tumble.contact_potential({"distance": -0.1, "gradient_a": [0, 0, 1],
                                  "gradient_b": [0] * 6}, 1.0, 1.0)
    with pytest.raises(ValueError, match="no 'distance'"):
        tumble.contact_potential({}, 1.0, 1.0)
    with pytest.raises(ValueError, match="distance must be a number"):
        tumble.contact_potential({"distance": "deep", "gradient_a": [0] * 6,
                                  "gradient_b": [0] * 6}, 1.0, 1.0)
    with pytest.raises(ValueError, match="gradient_b must be 6 numbers"):
        tumble.contact_potential({"distance": -0.1, "gradient_a": [0] * 6,
                                  "gradient_b": ["x"] * 6}, 1.0, 1.0)


def _turned(pose, axis, angle):
    """pose (7 numbers) turned by `angle` about world axis `axis` about its position."""
    half = angle / 2
    a = np.zeros(4)
    a[0] = math.cos(half)
    a[1 + axis] = math.sin(half)
    b = np.asarray(pose[3:])
    q = [a[0] * b[0] - a[1:] @ b[1:], *(a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:]))]
    return [*pose[:3], *q]


def test_rotation_gradients_turn_about_the_pose_position():
    # A hull written 1.5 m from its frame's origin: the library turns bodies about their centre
    # of mass, tumble.distance about the pose given, and its rotation gradients must be those.
    rng = np.random.default_rng(3)
    hull = {"type": "hull", "points": (rng.uniform(-0.3, 0.3, size=(12, 3)) + 1.5).tolist()}
    box = {"type": "box", "half_extents": [0.4, 0.3, 0.2]}
    h = 1e-6
    checked = 0
    for _ in range(30):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        pose_b = [*rng.uniform(-1, 1, size=3), *q]
        pose_a = [*rng.uniform(1, 2, size=3), 1, 0, 0, 0]
        d = tumble.distance(box, pose_a, hull, pose_b)
        for k in range(3):
            fd = (tumble.distance(box, pose_a, hull, _turned(pose_b, k, h))["distance"] -
                  tumble.distance(box, pose_a, hull, _turned(pose_b, k, -h))["distance"]) / (2 * h)
            assert d["gradient_b"][3 + k] == pytest.approx(fd, abs=1e-5)
            checked += 1
    assert checked == 90
