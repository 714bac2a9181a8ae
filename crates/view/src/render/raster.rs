//! A [`Drawing`] rasterised to pixels and encoded as PNG, for reports and terminals without a
//! browser.
//!
//! Paper millimetres map to pixels by one scale `k` (pixels per millimetre), `k = dpi / 25.4`
//! or `k = width_px / width_mm`, with y flipped (paper y up, pixel rows down):
//!
//! ```text
//! px = x_mm * k        py = (height_mm - y_mm) * k        image = round(width_mm * k) x round(height_mm * k)
//! ```
//!
//! Pixel `(i, j)` covers `[i, i+1) x [j, j+1)`, so a point at `(px, py)` lies in pixel
//! `(floor(px), floor(py))`. Paths are filled and stroked anti-aliased by tiny-skia (nonzero
//! winding, round joins, butt caps, as the SVG writer's defaults); text is drawn from the glyph
//! outlines of the embedded DejaVu Sans subset (see `assets/fonts/README.md`), scaled so that the
//! capital height is the item's `size_mm`, advances from the font's `hmtx` without kerning.
//! Everything is plain arithmetic on the inputs, so the same drawing gives the same bytes.

use std::io::Cursor;
use std::path::Path;
use std::sync::OnceLock;

use tiny_skia::{FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, StrokeDash, Transform};

use crate::drawing::{Anchor, Drawing, Item, Rgb, Stroke};
use crate::ViewError;
use hull::write_atomic;

/// The embedded font: DejaVu Sans, subset to Latin-1, Greek, super/subscript digits, arrows and a
/// few mathematical signs (Bitstream Vera / Arev licence, `assets/fonts/LICENSE-DejaVu.txt`).
const FONT_TTF: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// Largest image produced, in pixels (width x height): 10^8 pixels are 400 MB of RGBA, more
/// than a report needs (A0 at 300 dpi is 1.4 x 10^8; A3 at 600 dpi is 7 x 10^7).
pub const MAX_PIXELS: u64 = 100_000_000;

/// Millimetres per inch.
const MM_PER_INCH: f64 = 25.4;

/// How a drawing is turned into pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct RasterOptions {
    /// Resolution in dots (pixels) per inch of paper; used unless `width_px` is set.
    pub dpi: f64,
    /// Image width in pixels; the height follows from the sheet's aspect ratio. Overrides `dpi`.
    pub width_px: Option<u32>,
    /// Colour of the sheet under the items.
    pub background: Rgb,
}

impl Default for RasterOptions {
    /// 150 dpi (an A3 sheet, 420 x 297 mm, gives 2480 x 1754 pixels), white paper.
    fn default() -> Self {
        RasterOptions { dpi: 150.0, width_px: None, background: Rgb::WHITE }
    }
}

impl RasterOptions {
    /// Options for an image `width_px` pixels wide.
    pub fn with_width(width_px: u32) -> Self {
        RasterOptions { width_px: Some(width_px), ..RasterOptions::default() }
    }
}

/// An opaque RGB image, 8 bits per channel, stored as RGBA rows top to bottom (alpha 255).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
    /// Pixels per metre of paper, written as the PNG `pHYs` chunk when known.
    pixels_per_metre: Option<u32>,
}

