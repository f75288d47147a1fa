//! EAT-SA (Liu et al. 2020, Fig. 8): the totals of the three lists and χ.

use super::registry::EatRegistry;

/// V, E, F and the Euler characteristic χ = V − E + F (eq. 1), F counting every facet
/// record and V the vertices some facet uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct EatStatistics {
    pub vertices: usize,
    pub edges: usize,
    pub facets: usize,
    pub euler_characteristic: i64,
}

impl EatStatistics {
    /// EAT-SA on the registry as it stands.
    pub fn of(registry: &EatRegistry) -> Self {
        let (v, e, f) = (
            registry.vertex_count(),
            registry.edge_count(),
            registry.facet_count(),
        );
        EatStatistics {
            vertices: v,
            edges: e,
            facets: f,
            euler_characteristic: v as i64 - e as i64 + f as i64,
        }
    }

    /// The paper's screenshot lines (Fig. 10).
    pub fn render(&self) -> String {
        format!(
            "vertex number ***{}***vertex number\nedge number ***{}***edge number\nfacet number ***{}***facet number\nEuler characteristic***{}***Euler characteristic\n",
            self.vertices, self.edges, self.facets, self.euler_characteristic
        )
    }
}
