//! Layer data on the GPU: growable buffers that send only the bytes that changed, and the
//! vertex data of a line layer.

use eframe::egui_wgpu::wgpu;

use crate::render::geometry::LineSegment;

/// A growable GPU buffer of `count` elements.
pub(super) struct GpuArray {
    /// The buffer.
    pub(super) buffer: wgpu::Buffer,
    /// Its size (bytes).
    capacity_bytes: u64,
    /// Elements it holds.
    pub(super) count: u32,
    /// Its label.
    label: &'static str,
    /// Its usage (`COPY_DST` added).
    usage: wgpu::BufferUsages,
    /// The bytes the buffer holds (its first `shadow.len()` bytes), kept on the CPU so a
    /// write sends only the range that differs: the same data again (a layer rebuilt with
    /// nothing changed, the unchanged index buffer of a mesh whose heights changed) sends
    /// nothing and leaves the view's image valid.
    shadow: Vec<u8>,
    /// Bytes sent by the last write that changed something (for `?hide=marks`).
    pub(super) sent_bytes: usize,
}

/// Bytes compared at a time when looking for the first or last difference (a slice
/// comparison per chunk, then byte by byte inside the chunk that differs).
const DIFF_CHUNK_BYTES: usize = 256;

/// The first index below `min(a.len(), b.len())` where `a` and `b` differ.
fn first_difference(a: &[u8], b: &[u8]) -> Option<usize> {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let chunk = a.chunks(DIFF_CHUNK_BYTES).zip(b.chunks(DIFF_CHUNK_BYTES)).position(|(x, y)| x != y)?;
    let from = chunk * DIFF_CHUNK_BYTES;
    a[from..].iter().zip(&b[from..]).position(|(x, y)| x != y).map(|i| from + i)
}

/// The last index below `min(a.len(), b.len())` where `a` and `b` differ.
fn last_difference(a: &[u8], b: &[u8]) -> Option<usize> {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let chunk = a.rchunks(DIFF_CHUNK_BYTES).zip(b.rchunks(DIFF_CHUNK_BYTES)).position(|(x, y)| x != y)?;
    let to = n - chunk * DIFF_CHUNK_BYTES;
    let from = to.saturating_sub(DIFF_CHUNK_BYTES);
    a[from..to].iter().zip(&b[from..to]).rposition(|(x, y)| x != y).map(|i| from + i)
}

/// The byte range of `new` to send to a buffer holding `old` so that it holds `new`, the
/// first `known_same` bytes being known equal (rounded to whole 4-byte words, as
/// `write_buffer` wants); `None` if nothing differs.
fn changed_range(old: &[u8], new: &[u8], known_same: usize) -> Option<std::ops::Range<usize>> {
    let skip = known_same.min(old.len()).min(new.len());
    let common = old.len().min(new.len());
    let first = first_difference(&old[skip..common], &new[skip..common]).map(|i| skip + i);
    let last = last_difference(&old[skip..common], &new[skip..common]).map(|i| skip + i);
    let grown = new.len() > common;
    let (start, end) = match (first, last) {
        (Some(f), _) if grown => (f, new.len()),
        (Some(f), Some(l)) => (f, l + 1),
        _ if grown => (common, new.len()),
        _ => return None,
    };
    let start = start & !3;
    let end = end.next_multiple_of(4).min(new.len());
    Some(start..end)
}

impl GpuArray {
    /// An empty array with room for `capacity_bytes` (at least 64).
    pub(super) fn with_capacity(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
        capacity_bytes: usize,
    ) -> Self {
        let size = (capacity_bytes as u64).max(64).next_multiple_of(4);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { buffer, capacity_bytes: size, count: 0, label, usage, shadow: Vec::new(), sent_bytes: 0 }
    }