impl Image {
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels as RGBA bytes, row by row from the top.
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }

    /// The colour of pixel `(x, y)` (column, row from the top), `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Rgb> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        Some(Rgb(self.rgba[i], self.rgba[i + 1], self.rgba[i + 2]))
    }

    /// Encode as an 8-bit RGB PNG (with a `pHYs` chunk when the resolution is known).
    ///
    /// # Errors
    /// [`ViewError::PngEncode`] if the encoder fails (it does not on an image built here: the
    /// output is an in-memory buffer).
    pub fn to_png(&self) -> Result<Vec<u8>, ViewError> {
        let encode_error = |e: png::EncodingError| ViewError::PngEncode { reason: e.to_string() };
        let rgb: Vec<u8> = self.rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        let mut out = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_compression(png::Compression::Balanced);
            if let Some(ppm) = self.pixels_per_metre {
                encoder.set_pixel_dims(Some(png::PixelDimensions { xppu: ppm, yppu: ppm, unit: png::Unit::Meter }));
            }
            let mut writer = encoder.write_header().map_err(encode_error)?;
            writer.write_image_data(&rgb).map_err(encode_error)?;
            writer.finish().map_err(encode_error)?;
        }
        Ok(out)
    }

    /// Decode a PNG (any colour type and bit depth; transparency is composited on white).
    ///
    /// # Errors
    /// [`ViewError::PngDecode`] if `bytes` is not a PNG the decoder reads,
    /// [`ViewError::TooManyPixels`] if it is larger than [`MAX_PIXELS`].
    pub fn from_png(bytes: &[u8]) -> Result<Image, ViewError> {
        let decode_error = |e: png::DecodingError| ViewError::PngDecode { reason: e.to_string() };
        let mut decoder = png::Decoder::new(Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        let mut reader = decoder.read_info().map_err(decode_error)?;
        let (width, height) = (reader.info().width, reader.info().height);
        check_size(width, height)?;
        let size = reader.output_buffer_size().ok_or(ViewError::PngTooLarge { width, height })?;
        let mut buf = vec![0; size];
        let info = reader.next_frame(&mut buf).map_err(decode_error)?;
        let channels = info.color_type.samples();
        let mut rgba = Vec::with_capacity(4 * width as usize * height as usize);
        for row in buf.chunks_exact(info.line_size).take(height as usize) {
            for p in row.chunks_exact(channels).take(width as usize) {
                let (rgb, a) = match channels {
                    1 => ([p[0]; 3], 255),
                    2 => ([p[0]; 3], p[1]),
                    3 => ([p[0], p[1], p[2]], 255),
                    _ => ([p[0], p[1], p[2]], p[3]),
                };
                // Over white: c' = c a + 255 (1 - a), in 8-bit integers rounded to nearest.
                let over = |c: u8| ((c as u32 * a as u32 + 255 * (255 - a as u32) + 127) / 255) as u8;
                rgba.extend_from_slice(&[over(rgb[0]), over(rgb[1]), over(rgb[2]), 255]);
            }
        }
        Ok(Image { width, height, rgba, pixels_per_metre: None })
    }

    /// Convert a tiny-skia pixmap whose pixels are all opaque (premultiplied = straight).
    pub(crate) fn from_pixmap(pixmap: Pixmap, pixels_per_metre: Option<u32>) -> Image {
        let (width, height) = (pixmap.width(), pixmap.height());
        Image { width, height, rgba: pixmap.take_demultiplied(), pixels_per_metre }
    }
}

/// The paper-to-pixel mapping of one rendering: `px = x k`, `py = (height_mm - y) k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mapping {
    /// Pixels per paper millimetre.
    pub k: f64,
    /// Sheet height in millimetres.
    pub height_mm: f64,
}

impl Mapping {
    /// Pixel coordinates of a paper point, as f32 for tiny-skia.
    fn px(&self, p: [f64; 2]) -> (f32, f32) {
        ((p[0] * self.k) as f32, ((self.height_mm - p[1]) * self.k) as f32)
    }
}

/// Image size of a drawing and its mapping.
///
/// # Errors
/// [`ViewError::SheetSize`], [`ViewError::ImageWidth`] or [`ViewError::Resolution`] for a sheet
/// or resolution that is not finite and positive, [`ViewError::ImageTooLarge`] for an image
/// above [`MAX_PIXELS`].
pub(crate) fn layout(d: &Drawing, options: &RasterOptions) -> Result<(u32, u32, Mapping), ViewError> {
    if !(d.width_mm.is_finite() && d.width_mm > 0.0 && d.height_mm.is_finite() && d.height_mm > 0.0) {
        return Err(ViewError::SheetSize { width_mm: d.width_mm, height_mm: d.height_mm });
    }
    let k = match options.width_px {
        Some(0) => return Err(ViewError::ImageWidth { width_px: 0 }),
        Some(w) => w as f64 / d.width_mm,
        None if options.dpi.is_finite() && options.dpi > 0.0 => options.dpi / MM_PER_INCH,
        None => return Err(ViewError::Resolution { dpi: options.dpi }),
    };
    let (w, h) = ((d.width_mm * k).round().max(1.0), (d.height_mm * k).round().max(1.0));
    if w * h > MAX_PIXELS as f64 {
        return Err(ViewError::ImageTooLarge { width: w, height: h, max: MAX_PIXELS });
    }
    Ok((w as u32, h as u32, Mapping { k, height_mm: d.height_mm }))
}

