//! Duplicate keys in a JSON document. serde_json keeps the last of two equal keys in an
//! object without a word, so `"radius": 5.0, "radius": 3.0` would silently mean 3. The
//! format promises that a typo is never ignored: this pass walks the document once (no
//! values kept, depth bounded by serde_json's recursion limit) and names the first repeated
//! key with its key path.

use std::collections::HashSet;
use std::fmt;

use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

/// The key path of the first key repeated inside one object (`surfaces[0].radius`), or
/// `None` when there is none. Syntax errors are left to the real parse (`None`).
#[must_use]
pub fn first_duplicate_key(text: &str) -> Option<String> {
    let mut de = serde_json::Deserializer::from_str(text);
    (Walk { path: String::new() }).deserialize(&mut de).unwrap_or_default()
}

/// Walks one value at `path`; yields the path of the first duplicate found inside it.
struct Walk {
    path: String,
}

impl<'de> DeserializeSeed<'de> for Walk {
    type Value = Option<String>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

fn child(path: &str, key: &str) -> String {
    if path.is_empty() { key.to_owned() } else { format!("{path}.{key}") }
}

impl<'de> Visitor<'de> for Walk {
    type Value = Option<String>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut seen = HashSet::new();
        let mut found = None;
        while let Some(key) = map.next_key::<String>()? {
            if found.is_some() {
                map.next_value::<IgnoredAny>()?;
                continue;
            }
            let path = child(&self.path, &key);
            if !seen.insert(key) {
                found = Some(path);
                map.next_value::<IgnoredAny>()?;
                continue;
            }
            found = map.next_value_seed(Walk { path })?;
        }
        Ok(found)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut found = None;
        let mut i = 0usize;
        loop {
            if found.is_some() {
                if seq.next_element::<IgnoredAny>()?.is_none() {
                    break;
                }
                continue;
            }
            match seq.next_element_seed(Walk { path: format!("{}[{i}]", self.path) })? {
                Some(f) => found = f,
                None => break,
            }
            i += 1;
        }
        Ok(found)
    }

    fn visit_bool<E: de::Error>(self, _: bool) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_i64<E: de::Error>(self, _: i64) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_u64<E: de::Error>(self, _: u64) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_f64<E: de::Error>(self, _: f64) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_str<E: de::Error>(self, _: &str) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::first_duplicate_key;

    #[test]
    fn the_first_repeated_key_is_named_with_its_path() {
        assert_eq!(first_duplicate_key(r#"{"a": 1, "b": {"c": 2}}"#), None);
        assert_eq!(first_duplicate_key(r#"{"a": 1, "a": 2}"#).as_deref(), Some("a"));
        let nested = r#"{"surfaces": [{"radius": 5.0}, {"type": "x", "radius": 5.0, "radius": 3.0}]}"#;
        assert_eq!(first_duplicate_key(nested).as_deref(), Some("surfaces[1].radius"));
        // Equal keys in different objects are not duplicates.
        assert_eq!(first_duplicate_key(r#"[{"k": 1}, {"k": 2}]"#), None);
        // Broken JSON is the real parser's to report.
        assert_eq!(first_duplicate_key(r#"{"a": "#), None);
    }
}
