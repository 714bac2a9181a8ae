//! The PNG pictures, checked by their pixels: drawings rasterised where their items are, the
//! curvature map's colours against closed-form curvature (cylinder K = 0 and H = 1/(2R), sphere
//! K = 1/R²) and the sample hull's silhouette against its extent, the convergence plot's line,
//! and byte-for-byte determinism.

use std::f64::consts::FRAC_1_SQRT_2;

use hull::{fit_offsets, series60_sample, CurvatureField, FitConfig};
use nurbs::{KnotVector, NurbsSurface, Vec3};
use view::{
    convergence_plot, curvature_image, curvature_map_png, render_png, render_rgba, CurvatureImage,
    CurvatureImageOptions, Image, RasterOptions, ViewDirection, ViewError,
};
use view::{Anchor, Drawing, Item, Rgb, Stroke};

/// Darkness of a pixel in [0, 1]: 1 - mean channel / 255 (0 white, 1 black).
fn ink(p: Rgb) -> f64 {
    1.0 - (p.0 as f64 + p.1 as f64 + p.2 as f64) / (3.0 * 255.0)
}

fn px(img: &Image, x: u32, y: u32) -> Rgb {
    img.pixel(x, y).expect("pixel inside the image")
}

/// Bounding box `[x0, y0, x1, y1]` (inclusive) of the pixels where `pred` holds.
fn bbox(img: &Image, pred: impl Fn(u32, u32, Rgb) -> bool) -> Option<[u32; 4]> {
    let mut b: Option<[u32; 4]> = None;
    for y in 0..img.height() {
        for x in 0..img.width() {
            if pred(x, y, px(img, x, y)) {
                b = Some(match b {
                    None => [x, y, x, y],
                    Some([x0, y0, x1, y1]) => [x0.min(x), y0.min(y), x1.max(x), y1.max(y)],
                });
            }
        }
    }
    b
}

fn layer(s: &str) -> String {
    s.to_string()
}

// ----- the Drawing rasteriser -----

#[test]
fn horizontal_line_paints_its_rows_and_nothing_else() {
    // 2 px per mm: a 1 mm line at y = 20 mm on a 50 mm sheet spans rows (50 - 20) * 2 -+ 1,
    // i.e. [59, 61): rows 59 and 60 exactly, from x = 10 mm (col 20) to x = 90 mm (col 180).
    let mut d = Drawing::new(100.0, 50.0, "line");
    d.push(Item::Polyline {
        points: vec![[10.0, 20.0], [90.0, 20.0]],
        closed: false,
        stroke: Stroke::solid(Rgb::BLACK, 1.0),
        layer: layer("t"),
    });
    let img = Image::from_png(&render_png(&d, &RasterOptions::with_width(200)).expect("renders")).expect("decodes");
    assert_eq!((img.width(), img.height()), (200, 100));
    for y in 0..100 {
        for x in 0..200 {
            let p = px(&img, x, y);
            let on_line = (59..=60).contains(&y) && (20..180).contains(&x);
            if on_line {
                assert_eq!(p, Rgb::BLACK, "({x}, {y}) should be black");
            } else {
                assert_eq!(p, Rgb::WHITE, "({x}, {y}) should be white");
            }
        }
    }
}

#[test]
fn marker_is_a_disc_of_its_diameter() {
    // 4 px per mm: a 10 mm marker is a disc of radius 20 px; its anti-aliased ink adds up to
    // the disc's area pi r^2 = 1256.6 px (coverage is exact to well under 1 % at this size).
    let mut d = Drawing::new(100.0, 50.0, "marker");
    d.push(Item::Marker { at: [50.0, 25.0], size_mm: 10.0, fill: Rgb::BLACK, layer: layer("t") });
    let img = render_rgba(&d, &RasterOptions::with_width(400)).expect("renders");
    let mut area = 0.0;
    for y in 0..img.height() {
        for x in 0..img.width() {
            area += ink(px(&img, x, y));
        }
    }
    let disc = std::f64::consts::PI * 20.0 * 20.0;
    assert!((area - disc).abs() < 0.01 * disc, "ink {area} vs disc {disc}");
    // Centre at (200, 100): the row through it is dark from column 180 to 219.
    let dark: Vec<u32> = (0..400).filter(|&x| ink(px(&img, x, 100)) > 0.5).collect();
    assert_eq!((dark.first().copied(), dark.last().copied()), (Some(180), Some(219)));
    let b = bbox(&img, |_, _, p| ink(p) > 0.5).expect("the disc is drawn");
    assert_eq!(b, [180, 80, 219, 119]);
}

