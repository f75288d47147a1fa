//! The progressive EAT procedure (Liu et al. 2020 §3.4): test points where χ so far is
//! compared with the corresponding part of the target; on a mismatch, the facets added
//! since the last verified point are reported with their vertices' `vc` and edges' `ec`
//! (the information of the paper's Figs. 14, 20, 23 and 24).

use super::registry::{EatRegistry, FacetRegistration};
use super::statistics::EatStatistics;
use crate::error::Result;
use crate::halfedge::{self, FaceStatus, OpenMeshHalfEdge};
use crate::limits::MemoryBudget;
use crate::mesh::PolygonMesh;

/// A facet registered since the last verified point, with its counters as they stand.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct FacetDetail {
    /// Position in the Facet list (fID), and the caller's id for it (e.g. input face id).
    pub facet: u32,
    pub input_id: u32,
    pub fc: u32,
    /// (vID = input vertex id, vc).
    pub vertices: Vec<(u32, u32)>,
    /// (eID = Edge-list position, ec).
    pub edges: Vec<(u32, u32)>,
}

/// The outcome of a test point.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Checkpoint {
    pub verified: bool,
    pub expected_euler_characteristic: i64,
    pub statistics: EatStatistics,
    /// Facet count at the last verified point before this one.
    pub last_verified_facets: usize,
    /// Every facet registered since the last verified point (empty when verified).
    pub since_last_verified: Vec<FacetDetail>,
}

/// A registry fed facet by facet, as a modelling program's companion would, with test
/// points; optionally mirrored into an OpenMesh half-edge mesh for location queries.
#[derive(Default)]
pub struct ModelCompanion {
    registry: EatRegistry,
    input_ids: Vec<u32>,
    last_verified: usize,
    mirror: Option<HalfEdgeMirror>,
}

/// The OpenMesh half-edge mesh that follows the registry: facets are handed over in one
/// batched call when a location query needs them, not one call per facet.
struct HalfEdgeMirror {
    mesh: OpenMeshHalfEdge,
    mirrored: usize,
    status: Vec<FaceStatus>,
    messages: String,
}

impl ModelCompanion {
    pub fn new() -> Self {
        ModelCompanion {
            registry: EatRegistry::new(),
            ..Default::default()
        }
    }

    /// EAT-TA for one facet; `input_id` is how the caller names it in reports.
    ///
    /// # Errors
    /// [`crate::Error::ResourceLimit`] when a vertex id is beyond what the process's memory
    /// budget ([`MemoryBudget::default`]) allows the registry (it keeps an item per id up to
    /// the largest); nothing is registered then.
    pub fn register_facet(&mut self, corners: &[u32], input_id: u32) -> Result<FacetRegistration> {
        self.make_room(corners)?;
        self.input_ids.push(input_id);
        Ok(self.registry.register_facet(corners))
    }

    /// Room in the registry for `corners`' ids, checked against the memory budget only
    /// when the registry must grow (rarely: its arrays grow geometrically).
    fn make_room(&mut self, corners: &[u32]) -> Result<()> {
        match corners.iter().max() {
            Some(&max) if max as usize >= self.registry.id_capacity() => self
                .registry
                .reserve_vertex_ids(max, MemoryBudget::default()),
            _ => Ok(()),
        }
    }

    /// A companion whose accepted facets are mirrored into an OpenMesh half-edge mesh over
    /// `positions` (the modelling program's original vertices V₀, ids by position).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] for a non-finite coordinate; [`crate::Error::Ffi`].
    pub fn with_halfedge(positions: &[[f64; 3]]) -> Result<Self> {
        let vertices = PolygonMesh {
            positions: positions.to_vec(),
            ..Default::default()
        };
        let built = halfedge::build(&vertices)?;
        Ok(ModelCompanion {
            registry: EatRegistry::new(),
            mirror: Some(HalfEdgeMirror {
                mesh: built.mesh,
                mirrored: 0,
                status: Vec::new(),
                messages: String::new(),
            }),
            ..Default::default()
        })
    }

    /// The OpenMesh half-edge mesh of the accepted facets registered so far (None without
    /// [`with_halfedge`](Self::with_halfedge)), with what happened to each facet.
    ///
    /// # Errors
    /// [`crate::Error::Ffi`] when OpenMesh fails (a corner beyond the vertices given).
    pub fn halfedge(&mut self) -> Result<Option<(&OpenMeshHalfEdge, &[FaceStatus], &str)>> {
        let Some(mirror) = self.mirror.as_mut() else {
            return Ok(None);
        };
        let count = self.registry.facet_count();
        if mirror.mirrored < count {
            let (offsets, corners) = self.registry.facet_arrays();
            let base = offsets[mirror.mirrored];
            let rebased: Vec<u32> = offsets[mirror.mirrored..=count]
                .iter()
                .map(|o| o - base)
                .collect();
            let (status, said) = mirror.mesh.add_faces(
                &rebased,
                &corners[base as usize..offsets[count] as usize],
                mirror.mirrored as u32,
            )?;
            mirror.status.extend(status);
            mirror.messages.push_str(&said);
            mirror.mirrored = count;
        }
        Ok(Some((&mirror.mesh, &mirror.status, &mirror.messages)))
    }

