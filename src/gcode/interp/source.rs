//! Where program lines come from: a [`Source`] hands out one line at a time and can jump back
//! to a line it handed out before (loops, subroutine calls, `GOTO`), so the interpreter never
//! holds the program's text — memory follows the motions, not the file.
//!
//! [`TextSource`] reads a string already in memory (the browser's file, a test);
//! [`ReaderSource`] reads an open file through a buffer (the command line), so a 256 MiB
//! program costs a line buffer, not 256 MiB.

use thiserror::Error;

use crate::numerics::limits::MAX_LINE_BYTES;

/// A position in a source: the byte offset of a line's start and its 1-based number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SourcePos {
    /// Byte offset of the line's first character.
    pub offset: u64,
    /// The line's number (1-based).
    pub line: u32,
}

/// Why a source could not hand out a line.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum SourceError {
    /// A line longer than [`MAX_LINE_BYTES`].
    #[error(
        "the line is longer than {max} characters; a G-code block is far shorter — check that the file is a program"
    )]
    LineTooLong {
        /// The line.
        line: u32,
        /// The cap.
        max: usize,
    },
    /// Bytes that are not UTF-8.
    #[error("the text is not UTF-8 (the program must be plain text: ASCII or UTF-8)")]
    NotUtf8 {
        /// The line.
        line: u32,
    },
    /// The program is larger than the cap on programs.
    #[error("the program is larger than {cap_mib} MiB, the most read; split it or check the path")]
    TooLarge {
        /// The cap (MiB).
        cap_mib: u64,
    },
    /// Reading failed.
    #[error("reading the program failed: {0}")]
    Io(String),
    /// More lines than a line number can count.
    #[error("the program has more than {} lines", u32::MAX)]
    TooManyLines,
}

/// Lines of a program, with the positions to come back to.
pub trait Source {
    /// Reads the next line into `buf` (cleared first; without its line break). Returns the
    /// line's position, or `None` at the end.
    ///
    /// # Errors
    /// [`SourceError`].
    fn next_line(&mut self, buf: &mut String) -> Result<Option<SourcePos>, SourceError>;

    /// The position of the line the next [`Source::next_line`] reads.
    fn tell(&self) -> SourcePos;

    /// Goes back (or forward) to a position a previous [`Source::next_line`] returned: the
    /// next line read is the one starting there.
    ///
    /// # Errors
    /// [`SourceError::Io`] when the underlying reader cannot seek.
    fn seek(&mut self, pos: SourcePos) -> Result<(), SourceError>;
}

/// A program held in a string.
#[derive(Clone, Debug)]
pub struct TextSource<'a> {
    text: &'a str,
    offset: usize,
    line: u32,
}

impl<'a> TextSource<'a> {
    /// Lines of `text`.
    #[must_use]
    pub fn new(text: &'a str) -> Self {
        Self { text, offset: 0, line: 0 }
    }
}

impl Source for TextSource<'_> {
    fn next_line(&mut self, buf: &mut String) -> Result<Option<SourcePos>, SourceError> {
        buf.clear();
        if self.offset >= self.text.len() {
            return Ok(None);
        }
        let rest = &self.text[self.offset..];
        let (body, step) = match rest.find('\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.line = self.line.checked_add(1).ok_or(SourceError::TooManyLines)?;
        let pos = SourcePos { offset: self.offset as u64, line: self.line };
        self.offset += step;
        if body.len() > MAX_LINE_BYTES {
            return Err(SourceError::LineTooLong { line: self.line, max: MAX_LINE_BYTES });
        }
        buf.push_str(body.strip_suffix('\r').unwrap_or(body));
        Ok(Some(pos))
    }

    fn tell(&self) -> SourcePos {
        SourcePos { offset: self.offset as u64, line: self.line.saturating_add(1) }
    }

    fn seek(&mut self, pos: SourcePos) -> Result<(), SourceError> {
        self.offset = (pos.offset as usize).min(self.text.len());
        self.line = pos.line.saturating_sub(1);
        Ok(())
    }
}

/// A program held in a shared string the source owns (the browser's file, read in slices
/// over several frames).
#[derive(Clone, Debug)]
pub struct SharedTextSource {
    text: std::sync::Arc<str>,
    offset: usize,
    line: u32,
}