#[test]
fn polygon_fills_its_inside_only() {
    let mut d = Drawing::new(100.0, 100.0, "square");
    let red = Rgb(200, 20, 20);
    d.push(Item::Polygon {
        points: vec![[20.0, 20.0], [60.0, 20.0], [60.0, 50.0], [20.0, 50.0]],
        fill: red,
        layer: layer("t"),
    });
    // 1 px per mm: the square covers columns 20..60 and rows (100-50)..(100-20) = 50..80 exactly.
    let img = render_rgba(&d, &RasterOptions::with_width(100)).expect("renders");
    assert_eq!(bbox(&img, |_, _, p| p != Rgb::WHITE), Some([20, 50, 59, 79]));
    assert!((20..60).all(|x| (50..80).all(|y| px(&img, x, y) == red)));
}

/// Ink box of a text drawn alone, anchored at (50, 20) mm, 4 px per mm.
fn text_box(text: &str, anchor: Anchor) -> [u32; 4] {
    let mut d = Drawing::new(100.0, 40.0, "text");
    d.push(Item::Text {
        at: [50.0, 20.0],
        text: text.into(),
        size_mm: 5.0,
        anchor,
        color: Rgb::BLACK,
        layer: layer("t"),
    });
    let img = render_rgba(&d, &RasterOptions::with_width(400)).expect("renders");
    bbox(&img, |_, _, p| ink(p) > 0.25).expect("text paints pixels")
}

#[test]
fn text_paints_inside_its_box() {
    // Capitals without overshoot sit on the baseline (row (40 - 20) * 4 = 80) and reach the
    // capital height 5 mm = 20 px above it (row 60); 1 px of tolerance for anti-aliasing.
    let [x0, y0, x1, y1] = text_box("HELL", Anchor::Start);
    assert!((59..=61).contains(&y0), "top row {y0}");
    assert!((78..=80).contains(&y1), "bottom row {y1}");
    // Anchored at column 200: Start ink begins just right of it (the H's side bearing is
    // 201/2048 em ~ 1.4 px at this size), End ink ends just left of it, Middle is centred.
    assert!((200..=203).contains(&x0), "start {x0}");
    let width = x1 - x0;
    assert!(width > 60, "four capitals of 5 mm are wider than 15 mm: {width} px");
    let [e0, _, e1, _] = text_box("HELL", Anchor::End);
    assert!((194..=200).contains(&e1), "end {e1}");
    assert!(width.abs_diff(e1 - e0) <= 1);
    let [m0, _, m1, _] = text_box("HELL", Anchor::Middle);
    let centre = 0.5 * (m0 + m1) as f64;
    assert!((centre - 200.0).abs() <= 4.0, "middle centred at {centre}");
    // A descender goes below the baseline.
    let [_, _, _, g1] = text_box("g", Anchor::Start);
    assert!(g1 > 83, "descender reaches row {g1}");
}

#[test]
fn png_carries_size_and_resolution() {
    let d = Drawing::new(420.0, 297.0, "A3");
    let bytes = render_png(&d, &RasterOptions::default()).expect("renders");
    let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
    let reader = decoder.read_info().expect("a PNG");
    let info = reader.info();
    assert_eq!((info.width, info.height), (2480, 1754));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    // 150 dpi = 150 / 0.0254 px per metre = 5905.5 -> 5906.
    let dims = info.pixel_dims.expect("pHYs chunk");
    assert_eq!((dims.xppu, dims.yppu, dims.unit), (5906, 5906, png::Unit::Meter));
}

