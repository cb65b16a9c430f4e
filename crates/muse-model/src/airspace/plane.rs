//! Where an airspace's nodes are in its local metric plane (docs/reference.md#metric-separation):
//! the positions metric separation is planned and checked in.

use std::sync::Arc;

use super::{Airspace, AirspaceError};
use crate::frame::LocalFrame;

impl Airspace {
    /// This airspace with its flat nodes placed in its local metric plane (metres east and
    /// north, `plane[n]` for flat node `n`): the positions metric separation
    /// (docs/reference.md#metric-separation) is planned and checked in. The layers above share
    /// the flat nodes' positions.
    ///
    /// ```
    /// use muse_model::Airspace;
    /// let a = Airspace::line(&[1_000.0, 500.0]);
    /// assert_eq!(a.plane()[2], [1_500.0, 0.0]);
    /// let moved = a.with_plane(vec![[0.0, 0.0], [0.0, 1_000.0], [0.0, 1_500.0]]).unwrap();
    /// assert_eq!(moved.plane()[1], [0.0, 1_000.0]);
    /// assert!(moved.with_plane(vec![[0.0, 0.0]]).is_err());
    /// ```
    ///
    /// # Errors
    /// [`AirspaceError::Plane`] if `plane` does not hold one finite position per flat node.
    pub fn with_plane(mut self, plane: Vec<[f64; 2]>) -> Result<Airspace, AirspaceError> {
        let flat = self.flat().node_count();
        if plane.len() != flat || plane.iter().flatten().any(|c| !c.is_finite()) {
            return Err(AirspaceError::Plane {
                given: plane.len(),
                nodes: flat,
            });
        }
        let plane: Arc<[[f64; 2]]> = plane.into();
        if let Some(layout) = &mut self.layout {
            layout.base.plane = Some(Arc::clone(&plane));
        }
        self.plane = Some(plane);
        Ok(self)
    }

    /// Where the flat nodes are in the airspace's local metric plane, metres east and north:
    /// as set by [`Airspace::with_plane`], or else the plane tangent to the ellipsoid at the
    /// nodes' centre ([`LocalFrame::around`]).
    pub fn plane(&self) -> std::borrow::Cow<'_, [[f64; 2]]> {
        let flat = self.flat();
        if let Some(p) = &flat.plane {
            return std::borrow::Cow::Borrowed(p);
        }
        let frame = LocalFrame::around(flat.nodes.iter().map(|n| n.pos));
        std::borrow::Cow::Owned(
            flat.nodes
                .iter()
                .map(|n| {
                    let (x, y) = frame.to_xy(n.pos);
                    [x, y]
                })
                .collect(),
        )
    }
}
