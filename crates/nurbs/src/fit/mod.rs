//! Fitting: parameterization, knot vectors, interpolation, least squares, skinning.
