//! Seed 002 (Ji, Zhou, An & Zhang, 2010): five-axis machines, the nonlinear error of
//! linear joint interpolation, and tool-step selection along a path.
