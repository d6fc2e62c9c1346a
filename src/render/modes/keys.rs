//! What a mode reads its parameters from: the keys of its scene section (`[zebra]`, figure
//! specs' `params`, the viewer's page keys, the command line's mode flags written into that
//! section), with the checks every parameter shares. Each mode reads and checks its own keys
//! ([`super::ModeKind::configure`]); an error names the key as `section.key`.

use glam::DVec3;

use crate::error::{Error, Problem, Result};

/// One scene key of a mode: its name in the mode's section and what it sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    /// Name in the section (`stripes` of `[zebra]`).
    pub name: &'static str,
    /// What it sets, with its default and range.
    pub help: &'static str,
    /// Whether its value names a file (made relative to the folder of the file it is written
    /// in; never settable from the viewer's page).
    pub file: bool,
    /// What the file is, for messages about inputs and outputs ("the environment map").
    pub what: &'static str,
    /// The same with the indefinite article ("an environment map").
    pub what_an: &'static str,
    /// Values of a file key that name no file but something built in.
    pub builtins: &'static [&'static str],
}

impl Key {
    /// A key taking a value.
    pub const fn new(name: &'static str, help: &'static str) -> Key {
        Key {
            name,
            help,
            file: false,
            what: "",
            what_an: "",
            builtins: &[],
        }
    }

    /// A key whose value names a file (`what` it is, `what_an` with the indefinite
    /// article), or one of `builtins`.
    pub const fn file(
        name: &'static str,
        help: &'static str,
        [what, what_an]: [&'static str; 2],
        builtins: &'static [&'static str],
    ) -> Key {
        Key {
            name,
            help,
            file: true,
            what,
            what_an,
            builtins,
        }
    }

    /// Whether `value` of this key names a file.
    pub fn names_file(&self, value: &str) -> bool {
        self.file && !self.builtins.contains(&value)
    }
}

/// How the command line's text of a mode flag becomes the value of its scene key.
pub type FlagParser = fn(&str) -> std::result::Result<toml::Value, String>;

/// One command-line flag of a mode: `--LONG VALUE` (or the bare switch `--LONG`) sets `key` of
/// the mode's section, overriding the scene.
#[derive(Clone, Copy, Debug)]
pub struct Flag {
    /// Flag name without the dashes (`zebra-stripes`).
    pub long: &'static str,
    /// Scene key it sets.
    pub key: &'static str,
    /// What `-h` shows.
    pub help: &'static str,
    /// Placeholder of the value in `-h` (unused by switches).
    pub value_name: &'static str,
    /// The value: parsed from the flag's text, or None for a switch that sets the key to
    /// false.
    pub value: Option<FlagParser>,
    /// The accepted values with their help, when the value is one of a list.
    pub choices: &'static [(&'static str, &'static str)],
    /// Whether the value may start with `-` (negative numbers, directions).
    pub hyphen_values: bool,
    /// Keys of the same section the flag replaces: the scene's value of each is dropped.
    pub replaces: &'static [&'static str],
    /// Flags of the same mode that set the same thing: both on one command line are refused.
    pub conflicts: &'static [&'static str],
}

impl Flag {
    /// A flag `--long VALUE` setting `key` to the parsed value.
    pub const fn value(
        long: &'static str,
        key: &'static str,
        value_name: &'static str,
        help: &'static str,
        value: FlagParser,
    ) -> Flag {
        Flag {
            long,
            key,
            help,
            value_name,
            value: Some(value),
            choices: &[],
            hyphen_values: true,
            replaces: &[],
            conflicts: &[],
        }
    }

    /// A switch `--long` setting `key` to false.
    pub const fn off(long: &'static str, key: &'static str, help: &'static str) -> Flag {
        Flag {
            long,
            key,
            help,
            value_name: "",
            value: None,
            choices: &[],
            hyphen_values: false,
            replaces: &[],
            conflicts: &[],
        }
    }

    /// A flag `--long NAME` setting `key` to one of `choices` (name, help).
    pub const fn choice(
        long: &'static str,
        key: &'static str,
        help: &'static str,
        choices: &'static [(&'static str, &'static str)],
    ) -> Flag {
        Flag {
            long,
            key,
            help,
            value_name: "",
            value: Some(text),
            choices,
            hyphen_values: false,
            replaces: &[],
            conflicts: &[],
        }
    }
}

