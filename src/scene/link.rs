//! Share links: a scene carried in a URL fragment, `#scene=<base64url of the compact JSON>`.
//!
//! Base64url (RFC 4648 §5, no padding) keeps the fragment free of characters that browsers
//! or chat programs would escape or cut. Decoding accepts padding and standard-alphabet
//! characters too, so a link that passed through a lenient re-encoder still opens.

use super::{Scene, SceneError};

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";

/// The fragment key.
pub const KEY: &str = "scene=";

/// Encodes bytes as base64url without padding.
#[must_use]
pub fn base64url_encode(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        let chars = chunk.len() + 1;
        for i in 0..chars {
            out.push(char::from(ALPHABET[((n >> (18 - 6 * i)) & 63) as usize]));
        }
    }
    out
}

/// Decodes base64url (or standard base64), ignoring padding. `None` on any other character
/// or an impossible length.
#[must_use]
pub fn base64url_decode(text: &str) -> Option<Vec<u8>> {
    let digits: Vec<u8> = text
        .trim_end_matches('=')
        .bytes()
        .map(|c| match c {
            b'A'..=b'Z' => Some(c - b'A'),
            b'a'..=b'z' => Some(c - b'a' + 26),
            b'0'..=b'9' => Some(c - b'0' + 52),
            b'-' | b'+' => Some(62),
            b'_' | b'/' => Some(63),
            _ => None,
        })
        .collect::<Option<_>>()?;
    if digits.len() % 4 == 1 {
        return None;
    }
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        let mut n = 0u32;
        for (i, d) in chunk.iter().enumerate() {
            n |= u32::from(*d) << (18 - 6 * i);
        }
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..chunk.len() - 1]);
    }
    Some(out)
}

impl Scene {
    /// The URL fragment (without `#`) that carries this scene.
    #[must_use]
    pub fn to_link_fragment(&self) -> String {
        format!("{KEY}{}", base64url_encode(self.to_json_compact().as_bytes()))
    }

    /// Reads a scene from a URL fragment (with or without the leading `#`). `Ok(None)` when
    /// the fragment carries no scene at all.
    ///
    /// # Errors
    /// When it carries a scene that cannot be decoded or is invalid; the error's path starts
    /// with `(link)` for decoding problems and is the scene's key path otherwise.
    pub fn from_link_fragment(fragment: &str) -> Result<Option<Self>, SceneError> {
        let f = fragment.strip_prefix('#').unwrap_or(fragment);
        let Some(payload) = f.split('&').find_map(|part| part.strip_prefix(KEY)) else {
            return Ok(None);
        };
        let bytes = base64url_decode(payload).ok_or_else(|| {
            SceneError::new(
                "(link)",
                "the scene in the link is not valid base64url",
                "copy the whole link again; it may have been cut short",
            )
        })?;
        let text = String::from_utf8(bytes).map_err(|_| {
            SceneError::new(
                "(link)",
                "the scene in the link is not text",
                "copy the whole link again; it may have been cut short",
            )
        })?;
        Self::from_json(&text).map(Some)
    }
}
