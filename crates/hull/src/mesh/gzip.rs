//! Gzip-compressed meshes (`.stl.gz`, `.obj.gz`, `.wrl.gz`): recognised by the magic bytes, decompressed
//! by flate2 behind the cargo feature `gzip` (on by default). Without it a gzip stream is a
//! [`HullError::FeatureDisabled`] error, never a panic.

#[cfg(feature = "gzip")]
use std::io::Read;

use crate::error::HullError;
#[cfg(feature = "gzip")]
use crate::error::Location;

#[cfg(feature = "gzip")]
use super::mesh_error;

/// Largest decompressed size of a gzip-compressed mesh, bytes (1 GiB: a 20-million-triangle
/// ASCII STL); a larger stream is refused rather than exhausting memory.
pub const MAX_DECOMPRESSED: u64 = 1 << 30;

/// True if `bytes` start with the gzip magic number `1f 8b` (RFC 1952, 2.3.1).
pub fn is_gzip(bytes: &[u8]) -> bool {
    bytes.starts_with(&[0x1f, 0x8b])
}

/// The largest expansion of deflate: 1032 to 1 (RFC 1951, section 3.2.5: a match of 258 bytes
/// in as few as 2 bits).
#[cfg(feature = "gzip")]
const MAX_DEFLATE_RATIO: usize = 1032;

/// Decompresses a gzip stream (all its members), up to [`MAX_DECOMPRESSED`] bytes.
///
/// # Errors
/// [`InputErrorKind::Mesh`](crate::InputErrorKind::Mesh) for a corrupt or truncated stream, or one that decompresses to
/// more than [`MAX_DECOMPRESSED`] bytes; [`HullError::FeatureDisabled`] when the crate is built
/// without its cargo feature `gzip` (flate2).
pub fn gunzip(bytes: &[u8], source: &str) -> Result<Vec<u8>, HullError> {
    inflate(bytes, source)
}

/// [`gunzip`] in a build without flate2: the input is named, not read.
#[cfg(not(feature = "gzip"))]
fn inflate(_bytes: &[u8], source: &str) -> Result<Vec<u8>, HullError> {
    Err(HullError::FeatureDisabled {
        source_name: source.to_string(),
        input: "a gzip-compressed mesh",
        feature: "gzip",
    })
}

/// [`gunzip`] with flate2.
#[cfg(feature = "gzip")]
fn inflate(bytes: &[u8], source: &str) -> Result<Vec<u8>, HullError> {
    // The trailer's ISIZE (size mod 2^32) is a good first guess of the capacity, but only a
    // guess: a truncated or forged file ends in any four bytes. Deflate expands at most 1032
    // times (a 258-byte match coded in two bits, RFC 1951 3.2.5), so no stream of these bytes
    // can need more; beyond that the vector grows as the data come.
    let hint = bytes
        .len()
        .checked_sub(4)
        .map_or(0, |i| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]) as usize);
    let most = bytes.len().saturating_mul(MAX_DEFLATE_RATIO);
    let mut out = Vec::with_capacity(hint.min(most).min(MAX_DECOMPRESSED as usize));
    let mut reader = flate2::read::MultiGzDecoder::new(bytes).take(MAX_DECOMPRESSED + 1);
    reader.read_to_end(&mut out).map_err(|e| {
        mesh_error(
            Location::file(source),
            format!("corrupt gzip stream after {} decompressed bytes: {e}", out.len()),
            "a complete gzip file (RFC 1952)",
        )
    })?;
    if out.len() as u64 > MAX_DECOMPRESSED {
        return Err(mesh_error(
            Location::file(source),
            format!("the gzip stream decompresses to more than {MAX_DECOMPRESSED} bytes"),
            "a mesh of at most 1 GiB uncompressed",
        ));
    }
    Ok(out)
}

#[cfg(all(test, feature = "gzip"))]
mod tests {
    use super::*;
    use crate::mesh::{parse_mesh, MeshReadOptions};

    #[test]
    fn a_truncated_gzip_does_not_trust_its_last_four_bytes() {
        // 1 MiB of zeros: deflate packs it near its best ratio, so the capacity bound holds.
        let mut gz = Vec::new();
        let mut enc = flate2::write::GzEncoder::new(&mut gz, flate2::Compression::best());
        std::io::Write::write_all(&mut enc, &vec![0u8; 1 << 20]).expect("compress");
        enc.finish().expect("finish");
        assert!(gz.len() * MAX_DEFLATE_RATIO >= 1 << 20, "{} bytes compressed", gz.len());
        assert_eq!(gunzip(&gz, "z.gz").expect("whole").len(), 1 << 20);
        // Cut short and ending in a forged ISIZE of 4 GiB - 1: an error. (That no 1 GiB vector
        // is reserved on the way is checked under an address-space cap by the CLI's bad-input
        // test, `stl_gz_truncated.stl.gz`: a 150-byte file.)
        let mut cut = gz[..gz.len() / 2].to_vec();
        cut.extend_from_slice(&u32::MAX.to_le_bytes());
        let e = gunzip(&cut, "cut.gz").expect_err("truncated").to_string();
        assert!(e.starts_with("cut.gz: corrupt gzip stream"), "{e}");
    }

    #[test]
    fn corrupt_gzip_is_an_error_naming_the_file() {
        let e = parse_mesh(&[0x1f, 0x8b, 8, 0, 1, 2, 3], "hull.stl.gz", None, &MeshReadOptions::default())
            .expect_err("corrupt");
        let s = e.to_string();
        assert!(s.starts_with("hull.stl.gz: corrupt gzip stream"), "{s}");
    }
}