#[test]
fn same_drawing_gives_the_same_bytes() {
    let h: Vec<f64> = (0..50).map(|i| 1.0 / (1.0 + i as f64)).collect();
    let d = convergence_plot(&[("GA", &h)], "determinism", "m");
    let a = render_png(&d, &RasterOptions::default()).expect("renders");
    let b = render_png(&d.clone(), &RasterOptions::default()).expect("renders");
    assert_eq!(a, b);
}

#[test]
fn invalid_options_are_errors_not_panics() {
    let d = Drawing::new(f64::NAN, 10.0, "bad");
    let err = render_png(&d, &RasterOptions::default()).expect_err("a NaN sheet");
    assert!(matches!(err, ViewError::SheetSize { width_mm, height_mm: 10.0 } if width_mm.is_nan()), "{err}");
    assert_eq!(err.to_string(), "cannot rasterise a sheet of NaN x 10 mm (expected a finite positive size)");
    let cyl = cylinder(1.0, 4.0);
    let map_error = |bad: CurvatureImageOptions| match curvature_image(&cyl, CurvatureField::Gaussian, &bad) {
        Err(e) => e,
        Ok(_) => panic!("{bad:?} makes a map"),
    };
    let err = map_error(CurvatureImageOptions { percentile: 0.0, ..CurvatureImageOptions::default() });
    assert!(matches!(err, ViewError::Percentile { percentile: 0.0 }), "{err}");
    assert_eq!(err.to_string(), "percentile 0 (expected a number in (0, 100])");
    let err = map_error(CurvatureImageOptions { limit: Some(-1.0), ..CurvatureImageOptions::default() });
    assert!(matches!(err, ViewError::ColourLimit { limit: -1.0 }), "{err}");
    assert_eq!(err.to_string(), "colour limit -1 (expected a finite positive number)");
    let err = map_error(CurvatureImageOptions { width_px: 10, ..CurvatureImageOptions::default() });
    assert!(matches!(err, ViewError::CurvatureImageWidth { width_px: 10, min: 320 }), "{err}");
    assert_eq!(err.to_string(), "curvature map width 10 px (expected at least 320)");
}

// ----- the curvature map -----

/// A bilge-like quarter cylinder of radius `r` and length `l` along x: the arc from (y, z) =
/// (0, 0) to (r, r) about (0, r), exact as a rational quadratic (weights 1, 1/sqrt 2, 1).
fn cylinder(r: f64, l: f64) -> NurbsSurface {
    let arc = [(0.0, 0.0), (r, 0.0), (r, r)];
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for x in [0.0, l] {
        for (k, &(y, z)) in arc.iter().enumerate() {
            pts.push(Vec3::new(x, y, z));
            w.push(if k == 1 { FRAC_1_SQRT_2 } else { 1.0 });
        }
    }
    let ku = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("linear knots");
    let kv = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("quadratic knots");
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid cylinder")
}

/// The sphere of radius `r` about the origin between latitudes -45 and 45 degrees and
/// longitudes 0 to 90 degrees, exact as a surface of revolution (The NURBS Book, sec. 8.5):
/// meridian arc times longitude arc, weights multiplied.
fn sphere_patch(r: f64) -> NurbsSurface {
    let c = FRAC_1_SQRT_2;
    // Meridian (radius from the z axis, z) with weights: the 90-degree arc from -45 to 45 deg.
    let meridian = [(r * c, -r * c, 1.0), (r / c, 0.0, c), (r * c, r * c, 1.0)];
    let longitude = [(1.0, 0.0, 1.0), (1.0, 1.0, c), (0.0, 1.0, 1.0)];
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for &(rho, z, wm) in &meridian {
        for &(cx, cy, wl) in &longitude {
            pts.push(Vec3::new(rho * cx, rho * cy, z));
            w.push(wm * wl);
        }
    }
    let k = || KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("quadratic knots");
    NurbsSurface::try_new(k(), k(), &pts, Some(&w)).expect("valid sphere patch")
}

