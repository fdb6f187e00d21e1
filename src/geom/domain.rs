//! Parameter domains of surfaces, with periodic (full-turn) directions.

use std::f64::consts::TAU;

use crate::numerics::tolerance;

/// What a surface parameter measures; decides how it is written in scene and output files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamUnit {
    /// An angle: radians inside the core, degrees in files and UI.
    Angle,
    /// A length in mm (plane and cylinder-axis parameters).
    Length,
    /// A NURBS knot parameter (dimensionless).
    Knot,
}

impl ParamUnit {
    /// Converts an internal value to the file unit (degrees for angles).
    #[must_use]
    pub fn to_file(self, internal: f64) -> f64 {
        match self {
            Self::Angle => internal.to_degrees(),
            Self::Length | Self::Knot => internal,
        }
    }

    /// Converts a file value (degrees for angles) to the internal unit.
    #[must_use]
    pub fn from_file(self, file: f64) -> f64 {
        match self {
            Self::Angle => file.to_radians(),
            Self::Length | Self::Knot => file,
        }
    }

    /// Unit suffix for display ("°", "mm", "").
    #[must_use]
    pub fn suffix(self) -> &'static str {
        match self {
            Self::Angle => "°",
            Self::Length => "mm",
            Self::Knot => "",
        }
    }
}

/// One parameter's range `[min, max]` in internal units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamRange {
    /// Lower end (internal units).
    pub min: f64,
    /// Upper end (internal units).
    pub max: f64,
    /// Whether the parameter wraps around (an angular range of exactly one full turn).
    pub periodic: bool,
    /// What the parameter measures.
    pub unit: ParamUnit,
}

impl ParamRange {
    /// A range; an angular range of one full turn (to 1e-9 rad) is made periodic.
    #[must_use]
    pub fn new(min: f64, max: f64, unit: ParamUnit) -> Self {
        let periodic =
            unit == ParamUnit::Angle && ((max - min) - TAU).abs() < crate::numerics::tolerance::FULL_TURN_SLACK_RAD;
        Self { min, max, periodic, unit }
    }

    /// Width of the range (internal units).
    #[must_use]
    pub fn width(&self) -> f64 {
        self.max - self.min
    }

    /// Middle of the range.
    #[must_use]
    pub fn mid(&self) -> f64 {
        0.5 * (self.min + self.max)
    }

    /// Brings a periodic value back into `[min, max)`; other values are returned unchanged.
    #[must_use]
    pub fn wrap(&self, x: f64) -> f64 {
        if self.periodic && (x < self.min || x >= self.max) {
            let w = self.width();
            let y = self.min + (x - self.min).rem_euclid(w);
            if y >= self.max { self.min } else { y }
        } else {
            x
        }
    }

    /// Whether `x` lies in the range (always true for a periodic range), allowing rounding
    /// slack at the ends.
    #[must_use]
    pub fn contains(&self, x: f64) -> bool {
        if self.periodic {
            return x.is_finite();
        }
        let slack = tolerance::DOMAIN_SLACK * self.width().max(1.0);
        x >= self.min - slack && x <= self.max + slack
    }

    /// Clamps a non-periodic value into the range; wraps a periodic one.
    #[must_use]
    pub fn clamp(&self, x: f64) -> f64 {
        if self.periodic { self.wrap(x) } else { x.clamp(self.min, self.max) }
    }
}

/// Rectangular parameter domain `u × v` of a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    /// Range of u.
    pub u: ParamRange,
    /// Range of v.
    pub v: ParamRange,
}

impl Domain {
    /// Wraps periodic parameters into range.
    #[must_use]
    pub fn wrap(&self, uv: glam::DVec2) -> glam::DVec2 {
        glam::DVec2::new(self.u.wrap(uv.x), self.v.wrap(uv.y))
    }

    /// Whether both parameters lie in the domain.
    #[must_use]
    pub fn contains(&self, uv: glam::DVec2) -> bool {
        self.u.contains(uv.x) && self.v.contains(uv.y)
    }

    /// Clamps (or wraps) both parameters into the domain.
    #[must_use]
    pub fn clamp(&self, uv: glam::DVec2) -> glam::DVec2 {
        glam::DVec2::new(self.u.clamp(uv.x), self.v.clamp(uv.y))
    }

    /// Internal parameters → file units (degrees for angles).
    #[must_use]
    pub fn to_file(&self, uv: glam::DVec2) -> glam::DVec2 {
        glam::DVec2::new(self.u.unit.to_file(uv.x), self.v.unit.to_file(uv.y))
    }
}
