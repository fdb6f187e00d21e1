//! A CC node: one point of a finishing path with its cutter location — the unit the paths
//! ([`super::paths`]), the swept-cutter measures ([`super::sweep`]) and the programs
//! ([`super::program`]) share.

use glam::DVec3;

use super::contact::{ContactFrame, Pose};
use super::gouge::Adjustment;

/// One CC point of a path with its cutter location.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcNode {
    /// The local frame (CC point, normal, feed).
    pub frame: ContactFrame,
    /// The orientation.
    pub pose: Pose,
    /// Tool tip (mm, workpiece coordinates).
    pub tip: DVec3,
    /// Unit tool axis.
    pub axis: DVec3,
    /// Width of the strip within the scallop height h (mm).
    pub strip_mm: f64,
    /// Side step to the next path from this node (mm), if solved here.
    pub side_step_mm: Option<f64>,
    /// Scallop to the next path at this node (mm): the cusp measured between the two paths
    /// built from their swept cutters, or, where none could be, as the side step solved it.
    pub scallop_mm: Option<f64>,
    /// What the gouge checks changed, if anything.
    pub adjusted: Option<Adjustment>,
    /// A lead-out past the path's end or a lead-in before its start, not a CC point: the
    /// last (first) node's cutter moved on (back) along its feed with the surface's
    /// continuation (`frame` moved and turned with it by `paths::lead_out_frame`, off the surface,
    /// `frame.uv` the edge's). See `paths::lead_out_mm`.
    pub lead_out: bool,
}
