//! Drawing sheets: the ISO 216 A sizes and the elongated sizes of ISO 5457, landscape.
//!
//! A ship's lines plan is long and low (the profile and the half-breadth plan of a hull 7 to
//! 10 times longer than it is broad), so on an A sheet most of the paper stays empty at any
//! scale. ISO 5457 gives elongated sheets for such drawings: `An x m` is the long side of `An`
//! high and `m` times its short side wide (rounded to the millimetre): `A3x4` is
//! 420 x 1189 mm, `A4x9` 297 x 1892 mm.

use std::fmt;

/// A sheet of paper, landscape (`width_mm >= height_mm`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheet {
    /// The ISO name (`A3`, `A3x4`), or `custom` for a size given in millimetres.
    pub name: &'static str,
    pub width_mm: f64,
    pub height_mm: f64,
}

impl Sheet {
    /// A3 landscape, 420 x 297 mm.
    pub const A3: Sheet = Sheet { name: "A3", width_mm: 420.0, height_mm: 297.0 };

    /// The standard sheets, smallest area first: A4 to A0 (ISO 216) and the special and
    /// exceptional elongated sizes of ISO 5457 (A3x3 to A0x3), all landscape.
    pub fn standard() -> &'static [Sheet] {
        const fn s(name: &'static str, height_mm: f64, width_mm: f64) -> Sheet {
            Sheet { name, width_mm, height_mm }
        }
        const SHEETS: [Sheet; 24] = [
            s("A4", 210.0, 297.0),
            s("A3", 297.0, 420.0),
            s("A4x3", 297.0, 630.0),
            s("A2", 420.0, 594.0),
            s("A4x4", 297.0, 841.0),
            s("A4x5", 297.0, 1051.0),
            s("A3x3", 420.0, 891.0),
            s("A4x6", 297.0, 1261.0),
            s("A4x7", 297.0, 1471.0),
            s("A3x4", 420.0, 1189.0),
            s("A1", 594.0, 841.0),
            s("A4x8", 297.0, 1682.0),
            s("A4x9", 297.0, 1892.0),
            s("A3x5", 420.0, 1486.0),
            s("A3x6", 420.0, 1783.0),
            s("A2x3", 594.0, 1261.0),
            s("A3x7", 420.0, 2080.0),
            s("A2x4", 594.0, 1682.0),
            s("A0", 841.0, 1189.0),
            s("A2x5", 594.0, 2102.0),
            s("A1x3", 841.0, 1783.0),
            s("A1x4", 841.0, 2378.0),
            s("A0x2", 1189.0, 1682.0),
            s("A0x3", 1189.0, 2523.0),
        ];
        &SHEETS
    }

    /// The standard sheet of this name (`a3`, `A3x4`, `A3×4`; case and the multiplication
    /// sign do not matter).
    pub fn named(name: &str) -> Option<Sheet> {
        let key = name.trim().replace('×', "x").to_ascii_uppercase().replace('X', "x");
        Sheet::standard().iter().copied().find(|s| s.name == key)
    }

    /// A sheet of the given size in millimetres, named after the standard sheet of that size
    /// (either orientation, within 0.5 mm), else `custom`; turned landscape.
    pub fn of_size(width_mm: f64, height_mm: f64) -> Sheet {
        let (w, h) = if width_mm >= height_mm { (width_mm, height_mm) } else { (height_mm, width_mm) };
        let name = Sheet::standard()
            .iter()
            .find(|s| (s.width_mm - w).abs() <= 0.5 && (s.height_mm - h).abs() <= 0.5)
            .map_or("custom", |s| s.name);
        Sheet { name, width_mm: w, height_mm: h }
    }

    /// Area in square millimetres.
    pub fn area_mm2(&self) -> f64 {
        self.width_mm * self.height_mm
    }
}

impl fmt::Display for Sheet {
    /// `A3 (420 x 297 mm)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({} x {} mm)", self.name, self.width_mm, self.height_mm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sheets_are_iso_sizes_ordered_by_area() {
        let all = Sheet::standard();
        for w in all.windows(2) {
            assert!(w[0].area_mm2() <= w[1].area_mm2(), "{} before {}", w[0], w[1]);
        }
        for s in all {
            assert!(s.width_mm >= s.height_mm, "{s} is landscape");
        }
        // An elongated size An x m: the long side of An by m times its short side (ISO 5457
        // rounds to the millimetre).
        for s in all.iter().filter(|s| s.name.contains('x')) {
            let (base, m) = s.name.split_once('x').expect("An x m");
            let a = Sheet::named(base).expect("base size");
            let m: f64 = m.parse().expect("a multiple");
            assert_eq!(s.height_mm, a.width_mm, "{s}");
            assert!((s.width_mm - m * a.height_mm).abs() <= 2.0, "{s}: {m} x {}", a.height_mm);
        }
    }

    #[test]
    fn names_and_sizes() {
        assert_eq!(Sheet::named("a3x4").map(|s| s.width_mm), Some(1189.0));
        assert_eq!(Sheet::named("A3×4"), Sheet::named("A3X4"));
        assert_eq!(Sheet::named("A7"), None);
        assert_eq!(Sheet::of_size(297.0, 420.0).name, "A3");
        assert_eq!(Sheet::of_size(500.0, 300.0).name, "custom");
        assert_eq!(Sheet::A3.to_string(), "A3 (420 x 297 mm)");
    }
}