fn check_size(width: u32, height: u32) -> Result<(), ViewError> {
    if width as u64 * height as u64 > MAX_PIXELS {
        return Err(ViewError::TooManyPixels { width, height, max: MAX_PIXELS });
    }
    Ok(())
}

/// A blank opaque canvas of `width x height` pixels.
pub(crate) fn canvas(width: u32, height: u32, background: Rgb) -> Result<Pixmap, ViewError> {
    check_size(width, height)?;
    let mut pixmap = Pixmap::new(width, height).ok_or(ViewError::Allocation { width, height })?;
    pixmap.fill(tiny_skia::Color::from_rgba8(background.0, background.1, background.2, 255));
    Ok(pixmap)
}

/// Rasterise a drawing into RGBA pixels.
///
/// # Errors
/// [`ViewError::SheetSize`], [`ViewError::ImageWidth`] or [`ViewError::Resolution`] for a sheet
/// size or resolution that is not finite and positive, [`ViewError::ImageTooLarge`] for an image
/// above [`MAX_PIXELS`]. Items with non-finite coordinates are skipped, not errors.
pub fn render_rgba(d: &Drawing, options: &RasterOptions) -> Result<Image, ViewError> {
    let (w, h, mapping) = layout(d, options)?;
    let mut pixmap = canvas(w, h, options.background)?;
    draw_items(&mut pixmap, &d.items, mapping);
    Ok(Image::from_pixmap(pixmap, pixels_per_metre(mapping.k)))
}

/// Rasterise a drawing and encode it as PNG (8-bit RGB, `pHYs` set to the paper resolution so
/// that the picture prints at the sheet's size).
///
/// # Errors
/// As [`render_rgba`].
pub fn render_png(d: &Drawing, options: &RasterOptions) -> Result<Vec<u8>, ViewError> {
    render_rgba(d, options)?.to_png()
}

/// [`render_png`] written to `path` atomically ([`write_atomic`]).
///
/// # Errors
/// As [`render_png`], and [`ViewError::Io`] if the file cannot be written.
pub fn write_png(path: &Path, d: &Drawing, options: &RasterOptions) -> Result<(), ViewError> {
    let bytes = render_png(d, options)?;
    write_atomic(path, |w| w.write_all(&bytes)).map_err(|error| ViewError::Io { path: path.to_path_buf(), error })
}

/// Pixels per metre for `k` pixels per millimetre, if representable.
pub(crate) fn pixels_per_metre(k: f64) -> Option<u32> {
    let ppm = (k * 1000.0).round();
    (ppm >= 1.0 && ppm <= u32::MAX as f64).then_some(ppm as u32)
}

fn paint(color: Rgb) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color_rgba8(color.0, color.1, color.2, 255);
    paint.anti_alias = true;
    paint
}

fn path_of(points: &[[f64; 2]], closed: bool, m: Mapping) -> Option<tiny_skia::Path> {
    if points.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return None;
    }
    let mut pb = PathBuilder::new();
    let (first, rest) = points.split_first()?;
    let (x, y) = m.px(*first);
    pb.move_to(x, y);
    for p in rest {
        let (x, y) = m.px(*p);
        pb.line_to(x, y);
    }
    if closed {
        pb.close();
    }
    pb.finish()
}