    /// Writes `bytes` (all `count` elements), sending only the range that differs from what
    /// the buffer holds; the first `unchanged_prefix_bytes` are known to be the same (the
    /// path grows by appending) and are not compared. Returns whether the contents changed
    /// (false: the same data again, nothing sent).
    pub(super) fn write(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        bytes: &[u8],
        count: u32,
        unchanged_prefix_bytes: u64,
    ) -> bool {
        self.sent_bytes = 0;
        if bytes.len() as u64 > self.capacity_bytes {
            *self = Self::with_capacity(device, self.label, self.usage, bytes.len() * 3 / 2);
            queue.write_buffer(&self.buffer, 0, bytes);
            self.shadow.extend_from_slice(bytes);
            self.sent_bytes = bytes.len();
            self.count = count;
            return true;
        }
        let known_same = usize::try_from(unchanged_prefix_bytes).unwrap_or(usize::MAX);
        let range = changed_range(&self.shadow, bytes, known_same);
        if range.is_none() && count == self.count {
            return false;
        }
        self.shadow.resize(bytes.len(), 0);
        self.sent_bytes = range.as_ref().map_or(0, std::ops::Range::len);
        if let Some(r) = range.filter(|r| !r.is_empty()) {
            // write_buffer needs a multiple of 4 bytes; vertex data always is.
            queue.write_buffer(&self.buffer, r.start as u64, &bytes[r.clone()]);
            self.shadow[r.clone()].copy_from_slice(&bytes[r]);
        }
        self.count = count;
        true
    }

    /// Bytes the buffer is known to hold (its CPU copy).
    pub(super) fn held_bytes(&self) -> usize {
        self.shadow.len()
    }

    /// Writes contents made of the buffer's own first `prefix_bytes` (at most
    /// [`GpuArray::held_bytes`]) followed by `tail`, `count` elements in all: a layer that
    /// grew by appending passes only what follows the part already sent, which is neither
    /// copied nor compared. Returns whether the contents changed.
    pub(super) fn write_tail(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        prefix_bytes: usize,
        tail: &[u8],
        count: u32,
    ) -> bool {
        let prefix = prefix_bytes.min(self.shadow.len());
        let len = prefix + tail.len();
        if len as u64 > self.capacity_bytes {
            // A bigger buffer holds nothing: all of it is sent.
            let mut all = std::mem::take(&mut self.shadow);
            all.truncate(prefix);
            all.extend_from_slice(tail);
            *self = Self::with_capacity(device, self.label, self.usage, len * 3 / 2);
            queue.write_buffer(&self.buffer, 0, &all);
            self.sent_bytes = all.len();
            self.shadow = all;
            self.count = count;
            return true;
        }
        self.sent_bytes = 0;
        let range = changed_range(&self.shadow[prefix..], tail, 0);
        if range.is_none() && count == self.count && len == self.shadow.len() {
            return false;
        }
        self.shadow.resize(len, 0);
        if let Some(r) = range.filter(|r| !r.is_empty()) {
            let at = prefix + r.start;
            queue.write_buffer(&self.buffer, at as u64, &tail[r.clone()]);
            self.shadow[at..prefix + r.end].copy_from_slice(&tail[r.clone()]);
            self.sent_bytes = r.len();
        }
        self.count = count;
        true
    }
}

/// A mesh layer's buffers.
pub(super) struct MeshBuffers {
    /// Its vertices.
    pub(super) vertices: GpuArray,
    /// Its triangles' indices.
    pub(super) indices: GpuArray,
}

/// Vertices of a line segment's quad (two triangles; `vs_line` in scene.wgsl).
pub(super) const LINE_CORNERS: usize = 6;

/// The vertex data of a line layer: each segment once per corner of its quad, in order, so
/// vertex `i` belongs to segment `i / LINE_CORNERS` and is its corner `i % LINE_CORNERS`.
pub(super) fn per_corner(lines: &[LineSegment], out: &mut Vec<LineSegment>) {
    out.clear();
    out.extend(lines.iter().flat_map(|l| std::iter::repeat_n(*l, LINE_CORNERS)));
}