    /// A companion with room for about `vertices`, `facets` and `corners`.
    pub fn with_capacity(vertices: usize, facets: usize, corners: usize) -> Self {
        ModelCompanion {
            registry: EatRegistry::with_capacity(vertices, facets, corners),
            input_ids: Vec::with_capacity(facets),
            last_verified: 0,
            mirror: None,
        }
    }

    /// EAT-TA for one facet without the per-facet report (for scanning whole meshes).
    ///
    /// # Errors
    /// Those of [`register_facet`](Self::register_facet).
    pub fn register(&mut self, corners: &[u32], input_id: u32) -> Result<u32> {
        self.make_room(corners)?;
        self.input_ids.push(input_id);
        Ok(self.registry.register(corners))
    }

    pub fn registry(&self) -> &EatRegistry {
        &self.registry
    }

    /// EAT-SA now.
    pub fn statistics(&self) -> EatStatistics {
        EatStatistics::of(&self.registry)
    }

    /// A test point: compares χ with `expected`. When equal, this becomes the last
    /// verified point; otherwise the facets since the last verified point are returned
    /// with their counters, and the last verified point stays where it was.
    pub fn checkpoint(&mut self, expected: i64) -> Checkpoint {
        let statistics = self.statistics();
        let verified = statistics.euler_characteristic == expected;
        let last_verified_facets = self.last_verified;
        let since_last_verified = if verified {
            self.last_verified = self.registry.facet_count();
            Vec::new()
        } else {
            (last_verified_facets..self.registry.facet_count())
                .map(|f| self.detail(f))
                .collect()
        };
        Checkpoint {
            verified,
            expected_euler_characteristic: expected,
            statistics,
            last_verified_facets,
            since_last_verified,
        }
    }

    fn detail(&self, f: usize) -> FacetDetail {
        let r = &self.registry;
        let corners = r.facet(f);
        let n = corners.len();
        let vertices = corners
            .iter()
            .map(|&v| (v, r.vertex(v).map_or(0, |i| i.vc)))
            .collect();
        let edges = (0..n)
            .filter_map(|k| {
                let slot = r.edge_slot(corners[k], corners[(k + 1) % n])?;
                Some((slot, r.edges()[slot as usize].ec))
            })
            .filter(|_| n >= 2)
            .collect();
        FacetDetail {
            facet: f as u32,
            input_id: self.input_ids[f],
            fc: r.facet_counter(f),
            vertices,
            edges,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_triangle_fails_the_test_point_and_names_the_new_facets() {
        // A closed tetrahedron (χ = 2) drawn in two stages; the second stage forgets a face.
        let mut c = ModelCompanion::new();
        c.register_facet(&[0, 1, 2], 0).unwrap();
        let first = c.checkpoint(1); // a triangle is a disk
        assert!(first.verified);
        c.register_facet(&[0, 3, 1], 1).unwrap();
        c.register_facet(&[1, 3, 2], 2).unwrap();
        let second = c.checkpoint(2);
        assert!(!second.verified);
        assert_eq!(second.statistics.euler_characteristic, 1);
        assert_eq!(second.last_verified_facets, 1);
        let ids: Vec<u32> = second
            .since_last_verified
            .iter()
            .map(|d| d.input_id)
            .collect();
        assert_eq!(ids, vec![1, 2]);
        // Edge {3,1} has two facets, edge {0,3} one: the open edges border the gap.
        let d = &second.since_last_verified[0];
        assert_eq!(d.vertices, vec![(0, 3), (3, 3), (1, 3)]);
        c.register_facet(&[0, 2, 3], 3).unwrap();
        let third = c.checkpoint(2);
        assert!(third.verified);
        assert_eq!(third.statistics.facets, 4);
    }

    #[test]
    fn the_mirror_follows_the_registry_in_batches() {
        use crate::halfedge::HalfEdgeTopology;
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut c = ModelCompanion::with_halfedge(&positions).unwrap();
        c.register_facet(&[0, 1, 2], 0).unwrap();
        c.register_facet(&[0, 3, 1], 1).unwrap();
        {
            let (mesh, status, _) = c.halfedge().unwrap().unwrap();
            assert_eq!(mesh.face_count(), 2);
            assert_eq!(mesh.boundary_loops().unwrap().len(), 1);
            assert_eq!(status, &[FaceStatus::Added, FaceStatus::Added]);
        }
        c.register_facet(&[1, 3, 2], 2).unwrap();
        c.register_facet(&[0, 2, 3], 3).unwrap();
        c.register_facet(&[0, 1, 2], 4).unwrap(); // the first facet again: OpenMesh refuses it
        let (mesh, status, said) = c.halfedge().unwrap().unwrap();
        assert_eq!(mesh.face_count(), 4);
        assert_eq!(mesh.boundary_loops().unwrap().len(), 0);
        // Every vertex of the closed tetrahedron is interior: OpenMesh names the vertex.
        assert_eq!(status[4], FaceStatus::ComplexVertex);
        assert!(said.contains("face 4"));
        assert_eq!(
            c.statistics().facets,
            5,
            "the registry counts the refused facet"
        );
    }
}
