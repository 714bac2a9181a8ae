//! Knot insertion (A5.1) and knot refinement (A5.4) for curves and surfaces.
