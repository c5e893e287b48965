//! Strict reading of JSON documents into typed structs.
//!
//! `serde` alone lets two kinds of mistake through silently: a misspelt key is ignored (a
//! scene with `"triangels"` renders the background with exit 0), and a struct accepts a
//! positional array (`[64, 48]` reads as `width` and `height`). Here:
//! - the document must be a JSON object;
//! - every key serde ignores is reported with its path and the closest known key of the
//!   object it sits in (field names come from the types themselves, not a second list);
//! - a type error names the path of the value (`triangles[0].v[1]`), not only a line.

use serde::de::DeserializeOwned;
use std::collections::BTreeSet;

/// A key that no field of its object takes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownKey {
    /// Path of the key, e.g. `camera.eyes` or `lights[0].positon`.
    pub path: String,
    /// The closest known key of the same object, when one is close.
    pub suggestion: Option<String>,
}

impl std::fmt::Display for UnknownKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "unknown key `{}`", self.path)?;
        if let Some(s) = &self.suggestion {
            write!(f, " (did you mean `{s}`?)")?;
        }
        Ok(())
    }
}

/// Why a document did not parse.
#[derive(Debug, thiserror::Error)]
pub enum StrictError {
    /// Not JSON at all (syntax), with serde's line and column.
    #[error("{0}")]
    Syntax(serde_json::Error),
    /// The top level is not an object.
    #[error("the top level must be a JSON object {{...}}, found {0}")]
    NotObject(&'static str),
    /// A value has the wrong type or range.
    #[error("{path}: {msg}")]
    Value {
        /// Path of the offending value.
        path: String,
        /// serde's message, made readable.
        msg: String,
    },
}

/// The field names a type declares (from its `Deserialize` implementation).
pub type FieldLister = fn() -> Vec<&'static str>;

/// Parses `text` as `T`. `schema` maps an object's path (with array indices replaced by
/// `[]`, the top level as `""`) to the function listing its fields, for suggestions.
pub fn parse<T: DeserializeOwned>(
    text: &str,
    schema: &[(&str, FieldLister)],
) -> Result<(T, Vec<UnknownKey>), StrictError> {
    // Streamed straight from the text (no intermediate `Value`: a scene of a million
    // triangles would take several times its size in memory as a tree).
    match text.trim_start().chars().next() {
        Some('{') => {}
        Some('[') => return Err(StrictError::NotObject("an array")),
        Some('"') => return Err(StrictError::NotObject("a string")),
        Some(c) if c == '-' || c.is_ascii_digit() => {
            return Err(StrictError::NotObject("a number"))
        }
        Some('t' | 'f') => return Err(StrictError::NotObject("a boolean")),
        Some('n') => return Err(StrictError::NotObject("null")),
        _ => {
            // Empty or not JSON: let serde name the syntax error with its position.
            return Err(StrictError::Syntax(
                serde_json::from_str::<serde::de::IgnoredAny>(text)
                    .err()
                    .unwrap_or_else(|| serde::de::Error::custom("expected a JSON object")),
            ));
        }
    }
    let mut unknown = Vec::new();
    let mut note = |p: serde_ignored::Path| unknown.push(p.to_string());
    let mut json = serde_json::Deserializer::from_str(text);
    let de = serde_ignored::Deserializer::new(&mut json, &mut note);
    let t: T = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let msg = inner.to_string();
        // serde_json reports a fixed-size array with extra elements as a syntax error
        // ("trailing characters") inside the value: that is a value error at `path`.
        let too_long = msg.starts_with("trailing characters") && path != ".";
        if (inner.is_syntax() || inner.is_eof()) && !too_long {
            return StrictError::Syntax(inner);
        }
        StrictError::Value {
            path,
            msg: readable(&msg),
        }
    })?;
    json.end().map_err(StrictError::Syntax)?;
    let unknown = unknown
        .into_iter()
        .map(|p| with_suggestion(p, schema))
        .collect();
    Ok((t, unknown))
}

/// serde's wording for a too-long fixed array ("trailing characters", "expected fewer
/// elements") does not say what is wrong; say it.
fn readable(msg: &str) -> String {
    if msg.starts_with("trailing characters") || msg.ends_with("expected fewer elements in array") {
        return "too many elements in this array".to_string();
    }
    msg.to_string()
}

