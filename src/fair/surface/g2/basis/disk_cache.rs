//! The patch matrices kept on disk between runs: a valence's basis takes 0.15 s (k = 3) to
//! several seconds (k = 16) to compute and is the same in every run of the same build, so
//! the first run on a machine stores it and later runs read it.
//!
//! Where: `$SURFKIT_CACHE_DIR` (empty: no disk cache), else `$XDG_CACHE_HOME/surfkit`, else
//! `$HOME/.cache/surfkit`. One file per valence, named by a fingerprint of the code that
//! computes the basis (the sources of this folder and of the constrained solve, hashed at
//! run time from the text compiled in), so a build whose construction differs never reads
//! another's file. A file is written whole to a temporary name and renamed; one that is
//! short, long, of other dimensions or whose checksum does not match is ignored and
//! rewritten. The cache is an optimization only: any failure to read or write it falls
//! back to computing.

use std::io::Write;
use std::path::{Path, PathBuf};

use faer::Mat;

use super::bernstein::COEFFICIENTS;
use super::domain_net::PER_SECTOR;
use super::junction::{Junction, SectorDomain};
use super::patch_matrix::PatchMatrix;
use super::sides::Side;

/// The code the basis depends on; its hash names the cache files.
const CONSTRUCTION: [&str; 13] = [
    include_str!("auxiliary.rs"),
    include_str!("bernstein.rs"),
    include_str!("division_curve.rs"),
    include_str!("domain_derivatives.rs"),
    include_str!("domain_net.rs"),
    include_str!("junction.rs"),
    include_str!("patch_matrix.rs"),
    include_str!("polynomial.rs"),
    include_str!("sides.rs"),
    include_str!("space.rs"),
    include_str!("disk_cache.rs"),
    include_str!("../../../../linalg/constrained.rs"),
    include_str!("../../../../tolerance.rs"),
];

const MAGIC: &[u8; 16] = b"surfkit G2 basis";

/// 64-bit FNV-1a.
fn fnv1a(bytes: impl IntoIterator<Item = u8>, mut hash: u64) -> u64 {
    for b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// The fingerprint of this build's construction.
fn fingerprint() -> u64 {
    CONSTRUCTION
        .iter()
        .fold(FNV_OFFSET, |h, text| fnv1a(text.bytes(), h))
}

/// The folder of the disk cache, if there is one.
pub fn default_dir() -> Option<PathBuf> {
    let from = |var: &str| std::env::var_os(var).filter(|v| !v.is_empty());
    if let Some(dir) = std::env::var_os("SURFKIT_CACHE_DIR") {
        return (!dir.is_empty()).then(|| PathBuf::from(dir));
    }
    from("XDG_CACHE_HOME")
        .map(|d| PathBuf::from(d).join("surfkit"))
        .or_else(|| from("HOME").map(|h| PathBuf::from(h).join(".cache").join("surfkit")))
}

/// The file of valence k's basis in `dir`.
pub fn file(dir: &Path, k: usize) -> PathBuf {
    dir.join(format!("g2-basis-{:016x}-k{k}.bin", fingerprint()))
}

/// Lengths of the stored arrays of valence k: δ₀'s two coordinates, the 4 × 4 junction
/// functions (their degrees + 1), the patch matrix.
fn array_lengths(k: usize) -> Vec<usize> {
    let junctions = Side::ALL
        .iter()
        .flat_map(|side| side.junction_degrees().map(|d| d + 1));
    [COEFFICIENTS, COEFFICIENTS]
        .into_iter()
        .chain(junctions)
        .chain([k * COEFFICIENTS * (1 + PER_SECTOR * k)])
        .collect()
}

fn encode(basis: &PatchMatrix) -> Vec<u8> {
    let first = &basis.sectors[0];
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&fingerprint().to_le_bytes());
    for n in [basis.k, basis.inner_dimension] {
        out.extend_from_slice(&(n as u64).to_le_bytes());
    }
    let mut put = |values: &mut dyn Iterator<Item = f64>, len: usize| {
        out.extend_from_slice(&(len as u64).to_le_bytes());
        for v in values {
            out.extend_from_slice(&v.to_le_bytes());
        }
    };
    for v in first
        .patch
        .iter()
        .chain(first.junctions.iter().flat_map(|j| j.0.iter()))
    {
        put(&mut v.iter().copied(), v.len());
    }
    let m = &basis.matrix;
    put(
        &mut (0..m.ncols()).flat_map(|j| (0..m.nrows()).map(move |i| m[(i, j)])),
        m.nrows() * m.ncols(),
    );
    let sum = fnv1a(out.iter().copied(), FNV_OFFSET);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// Reads little-endian words from a byte slice.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn word(&mut self) -> Option<u64> {
        let (head, rest) = self.0.split_first_chunk::<8>()?;
        self.0 = rest;
        Some(u64::from_le_bytes(*head))
    }

    /// An array of exactly `len` values (its stored length must say so).
    fn array(&mut self, len: usize) -> Option<Vec<f64>> {
        if self.word()? != len as u64 || self.0.len() < 8 * len {
            return None;
        }
        let (values, rest) = self.0.split_at(8 * len);
        self.0 = rest;
        Some(
            values
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
                .collect(),
        )
    }
}

