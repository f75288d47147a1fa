//! Fast paths for the binary PLY layouts nearly every file uses: a vertex element of
//! scalar properties only (fixed record size), and a face element holding only the corner
//! list. Records are decoded straight from the byte slice with decoders chosen once per
//! property, instead of one dynamic dispatch per value.

use super::face_check::out_of_range;

/// Decodes one value of a scalar type and byte order from the start of a slice.
pub type Decode = fn(&[u8]) -> f64;

macro_rules! decoders {
    ($($t:ty),*) => {
        /// The decoder for `size`-byte values of type index `kind` (see `decoder`).
        fn pick(kind: usize, big_endian: bool) -> Decode {
            let table: [[Decode; 2]; 8] = [$(
                [
                    |b: &[u8]| <$t>::from_le_bytes(b[..std::mem::size_of::<$t>()].try_into().unwrap()) as f64,
                    |b: &[u8]| <$t>::from_be_bytes(b[..std::mem::size_of::<$t>()].try_into().unwrap()) as f64,
                ]
            ),*];
            table[kind][usize::from(big_endian)]
        }
    };
}

decoders!(i8, u8, i16, u16, i32, u32, f32, f64);

/// A decoder for a PLY scalar type, given as (index in char, uchar, short, ushort, int,
/// uint, float, double order, size in bytes).
pub fn decoder(kind: usize, big_endian: bool) -> Decode {
    pick(kind, big_endian)
}

/// Reads `count` fixed-size records of `stride` bytes starting at `start`; for each one,
/// fills `slots[k]` with property `k` (at `offsets[k]`, decoded by `decode[k]`) and calls
/// `store`. Returns the end offset, or the index of the first record that does not fit.
pub fn read_fixed_records(
    data: &[u8],
    start: usize,
    count: usize,
    stride: usize,
    offsets: &[usize],
    decode: &[Decode],
    mut store: impl FnMut(usize, &[f64]) -> Result<(), String>,
) -> Result<usize, (usize, String)> {
    let available = (data.len() - start) / stride.max(1);
    let mut slots = vec![0.0; offsets.len()];
    let body = &data[start..];
    for index in 0..count.min(available) {
        let record = &body[index * stride..(index + 1) * stride];
        for k in 0..offsets.len() {
            slots[k] = decode[k](&record[offsets[k]..]);
        }
        store(index, &slots).map_err(|m| (index, m))?;
    }
    if available < count {
        return Err((available, "the file ends inside this element".into()));
    }
    Ok(start + count * stride)
}

/// Reads `count` faces made of one list (count type of `count_size` bytes, items of
/// `item_size` bytes) starting at `start`, appending corners to `indices` and offsets to
/// `offsets`. `check` validates each face's corners. Returns the end offset, or the face
/// index, its byte offset and the problem.
#[allow(clippy::too_many_arguments)]
pub fn read_list_faces(
    data: &[u8],
    start: usize,
    count: usize,
    (count_decode, count_size): (Decode, usize),
    (item_decode, item_size): (Decode, usize),
    vertex_count: usize,
    indices: &mut Vec<u32>,
    offsets: &mut Vec<u32>,
    mut check: impl FnMut(&[u32]) -> Option<String>,
) -> Result<usize, (usize, usize, String)> {
    let mut pos = start;
    for index in 0..count {
        let at = pos;
        let truncated = || (index, at, "the file ends inside this element".to_string());
        let n_bytes = data.get(pos..pos + count_size).ok_or_else(truncated)?;
        let n = count_decode(n_bytes);
        if n < 0.0 {
            return Err((
                index,
                at,
                format!("the face has a negative corner count {n}"),
            ));
        }
        let n = n as usize;
        pos += count_size;
        let items = data.get(pos..pos + n * item_size).ok_or_else(truncated)?;
        let first = indices.len();
        for k in 0..n {
            let i = item_decode(&items[k * item_size..]);
            // `as` saturates and maps NaN to 0: a value that does not come back is no
            // integer (a float list with 1.5 or NaN), and must not be truncated.
            let j = i as i64;
            if j as f64 != i {
                return Err((index, at, format!("vertex index {i} is not an integer")));
            }
            if let Some(m) = out_of_range(j, vertex_count, 0) {
                return Err((index, at, m));
            }
            indices.push(j as u32);
        }
        if let Some(m) = check(&indices[first..]) {
            return Err((index, at, m));
        }
        offsets.push(indices.len() as u32);
        pos += n * item_size;
    }
    Ok(pos)
}
