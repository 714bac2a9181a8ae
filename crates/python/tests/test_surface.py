"""Surface evaluation over arrays: against closed forms (a rational quadratic cylinder),
central differences, the library's projector; shapes and broadcasting."""

import numpy as np
import pytest

import hullskin

R, H = 2.0, 3.0


def cylinder():
    """A quarter cylinder of radius R and height H: a rational quadratic arc (weights 1,
    sqrt(2)/2, 1) along u, a line along v. Exactly S(u, v) on x^2 + y^2 = R^2."""
    w = np.sqrt(0.5)
    arc = [(R, 0.0), (R, R), (0.0, R)]
    cp = np.array([[[x, y, z] for z in (0.0, H)] for (x, y) in arc])
    weights = np.array([[1.0, 1.0], [w, w], [1.0, 1.0]])
    return hullskin.Surface((2, 1), [0, 0, 0, 1, 1, 1], [0, 0, 1, 1], cp, weights)


def test_a_rational_quadratic_is_an_exact_cylinder():
    s = cylinder()
    u, v = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 1, 7), indexing="ij")
    p = s.evaluate(u, v)
    assert p.shape == (41, 7, 3)
    # On the circle to round-off (1e-12 of R: a few ulps of the rational evaluation).
    np.testing.assert_allclose(np.hypot(p[..., 0], p[..., 1]), R, rtol=1e-12)
    np.testing.assert_allclose(p[..., 2], H * v, atol=1e-12)
    c = s.curvature(u, v)
    # A cylinder: K = 0, |H| = 1/(2R), principal curvatures 1/R and 0 (up to sign).
    np.testing.assert_allclose(c["gaussian"], 0.0, atol=1e-10)
    np.testing.assert_allclose(np.abs(c["mean"]), 1 / (2 * R), rtol=1e-9)
    np.testing.assert_allclose(np.maximum(np.abs(c["k1"]), np.abs(c["k2"])), 1 / R, rtol=1e-9)
    n = s.normal(u, v)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, rtol=1e-12)
    # The normal is radial.
    radial = p[..., :2] / R
    np.testing.assert_allclose(np.abs(np.sum(n[..., :2] * radial, axis=-1)), 1.0, rtol=1e-9)


def test_derivatives_equal_central_differences(sample_fit):
    s = sample_fit.surface
    rng = np.random.default_rng(1)
    u, v = rng.uniform(0.05, 0.95, 50), rng.uniform(0.05, 0.95, 50)
    d = s.derivatives(u, v)
    # evaluate uses the kernel's scattered-point evaluator: the same point to rounding (a few
    # ulps of the hull's 122 m: 1e-12 relative).
    np.testing.assert_allclose(d["point"], s.evaluate(u, v), rtol=0, atol=1e-12 * np.abs(d["point"]).max())
    h = 1e-5
    fd_u = (s.evaluate(u + h, v) - s.evaluate(u - h, v)) / (2 * h)
    fd_v = (s.evaluate(u, v + h) - s.evaluate(u, v - h)) / (2 * h)
    # Central differences err by O(h^2 |S'''|) plus round-off O(eps |S| / h) ~ 1e-9 here
    # (|S| ~ 100 m): 1e-5 relative to the derivative's size covers both, away from the
    # knots where S''' jumps (a jump costs O(h |S'''|), still within it).
    scale_u = np.abs(d["su"]).max()
    scale_v = np.abs(d["sv"]).max()
    np.testing.assert_allclose(d["su"], fd_u, atol=1e-5 * scale_u)
    np.testing.assert_allclose(d["sv"], fd_v, atol=1e-5 * scale_v)
    fd_uv = (s.derivatives(u, v + h)["su"] - s.derivatives(u, v - h)["su"]) / (2 * h)
    np.testing.assert_allclose(d["suv"], fd_uv, atol=1e-4 * np.abs(d["suv"]).max())


def test_shapes_and_broadcasting(sample_fit):
    s = sample_fit.surface
    assert s.evaluate(0.3, 0.4).shape == (3,)
    assert s.evaluate(0.3, [0.1, 0.2, 0.3]).shape == (3, 3)
    assert s.evaluate(np.zeros((2, 5)), 0.5).shape == (2, 5, 3)
    assert s.curvature([0.1, 0.2], [0.3, 0.4])["gaussian"].shape == (2,)
    # Integers and lists are numbers too.
    np.testing.assert_array_equal(s.evaluate(0, 1), s.evaluate(0.0, 1.0))


def test_closest_points_find_points_of_the_surface(sample_fit):
    s = sample_fit.surface
    u, v = np.linspace(0.1, 0.9, 20), np.linspace(0.2, 0.8, 20)
    p = s.evaluate(u, v)
    r = s.closest_points(p)
    # Points on the surface: distance within the projector's tolerance (1e-9 of the model
    # size, ~1e-7 m on a 122 m hull), parameters back.
    assert r["distance"].max() < 1e-6
    assert r["converged"].all()
    np.testing.assert_allclose(r["points"], p, atol=1e-6)
    # The measured errors of the fit are these distances: the worst offset's.
    worst = sample_fit.error["worst"]
    d = s.closest_points(np.array([worst["point"]]))["distance"][0]
    assert d == worst["distance"]


def test_surface_properties_read_back_into_a_surface(sample_fit):
    s = sample_fit.surface
    t = hullskin.Surface(s.degree, s.knots_u, s.knots_v, s.control_points, s.weights, units=s.units)
    assert t == s
