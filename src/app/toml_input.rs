//! TOML input files (scene files, figure specs): errors on one line,
//! `FILE:LINE:COLUMN: KEY: message`, and arrays of an exact length (serde's fixed-size arrays
//! would silently drop extra elements of a TOML array).

use serde::de::{DeserializeOwned, Error as _};
use serde::{Deserialize, Deserializer};

use crate::error::{Error, Result};

/// Parses TOML `text` read from `origin` (the file name, or a description such as
/// `scene file`) into `T`; see [`one_line`] for the errors.
pub(crate) fn parse<T: DeserializeOwned>(text: &str, origin: &str) -> Result<T> {
    toml::from_str(text).map_err(|e| one_line(&e, text, origin))
}

/// True if TOML `text` has any of `keys` at its top level (false when it is no TOML): tells
/// one kind of input file from another, e.g. a figure spec given where a scene file belongs.
pub(crate) fn has_top_level_key(text: &str, keys: &[&str]) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|table| keys.iter().any(|k| table.contains_key(*k)))
}

/// The key path and message of a TOML error, `KEY: message` (just the message when the error
/// concerns no key, e.g. a syntax error), on one line.
pub(crate) fn describe(e: &toml::de::Error) -> String {
    // Without its input, the error shows the message and then, on its own line, the key path
    // as "in `render.size`" (with the input it draws a multi-line excerpt instead).
    let mut bare = e.clone();
    bare.set_input(None);
    let shown = bare.to_string();
    let mut lines: Vec<&str> = shown
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let key = lines
        .last()
        .and_then(|l| l.strip_prefix("in `"))
        .and_then(|l| l.strip_suffix('`'))
        .map(str::to_owned);
    if key.is_some() {
        lines.pop();
    }
    let message = lines.join(" ");
    match key {
        Some(key) => format!("{key}: {message}"),
        None => message,
    }
}

/// The error of `e` on one line, `ORIGIN:LINE:COLUMN: KEY: message` (line and column of the
/// start of the offending text, from 1; the key path when the error concerns a key).
pub(crate) fn one_line(e: &toml::de::Error, text: &str, origin: &str) -> Error {
    let position = e.span().map(|span| {
        let before = &text[..span.start.min(text.len())];
        let line = 1 + before.matches('\n').count();
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = 1 + before[line_start..].chars().count();
        format!("{line}:{column}: ")
    });
    Error::Invalid(format!(
        "{origin}:{}{}",
        position.unwrap_or_else(|| " ".into()),
        describe(e)
    ))
}

/// Deserializes an optional array of exactly `N` elements, for
/// `#[serde(default, deserialize_with = "exact")]`: `size = [48, 32, 999]` is an error
/// ("invalid length 3, expected 2 elements"), not `[48, 32]`.
pub(crate) fn exact<'de, D, T, const N: usize>(d: D) -> Result<Option<[T; N]>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    let Some(values) = Option::<Vec<T>>::deserialize(d)? else {
        return Ok(None);
    };
    let len = values.len();
    values.try_into().map(Some).map_err(|_| {
        let expected = format!("{N} elements");
        D::Error::invalid_length(len, &expected.as_str())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Section {
        #[serde(default, deserialize_with = "exact")]
        size: Option<[u32; 2]>,
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Doc {
        render: Option<Section>,
    }

    fn error(text: &str) -> String {
        parse::<Doc>(text, "s.toml")
            .expect_err("invalid")
            .to_string()
    }

    #[test]
    fn errors_are_one_line_with_position_and_key() {
        let err = error("[render]\nsize = [48, 32, 999]\n");
        assert!(!err.contains('\n'), "{err}");
        assert!(
            err.starts_with("s.toml:2:8: render.size: invalid length 3, expected 2 elements"),
            "{err}"
        );
        let err = error("[render]\nsize = [1, 2]\nfoo = 3\n");
        assert!(!err.contains('\n'), "{err}");
        assert!(
            err.starts_with("s.toml:3:1: render: unknown field `foo`"),
            "{err}"
        );
        let err = error("[render]\nsize = \"big\"\n");
        assert!(
            err.starts_with("s.toml:2:8: render.size: invalid type"),
            "{err}"
        );
        let err = error("[render\n");
        assert!(err.starts_with("s.toml:1:8: "), "{err}");
        assert!(!err.contains('\n'), "{err}");
    }

    #[test]
    fn arrays_of_the_right_length_parse() {
        let doc: Doc = parse("[render]\nsize = [48, 32]\n", "s.toml").expect("valid");
        assert_eq!(doc.render.and_then(|r| r.size), Some([48, 32]));
        let doc: Doc = parse("[render]\n", "s.toml").expect("valid");
        assert_eq!(doc.render.and_then(|r| r.size), None);
        assert!(error("[render]\nsize = [48]\n").contains("invalid length 1"));
    }
}
