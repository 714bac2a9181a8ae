//! A drawing as plain geometry on paper, independent of the file format: the lines plan, the
//! convergence plot and other figures are built once as a [`Drawing`] and then written as SVG,
//! DXF or PNG by their writers.
//!
//! Coordinates are paper millimetres, origin at the bottom-left corner of the sheet, y up (as
//! in DXF and in the drawings' model space); the SVG writer flips y.

pub use hull::Rgb;

/// How a line is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    pub color: Rgb,
    /// Line width in paper millimetres.
    pub width_mm: f64,
    /// Dash pattern in paper millimetres (on, off, ...); `None` for a solid line.
    pub dash: Option<Vec<f64>>,
}

impl Stroke {
    /// A solid line.
    pub fn solid(color: Rgb, width_mm: f64) -> Self {
        Stroke { color, width_mm, dash: None }
    }
}

/// Horizontal alignment of a text relative to its anchor point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// One element of a drawing. `layer` groups elements (SVG `<g id>`, DXF layer): for the lines
/// plan e.g. `stations`, `waterlines`, `buttocks`, `offsets`, `frame`, `title`.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// An open or closed polyline.
    Polyline { points: Vec<[f64; 2]>, closed: bool, stroke: Stroke, layer: String },
    /// A filled polygon without outline.
    Polygon { points: Vec<[f64; 2]>, fill: Rgb, layer: String },
    /// A filled round marker of diameter `size_mm` centred at `at`.
    Marker { at: [f64; 2], size_mm: f64, fill: Rgb, layer: String },
    /// One line of text, baseline at `at`, cap height about `size_mm`.
    Text { at: [f64; 2], text: String, size_mm: f64, anchor: Anchor, color: Rgb, layer: String },
}

impl Item {
    /// The item's layer.
    pub fn layer(&self) -> &str {
        match self {
            Item::Polyline { layer, .. }
            | Item::Polygon { layer, .. }
            | Item::Marker { layer, .. }
            | Item::Text { layer, .. } => layer,
        }
    }
}

/// A sheet of paper with items on it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drawing {
    pub width_mm: f64,
    pub height_mm: f64,
    /// Title of the drawing (SVG `<title>`, the title block's first line).
    pub title: String,
    pub items: Vec<Item>,
}

impl Drawing {
    /// An empty sheet.
    pub fn new(width_mm: f64, height_mm: f64, title: impl Into<String>) -> Self {
        Drawing { width_mm, height_mm, title: title.into(), items: Vec::new() }
    }

    /// Add an item.
    pub fn push(&mut self, item: Item) {
        self.items.push(item);
    }

    /// The items on one layer.
    pub fn layer<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Item> + 'a {
        self.items.iter().filter(move |i| i.layer() == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_is_two_digits_per_channel() {
        assert_eq!(Rgb(255, 0, 16).hex(), "#ff0010");
    }

    #[test]
    fn layer_filters_items() {
        let mut d = Drawing::new(420.0, 297.0, "t");
        d.push(Item::Marker { at: [1.0, 2.0], size_mm: 1.0, fill: Rgb::BLACK, layer: "offsets".into() });
        d.push(Item::Polyline {
            points: vec![[0.0, 0.0], [1.0, 1.0]],
            closed: false,
            stroke: Stroke::solid(Rgb::GREY, 0.25),
            layer: "stations".into(),
        });
        assert_eq!(d.layer("offsets").count(), 1);
        assert_eq!(d.layer("stations").count(), 1);
        assert_eq!(d.layer("title").count(), 0);
    }
}
