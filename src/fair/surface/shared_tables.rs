//! One copy of each distinct coefficient table among a representation's quadrature points.
//!
//! A point's coefficients (9 derivatives × its control vertices, 1152 bytes for a bicubic
//! patch) were most of a representation's memory, yet most points repeat another's table:
//! with vertices in the patch's own order (not by id), every ordinary patch has the same
//! B-spline values at the same nodes whatever the mesh's numbering. Equal tables (bit for
//! bit) are stored once and shared.

use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex, PoisonError};

use foldhash::HashSet;

use crate::fair::surface::representation::DERIVATIVES;

/// A coefficient table, compared and hashed by its bits.
struct Table(Arc<[[f64; DERIVATIVES]]>);

impl PartialEq for Table {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len()
            && self
                .0
                .iter()
                .flatten()
                .zip(other.0.iter().flatten())
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

impl Eq for Table {}

impl Hash for Table {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.len().hash(state);
        for x in self.0.iter().flatten() {
            x.to_bits().hash(state);
        }
    }
}

/// The distinct tables seen so far while a representation is built (from any thread).
#[derive(Default)]
pub(crate) struct SharedTables {
    tables: Mutex<HashSet<Table>>,
}

impl SharedTables {
    /// The stored table equal to `coefficients`, stored first if it is new.
    pub(crate) fn share(&self, coefficients: Vec<[f64; DERIVATIVES]>) -> Arc<[[f64; DERIVATIVES]]> {
        let table = Table(coefficients.into());
        // A panic elsewhere cannot leave the set half-updated: insertion is one call.
        let mut tables = self.tables.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(known) = tables.get(&table) {
            return Arc::clone(&known.0);
        }
        let shared = Arc::clone(&table.0);
        tables.insert(table);
        shared
    }

    /// Number of distinct tables stored.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.tables
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_tables_are_stored_once_and_bitwise_different_ones_apart() {
        let tables = SharedTables::default();
        let a = tables.share(vec![[1.0; DERIVATIVES], [0.5; DERIVATIVES]]);
        let b = tables.share(vec![[1.0; DERIVATIVES], [0.5; DERIVATIVES]]);
        assert!(Arc::ptr_eq(&a, &b));
        // −0 equals 0 as a number but is another table: shared tables stay bit-identical.
        let mut signed = [1.0; DERIVATIVES];
        signed[3] = -0.0;
        let mut zero = [1.0; DERIVATIVES];
        zero[3] = 0.0;
        let c = tables.share(vec![signed]);
        let d = tables.share(vec![zero]);
        assert!(!Arc::ptr_eq(&c, &d));
        assert_eq!(c[0][3].to_bits(), (-0.0f64).to_bits());
        assert_eq!(tables.len(), 3);
    }
}