/// Flag value: a number (as the shell wrote it; `invalid float literal` otherwise).
pub fn number(text: &str) -> std::result::Result<toml::Value, String> {
    text.parse::<f64>()
        .map(toml::Value::Float)
        .map_err(|e| e.to_string())
}

/// Flag value: the text as it is.
pub fn text(text: &str) -> std::result::Result<toml::Value, String> {
    Ok(toml::Value::String(text.to_string()))
}

/// Flag value: a number when the text is one, else the trimmed text (for keys taking either,
/// checked by the mode).
pub fn number_or_text(text: &str) -> std::result::Result<toml::Value, String> {
    Ok(match text.trim().parse::<f64>() {
        Ok(x) => toml::Value::Float(x),
        Err(_) => toml::Value::String(text.trim().to_string()),
    })
}

/// Flag value: `X,Y,Z` of finite numbers, as an array.
pub fn triple(text: &str) -> std::result::Result<toml::Value, String> {
    parse_triple(text)
        .map(|v| toml::Value::Array(v.iter().map(|x| toml::Value::Float(*x)).collect()))
}

/// Flag value: `X,Y,Z` as an array when it is one, else the trimmed text (a name, or anything
/// else for the mode's check to name).
pub fn triple_or_text(text: &str) -> std::result::Result<toml::Value, String> {
    Ok(match triple(text) {
        Ok(v) => v,
        Err(_) => toml::Value::String(text.trim().to_string()),
    })
}

/// `X,Y,Z` of finite numbers (the text of a vector flag or key).
pub fn parse_triple(text: &str) -> std::result::Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("'{text}' is not X,Y,Z"));
    }
    let mut out = [0.0; 3];
    for (slot, part) in out.iter_mut().zip(parts) {
        *slot = part
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("'{part}' in '{text}' is not a finite number"))?;
    }
    Ok(out)
}

/// The keys of one mode's section, read by name; every read names the key as
/// `section.key` in its error.
#[derive(Clone, Copy, Debug)]
pub struct Keys<'a> {
    section: &'a str,
    table: &'a toml::Table,
}