/// The pixels drawn by the surface inside a view: inside its rectangle shrunk by `inset` px
/// (away from the outline strokes), where the pixel is not the white background.
fn view_pixels(map: &CurvatureImage, view: usize, inset: f64) -> Vec<Rgb> {
    let [l, t, r, b] = map.views[view].rect_px;
    let mut out = Vec::new();
    for y in (t + inset).ceil() as u32..(b - inset).floor() as u32 {
        for x in (l + inset).ceil() as u32..(r - inset).floor() as u32 {
            let p = px(&map.image, x, y);
            if p != Rgb::WHITE {
                out.push(p);
            }
        }
    }
    out
}

fn small() -> CurvatureImageOptions {
    CurvatureImageOptions { width_px: 800, samples: 60, units: "m".into(), ..CurvatureImageOptions::default() }
}

#[test]
fn cylinder_has_zero_gaussian_curvature_and_reads_white() {
    let map = curvature_image(&cylinder(1.0, 4.0), CurvatureField::Gaussian, &small()).expect("renders");
    // K is round-off (|K| far below 1e-9 for R = 1), so the limit is the floor
    // (1e-3 / D)^2 with D = diagonal of the sampled box = sqrt(16 + 1 + 1).
    let (lo, hi) = map.range.expect("defined everywhere");
    assert!(lo.abs() < 1e-9 && hi.abs() < 1e-9, "K range {lo} .. {hi}");
    assert!((map.limit - 1e-6 / 18.0).abs() < 1e-6 * 1e-6 / 18.0, "limit {}", map.limit);
    for view in 0..2 {
        let pixels = view_pixels(&map, view, 3.0);
        assert!(pixels.len() > 1000, "view {view} shows the surface");
        // diverging(0) = (247, 247, 247); |K| / L < 1e-3 moves each channel by under 1.
        assert!(pixels.iter().all(|p| p.0 >= 245 && p.1 >= 245 && p.2 >= 245), "view {view} is near-white");
    }
}

#[test]
fn cylinder_mean_curvature_is_positive_half_inverse_radius() {
    // H = 1 / (2R) on a cylinder; the bilge is convex, so positive with the inward normal.
    let r = 2.0;
    let map = curvature_image(&cylinder(r, 8.0), CurvatureField::Mean, &small()).expect("renders");
    let (lo, hi) = map.range.expect("defined everywhere");
    // Rational quadratic evaluation is exact to round-off: 1e-12 relative.
    assert!((lo - 0.25).abs() < 1e-12 && (hi - 0.25).abs() < 1e-12, "H range {lo} .. {hi}");
    assert!((map.limit - 0.25).abs() < 1e-12);
    // Every value equals the limit: every hull pixel is the diverging map's red end.
    let pixels = view_pixels(&map, 0, 3.0);
    assert!(pixels.len() > 1000);
    assert!(pixels.iter().all(|p| p.0 >= 170 && p.2 <= 60), "all red");
}

#[test]
fn sphere_patch_is_all_on_the_positive_side() {
    let r = 3.0;
    let map = curvature_image(&sphere_patch(r), CurvatureField::Gaussian, &small()).expect("renders");
    let (lo, hi) = map.range.expect("no degenerate point on this patch");
    let k = 1.0 / (r * r);
    assert!((lo - k).abs() < 1e-9 * k && (hi - k).abs() < 1e-9 * k, "K range {lo} .. {hi}");
    assert_eq!(map.undefined, 0);
    for view in 0..2 {
        let pixels = view_pixels(&map, view, 3.0);
        assert!(pixels.len() > 1000, "view {view} shows the surface");
        // No pixel on the blue side; all but the outline's anti-aliased arc (dark grey over
        // red, where the silhouette crosses the view's box) at the red end.
        assert!(pixels.iter().all(|p| p.0 >= p.2), "view {view} has a blue pixel");
        let red = pixels.iter().filter(|p| p.0 as i32 - p.2 as i32 > 100).count();
        assert!(red as f64 > 0.95 * pixels.len() as f64, "view {view}: {red} red of {}", pixels.len());
    }
}