/// tiny-skia's stroke for a drawing stroke: width and dashes scaled to pixels. A dash list of
/// odd length is repeated once (as SVG does); an unusable one (negative, zero sum) draws solid.
fn skia_stroke(stroke: &Stroke, k: f64) -> Option<tiny_skia::Stroke> {
    if !(stroke.width_mm.is_finite() && stroke.width_mm >= 0.0) {
        return None;
    }
    let dash = stroke.dash.as_ref().and_then(|d| {
        let mut pattern: Vec<f32> = d.iter().map(|v| (v * k) as f32).collect();
        if pattern.len() % 2 == 1 {
            pattern.extend_from_within(..);
        }
        StrokeDash::new(pattern, 0.0)
    });
    Some(tiny_skia::Stroke {
        width: (stroke.width_mm * k) as f32,
        line_cap: LineCap::Butt,
        line_join: LineJoin::Round,
        dash,
        ..tiny_skia::Stroke::default()
    })
}

/// Draw items in order onto `pixmap` (later items on top).
pub(crate) fn draw_items(pixmap: &mut Pixmap, items: &[Item], m: Mapping) {
    for item in items {
        match item {
            Item::Polyline { points, closed, stroke, .. } => {
                if let (Some(path), Some(s)) = (path_of(points, *closed, m), skia_stroke(stroke, m.k)) {
                    pixmap.stroke_path(&path, &paint(stroke.color), &s, Transform::identity(), None);
                }
            }
            Item::Polygon { points, fill, .. } => {
                if let Some(path) = path_of(points, true, m) {
                    pixmap.fill_path(&path, &paint(*fill), FillRule::Winding, Transform::identity(), None);
                }
            }
            Item::Marker { at, size_mm, fill, .. } => {
                let (x, y) = m.px(*at);
                let r = (0.5 * size_mm * m.k) as f32;
                if let Some(path) = PathBuilder::from_circle(x, y, r) {
                    pixmap.fill_path(&path, &paint(*fill), FillRule::Winding, Transform::identity(), None);
                }
            }
            Item::Text { at, text, size_mm, anchor, color, .. } => {
                if let Some(path) = text_path(font(), text, *at, *size_mm, *anchor, m) {
                    pixmap.fill_path(&path, &paint(*color), FillRule::Winding, Transform::identity(), None);
                }
            }
        }
    }
}

/// The parsed embedded font and the metrics used for layout.
pub(crate) struct Font {
    face: ttf_parser::Face<'static>,
    /// Capital height in font units (the top of `H`).
    cap_height: f64,
}

/// The embedded font, parsed once.
pub(crate) fn font() -> &'static Font {
    static FONT: OnceLock<Font> = OnceLock::new();
    FONT.get_or_init(|| {
        let face = ttf_parser::Face::parse(FONT_TTF, 0).expect("the embedded font parses (tested in raster::tests)");
        let cap_height = face
            .capital_height()
            .map(f64::from)
            .filter(|&h| h > 0.0)
            .or_else(|| {
                let h = face.glyph_index('H')?;
                face.glyph_bounding_box(h).map(|b| f64::from(b.y_max))
            })
            .unwrap_or(0.73 * f64::from(face.units_per_em()));
        Font { face, cap_height }
    })
}

impl Font {
    fn glyph(&self, c: char) -> ttf_parser::GlyphId {
        self.face.glyph_index(c).unwrap_or(ttf_parser::GlyphId(0))
    }

    /// Advance of `text` in font units (sum of the glyphs' horizontal advances).
    fn advance_units(&self, text: &str) -> f64 {
        text.chars().map(|c| f64::from(self.face.glyph_hor_advance(self.glyph(c)).unwrap_or(0))).sum()
    }

    /// Width of `text` in millimetres at capital height `size_mm`.
    pub(crate) fn text_width_mm(&self, text: &str, size_mm: f64) -> f64 {
        self.advance_units(text) * size_mm / self.cap_height
    }
}

