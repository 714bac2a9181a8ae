//! The planes of a lines plan: stations (`x = c`), waterlines (`z = c`) and buttocks (`y = c`),
//! cut by the kernel's [`cut_surface`](nurbs::cut_surface).
//!
//! A [`CutPlane`] converts into the kernel's [`AxisPlane`] (station = x-plane, buttock =
//! y-plane, waterline = z-plane) and back, so `cut_surface(&surface, CutPlane::Station(x),
//! &options)` and [`cut_surface_many`](nurbs::cut_surface_many) take it as it is. In the
//! kernel's terms, for a hull in hullskin's axes (x forward, y to starboard, z up):
//!
//! - the drawing coordinates ([`AxisPlane::coords`]) are the body plan's `(y, z)` for a
//!   station, the half-breadth plan's `(x, y)` for a waterline and the profile's `(x, z)` for a
//!   buttock, each seen along its view normal (`+x`, `+z`, `-y`), so that a positive
//!   [`CutPoint::curvature`](nurbs::CutPoint::curvature) turns counter-clockwise on the
//!   drawing;
//! - open branches run keel to deck for stations (z increasing from the first to the last
//!   point; on a tie, y increasing), aft to fore for waterlines and buttocks (x increasing; on
//!   a tie, y resp. z increasing); closed loops run counter-clockwise on the drawing;
//! - a plane through a whole grid line of the surface, such as the flat bottom at the
//!   baseline or the centre-plane keel edge, still yields the line along it.

use nurbs::{Axis, AxisPlane};
use serde::Serialize;

/// A plane of the lines plan, normal to one of the hull's axes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum CutPlane {
    /// The station plane `x = c` (body plan).
    Station(f64),
    /// The waterline plane `z = c` (half-breadth plan).
    Waterline(f64),
    /// The buttock plane `y = c` (profile).
    Buttock(f64),
}

impl CutPlane {
    /// The plane's constant `c`.
    pub fn value(&self) -> f64 {
        match *self {
            CutPlane::Station(c) | CutPlane::Waterline(c) | CutPlane::Buttock(c) => c,
        }
    }

    /// `"station"`, `"waterline"` or `"buttock"`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            CutPlane::Station(_) => "station",
            CutPlane::Waterline(_) => "waterline",
            CutPlane::Buttock(_) => "buttock",
        }
    }
}

impl From<CutPlane> for AxisPlane {
    /// Station -> `x = c`, buttock -> `y = c`, waterline -> `z = c`.
    fn from(plane: CutPlane) -> Self {
        match plane {
            CutPlane::Station(c) => AxisPlane::x(c),
            CutPlane::Buttock(c) => AxisPlane::y(c),
            CutPlane::Waterline(c) => AxisPlane::z(c),
        }
    }
}

impl From<AxisPlane> for CutPlane {
    /// `x = c` -> station, `y = c` -> buttock, `z = c` -> waterline.
    fn from(plane: AxisPlane) -> Self {
        match plane.axis {
            Axis::X => CutPlane::Station(plane.value),
            Axis::Y => CutPlane::Buttock(plane.value),
            Axis::Z => CutPlane::Waterline(plane.value),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::Vec3;

    #[test]
    fn lines_plan_planes_are_the_axis_planes_with_the_drawing_views() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        for (plane, axis, view, normal) in [
            (CutPlane::Station(0.5), Axis::X, [2.0, 3.0], Vec3::new(1.0, 0.0, 0.0)),
            (CutPlane::Waterline(0.5), Axis::Z, [1.0, 2.0], Vec3::new(0.0, 0.0, 1.0)),
            (CutPlane::Buttock(0.5), Axis::Y, [1.0, 3.0], Vec3::new(0.0, -1.0, 0.0)),
        ] {
            let kernel = AxisPlane::from(plane);
            assert_eq!(kernel, AxisPlane::new(axis, 0.5));
            assert_eq!(CutPlane::from(kernel), plane);
            // Body plan (y, z), half-breadth plan (x, y), profile (x, z).
            assert_eq!(kernel.coords(p), view, "{plane:?}");
            assert_eq!(kernel.view_normal(), normal, "{plane:?}");
            assert_eq!(plane.value(), 0.5);
        }
        assert_eq!(CutPlane::Buttock(0.0).kind_name(), "buttock");
    }
}
