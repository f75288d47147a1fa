//! Test shapes: the paper's junctions of tubes (§6) and a disc around one vertex of any
//! valence.

pub(crate) mod disc;
pub(crate) mod tubes;
