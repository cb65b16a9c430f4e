//! Dense indices of nodes and edges.
//!
//! Files name nodes and edges by string ids; inside MUSE they are dense `u32` indices into
//! the [`Airspace`](crate::Airspace) arrays, so that per-element tables are plain vectors.

use std::fmt;

/// Index of a node in an [`Airspace`](crate::Airspace).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeId(pub u32);

/// Index of an edge in an [`Airspace`](crate::Airspace).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct EdgeId(pub u32);

impl NodeId {
    /// The index as `usize`, for indexing vectors.
    ///
    /// ```
    /// assert_eq!(muse_model::NodeId(3).index(), 3);
    /// ```
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

impl EdgeId {
    /// The index as `usize`, for indexing vectors.
    ///
    /// ```
    /// assert_eq!(muse_model::EdgeId(7).index(), 7);
    /// ```
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

impl fmt::Display for NodeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "node#{}", self.0)
    }
}

impl fmt::Display for EdgeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "edge#{}", self.0)
    }
}
