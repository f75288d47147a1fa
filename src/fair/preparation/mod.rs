//! What a mesh needs before it is optimized (paper §2, §4): its topology and the paper's
//! conditions, refinement until they hold, the author's surface refinement, and the fixed
//! vertices (by distance to the boundary or from the user's selection).

pub(crate) mod prepare;
pub(crate) mod selection;
pub(crate) mod surface_refine;
pub(crate) mod topology;