#[test]
fn degenerate_pole_is_grey_not_nan() {
    // The sphere octant from the equator to the pole: one edge collapses to the pole, where
    // S_u x S_v = 0 and the curvature is undefined.
    // The kernel's octant (pole at u = 0) with u reversed: u from the equator to the pole.
    let octant = nurbs::fixtures::sphere_octant(1.0).reversed_u();
    let map = curvature_image(&octant, CurvatureField::Gaussian, &small()).expect("renders");
    // The whole u = 1 line (the pole) is undefined; elsewhere K = 1.
    assert_eq!(map.undefined, map.grid.1);
    let (lo, hi) = map.range.expect("defined off the pole");
    assert!((lo - 1.0).abs() < 1e-6 && (hi - 1.0).abs() < 1e-6, "K range {lo} .. {hi}");
    // The bottom view projects on (x, y), where the cells around the pole fan out into a
    // quarter disc whose colours blend from the red end (K = 1 = L) to grey at the pole: some
    // pixels there are grey-ish (red and blue channels within 60).
    let greyish = view_pixels(&map, 1, 0.0).iter().any(|p| (p.0 as i32 - p.2 as i32).abs() < 60);
    assert!(greyish, "the undefined pole shows grey");
}

fn sample_map(field: CurvatureField, width_px: u32) -> (NurbsSurface, CurvatureImage) {
    let fit = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits");
    let o = CurvatureImageOptions { width_px, samples: 100, units: "m".into(), ..CurvatureImageOptions::default() };
    let map = curvature_image(&fit.surface, field, &o).expect("renders");
    (fit.surface, map)
}

#[test]
fn sample_hull_map_has_both_signs_and_true_shape_silhouette() {
    let (surface, map) = sample_map(CurvatureField::Gaussian, 1000);
    // A ship hull has domes (bilge turn, K > 0) and saddles (fore and aft shoulders, K < 0).
    let pixels: Vec<Rgb> = (0..2).flat_map(|v| view_pixels(&map, v, 2.0)).collect();
    let red = pixels.iter().filter(|p| p.0 as i32 - p.2 as i32 > 60).count();
    let blue = pixels.iter().filter(|p| p.2 as i32 - p.0 as i32 > 60).count();
    assert!(red > 100 && blue > 100, "red {red}, blue {blue} pixels");

    // Extent of the surface from a dense sampling independent of the map's grid.
    let (au, bu) = surface.domain_u();
    let (av, bv) = surface.domain_v();
    let n = 200;
    let pts: Vec<Vec3> = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i, j)))
        .map(|(i, j)| surface.point(au + (bu - au) * i as f64 / n as f64, av + (bv - av) * j as f64 / n as f64))
        .collect();
    let ext = |f: fn(&Vec3) -> f64| {
        pts.iter().map(f).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
    };
    let (x, y, z) = (ext(|p| p.x), ext(|p| p.y), ext(|p| p.z));
    assert_eq!(map.views[0].view, ViewDirection::Profile);
    for (k, vert) in [(0, z), (1, y)] {
        let frame = map.views[k];
        let [l, t, r, b] = frame.rect_px;
        // The silhouette: non-white pixels near the view (outline strokes included; the scale's
        // tick marks end 4 px left of the view).
        let found = bbox(&map.image, |px, py, p| {
            p != Rgb::WHITE
                && (px as f64) > l - 2.5
                && (px as f64) < r + 2.5
                && (py as f64) > t - 2.5
                && (py as f64) < b + 2.5
        })
        .expect("the view is drawn");
        let w = (found[2] - found[0] + 1) as f64;
        let h = (found[3] - found[1] + 1) as f64;
        // True shape: the extents times one scale, within 3 px (outline stroke 1.2 px each
        // side plus anti-aliasing).
        assert!((w - (x.1 - x.0) * map.scale).abs() <= 3.0, "view {k}: width {w} vs {}", (x.1 - x.0) * map.scale);
        assert!(
            (h - (vert.1 - vert.0) * map.scale).abs() <= 3.0,
            "view {k}: height {h} vs {}",
            (vert.1 - vert.0) * map.scale
        );
        // And where the projection puts the box's corners.
        let corner = frame.project(Vec3::new(x.0, y.0, z.1));
        assert!(
            (found[0] as f64 - corner[0]).abs() <= 2.0 && (found[1] as f64 - corner[1]).abs() <= 2.0,
            "view {k}: {found:?} vs {corner:?}"
        );
    }
    // The hull (Lpp 121.92 m) fills the width less margins and the vertical scale.
    assert!(map.scale * (x.1 - x.0) > 0.8 * map.image.width() as f64);
}

