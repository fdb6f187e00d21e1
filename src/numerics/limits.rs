//! Size limits on what the program reads and how much work one request may ask for.
//!
//! Every file the command line and the app read is read through a size cap, so a wrong
//! path (`/dev/zero`, a video) is refused with a message instead of filling the memory, and
//! work whose amount follows from the input (periods, samples) is estimated and refused
//! before it starts when it exceeds a cap. The caps are far above any real scene or
//! program: they bound the damage of a mistake, not the size of honest work.

/// Largest scene file read (bytes, 64 MiB): a NURBS scene with a million control points
/// written out in full decimal is about 60 MB.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// Largest G-code program read (bytes, 256 MiB): about eight million G01 lines.
pub const MAX_PROGRAM_BYTES: u64 = 256 << 20;

/// Most nodes of an arc-length table (`nurbs_path::measure::ArcLengthTable`): about 16 MB
/// of table. A crease of 200 000 periods needs about 4 nodes per period at the table's 1e-8
/// relative accuracy; past the budget, cells are accepted as they are (the lengths are
/// then accurate to the Gauss rule on the cell, still far below any output resolution).
pub const MAX_ARC_TABLE_NODES: usize = 1 << 20;

/// Most moves `replay --scene`/`--profile` measures against a design (each move's pieces
/// are sampled and searched: about 12 s for a million lines on the development machine,
/// 22 s for 100 000 full circles); the program is refused after reading that many, or
/// when its weighted count ([`DEVIATION_CURVE_WEIGHT`]) passes it, before measuring.
pub const MAX_DEVIATION_MOVES: usize = 1_200_000;

/// What one arc or curve (G02, G03, G06.2) costs `replay --scene` in straight moves (a
/// full circle measured against a design: about 20× a line's work).
pub const DEVIATION_CURVE_WEIGHT: usize = 20;

/// Most samples a G-code check (`gcode::replay::deviation`) takes of the program and the
/// design together (about 50 MB of samples and their grid): past it the sample spacing
/// grows, and the spacing used is reported with the result.
pub const MAX_REPLAY_SAMPLES: usize = 1_000_000;

/// Longest line of a G-code program (bytes): a block is rarely over a hundred characters
/// (LinuxCNC's own limit is 255); beyond this the file is not a program, and one huge line
/// is refused instead of being held in memory.
pub const MAX_LINE_BYTES: usize = 64 << 10;

/// Largest |coordinate| of a scene's `path.start` and `path.end` (mm): a kilometre, past any
/// machine's travel. Beyond it, the squares and cross products of the crease solve lose all
/// precision or overflow (z = 1e308 would square to infinity).
pub const MAX_COORDINATE_MM: f64 = 1e6;

/// Largest programmed feed a G-code program is written with (mm/min): a kilometre a minute,
/// beyond any machine.
pub const MAX_FEED_MM_PER_MIN: f64 = 1e6;

/// Most repeats (L) one canned-cycle block may ask for: a hundred thousand holes in a row is
/// far past any real drilling pattern (`gcode::interp::cycles`).
pub const MAX_CYCLE_REPEATS: u32 = 100_000;

/// Most pecks of one G73/G83 hole (depth / Q): a 1 m deep hole in 10 µm pecks.
pub const MAX_CYCLE_PECKS: usize = 100_000;

/// Most moves one canned-cycle block may expand to (all repeats and pecks together), checked
/// before the first move: about 100 MB of moves.
pub const MAX_CYCLE_MOVES: usize = 2_000_000;

/// Most tools one tool table may hold (`gcode::interp::tools`): LinuxCNC's pockets go to
/// 1000; ten times that bounds a mistaken file, not a real changer.
pub const MAX_TOOLS: usize = 10_000;

/// Largest tool table read (bytes, 16 MiB): ten thousand tools with long remarks are about
/// 2 MB.
pub const MAX_TOOL_TABLE_BYTES: u64 = 16 << 20;

/// Most characters of text in one comment of a written program
/// ([`crate::gcode::comment::safe_comment`]; longer text is cut, ending in `...`), and of a
/// user's text on one comment line of a CSV output ([`crate::report::csv_comment_text`]). A
/// comment line is then at most 202 characters, under LinuxCNC's 256-character line and
/// Sinumerik's 512; every name of the presets and examples fits whole.
pub const MAX_COMMENT_CHARS: usize = 200;

/// Why a file's bytes are not usable as text.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TextError {
    /// The file is larger than the cap.
    #[error(
        "the file is larger than {cap_mib} MiB, the most this command reads; check the path (a {what} is far smaller)"
    )]
    TooLarge {
        /// The cap (MiB).
        cap_mib: u64,
        /// What kind of file was expected ("scene", "G-code program").
        what: &'static str,
    },
    /// Not UTF-8: the 1-based line and byte column of the first invalid byte.
    #[error("line {line}: byte {column} is not UTF-8 text (the file must be plain text: ASCII or UTF-8)")]
    NotUtf8 {
        /// Line (1-based).
        line: usize,
        /// Byte column in that line (1-based).
        column: usize,
    },
}