/// Valence k's basis from `dir`, if a whole file of this build's construction is there.
/// The file must have the size valence k implies before it is read, and every array the
/// length, so a damaged or foreign file cannot ask for any allocation.
pub fn load(dir: &Path, k: usize) -> Option<PatchMatrix> {
    let path = file(dir, k);
    // Header (magic, fingerprint, k, inner dimension), each array with its length, checksum.
    let expected =
        MAGIC.len() + 3 * 8 + array_lengths(k).iter().map(|n| 8 + 8 * n).sum::<usize>() + 8;
    if std::fs::metadata(&path).ok()?.len() != expected as u64 {
        return None;
    }
    let bytes = std::fs::read(&path).ok()?;
    let (body, sum) = bytes.split_last_chunk::<8>()?;
    if fnv1a(body.iter().copied(), FNV_OFFSET) != u64::from_le_bytes(*sum) {
        return None;
    }
    let body = body.strip_prefix(MAGIC)?;
    let mut r = Reader(body);
    if r.word()? != fingerprint() || r.word()? != k as u64 {
        return None;
    }
    let inner_dimension = usize::try_from(r.word()?).ok()?;
    let lengths = array_lengths(k);
    let mut arrays = Vec::with_capacity(lengths.len());
    for &len in &lengths {
        arrays.push(r.array(len)?);
    }
    if !r.0.is_empty() || arrays.iter().flatten().any(|v| !v.is_finite()) {
        return None;
    }
    let values = arrays.pop()?;
    let (rows, cols) = (k * COEFFICIENTS, 1 + PER_SECTOR * k);
    let matrix = Mat::from_fn(rows, cols, |i, j| values[j * rows + i]);
    let mut arrays = arrays.into_iter();
    let mut next = || arrays.next().expect("lengths counted");
    let patch = [next(), next()];
    let junctions = std::array::from_fn(|_| Junction([next(), next(), next(), next()]));
    let first = SectorDomain { patch, junctions };
    Some(PatchMatrix {
        k,
        sectors: (0..k).map(|s| first.rotated(s, k)).collect(),
        matrix,
        inner_dimension,
    })
}

/// Stores `basis` in `dir` (created if needed), atomically; errors are the caller's to
/// ignore or report.
pub fn store(dir: &Path, basis: &PatchMatrix) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut temporary = tempfile::NamedTempFile::new_in(dir)?;
    temporary.write_all(&encode(basis))?;
    temporary.as_file().sync_all()?;
    temporary.persist(file(dir, basis.k)).map_err(|e| e.error)?;
    Ok(())
}

/// Whether `a` and `b` are the same basis, bit for bit (what is stored: valence, inner
/// dimension, δ₀, the junction functions and the patch matrix; the other sectors are δ₀
/// turned).
pub fn identical(a: &PatchMatrix, b: &PatchMatrix) -> bool {
    encode(a) == encode(b)
}