#[test]
fn sample_hull_mean_curvature_is_mostly_convex() {
    // The bilge and the bottom's round turns are convex: with the inward normal the mean
    // curvature is positive over most of the hull.
    let (_, map) = sample_map(CurvatureField::Mean, 800);
    let pixels: Vec<Rgb> = (0..2).flat_map(|v| view_pixels(&map, v, 2.0)).collect();
    let red = pixels.iter().filter(|p| p.0 > p.2).count();
    let blue = pixels.iter().filter(|p| p.2 > p.0).count();
    assert!(red > 2 * blue, "red {red}, blue {blue}");
}

#[test]
fn curvature_map_is_deterministic() {
    let s = sphere_patch(2.0);
    let a = curvature_map_png(&s, CurvatureField::Mean, &small()).expect("renders");
    let b = curvature_map_png(&s, CurvatureField::Mean, &small()).expect("renders");
    assert_eq!(a, b);
    let img = Image::from_png(&a).expect("decodes");
    assert_eq!(img.width(), 800);
}

// ----- the convergence plot -----

/// Mean row of the pixels of `color` (within 40 per channel) in each column that has any.
fn colour_profile(img: &Image, color: Rgb) -> Vec<(u32, f64)> {
    let near = |p: Rgb| {
        (p.0 as i32 - color.0 as i32).abs() < 40
            && (p.1 as i32 - color.1 as i32).abs() < 40
            && (p.2 as i32 - color.2 as i32).abs() < 40
    };
    (0..img.width())
        .filter_map(|x| {
            let rows: Vec<u32> = (0..img.height()).filter(|&y| near(px(img, x, y))).collect();
            (!rows.is_empty()).then(|| (x, rows.iter().sum::<u32>() as f64 / rows.len() as f64))
        })
        .collect()
}

#[test]
fn convergence_line_descends_left_to_right() {
    let h: Vec<f64> = (0..100).map(|i| 0.05 * (-(i as f64) / 20.0).exp() + 1e-4).collect();
    let mut d = convergence_plot(&[("GA", &h)], "GA", "m");
    d.items.retain(|i| i.layer() != "legend"); // its line sample would be counted too
    let img = render_rgba(&d, &RasterOptions::default()).expect("renders");
    let line = colour_profile(&img, Rgb(0, 114, 178));
    assert!(line.len() > 900, "the line spans the plot: {} columns", line.len());
    // Rows grow downward: a decreasing error means the mean row never goes up by more than
    // anti-aliasing noise (0.5 px) from one column to the next, and drops a lot overall.
    for w in line.windows(2) {
        assert!(w[1].1 >= w[0].1 - 0.5, "rises at column {}: {:?}", w[1].0, w);
    }
    let (first, last) = (line[0].1, line[line.len() - 1].1);
    assert!(last - first > 0.5 * img.height() as f64, "falls {first} -> {last}");
}

#[test]
fn convergence_series_have_distinct_colours() {
    let a: Vec<f64> = (0..40).map(|i| 1.0 / (1.0 + i as f64)).collect();
    let b: Vec<f64> = (0..40).map(|i| 0.5 / (1.0 + 0.5 * i as f64)).collect();
    let d = convergence_plot(&[("PSO", &a), ("GSA", &b)], "two", "mm");
    let img = render_rgba(&d, &RasterOptions::with_width(1200)).expect("renders");
    let first = colour_profile(&img, Rgb(0, 114, 178));
    let second = colour_profile(&img, Rgb(213, 94, 0));
    assert!(first.len() > 500 && second.len() > 500, "{} and {} columns", first.len(), second.len());
}
