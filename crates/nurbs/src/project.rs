//! Closest-point projection onto curves and surfaces (The NURBS Book 6.1).
