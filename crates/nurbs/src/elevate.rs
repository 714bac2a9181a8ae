//! Degree elevation (A5.9) for curves and surfaces.
