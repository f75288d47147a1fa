//! The checks every reader applies to a face as it is read.

/// Why a face is degenerate, if it is: fewer than 3 corners, or a vertex repeated.
pub fn degeneracy(corners: &[u32]) -> Option<String> {
    if corners.len() < 3 {
        return Some(format!(
            "a face needs at least 3 vertices, this one has {}",
            corners.len()
        ));
    }
    let repeated = if corners.len() <= 16 {
        corners
            .iter()
            .enumerate()
            .find_map(|(i, a)| corners[i + 1..].contains(a).then_some(*a))
    } else {
        let mut sorted = corners.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    };
    repeated.map(|v| format!("vertex {v} is repeated in the face (0-based index)"))
}

/// The message for a 0-based index that names no vertex, or `None` when it is in range.
/// `base` is the numbering the file uses (0 for PLY and OFF, 1 for OBJ), so that the
/// message shows the index as the user wrote it.
pub fn out_of_range(index: i64, vertex_count: usize, base: i64) -> Option<String> {
    (index < 0 || index as u64 >= vertex_count as u64).then(|| {
        format!(
            "vertex index {} is out of range: the file has {vertex_count} vertices (valid: {base} to {})",
            index + base,
            vertex_count as i64 - 1 + base
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_repeats_short_and_long() {
        assert!(degeneracy(&[0, 1, 2]).is_none());
        assert!(degeneracy(&[0, 1]).is_some());
        assert!(degeneracy(&[0, 1, 0]).unwrap().contains("vertex 0"));
        let mut long: Vec<u32> = (0..40).collect();
        assert!(degeneracy(&long).is_none());
        long.push(17);
        assert!(degeneracy(&long).unwrap().contains("vertex 17"));
    }
}