/// Turns bytes into text, naming the line of the first byte that is not UTF-8.
///
/// # Errors
/// [`TextError::NotUtf8`].
pub fn text_from_bytes(bytes: Vec<u8>) -> Result<String, TextError> {
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let head = &e.as_bytes()[..valid];
        let line = head.iter().filter(|&&b| b == b'\n').count() + 1;
        let column = valid - head.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1) + 1;
        TextError::NotUtf8 { line, column }
    })
}

/// Reads at most `cap` bytes from `reader` (an opened file) as UTF-8 text: one byte past
/// the cap is read to tell a file of exactly `cap` bytes from a larger one, never more.
///
/// # Errors
/// An I/O error's text, [`TextError::TooLarge`] or [`TextError::NotUtf8`], as one line.
pub fn read_text(reader: impl std::io::Read, cap: u64, what: &'static str) -> Result<String, String> {
    use std::io::Read;
    let mut bytes = Vec::new();
    reader.take(cap.saturating_add(1)).read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    check_size(bytes.len(), cap, what).map_err(|e| e.to_string())?;
    text_from_bytes(bytes).map_err(|e| e.to_string())
}

/// Refuses `len` bytes above `cap`.
///
/// # Errors
/// [`TextError::TooLarge`].
pub fn check_size(len: usize, cap: u64, what: &'static str) -> Result<(), TextError> {
    if len as u64 > cap { Err(TextError::TooLarge { cap_mib: cap >> 20, what }) } else { Ok(()) }
}

/// Most points of a finishing scene's start curve (`finish.start.curve`): a curve a user
/// picks or sketches has tens of points; each is one vertex of the first path.
pub const MAX_START_CURVE_POINTS: usize = 1000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_utf8_names_its_line_and_column() {
        let bytes = b"G01 X1\nG01 Y2\nG01 \xffZ3\n".to_vec();
        assert_eq!(text_from_bytes(bytes), Err(TextError::NotUtf8 { line: 3, column: 5 }));
        assert_eq!(text_from_bytes(b"\xfe".to_vec()), Err(TextError::NotUtf8 { line: 1, column: 1 }));
        assert_eq!(text_from_bytes(b"ok\n".to_vec()).as_deref(), Ok("ok\n"));
    }

    #[test]
    fn sizes_above_the_cap_are_refused() {
        assert!(check_size(10, 10, "scene").is_ok());
        assert!(check_size(11, 10, "scene").is_err());
        assert_eq!(
            check_size((64 << 20) + 1, 64 << 20, "scene"),
            Err(TextError::TooLarge { cap_mib: 64, what: "scene" })
        );
    }

    #[test]
    fn an_endless_reader_stops_at_the_cap() {
        let e = read_text(std::io::repeat(0), 1 << 20, "scene").err().unwrap_or_default();
        assert!(e.contains("larger than 1 MiB") && e.contains("a scene is far smaller"), "{e}");
        assert_eq!(read_text(&b"exactly"[..], 7, "scene").as_deref(), Ok("exactly"));
        assert!(read_text(&b"exactly!"[..], 7, "scene").is_err());
    }
}

/// The share of one command's work its parts have left, when one command runs several
/// bounded parts in turn (`finish --gcode`: a finishing job's paths, then its program's
/// planning; `simulate --finish`: those, then the simulation's run). Each part has a cap of
/// its own (check cells, design evaluations, ray updates), each about the work of a whole
/// command; alone each bounds its part, but not their sum. So what a part spent, as a share
/// of its own cap, is taken from what the next ones may spend: the next part's cap is its
/// own times the share left ([`CommandShare::cap`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommandShare {
    left: f64,
}

impl Default for CommandShare {
    fn default() -> Self {
        Self::whole()
    }
}

impl CommandShare {
    /// A command with nothing spent yet.
    #[must_use]
    pub const fn whole() -> Self {
        Self { left: 1.0 }
    }

    /// Takes `spent` of a part whose cap is `cap` (the same unit) from the share left. A
    /// cap that is not a positive number takes nothing; the share never goes below 0.
    pub fn spend(&mut self, spent: f64, cap: f64) {
        if cap > 0.0 && spent > 0.0 {
            self.left = (self.left - spent / cap).max(0.0);
        }
    }

    /// The share of the command's work left, in [0, 1].
    #[must_use]
    pub fn left(&self) -> f64 {
        self.left
    }

    /// The cap of the next part whose own cap is `cap`: `cap` times the share left.
    #[must_use]
    pub fn cap(&self, cap: f64) -> f64 {
        cap * self.left
    }
}