/// Width of `text` in millimetres when drawn at capital height `size_mm` by this rasteriser.
pub(crate) fn text_width_mm(text: &str, size_mm: f64) -> f64 {
    font().text_width_mm(text, size_mm)
}

/// Collects a glyph outline (font units, y up) into a path in pixels: `p = origin + (x, -y) s`.
struct OutlineToPath<'a> {
    pb: &'a mut PathBuilder,
    origin: (f64, f64),
    scale: f64,
}

impl OutlineToPath<'_> {
    fn at(&self, x: f32, y: f32) -> (f32, f32) {
        ((self.origin.0 + f64::from(x) * self.scale) as f32, (self.origin.1 - f64::from(y) * self.scale) as f32)
    }
}

impl ttf_parser::OutlineBuilder for OutlineToPath<'_> {
    fn move_to(&mut self, x: f32, y: f32) {
        let (x, y) = self.at(x, y);
        self.pb.move_to(x, y);
    }
    fn line_to(&mut self, x: f32, y: f32) {
        let (x, y) = self.at(x, y);
        self.pb.line_to(x, y);
    }
    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let (x1, y1) = self.at(x1, y1);
        let (x, y) = self.at(x, y);
        self.pb.quad_to(x1, y1, x, y);
    }
    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let (x1, y1) = self.at(x1, y1);
        let (x2, y2) = self.at(x2, y2);
        let (x, y) = self.at(x, y);
        self.pb.cubic_to(x1, y1, x2, y2, x, y);
    }
    fn close(&mut self) {
        self.pb.close();
    }
}