impl<'a> Keys<'a> {
    /// The keys of `table`, the section called `section`; a key not in `known` is an error
    /// naming it and the known ones.
    pub fn new(section: &'a str, table: &'a toml::Table, known: &[Key]) -> Result<Keys<'a>> {
        if let Some(unknown) = table
            .keys()
            .find(|k| !known.iter().any(|key| key.name == k.as_str()))
        {
            let names: Vec<String> = known.iter().map(|k| format!("`{}`", k.name)).collect();
            return Err(unknown_key(Some(section), unknown, names));
        }
        Ok(Keys { section, table })
    }

    /// `section.key`, as errors name it.
    pub fn name(&self, key: &str) -> String {
        format!("{}.{key}", self.section)
    }

    /// The error of `key` having `problem`.
    pub fn error(&self, key: &str, problem: Problem) -> Error {
        Error::config(self.name(key), problem)
    }

    /// The raw value of `key`, if set.
    pub fn value(&self, key: &str) -> Option<&'a toml::Value> {
        self.table.get(key)
    }

    /// Whether `key` is set.
    pub fn has(&self, key: &str) -> bool {
        self.table.contains_key(key)
    }

    /// Refuses `a` and `b` both set.
    pub fn one_of(&self, a: &str, b: &str) -> Result<()> {
        if self.has(a) && self.has(b) {
            return Err(self.error(
                a,
                Problem::Conflict {
                    other: self.name(b),
                },
            ));
        }
        Ok(())
    }

    /// A number (integer or float).
    pub fn number(&self, key: &str) -> Result<Option<f64>> {
        self.value(key).map(|v| self.as_number(key, v)).transpose()
    }

    fn as_number(&self, key: &str, v: &toml::Value) -> Result<f64> {
        match v {
            toml::Value::Float(x) => Ok(*x),
            toml::Value::Integer(x) => Ok(*x as f64),
            other => Err(self.error(key, wrong_type(other, "a number"))),
        }
    }

    /// A whole number in `0..=u32::MAX`.
    pub fn count(&self, key: &str) -> Result<Option<u32>> {
        self.value(key)
            .map(|v| match v {
                toml::Value::Integer(x) => u32::try_from(*x).map_err(|_| {
                    self.error(
                        key,
                        wrong_type(x, &format!("a whole number in [0, {}]", u32::MAX)),
                    )
                }),
                other => Err(self.error(key, wrong_type(other, "a whole number"))),
            })
            .transpose()
    }

    /// true or false.
    pub fn flag(&self, key: &str) -> Result<Option<bool>> {
        self.value(key)
            .map(|v| match v {
                toml::Value::Boolean(b) => Ok(*b),
                other => Err(self.error(key, wrong_type(other, "true or false"))),
            })
            .transpose()
    }

    /// A string.
    pub fn text(&self, key: &str) -> Result<Option<&'a str>> {
        self.value(key)
            .map(|v| match v {
                toml::Value::String(s) => Ok(s.as_str()),
                other => Err(self.error(key, wrong_type(other, "a string"))),
            })
            .transpose()
    }

    /// An array of exactly three numbers.
    pub fn triple(&self, key: &str) -> Result<Option<[f64; 3]>> {
        self.value(key).map(|v| self.as_triple(key, v)).transpose()
    }

    /// `v`, the value of `key`, as an array of exactly three numbers.
    pub fn as_triple(&self, key: &str, v: &toml::Value) -> Result<[f64; 3]> {
        let toml::Value::Array(items) = v else {
            return Err(self.error(key, wrong_type(v, "an array [x, y, z]")));
        };
        if items.len() != 3 {
            return Err(self.error(
                key,
                Problem::WrongLength {
                    value: v.to_string(),
                    len: items.len(),
                    expected: 3,
                },
            ));
        }
        let mut out = [0.0; 3];
        for (slot, item) in out.iter_mut().zip(items) {
            *slot = match item {
                toml::Value::Float(x) => *x,
                toml::Value::Integer(x) => *x as f64,
                other => {
                    return Err(self.error(
                        key,
                        Problem::WrongElement {
                            element: other.to_string(),
                            expected: "a number",
                        },
                    ));
                }
            };
        }
        Ok(out)
    }

    /// A positive finite number.
    pub fn positive(&self, key: &str) -> Result<Option<f64>> {
        self.number(key)?
            .map(|x| positive(&self.name(key), x))
            .transpose()
    }

    /// A number in `[0, 1]`.
    pub fn fraction(&self, key: &str) -> Result<Option<f64>> {
        self.number(key)?
            .map(|x| fraction(&self.name(key), x))
            .transpose()
    }

    /// Non-negative finite linear RGB.
    pub fn colour(&self, key: &str) -> Result<Option<DVec3>> {
        self.triple(key)?
            .map(|c| colour(&self.name(key), c))
            .transpose()
    }

    /// A finite point.
    pub fn point(&self, key: &str) -> Result<Option<DVec3>> {
        self.triple(key)?
            .map(|p| finite_point(&self.name(key), p))
            .transpose()
    }

    /// A non-zero finite direction, normalised.
    pub fn direction(&self, key: &str) -> Result<Option<DVec3>> {
        self.triple(key)?
            .map(|p| direction(&self.name(key), p))
            .transpose()
    }
}

/// The error of key `key` not being one of `known` (each quoted as `` `name` ``) of `section`
/// (None: the top level).
pub fn unknown_key(section: Option<&str>, key: &str, known: Vec<String>) -> Error {
    Error::config(
        key,
        Problem::UnknownKey {
            section: section.map(str::to_string),
            known,
        },
    )
}

/// The error of `key` of `keys` refused by a check that gave `reason`.
pub fn refused(keys: &Keys<'_>, key: &str, reason: &Error) -> Error {
    keys.error(
        key,
        Problem::Refused {
            reason: reason.to_string(),
        },
    )
}

/// The problem of `value` not being `expected` (`a number`).
pub fn wrong_type(value: &dyn std::fmt::Display, expected: &str) -> Problem {
    Problem::WrongType {
        value: value.to_string(),
        expected: expected.to_string(),
    }
}

/// `x` when positive and finite; else an error naming `name`.
pub fn positive(name: &str, x: f64) -> Result<f64> {
    if x > 0.0 && x.is_finite() {
        Ok(x)
    } else {
        Err(Error::config(
            name,
            Problem::NotPositive {
                value: x.to_string(),
            },
        ))
    }
}

