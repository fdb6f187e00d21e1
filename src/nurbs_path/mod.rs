//! Seed 004 (Zhao, Huo & Song): NURBS curve fitting (interpolation and approximation) and
//! real-time NURBS interpolation (advancing the curve parameter each period).
