//! Planes normal to a coordinate axis, with the 2-D drawing coordinates of a point in them.

use std::ops::Index;

use crate::Vec3;

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// The coordinate's index in a point: 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// The unit vector along the axis.
    pub fn unit(self) -> Vec3 {
        match self {
            Axis::X => Vec3::new(1.0, 0.0, 0.0),
            Axis::Y => Vec3::new(0.0, 1.0, 0.0),
            Axis::Z => Vec3::new(0.0, 0.0, 1.0),
        }
    }
}

/// A point's coordinate along an axis: `p[Axis::Y] == p.y`.
impl Index<Axis> for Vec3 {
    type Output = f64;
    fn index(&self, axis: Axis) -> &f64 {
        match axis {
            Axis::X => &self.x,
            Axis::Y => &self.y,
            Axis::Z => &self.z,
        }
    }
}

/// The plane `p[axis] = value` normal to a coordinate axis.
///
/// Its 2-D drawing coordinates ([`AxisPlane::coords`]) are the two other coordinates, `(y, z)`
/// for an x-plane, `(x, z)` for a y-plane and `(x, y)` for a z-plane; they are right-handed
/// about [`AxisPlane::view_normal`] (`+x`, `-y`, `+z`), so that counter-clockwise in the
/// drawing is counter-clockwise about that normal.
///
/// ```
/// use nurbs::{Axis, AxisPlane, Vec3};
///
/// let plane = AxisPlane::y(2.0);
/// assert_eq!(plane, AxisPlane::new(Axis::Y, 2.0));
/// let p = Vec3::new(1.0, 5.0, 3.0);
/// assert_eq!(plane.signed_distance(p), 3.0);
/// assert_eq!(plane.coords(p), [1.0, 3.0]);
/// // e_x x e_z = -e_y: the drawing (x, z) is seen from -y.
/// assert_eq!(Vec3::new(1.0, 0.0, 0.0).cross(Vec3::new(0.0, 0.0, 1.0)), plane.view_normal());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPlane {
    pub axis: Axis,
    pub value: f64,
}

impl AxisPlane {
    /// The plane `p[axis] = value`.
    pub fn new(axis: Axis, value: f64) -> Self {
        AxisPlane { axis, value }
    }

    /// The plane `x = value`.
    pub fn x(value: f64) -> Self {
        AxisPlane::new(Axis::X, value)
    }

    /// The plane `y = value`.
    pub fn y(value: f64) -> Self {
        AxisPlane::new(Axis::Y, value)
    }

    /// The plane `z = value`.
    pub fn z(value: f64) -> Self {
        AxisPlane::new(Axis::Z, value)
    }

    /// The unit normal along the plane's axis: `+x`, `+y` or `+z`.
    pub fn normal(&self) -> Vec3 {
        self.axis.unit()
    }

    /// Signed distance of `p` from the plane, along [`AxisPlane::normal`]: `n . p - value`.
    pub fn signed_distance(&self, p: Vec3) -> f64 {
        self.normal().dot(p) - self.value
    }

    /// The distance of `p` from the plane, `|p[axis] - value|`.
    pub fn distance(&self, p: Vec3) -> f64 {
        self.signed_distance(p).abs()
    }

    /// 2-D coordinates of a point in the plane's drawing: `(y, z)` for an x-plane, `(x, z)` for
    /// a y-plane, `(x, y)` for a z-plane.
    pub fn coords(&self, p: Vec3) -> [f64; 2] {
        match self.axis {
            Axis::X => [p.y, p.z],
            Axis::Y => [p.x, p.z],
            Axis::Z => [p.x, p.y],
        }
    }

    /// `e_a x e_b` of the drawing coordinates `(a, b)` of [`AxisPlane::coords`]: `+x`, `-y` or
    /// `+z`. Counter-clockwise in the drawing is counter-clockwise about this normal.
    pub fn view_normal(&self) -> Vec3 {
        match self.axis {
            Axis::X => Vec3::new(1.0, 0.0, 0.0),
            Axis::Y => Vec3::new(0.0, -1.0, 0.0),
            Axis::Z => Vec3::new(0.0, 0.0, 1.0),
        }
    }

    /// The coordinates along which an open cut branch runs ([`cut_surface`](crate::cut_surface)):
    /// increasing in the first, on a tie in the second. `z` then `y` for an x-plane (the second
    /// drawing coordinate first), `x` then the other for a y- or z-plane (the first drawing
    /// coordinate first).
    pub(crate) fn run_axes(&self) -> (Axis, Axis) {
        match self.axis {
            Axis::X => (Axis::Z, Axis::Y),
            Axis::Y => (Axis::X, Axis::Z),
            Axis::Z => (Axis::X, Axis::Y),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coords_and_view_normals_are_right_handed() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(AxisPlane::x(0.0).coords(p), [2.0, 3.0]);
        assert_eq!(AxisPlane::z(0.0).coords(p), [1.0, 2.0]);
        assert_eq!(AxisPlane::y(0.0).coords(p), [1.0, 3.0]);
        for plane in [AxisPlane::x(0.5), AxisPlane::z(0.5), AxisPlane::y(0.5)] {
            // e_a x e_b from unit vectors mapped to (1, 0) and (0, 1) in the view.
            let basis = [Axis::X, Axis::Y, Axis::Z].map(Axis::unit);
            let ea = basis.iter().copied().find(|&e| plane.coords(e) == [1.0, 0.0]).expect("a axis");
            let eb = basis.iter().copied().find(|&e| plane.coords(e) == [0.0, 1.0]).expect("b axis");
            assert_eq!(ea.cross(eb), plane.view_normal(), "{plane:?}");
            assert_eq!(plane.signed_distance(Vec3::new(0.5, 0.5, 0.5)), 0.0);
            assert_eq!(plane.value, 0.5);
            assert_eq!(plane.normal()[plane.axis], 1.0);
        }
    }
}
