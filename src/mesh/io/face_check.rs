//! The checks every reader applies to a face as it is read.

/// Why a face is degenerate, if it is: fewer than 3 corners, or a vertex repeated (shown
/// as a 0-based index).
pub fn degeneracy(corners: &[u32]) -> Option<String> {
    degeneracy_as_written(corners, 0)
}

/// [`degeneracy`] for a reader: `base` is the numbering the file uses (0 for PLY and OFF,
/// 1 for OBJ), so that the message shows the repeated vertex as the user wrote it.
pub fn degeneracy_as_written(corners: &[u32], base: i64) -> Option<String> {
    if corners.len() < 3 {
        return Some(format!(
            "a face needs at least 3 vertices, this one has {}",
            corners.len()
        ));
    }
    repeated_vertex(corners).map(|v| {
        format!(
            "vertex index {} is repeated in the face",
            i64::from(v) + base
        )
    })
}

/// A vertex the face holds more than once, if any: small faces by pairs, large ones sorted
/// (a face may have a million corners).
pub fn repeated_vertex(corners: &[u32]) -> Option<u32> {
    if corners.len() <= 16 {
        corners
            .iter()
            .enumerate()
            .find_map(|(i, a)| corners[i + 1..].contains(a).then_some(*a))
    } else {
        let mut sorted = corners.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

/// The message for a 0-based index that names no vertex, or `None` when it is in range.
/// `base` is the numbering the file uses (0 for PLY and OFF, 1 for OBJ), so that the
/// message shows the index as the user wrote it.
pub fn out_of_range(index: i64, vertex_count: usize, base: i64) -> Option<String> {
    (index < 0 || index as u64 >= vertex_count as u64).then(|| {
        let shown = index.saturating_add(base);
        let valid = if vertex_count == 0 {
            "the file has no vertices".to_string()
        } else {
            format!(
                "the file has {vertex_count} vertices (valid: {base} to {})",
                vertex_count as i64 - 1 + base
            )
        };
        if index < 0 {
            format!("vertex index {shown} is negative: {valid}")
        } else {
            format!("vertex index {shown} is out of range: {valid}")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_repeats_short_and_long() {
        assert!(degeneracy(&[0, 1, 2]).is_none());
        assert_eq!(
            degeneracy(&[0, 1]).unwrap(),
            "a face needs at least 3 vertices, this one has 2"
        );
        assert_eq!(
            degeneracy(&[0, 1, 0]).unwrap(),
            "vertex index 0 is repeated in the face"
        );
        assert_eq!(
            degeneracy_as_written(&[0, 1, 0], 1).unwrap(),
            "vertex index 1 is repeated in the face"
        );
        let mut long: Vec<u32> = (0..40).collect();
        assert!(degeneracy(&long).is_none());
        long.push(17);
        assert_eq!(
            degeneracy(&long).unwrap(),
            "vertex index 17 is repeated in the face"
        );
    }

    #[test]
    fn range_messages() {
        assert_eq!(out_of_range(2, 3, 0), None);
        assert_eq!(
            out_of_range(3, 3, 0).unwrap(),
            "vertex index 3 is out of range: the file has 3 vertices (valid: 0 to 2)"
        );
        assert_eq!(
            out_of_range(3, 3, 1).unwrap(),
            "vertex index 4 is out of range: the file has 3 vertices (valid: 1 to 3)"
        );
        assert_eq!(
            out_of_range(-1, 3, 0).unwrap(),
            "vertex index -1 is negative: the file has 3 vertices (valid: 0 to 2)"
        );
        assert_eq!(
            out_of_range(0, 0, 0).unwrap(),
            "vertex index 0 is out of range: the file has no vertices"
        );
        assert!(out_of_range(i64::MIN, 3, 1).is_some());
    }
}
