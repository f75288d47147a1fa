//! The Euler Accompanying Test (Liu, Yue, Zhang, Li 2020) and the flaw locator.
//!
//! - `registry`: EAT-TA, the Facet/Edge/Vertex lists with counters fc, ec, vc, fed facet
//!   by facet (incremental, O(arity)); it counts every facet, refused by a half-edge
//!   structure or not.
//! - `statistics`: EAT-SA, V, E, F and χ at any moment.
//! - `progressive`: test points and the facets since the last verified point.
//! - `structure`, `locator`: raw-polygon topology and every flaw, classified and placed.
//! - `scan`: all of it over a finished mesh (`topology::scan(&mesh, &EatOptions)`), with the
//!   OpenMesh half-edge structure of the accepted facets.

mod cracks;
pub(crate) mod disjoint_sets;
mod flaw;
mod locator;
mod mark;
mod progressive;
mod registry;
mod scan;
mod stages;
mod statistics;
mod structure;
mod target;

pub use cracks::{stitch_cracks, Stitched, TJunction};
pub use flaw::{show_ids, show_measure, Flaw, FlawKind, LoopShape};
pub use locator::{boundary_walks, locate, LocatorOptions, DEFAULT_CRACK_TOLERANCE};
pub use mark::{flaw_color, mark_flaws, SOUND};
pub use progressive::{Checkpoint, FacetDetail, ModelCompanion};
pub use registry::{EatRegistry, EdgeItem, FacetRegistration, VertexItem};
pub use scan::{
    scan, ComponentTopology, EatOptions, EatReport, HalfEdgeReport, TestPoint, TopologyCounts,
};
pub use stages::{paired_test_points, stage_ends, test_points, StageSource};
pub use statistics::EatStatistics;
pub use structure::Structure;
pub use target::TargetTopology;