#[cfg(test)]
mod tests {
    use super::{LINE_CORNERS, changed_range, per_corner};
    use crate::render::geometry::LineSegment;

    /// A small deterministic generator (xorshift) for the byte patterns below.
    fn bytes(seed: &mut u64, n: usize) -> Vec<u8> {
        (0..n)
            .map(|_| {
                *seed ^= *seed << 13;
                *seed ^= *seed >> 7;
                *seed ^= *seed << 17;
                (*seed >> 56) as u8
            })
            .collect()
    }

    #[test]
    fn the_changed_range_makes_the_old_contents_the_new_and_starts_at_the_first_difference() {
        let mut seed = 0x9E37_79B9_7F4A_7C15;
        for case in 0..400 {
            let n_old = 4 * (case % 7) * (1 + case % 300);
            let old = bytes(&mut seed, n_old);
            let mut new = old.clone();
            // Grow, shrink or keep the length, then change a few bytes (or none).
            let n_new = match case % 3 {
                0 => n_old + 4 * (case % 5),
                1 => n_old - 4 * (case % 5).min(n_old / 4),
                _ => n_old,
            };
            new.resize(n_new, 0);
            let tail = bytes(&mut seed, n_new.saturating_sub(n_old));
            new[n_old.min(n_new)..].copy_from_slice(&tail);
            let changes = case % 4;
            for k in 0..changes {
                if n_new > 0 {
                    let at = (case * 7919 + k * 104_729) % n_new;
                    new[at] = new[at].wrapping_add(1);
                }
            }
            let first = (0..n_old.min(n_new)).find(|&i| old[i] != new[i]).or((n_new > n_old).then_some(n_old));
            let last = (0..n_old.min(n_new)).rev().find(|&i| old[i] != new[i]);
            match changed_range(&old, &new, 0) {
                None => assert_eq!(first, None, "case {case}: a difference was missed"),
                Some(r) => {
                    let f = first.expect("a range only where something differs");
                    assert_eq!(r.start, f & !3, "case {case}: starts at the first difference's word");
                    assert_eq!(r.start % 4, 0, "case {case}");
                    assert!(r.end % 4 == 0 && r.end <= n_new, "case {case}: {r:?} of {n_new}");
                    if n_new <= n_old {
                        assert_eq!(r.end, (last.expect("a last difference") + 1).next_multiple_of(4), "case {case}");
                    }
                    // Applying the range to the old contents gives the new ones.
                    let mut held = old.clone();
                    held.resize(n_new, 0);
                    held[r.clone()].copy_from_slice(&new[r]);
                    assert_eq!(held, new, "case {case}");
                }
            }
        }
    }

    #[test]
    fn a_known_same_prefix_is_not_compared() {
        let old = vec![1u8; 64];
        let mut new = old.clone();
        new[8] = 9; // inside the prefix said to be the same: not looked at
        new[40] = 9;
        assert_eq!(changed_range(&old, &new, 16), Some(40..44));
        assert_eq!(changed_range(&old, &old, 0), None);
        let mut longer = old.clone();
        longer.extend_from_slice(&[7; 8]);
        assert_eq!(changed_range(&old, &longer, 0), Some(64..72), "only the appended tail");
        assert_eq!(changed_range(&old, &old[..32], 0), None, "a shorter prefix sends nothing");
    }

    #[test]
    fn each_line_vertex_carries_its_segment() {
        let lines: Vec<LineSegment> = (0..5u8)
            .map(|i| LineSegment::new([f32::from(i), 0.0, 0.0], [0.0, f32::from(i), 1.0], 1.0 + f32::from(i), [1.0; 4]))
            .collect();
        let mut out = vec![LineSegment::default(); 3];
        per_corner(&lines, &mut out);
        assert_eq!(out.len(), lines.len() * LINE_CORNERS, "the scratch is cleared first");
        for (i, v) in out.iter().enumerate() {
            assert_eq!(*v, lines[i / LINE_CORNERS], "vertex {i}");
        }
    }
}