/// `x` when in `[0, 1]`; else an error naming `name`.
pub fn fraction(name: &str, x: f64) -> Result<f64> {
    if (0.0..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err(Error::config(
            name,
            Problem::NotFraction {
                value: x.to_string(),
            },
        ))
    }
}

/// `x` when in `[lo, hi]`; else an error naming `name`, the value and the bounds in
/// scientific notation (`1e-3`).
pub fn in_range(name: &str, x: f64, (lo, hi): (f64, f64)) -> Result<f64> {
    if (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(Error::config(
            name,
            Problem::OutOfRange {
                value: format!("{x:e}"),
                range: format!("[{lo:e}, {hi:e}]"),
            },
        ))
    }
}

/// `n` when in `lo..=hi`; else an error naming `name` and the range as `lo..=hi`.
pub fn in_count_range<T: PartialOrd + std::fmt::Display>(
    name: &str,
    n: T,
    lo: T,
    hi: T,
) -> Result<T> {
    if lo <= n && n <= hi {
        Ok(n)
    } else {
        Err(Error::config(
            name,
            Problem::OutOfRange {
                value: n.to_string(),
                range: format!("{lo}..={hi}"),
            },
        ))
    }
}

/// `value` when it is one of `known`; else an error naming `name` and the known values.
pub fn one_of<'k>(name: &str, value: &str, known: &[&'k str]) -> Result<&'k str> {
    known.iter().copied().find(|k| *k == value).ok_or_else(|| {
        Error::config(
            name,
            Problem::NotOneOf {
                value: value.to_string(),
                known: known.iter().map(|k| k.to_string()).collect(),
            },
        )
    })
}

/// `c` when finite and non-negative (linear RGB); else an error naming `name`.
pub fn colour(name: &str, c: [f64; 3]) -> Result<DVec3> {
    if c.iter().all(|x| x.is_finite() && *x >= 0.0) {
        Ok(DVec3::from_array(c))
    } else {
        Err(Error::config(
            name,
            Problem::NotColour {
                value: format!("{c:?}"),
            },
        ))
    }
}

/// `p` when finite; else an error naming `name`.
fn finite_point(name: &str, p: [f64; 3]) -> Result<DVec3> {
    let v = DVec3::from_array(p);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::config(
            name,
            Problem::NotFinite {
                value: format!("{p:?}"),
            },
        ))
    }
}

/// `p` normalised when finite and non-zero; else an error naming `name`.
pub fn direction(name: &str, p: [f64; 3]) -> Result<DVec3> {
    let v = finite_point(name, p)?;
    if v.length() > 0.0 {
        Ok(v.normalize())
    } else {
        Err(Error::config(
            name,
            Problem::Zero {
                value: format!("{p:?}"),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KNOWN: &[Key] = &[Key::new("a", ""), Key::new("b", "")];

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).expect("toml")
    }

    /// An unknown key is refused with the known ones; reads name `section.key`.
    #[test]
    fn keys_name_the_section_and_key() {
        let t = table("c = 1");
        let err = Keys::new("s", &t, KNOWN).expect_err("unknown").to_string();
        assert!(err.contains("`c`") && err.contains("`a`, `b`"), "{err}");
        let t = table("a = \"x\"\nb = [1, 2]");
        let keys = Keys::new("s", &t, KNOWN).expect("known");
        let err = keys.number("a").expect_err("string").to_string();
        assert!(err.contains("s.a"), "{err}");
        let err = keys.triple("b").expect_err("length").to_string();
        assert!(err.contains("s.b") && err.contains("length 2"), "{err}");
        assert!(keys.one_of("a", "b").is_err());
    }

    /// Integers read as numbers; ranges are checked.
    #[test]
    fn numbers_and_ranges() {
        let t = table("a = 3\nb = 1.5");
        let keys = Keys::new("s", &t, KNOWN).expect("known");
        assert_eq!(keys.number("a").expect("int"), Some(3.0));
        assert!(keys.fraction("b").is_err());
        assert_eq!(keys.positive("b").expect("positive"), Some(1.5));
        assert_eq!(keys.count("a").expect("count"), Some(3));
        assert!(keys.count("b").is_err());
    }
}