impl SharedTextSource {
    /// Lines of `text`.
    #[must_use]
    pub fn new(text: std::sync::Arc<str>) -> Self {
        Self { text, offset: 0, line: 0 }
    }

    /// Its length in bytes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.text.len()
    }

    /// Whether it is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.text.is_empty()
    }
}

impl Source for SharedTextSource {
    fn next_line(&mut self, buf: &mut String) -> Result<Option<SourcePos>, SourceError> {
        let mut t = TextSource { text: &self.text, offset: self.offset, line: self.line };
        let r = t.next_line(buf);
        self.offset = t.offset;
        self.line = t.line;
        r
    }

    fn tell(&self) -> SourcePos {
        SourcePos { offset: self.offset as u64, line: self.line.saturating_add(1) }
    }

    fn seek(&mut self, pos: SourcePos) -> Result<(), SourceError> {
        self.offset = (pos.offset as usize).min(self.text.len());
        self.line = pos.line.saturating_sub(1);
        Ok(())
    }
}

/// A program read through a buffered reader that can seek (an open file), at most
/// `cap` bytes.
#[derive(Debug)]
pub struct ReaderSource<R> {
    reader: R,
    offset: u64,
    line: u32,
    cap: u64,
}

impl<R: std::io::BufRead + std::io::Seek> ReaderSource<R> {
    /// Lines of `reader`, refusing to read past `cap` bytes.
    pub fn new(reader: R, cap: u64) -> Self {
        Self { reader, offset: 0, line: 0, cap }
    }

    /// Reads up to the next newline (kept) or one byte more than the longest line into
    /// `bytes`; returns the bytes read (0 at the end of the file).
    fn read_line(&mut self, bytes: &mut Vec<u8>) -> Result<usize, SourceError> {
        // One byte more than the longest line tells a line too long without reading it all.
        let limit = MAX_LINE_BYTES + 2;
        let mut n = 0;
        loop {
            let avail = match self.reader.fill_buf() {
                Ok(a) => a,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(SourceError::Io(e.to_string())),
            };
            if avail.is_empty() {
                return Ok(n);
            }
            let avail = &avail[..avail.len().min(limit - n)];
            let (used, ended) = match avail.iter().position(|&c| c == b'\n') {
                Some(at) => (at + 1, true),
                None => (avail.len(), false),
            };
            bytes.extend_from_slice(&avail[..used]);
            self.reader.consume(used);
            n += used;
            if ended || n == limit {
                return Ok(n);
            }
        }
    }

    /// After `n` bytes read into `bytes`: the line's position, its end of line taken off.
    fn line_end(&mut self, bytes: &mut Vec<u8>, n: usize) -> Result<Option<SourcePos>, SourceError> {
        if n == 0 {
            return Ok(None);
        }
        self.line = self.line.checked_add(1).ok_or(SourceError::TooManyLines)?;
        let pos = SourcePos { offset: self.offset, line: self.line };
        self.offset += n as u64;
        if self.offset > self.cap {
            return Err(SourceError::TooLarge { cap_mib: self.cap >> 20 });
        }
        if bytes.last() == Some(&b'\n') {
            bytes.pop();
        } else if n == MAX_LINE_BYTES + 2 {
            return Err(SourceError::LineTooLong { line: self.line, max: MAX_LINE_BYTES });
        }
        if bytes.last() == Some(&b'\r') {
            bytes.pop();
        }
        if bytes.len() > MAX_LINE_BYTES {
            return Err(SourceError::LineTooLong { line: self.line, max: MAX_LINE_BYTES });
        }
        Ok(Some(pos))
    }
}

impl<R: std::io::BufRead + std::io::Seek> Source for ReaderSource<R> {
    fn next_line(&mut self, buf: &mut String) -> Result<Option<SourcePos>, SourceError> {
        // The line is read straight into `buf`'s bytes and checked as UTF-8 once, in place.
        let mut bytes = std::mem::take(buf).into_bytes();
        bytes.clear();
        let r = self.read_line(&mut bytes);
        let r = r.and_then(|n| self.line_end(&mut bytes, n));
        if r.is_err() {
            bytes.clear();
        }
        match String::from_utf8(bytes) {
            Ok(s) => {
                *buf = s;
                r
            }
            Err(e) => {
                let mut bytes = e.into_bytes();
                bytes.clear();
                *buf = String::from_utf8(bytes).unwrap_or_default();
                Err(SourceError::NotUtf8 { line: self.line })
            }
        }
    }

