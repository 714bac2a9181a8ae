//! The file formats a surface is exported to, told from a file name or given by name, the
//! checks of an export request, and its defaults: the tolerance of a mesh or of a polynomial
//! approximation, and the date written into STEP and IGES headers.

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use nurbs::{NurbsSurface, TessellationOptions};

use crate::error::{FormatKind, HullError, InputNames};

/// What an export writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// STEP AP214: one B-spline face (`.stp`, `.step`).
    Step,
    /// IGES 5.3: the rational B-spline surface, entity 128 (`.igs`, `.iges`).
    Iges,
    /// IGES 5.3: the surface and the skinned sections as rational B-spline curves (126).
    IgesCurves,
    /// IGES 5.3: a polynomial (non-rational) surface within a tolerance of the surface, for
    /// systems that drop weights.
    IgesPolynomial,
    /// DXF R12: stations, waterlines and buttocks as 3-D polylines (`.dxf`).
    Dxf,
    /// Binary STL triangulated to a tolerance (`.stl`).
    Stl,
    /// ASCII STL triangulated to a tolerance.
    StlAscii,
    /// Wavefront OBJ with vertex normals, triangulated to a tolerance (`.obj`).
    Obj,
    /// Binary glTF 2.0 coloured by Gaussian curvature, in metres, Y up (`.glb`).
    Glb,
}

impl ExportFormat {
    /// Every format, in the order of the command line's list.
    pub const ALL: [ExportFormat; 9] = [
        ExportFormat::Step,
        ExportFormat::Iges,
        ExportFormat::IgesCurves,
        ExportFormat::IgesPolynomial,
        ExportFormat::Dxf,
        ExportFormat::Stl,
        ExportFormat::StlAscii,
        ExportFormat::Obj,
        ExportFormat::Glb,
    ];

    /// The format a file name's extension stands for (any case).
    ///
    /// ```
    /// use hull::ExportFormat;
    /// use std::path::Path;
    ///
    /// assert_eq!(ExportFormat::from_path(Path::new("hull.STEP")), Some(ExportFormat::Step));
    /// assert_eq!(ExportFormat::from_path(Path::new("hull.txt")), None);
    /// ```
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "stp" | "step" => ExportFormat::Step,
            "igs" | "iges" => ExportFormat::Iges,
            "dxf" => ExportFormat::Dxf,
            "stl" => ExportFormat::Stl,
            "obj" => ExportFormat::Obj,
            "glb" => ExportFormat::Glb,
            _ => return None,
        })
    }

    /// The name on the command line and in summaries.
    pub fn name(self) -> &'static str {
        match self {
            ExportFormat::Step => "step",
            ExportFormat::Iges => "iges",
            ExportFormat::IgesCurves => "iges-curves",
            ExportFormat::IgesPolynomial => "iges-polynomial",
            ExportFormat::Dxf => "dxf",
            ExportFormat::Stl => "stl",
            ExportFormat::StlAscii => "stl-ascii",
            ExportFormat::Obj => "obj",
            ExportFormat::Glb => "glb",
        }
    }

    /// What the format writes, in a line (the command line's help).
    pub fn description(self) -> &'static str {
        match self {
            ExportFormat::Step => "STEP AP214: one B-spline face (`.stp`, `.step`)",
            ExportFormat::Iges => "IGES 5.3: the rational B-spline surface, entity 128 (`.igs`, `.iges`)",
            ExportFormat::IgesCurves => {
                "IGES 5.3: the surface and the skinned sections as rational B-spline curves (126)"
            }
            ExportFormat::IgesPolynomial => {
                "IGES 5.3: a polynomial (non-rational) surface within --tolerance of the surface, for systems that \
                 drop weights"
            }
            ExportFormat::Dxf => "DXF R12: stations, waterlines and buttocks as 3-D polylines (`.dxf`)",
            ExportFormat::Stl => "Binary STL triangulated to --tolerance (`.stl`)",
            ExportFormat::StlAscii => "ASCII STL triangulated to --tolerance",
            ExportFormat::Obj => "Wavefront OBJ with vertex normals, triangulated to --tolerance (`.obj`)",
            ExportFormat::Glb => "Binary glTF 2.0 coloured by Gaussian curvature, in metres, Y up (`.glb`)",
        }
    }

    /// The file family: formats that share an extension (the IGES variants, the STLs).
    pub fn family(self) -> &'static str {
        match self {
            ExportFormat::Step => "STEP",
            ExportFormat::Iges | ExportFormat::IgesCurves | ExportFormat::IgesPolynomial => "IGES",
            ExportFormat::Dxf => "DXF",
            ExportFormat::Stl | ExportFormat::StlAscii => "STL",
            ExportFormat::Obj => "OBJ",
            ExportFormat::Glb => "glTF",
        }
    }

    /// The usual extension of the format's files.
    pub fn extension(self) -> &'static str {
        match self {
            ExportFormat::Step => "stp",
            ExportFormat::Iges | ExportFormat::IgesCurves | ExportFormat::IgesPolynomial => "igs",
            ExportFormat::Dxf => "dxf",
            ExportFormat::Stl | ExportFormat::StlAscii => "stl",
            ExportFormat::Obj => "obj",
            ExportFormat::Glb => "glb",
        }
    }

    /// Whether the format is a triangle mesh (STL, OBJ, glTF).
    pub fn is_mesh(self) -> bool {
        matches!(self, ExportFormat::Stl | ExportFormat::StlAscii | ExportFormat::Obj | ExportFormat::Glb)
    }

    /// Whether the format takes a tolerance: the meshes and `iges-polynomial`.
    pub fn takes_tolerance(self) -> bool {
        self.is_mesh() || self == ExportFormat::IgesPolynomial
    }

    /// The tolerance used when none is given: for a mesh the chord tolerance of
    /// [`TessellationOptions::for_surface`] (1e-4 of the control net's diagonal), for
    /// `iges-polynomial` 1e-5 of the diagonal (distance to the rational surface); `None` for
    /// the formats that take none.
    pub fn default_tolerance(self, surface: &NurbsSurface) -> Option<f64> {
        match self {
            ExportFormat::IgesPolynomial => {
                let (lo, hi) = surface.control_bounds();
                Some(1e-5 * (hi - lo).norm())
            }
            f if f.is_mesh() => Some(TessellationOptions::for_surface(surface).tolerance),
            _ => None,
        }
    }

    /// The format of an export to `out`: `format` when given, else the one of `out`'s
    /// extension; checked against that extension's family and against `tolerance` (only for
    /// the formats that take one, and positive). `names` spells the inputs in the messages.
    ///
    /// ```
    /// use hull::{ExportFormat, InputNames};
    /// use std::path::Path;
    ///
    /// let f = ExportFormat::for_file(None, Path::new("hull.igs"), None, InputNames::Flags)?;
    /// assert_eq!(f, ExportFormat::Iges);
    /// let e = ExportFormat::for_file(Some(ExportFormat::Stl), Path::new("x.stp"), None, InputNames::Flags);
    /// assert!(e.unwrap_err().to_string().contains("name it x.stl or pass --format step"));
    /// # Ok::<(), hull::HullError>(())
    /// ```
    ///
    /// # Errors
    /// [`HullError::Format`] when no format is given and the extension names none, when the
    /// extension names another family than `format`, and for a tolerance that does not apply;
    /// [`HullError::Setting`] for a tolerance that is not a positive length.
    pub fn for_file(
        format: Option<Self>,
        out: &Path,
        tolerance: Option<f64>,
        names: InputNames,
    ) -> Result<Self, HullError> {
        let p = names.prefix();
        let Some(format) = format.or_else(|| ExportFormat::from_path(out)) else {
            return Err(HullError::Format(FormatKind::Unknown { path: out.to_path_buf(), names }));
        };
        if let Some(named) = ExportFormat::from_path(out).filter(|n| n.family() != format.family()) {
            return Err(HullError::Format(FormatKind::ExtensionMismatch {
                format: format.name(),
                family: format.family(),
                extension: format.extension(),
                path: out.to_path_buf(),
                named: named.name(),
                named_family: named.family(),
                names,
            }));
        }
        if let Some(t) = tolerance {
            if !format.takes_tolerance() {
                return Err(HullError::Format(FormatKind::NoTolerance { format: format.name(), names }));
            }
            if !(t.is_finite() && t > 0.0) {
                return Err(HullError::Setting {
                    name: format!("{p}tolerance"),
                    value: t,
                    expected: "a positive length",
                });
            }
        }
        Ok(format)
    }
}

