//! Where test points go: at the end of each OBJ group or object, after given facet counts,
//! or every N facets; and the χ each is expected to have.

use super::scan::TestPoint;
use crate::error::{Error, Result};
use crate::mesh::{FaceLabels, PolygonMesh, NO_LABEL};

/// Stage ends from face labels: a stage ends where the label changes (and at the end).
pub fn stage_ends_from_labels(labels: &FaceLabels) -> Vec<(String, usize)> {
    let mut ends = Vec::new();
    for (f, w) in labels.of_face.windows(2).enumerate() {
        if w[0] != w[1] {
            ends.push((label_name(labels, w[0]), f + 1));
        }
    }
    if let Some(&last) = labels.of_face.last() {
        ends.push((label_name(labels, last), labels.of_face.len()));
    }
    ends
}

fn label_name(labels: &FaceLabels, id: u32) -> String {
    if id == NO_LABEL {
        "(no group)".to_string()
    } else {
        labels.names[id as usize].clone()
    }
}

/// Stage ends every `n` facets (and at the end).
pub fn stage_ends_every(n: usize, facets: usize) -> Vec<(String, usize)> {
    let n = n.max(1);
    let mut ends: Vec<(String, usize)> = (1..)
        .map(|k| k * n)
        .take_while(|&e| e < facets)
        .map(|e| (format!("facets 1-{e}"), e))
        .collect();
    ends.push((format!("facets 1-{facets}"), facets));
    ends
}

/// How the stages of a mesh are chosen.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StageSource {
    /// One stage: the whole mesh.
    Whole,
    Groups,
    Objects,
    /// After these facet counts (the last stage ends at the mesh's end if not given).
    FacetCounts(Vec<usize>),
    Every(usize),
}

/// The stage ends of `mesh` chosen by `source`.
///
/// # Errors
/// [`Error::InvalidInput`] when the mesh has no groups/objects to stage by, or a facet
/// count is beyond the mesh.
pub fn stage_ends(mesh: &PolygonMesh, source: &StageSource) -> Result<Vec<(String, usize)>> {
    let faces = mesh.face_count();
    Ok(match source {
        StageSource::Whole => vec![("whole mesh".into(), faces)],
        StageSource::Groups | StageSource::Objects => {
            let (labels, what) = match source {
                StageSource::Groups => (&mesh.groups, "groups (g)"),
                _ => (&mesh.objects, "objects (o)"),
            };
            let labels = labels.as_ref().ok_or_else(|| {
                Error::InvalidInput(format!("the mesh has no {what} to take stages from"))
            })?;
            stage_ends_from_labels(labels)
        }
        StageSource::FacetCounts(counts) => {
            let mut ends: Vec<(String, usize)> = Vec::new();
            for &c in counts {
                if c > faces {
                    return Err(Error::InvalidInput(format!(
                        "test point after {c} facets, but the mesh has {faces}"
                    )));
                }
                ends.push((format!("facets 1-{c}"), c));
            }
            if ends.last().is_none_or(|e| e.1 != faces) {
                ends.push((format!("facets 1-{faces}"), faces));
            }
            ends
        }
        StageSource::Every(n) => stage_ends_every(*n, faces),
    })
}

/// Test points from stage ends and the expected χ of each stage (one value per stage, or
/// a single value for the last stage only, the others then unchecked and left out).
///
/// # Errors
/// [`Error::InvalidInput`] when the number of expectations fits neither rule.
pub fn test_points(ends: &[(String, usize)], expected: &[i64]) -> Result<Vec<TestPoint>> {
    match (ends.len(), expected.len()) {
        (_, 0) => Ok(Vec::new()),
        (n, m) if n == m => paired_test_points(ends, expected),
        // The last stage (none on a mesh without faces: refused by the pairing).
        (n, 1) => paired_test_points(&ends[n.saturating_sub(1)..], expected),
        (n, m) => Err(Error::InvalidInput(format!(
            "{m} expected Euler characteristics for {n} stages: give one per stage or one for the whole mesh"
        ))),
    }
}

/// Test points given as (facet count, expected χ) pairs, as the C, C++ and Python doors
/// take them: the i-th stage end with the i-th value. The whole-mesh stage that
/// [`stage_ends`] adds after a last count short of the face count is scanned but not
/// checked (the CLI's rule of [`test_points`], one value for the last stage, would move a
/// single pair's χ to the whole mesh).
///
/// # Errors
/// [`Error::InvalidInput`] when there are more values than stages.
pub fn paired_test_points(ends: &[(String, usize)], expected: &[i64]) -> Result<Vec<TestPoint>> {
    if expected.len() > ends.len() {
        return Err(Error::InvalidInput(format!(
            "{} expected Euler characteristics for {} test points",
            expected.len(),
            ends.len()
        )));
    }
    Ok(ends
        .iter()
        .zip(expected)
        .map(|((label, facets), &expected)| TestPoint {
            label: label.clone(),
            facets: *facets,
            expected,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pair short of the face count is checked where it was given, not at the whole
    /// mesh (which [`test_points`]' one-value rule would pick).
    #[test]
    fn pairs_check_their_own_stage() {
        let ends = vec![
            ("facets 1-4".to_string(), 4),
            ("facets 1-32".to_string(), 32),
        ];
        let paired = paired_test_points(&ends, &[1]).unwrap();
        assert_eq!(paired.len(), 1);
        assert_eq!((paired[0].facets, paired[0].expected), (4, 1));
        assert_eq!(test_points(&ends, &[1]).unwrap()[0].facets, 32);
        let both = paired_test_points(&ends, &[1, 0]).unwrap();
        assert_eq!(
            both.iter().map(|p| p.facets).collect::<Vec<_>>(),
            vec![4, 32]
        );
        assert!(paired_test_points(&ends, &[1, 0, 0]).is_err());
    }

    #[test]
    fn label_runs_end_stages() {
        let labels = FaceLabels {
            names: vec!["a".into(), "b".into()],
            of_face: vec![0, 0, 1, 1, 1, 0],
        };
        let ends = stage_ends_from_labels(&labels);
        assert_eq!(
            ends,
            vec![("a".into(), 2), ("b".into(), 5), ("a".into(), 6)]
        );
        assert_eq!(
            stage_ends_every(4, 10)
                .iter()
                .map(|e| e.1)
                .collect::<Vec<_>>(),
            vec![4, 8, 10]
        );
        assert_eq!(test_points(&ends, &[7]).unwrap().len(), 1);
        assert!(test_points(&ends, &[1, 2]).is_err());
    }
}
