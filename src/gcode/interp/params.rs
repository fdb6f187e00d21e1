//! Parameters: numbered (`#1` … `#5602`, LinuxCNC's range, which holds FANUC's locals `#1`–`#33`,
//! commons `#100`–`#999` and the system block from `#5000`), named globals (`#<_name>`) and
//! named locals (`#<name>`, one set per subroutine call).
//!
//! A subroutine call saves `#1`–`#30` and the caller's named locals and restores them on
//! return, as LinuxCNC does; the system parameters of offsets and stored positions
//! (`#5161`…`#5390`) are written by the interpreter when the state they mirror changes.

use std::collections::HashMap;

/// Highest numbered parameter (LinuxCNC's `RS274NGC_MAX_PARAMETERS` − 1).
pub const MAX_NUMBERED: usize = 5602;

/// Numbered parameters saved across a call (`#1`–`#30`).
pub const CALL_ARGS: usize = 30;

/// Most named parameters alive at once (globals plus every frame's locals): a program that
/// makes more is refused rather than allowed to fill the memory with names.
pub const MAX_NAMED: usize = 100_000;

/// A parameter number within this of an integer names that parameter (`#[1 + 0.0000001]`).
const INDEX_SLACK: f64 = 1e-6;

/// Why a parameter cannot be read or written.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum ParamError {
    /// A numbered parameter outside 1…5602 (or not an integer).
    #[error("parameter #{0} does not exist; numbered parameters are #0 to #5602")]
    OutOfRange(String),
    /// A named parameter read before any value was given.
    #[error("named parameter #<{0}> has no value yet; set it (#<{0}> = …) before reading it")]
    Undefined(String),
    /// Too many names.
    #[error("more than {MAX_NAMED} named parameters; the program makes names without end")]
    TooMany,
}

/// A parameter as a program names it.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamRef {
    /// `#n`.
    Numbered(usize),
    /// `#<name>` (lower case, spaces removed); global when it starts with `_`.
    Named(String),
}

/// All parameters.
#[derive(Clone, Debug)]
pub struct Params {
    numbered: Vec<f64>,
    globals: HashMap<String, f64>,
    frames: Vec<Frame>,
    named_count: usize,
}

#[derive(Clone, Debug, Default)]
struct Frame {
    locals: HashMap<String, f64>,
    saved_args: [f64; CALL_ARGS],
}

impl Default for Params {
    fn default() -> Self {
        Self {
            numbered: vec![0.0; MAX_NUMBERED + 1],
            globals: HashMap::new(),
            frames: vec![Frame::default()],
            named_count: 0,
        }
    }
}

impl Params {
    /// Checks a computed parameter number (LinuxCNC accepts a value within 1e-6 of an
    /// integer).
    ///
    /// # Errors
    /// [`ParamError::OutOfRange`].
    pub fn index(value: f64) -> Result<usize, ParamError> {
        let r = value.round();
        // #0 is FANUC's vacant variable: it reads as 0 and cannot be set.
        if (value - r).abs() < INDEX_SLACK && (0.0..=MAX_NUMBERED as f64).contains(&r) {
            Ok(r as usize)
        } else {
            Err(ParamError::OutOfRange(crate::numerics::format::fmt_num(value)))
        }
    }

    /// Value of `#n` (unset parameters are 0).
    #[must_use]
    pub fn get(&self, n: usize) -> f64 {
        self.numbered.get(n).copied().unwrap_or(0.0)
    }

    /// Sets `#n` (n already checked by [`Params::index`]).
    pub fn set(&mut self, n: usize, v: f64) {
        if n == 0 {
            return;
        }
        if let Some(slot) = self.numbered.get_mut(n) {
            *slot = v;
        }
    }

    /// Value of a named parameter, `None` when it has none.
    #[must_use]
    pub fn named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.frames.last().and_then(|f| f.locals.get(name).copied())
        }
    }

    /// Sets a named parameter.
    ///
    /// # Errors
    /// [`ParamError::TooMany`].
    pub fn set_named(&mut self, name: &str, v: f64) -> Result<(), ParamError> {
        let map = if name.starts_with('_') {
            &mut self.globals
        } else {
            match self.frames.last_mut() {
                Some(f) => &mut f.locals,
                None => return Ok(()),
            }
        };
        if let Some(slot) = map.get_mut(name) {
            *slot = v;
            return Ok(());
        }
        if self.named_count >= MAX_NAMED {
            return Err(ParamError::TooMany);
        }
        self.named_count += 1;
        map.insert(name.to_owned(), v);
        Ok(())
    }

    /// Writes one parameter.
    ///
    /// # Errors
    /// [`ParamError::TooMany`].
    pub fn assign(&mut self, p: &ParamRef, v: f64) -> Result<(), ParamError> {
        match p {
            ParamRef::Numbered(n) => {
                self.set(*n, v);
                Ok(())
            }
            ParamRef::Named(name) => self.set_named(name, v),
        }
    }

    /// Enters a subroutine: saves `#1`–`#30` and the named locals, then sets the arguments
    /// (`#1` … `#k`; the rest of `#1`–`#30` keep the caller's values, as in LinuxCNC).
    pub fn push_frame(&mut self, args: &[f64]) {
        let mut saved = [0.0; CALL_ARGS];
        saved.copy_from_slice(&self.numbered[1..=CALL_ARGS]);
        self.frames.push(Frame { locals: HashMap::new(), saved_args: saved });
        for (i, a) in args.iter().take(CALL_ARGS).enumerate() {
            self.numbered[i + 1] = *a;
        }
    }

    /// Leaves a subroutine: restores the caller's `#1`–`#30` and named locals.
    pub fn pop_frame(&mut self) {
        if self.frames.len() > 1
            && let Some(f) = self.frames.pop()
        {
            self.named_count = self.named_count.saturating_sub(f.locals.len());
            self.numbered[1..=CALL_ARGS].copy_from_slice(&f.saved_args);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calls_save_and_restore_the_arguments_and_locals() {
        let mut p = Params::default();
        p.set(1, 5.0);
        p.set(31, 7.0);
        p.set_named("a", 1.0).ok();
        p.set_named("_g", 2.0).ok();
        p.push_frame(&[10.0, 20.0]);
        assert_eq!((p.get(1), p.get(2), p.get(31)), (10.0, 20.0, 7.0));
        assert_eq!(p.named("a"), None, "locals are per call");
        assert_eq!(p.named("_g"), Some(2.0), "globals are shared");
        p.set_named("a", 3.0).ok();
        p.set(31, 8.0);
        p.pop_frame();
        assert_eq!((p.get(1), p.get(2), p.get(31)), (5.0, 0.0, 8.0));
        assert_eq!(p.named("a"), Some(1.0));
    }

    #[test]
    fn numbers_must_be_integers_in_range() {
        assert_eq!(Params::index(5.0000001), Ok(5));
        assert!(Params::index(5.1).is_err());
        assert_eq!(Params::index(0.0), Ok(0), "FANUC's vacant #0");
        assert!(Params::index(-1.0).is_err());
        assert!(Params::index(5603.0).is_err());
        assert!(Params::index(f64::NAN).is_err());
    }
}