impl fmt::Display for ExportFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ExportFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let t = s.trim().to_ascii_lowercase();
        ExportFormat::ALL.into_iter().find(|f| f.name() == t).ok_or_else(|| {
            let names: Vec<&str> = ExportFormat::ALL.iter().map(|f| f.name()).collect();
            format!("unknown export format `{s}` (expected {})", names.join(", "))
        })
    }
}

/// The date written into STEP and IGES headers, as Unix seconds: `given`, else the
/// `SOURCE_DATE_EPOCH` environment variable (reproducible builds), else now.
pub fn export_timestamp(given: Option<i64>) -> i64 {
    given.or_else(|| std::env::var("SOURCE_DATE_EPOCH").ok().and_then(|s| s.trim().parse().ok())).unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| i64::try_from(d.as_secs()).unwrap_or(i64::MAX))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_extensions_name_their_family() {
        for f in ExportFormat::ALL {
            assert_eq!(f.name().parse::<ExportFormat>(), Ok(f));
            assert_eq!(
                ExportFormat::from_path(Path::new(&format!("a.{}", f.extension()))).map(|g| g.family()),
                Some(f.family())
            );
        }
        assert!("ply".parse::<ExportFormat>().expect_err("unknown").contains("iges-polynomial"));
    }

    #[test]
    fn tolerances_default_to_a_share_of_the_net() {
        let k = nurbs::KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let pts = [
            nurbs::Vec3::new(0., 0., 0.),
            nurbs::Vec3::new(0., 3., 0.),
            nurbs::Vec3::new(4., 0., 0.),
            nurbs::Vec3::new(4., 3., 0.),
        ];
        let s = NurbsSurface::try_new(k.clone(), k, &pts, None).expect("valid");
        assert_eq!(ExportFormat::Stl.default_tolerance(&s), Some(1e-4 * 5.0));
        assert_eq!(ExportFormat::IgesPolynomial.default_tolerance(&s), Some(1e-5 * 5.0));
        assert_eq!(ExportFormat::Step.default_tolerance(&s), None);
        let keywords = ExportFormat::for_file(None, Path::new("a.stp"), Some(1.0), InputNames::Keywords);
        assert_eq!(
            keywords.expect_err("no tolerance").to_string(),
            "tolerance applies to stl, stl-ascii, obj, glb and iges-polynomial, not step"
        );
        assert_eq!(export_timestamp(Some(42)), 42);
    }
}
