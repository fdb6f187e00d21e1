//! Seed 003: equal-error chord approximation of curves (planar non-circular curves and the
//! crease), compared with equal-interval and equal-step nodes.
