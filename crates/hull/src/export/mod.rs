//! Exports of the fitted surface to exchange formats: IGES 5.3 (entity 128) and the lossless
//! hullskin surface JSON. Writers are generic over [`std::io::Write`] and format every real
//! number through [`float::real`].

pub mod float;
pub mod iges;
pub mod surface_json;

pub use iges::{iges_timestamp, write_iges, IgesMeta, IgesUnits};
pub use surface_json::{read_surface_json, write_surface_json, SurfaceFile, SurfaceJsonError};