/// The outlines of `text` as one path in pixels, baseline at `at`, aligned by `anchor`.
fn text_path(
    font: &Font,
    text: &str,
    at: [f64; 2],
    size_mm: f64,
    anchor: Anchor,
    m: Mapping,
) -> Option<tiny_skia::Path> {
    if !(size_mm.is_finite() && size_mm > 0.0 && at[0].is_finite() && at[1].is_finite()) {
        return None;
    }
    let scale = size_mm * m.k / font.cap_height; // pixels per font unit
    let width = font.advance_units(text) * scale;
    let (x0, y0) = (at[0] * m.k, (m.height_mm - at[1]) * m.k);
    let mut pen = match anchor {
        Anchor::Start => x0,
        Anchor::Middle => x0 - 0.5 * width,
        Anchor::End => x0 - width,
    };
    let mut pb = PathBuilder::new();
    for c in text.chars() {
        let id = font.glyph(c);
        let mut sink = OutlineToPath { pb: &mut pb, origin: (pen, y0), scale };
        font.face.outline_glyph(id, &mut sink);
        pen += f64::from(font.face.glyph_hor_advance(id).unwrap_or(0)) * scale;
    }
    pb.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::Item;

    fn line(y: f64, width_mm: f64) -> Item {
        Item::Polyline {
            points: vec![[10.0, y], [90.0, y]],
            closed: false,
            stroke: Stroke::solid(Rgb::BLACK, width_mm),
            layer: "t".into(),
        }
    }

    #[test]
    fn a3_at_150_dpi_is_2480_by_1754() {
        // 420 mm / 25.4 * 150 = 2480.3 -> 2480; 297 / 25.4 * 150 = 1753.9 -> 1754.
        let d = Drawing::new(420.0, 297.0, "A3");
        let (w, h, m) = layout(&d, &RasterOptions::default()).expect("A3 lays out");
        assert_eq!((w, h), (2480, 1754));
        assert!((m.k - 150.0 / 25.4).abs() < 1e-12);
        let (w, h, _) = layout(&d, &RasterOptions::with_width(840)).expect("A3 lays out");
        assert_eq!((w, h), (840, 594)); // 2 px per mm exactly
    }

    #[test]
    fn bad_sizes_are_config_errors() {
        let d = Drawing::new(0.0, 10.0, "empty");
        assert!(matches!(render_rgba(&d, &RasterOptions::default()), Err(ViewError::SheetSize { .. })));
        let d = Drawing::new(10.0, 10.0, "ok");
        let bad = RasterOptions { dpi: f64::NAN, ..RasterOptions::default() };
        assert!(matches!(render_rgba(&d, &bad), Err(ViewError::Resolution { .. })));
        assert!(matches!(render_rgba(&d, &RasterOptions::with_width(0)), Err(ViewError::ImageWidth { width_px: 0 })));
        let huge = Drawing::new(1.0e6, 1.0e6, "huge");
        let err = render_rgba(&huge, &RasterOptions::default()).expect_err("too large");
        assert!(matches!(err, ViewError::ImageTooLarge { max: MAX_PIXELS, .. }), "{err}");
        assert!(err.to_string().ends_with("(expected at most 100000000 pixels: lower the dpi or width)"), "{err}");
    }

    #[test]
    fn pixel_row_of_a_line_follows_the_y_flip() {
        // 1 px per mm: a 1 mm line at y = 30 mm on a 100 mm sheet covers rows [69.5, 70.5),
        // i.e. half of row 69 and half of row 70; anti-aliasing paints both at about 50 %.
        let mut d = Drawing::new(100.0, 100.0, "t");
        d.push(line(30.0, 1.0));
        let img = render_rgba(&d, &RasterOptions::with_width(100)).expect("renders");
        let dark_rows: Vec<u32> = (0..100).filter(|&y| img.pixel(50, y).is_some_and(|p| p.0 < 200)).collect();
        assert_eq!(dark_rows, vec![69, 70]);
    }

    #[test]
    fn non_finite_items_are_skipped() {
        let mut d = Drawing::new(100.0, 100.0, "t");
        d.push(line(f64::NAN, 1.0));
        d.push(Item::Marker { at: [f64::INFINITY, 1.0], size_mm: 3.0, fill: Rgb::BLACK, layer: "t".into() });
        let img = render_rgba(&d, &RasterOptions::with_width(50)).expect("renders");
        assert!(img.rgba().chunks_exact(4).all(|p| p == [255, 255, 255, 255]));
    }

    #[test]
    fn odd_dash_list_repeats() {
        // [2] means 2 on, 2 off: along an 80 mm line at 1 px/mm about half the columns are dark.
        let mut d = Drawing::new(100.0, 20.0, "t");
        d.push(Item::Polyline {
            points: vec![[10.0, 10.0], [90.0, 10.0]],
            closed: false,
            stroke: Stroke { color: Rgb::BLACK, width_mm: 2.0, dash: Some(vec![2.0]) },
            layer: "t".into(),
        });
        let img = render_rgba(&d, &RasterOptions::with_width(100)).expect("renders");
        let dark = (10..90).filter(|&x| img.pixel(x, 10).is_some_and(|p| p.0 < 128)).count();
        assert!((38..=42).contains(&dark), "{dark} dark columns of 80");
    }

    #[test]
    fn font_metrics_are_those_of_dejavu_sans() {
        let f = font();
        // DejaVu Sans: 2048 units per em, capital H 1493 units high, "H" advances 1540 units.
        assert_eq!(f.face.units_per_em(), 2048);
        assert_eq!(f.cap_height, 1493.0);
        assert!((f.text_width_mm("H", 1493.0) - 1540.0).abs() < 1e-9);
        // Characters outside the subset fall back to .notdef, which still advances.
        assert!(f.text_width_mm("\u{4e2d}", 3.0) > 0.0);
    }

    #[test]
    fn png_round_trip_is_lossless() {
        let mut d = Drawing::new(40.0, 30.0, "t");
        d.push(Item::Marker { at: [20.0, 15.0], size_mm: 10.0, fill: Rgb(200, 30, 60), layer: "t".into() });
        let img = render_rgba(&d, &RasterOptions::with_width(80)).expect("renders");
        let back = Image::from_png(&img.to_png().expect("encodes")).expect("decodes");
        assert_eq!(back.rgba(), img.rgba());
        assert_eq!((back.width(), back.height()), (80, 60));
        assert!(Image::from_png(b"not a png").is_err());
    }
}
