//! The one error type of the crate: what a drawing, a picture or the report could not be made
//! from, with the offending values.

use std::path::PathBuf;

use hull::{HullError, Units};

/// Why a picture, a page or the report could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ViewError {
    /// An error of the hull layer (reading, fitting, hydrostatics, writing a directory), passed
    /// through with its own message.
    #[error(transparent)]
    Hull(#[from] HullError),

    /// A file that could not be written.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        #[source]
        error: std::io::Error,
    },

    /// A sheet whose size is not finite and positive.
    #[error("cannot rasterise a sheet of {width_mm} x {height_mm} mm (expected a finite positive size)")]
    SheetSize {
        /// Sheet width, millimetres.
        width_mm: f64,
        /// Sheet height, millimetres.
        height_mm: f64,
    },

    /// An image width of no pixels.
    #[error("image width {width_px} pixels (expected at least 1)")]
    ImageWidth {
        /// The width asked for.
        width_px: u32,
    },

    /// A resolution that is not finite and positive.
    #[error("resolution {dpi} dpi (expected a finite positive number)")]
    Resolution {
        /// The dots per inch asked for.
        dpi: f64,
    },

    /// A drawing whose picture at the resolution asked for would exceed `max` pixels.
    #[error("image of {width} x {height} pixels is too large (expected at most {max} pixels: lower the dpi or width)")]
    ImageTooLarge {
        /// Width in pixels (rounded, possibly beyond `u32`).
        width: f64,
        /// Height in pixels.
        height: f64,
        /// The limit, `MAX_PIXELS` (10^8).
        max: u64,
    },

    /// A picture (a canvas, or a PNG read back) of more than `max` pixels.
    #[error("image of {width} x {height} pixels is too large (expected at most {max} pixels)")]
    TooManyPixels {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The limit, `MAX_PIXELS` (10^8).
        max: u64,
    },

    /// A PNG whose decoded size does not fit in memory.
    #[error("PNG of {width} x {height} pixels is too large")]
    PngTooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },

    /// A canvas the allocator refused.
    #[error("cannot allocate an image of {width} x {height} pixels")]
    Allocation {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },

    /// The PNG encoder failed (it does not on an image built here: the output is in memory).
    #[error("PNG encoding failed: {reason}")]
    PngEncode {
        /// The encoder's message.
        reason: String,
    },

    /// Bytes that are not a PNG the decoder reads.
    #[error("not a readable PNG: {reason}")]
    PngDecode {
        /// The decoder's message.
        reason: String,
    },

    /// A curvature map narrower than its layout needs.
    #[error("curvature map width {width_px} px (expected at least {min})")]
    CurvatureImageWidth {
        /// The width asked for.
        width_px: u32,
        /// The least width.
        min: u32,
    },

    /// A colour-scale percentile outside `(0, 100]`.
    #[error("percentile {percentile} (expected a number in (0, 100])")]
    Percentile {
        /// The percentile asked for.
        percentile: f64,
    },

    /// A colour limit that is not finite and positive.
    #[error("colour limit {limit} (expected a finite positive number)")]
    ColourLimit {
        /// The limit asked for.
        limit: f64,
    },

    /// A sample count per parameter direction outside `2..=max`.
    #[error("{samples} samples (expected 2 to {max} per direction)")]
    Samples {
        /// The count asked for.
        samples: usize,
        /// The largest count.
        max: usize,
    },

    /// A surface with no extent along x, which the curvature map draws to the right.
    #[error("the surface has no length along x ({lo} to {hi}): the curvature map draws x to the right")]
    NoLength {
        /// The least x of the samples.
        lo: f64,
        /// The greatest x of the samples.
        hi: f64,
    },

    /// A density that is not a positive number.
    #[error("density {density}: expected a positive number in t/m³")]
    Density {
        /// The density asked for, t/m³.
        density: f64,
    },

    /// A design draft at or below the keel.
    #[error(
        "draft {draft}: at or below the keel (lowest z {bottom} {}): nothing is immersed (expected a draft above \
         {bottom} and at most {top})",
        .units.symbol()
    )]
    DraftAtKeel {
        /// The draft asked for.
        draft: f64,
        /// The lowest z of the surface.
        bottom: f64,
        /// The highest z of the surface.
        top: f64,
        /// The units of the three.
        units: Units,
    },

    /// A surface with no depth below the top of the range of drafts to tabulate.
    #[error("the surface has no depth below z = {top} {} (lowest z {bottom}): no draft to tabulate", .units.symbol())]
    NoDepth {
        /// The top of the range (of the offsets or of the surface).
        top: f64,
        /// The lowest z of the surface.
        bottom: f64,
        /// The units of the two.
        units: Units,
    },

    /// A writer into memory that failed (it does not on the writers of this crate).
    #[error("cannot write {what}: {error}")]
    Write {
        /// What was being written ("the lines plan SVG").
        what: &'static str,
        /// What the writer said.
        #[source]
        error: std::io::Error,
    },

    /// A text output that is not UTF-8 (it is always UTF-8 from the writers of this crate).
    #[error("{what} is not UTF-8: {error}")]
    NotUtf8 {
        /// What was written ("the viewer page").
        what: &'static str,
        /// Where the bytes stop being UTF-8.
        #[source]
        error: std::str::Utf8Error,
    },
}