fn with_suggestion(path: String, schema: &[(&str, FieldLister)]) -> UnknownKey {
    let (parent, key) = match path.rfind('.') {
        Some(i) => (&path[..i], &path[i + 1..]),
        None => ("", path.as_str()),
    };
    let generic: String = {
        // `lights.0` → `lights[]`: serde_ignored writes indices as path segments.
        let parts: Vec<&str> = parent.split('.').filter(|s| !s.is_empty()).collect();
        let mut g = String::new();
        for s in parts {
            if s.chars().all(|c| c.is_ascii_digit()) {
                g.push_str("[]");
            } else {
                if !g.is_empty() {
                    g.push('.');
                }
                g.push_str(s);
            }
        }
        g
    };
    let suggestion = schema
        .iter()
        .find(|(p, _)| *p == generic)
        .and_then(|(_, fields)| closest(key, &fields()));
    UnknownKey {
        path: display_path(&path),
        suggestion,
    }
}

/// `lights.0.positon` → `lights[0].positon`.
fn display_path(p: &str) -> String {
    let mut out = String::new();
    for s in p.split('.') {
        if s.chars().all(|c| c.is_ascii_digit()) && !s.is_empty() {
            out.push_str(&format!("[{s}]"));
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out.push_str(s);
        }
    }
    out
}

/// The known name closest to `key`, if it is close enough to be a likely typo.
pub fn closest(key: &str, known: &[&str]) -> Option<String> {
    let set: BTreeSet<&str> = known.iter().copied().collect();
    set.into_iter()
        .map(|k| (strsim::damerau_levenshtein(key, k), k))
        .filter(|(d, k)| *d <= 2.max(k.len() / 3))
        .min()
        .map(|(_, k)| k.to_string())
}

/// Field names of a `Deserialize` struct, read from its derive.
pub fn fields_of<T: DeserializeOwned>() -> Vec<&'static str> {
    serde_aux::serde_introspection::serde_introspect::<T>().to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Deserialize, Debug)]
    struct Inner {
        position: [f64; 3],
    }

    #[derive(Deserialize, Debug)]
    struct Doc {
        width: u32,
        #[serde(default)]
        triangles: Vec<u32>,
        #[serde(default)]
        lights: Vec<Inner>,
    }

    const SCHEMA: &[(&str, FieldLister)] =
        &[("", fields_of::<Doc>), ("lights[]", fields_of::<Inner>)];

    #[test]
    fn misspelt_keys_are_reported_with_the_closest_field() {
        let (doc, u) = parse::<Doc>(
            r#"{"width": 4, "triangels": [], "lights": [{"position": [0,0,0], "positon": 1}], "zzz": 0}"#,
            SCHEMA,
        )
        .unwrap();
        // The known fields still read normally beside the unknown ones.
        assert_eq!(doc.width, 4);
        assert!(doc.triangles.is_empty());
        assert_eq!(doc.lights[0].position, [0.0; 3]);
        let s: Vec<String> = u.iter().map(|k| k.to_string()).collect();
        assert!(
            s.contains(&"unknown key `triangels` (did you mean `triangles`?)".to_string()),
            "{s:?}"
        );
        assert!(
            s.contains(&"unknown key `lights[0].positon` (did you mean `position`?)".to_string()),
            "{s:?}"
        );
        assert!(s.contains(&"unknown key `zzz`".to_string()), "{s:?}");
    }

    #[test]
    fn a_bare_array_is_not_a_document() {
        let e = parse::<Doc>("[64, 48]", SCHEMA).unwrap_err().to_string();
        assert!(
            e.contains("must be a JSON object") && e.contains("an array"),
            "{e}"
        );
    }

    #[test]
    fn value_errors_name_the_path() {
        let e = parse::<Doc>(
            r#"{"width": 4, "lights": [{"position": [0,0,0,0]}]}"#,
            SCHEMA,
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("lights[0].position"), "{e}");
        assert!(e.contains("too many elements"), "{e}");
        let e = parse::<Doc>(r#"{"width": "wide"}"#, SCHEMA)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("width: invalid type"), "{e}");
    }
}