    fn tell(&self) -> SourcePos {
        SourcePos { offset: self.offset, line: self.line.saturating_add(1) }
    }

    fn seek(&mut self, pos: SourcePos) -> Result<(), SourceError> {
        self.reader.seek(std::io::SeekFrom::Start(pos.offset)).map_err(|e| SourceError::Io(e.to_string()))?;
        self.offset = pos.offset;
        self.line = pos.line.saturating_sub(1);
        Ok(())
    }
}

/// Finds the files a program calls by name (`o<name> call` → `name.ngc`; FANUC `M98 P1234`
/// → `O1234` when it is not in the same file): the directory of the program on the command
/// line, the files dropped together in the browser.
pub trait Library<'a> {
    /// The source of the subroutine file `name` (lower case, as the program calls it, e.g.
    /// `o<drill> call` asks for `drill`), or `None` when there is none.
    fn open(&mut self, name: &str) -> Option<Box<dyn Source + 'a>>;
}

/// No subroutine files.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoLibrary;

impl<'a> Library<'a> for NoLibrary {
    fn open(&mut self, _name: &str) -> Option<Box<dyn Source + 'a>> {
        None
    }
}

/// Subroutine files held in memory, by name without extension (lower case).
#[derive(Clone, Debug, Default)]
pub struct TextLibrary<'a> {
    files: Vec<(String, &'a str)>,
}

impl<'a> TextLibrary<'a> {
    /// An empty library.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file by its file name (`drill.ngc`, `O1234.nc`): the name without extension,
    /// lower case, is what a call finds.
    pub fn add(&mut self, file_name: &str, text: &'a str) {
        let stem = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name);
        let stem = stem.rsplit_once('.').map_or(stem, |(s, _)| s);
        self.files.push((stem.to_ascii_lowercase(), text));
    }
}

impl<'a> Library<'a> for TextLibrary<'a> {
    fn open(&mut self, name: &str) -> Option<Box<dyn Source + 'a>> {
        let name = name.to_ascii_lowercase();
        self.files.iter().find(|(n, _)| *n == name).map(|(_, t)| Box::new(TextSource::new(t)) as Box<dyn Source + 'a>)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(src: &mut dyn Source) -> Vec<(u32, String)> {
        let mut out = Vec::new();
        let mut buf = String::new();
        while let Ok(Some(p)) = src.next_line(&mut buf) {
            out.push((p.line, buf.clone()));
        }
        out
    }

    #[test]
    fn text_and_reader_sources_agree_and_seek_back() {
        let text = "G0 X1\r\n\nG1 X2 (é)\nM2";
        let mut a = TextSource::new(text);
        let mut b = ReaderSource::new(std::io::Cursor::new(text.as_bytes()), 1 << 20);
        let la = lines(&mut a);
        assert_eq!(la, lines(&mut b));
        assert_eq!(la, vec![(1, "G0 X1".into()), (2, String::new()), (3, "G1 X2 (é)".into()), (4, "M2".into())]);
        let mut buf = String::new();
        let mut c = TextSource::new(text);
        c.next_line(&mut buf).ok();
        let second = c.next_line(&mut buf).ok().flatten().unwrap_or_default();
        c.next_line(&mut buf).ok();
        c.seek(second).ok();
        assert_eq!(c.next_line(&mut buf).ok().flatten().map(|p| p.line), Some(2));
    }

    #[test]
    fn long_lines_and_big_files_are_refused() {
        let long = "X".repeat(MAX_LINE_BYTES + 10);
        let mut buf = String::new();
        let r = TextSource::new(&long).next_line(&mut buf);
        assert!(matches!(r, Err(SourceError::LineTooLong { line: 1, .. })), "{r:?}");
        let r = ReaderSource::new(std::io::Cursor::new(long.as_bytes()), 1 << 30).next_line(&mut buf);
        assert!(matches!(r, Err(SourceError::LineTooLong { line: 1, .. })), "{r:?}");
        let small = "G0 X1\n".repeat(100);
        let mut s = ReaderSource::new(std::io::Cursor::new(small.as_bytes()), 50);
        let mut err = None;
        for _ in 0..100 {
            if let Err(e) = s.next_line(&mut buf) {
                err = Some(e);
                break;
            }
        }
        assert_eq!(err, Some(SourceError::TooLarge { cap_mib: 0 }));
    }
}
