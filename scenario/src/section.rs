//! A participant's own table of the scenario. The coupler checks `[run]`,
//! `[coupling]` and `[participants]`; every other table belongs to the
//! participant of the same name, whose program reads it with [`read`] and
//! checks its values with [`checked`]. Both place every problem in the whole
//! file, so a solver's messages name the file, line and key as the
//! coupler's do: `file:line:col: key `a.b[0].c`: message`.

use crate::check::Checker;
use crate::error::ScenarioError;
use serde::de::{DeserializeOwned, DeserializeSeed, IgnoredAny, MapAccess, Visitor};
use std::fmt;
use std::marker::PhantomData;
use std::path::Path;

/// The table `name` of the scenario `text` as a `T`, or None when the file
/// has no such table. Unknown keys, wrong types and missing values are
/// reported at their place in the whole file (`path` names it).
pub fn read<T: DeserializeOwned>(
    path: &Path,
    text: &str,
    name: &str,
) -> Result<Option<T>, ScenarioError> {
    let pick = Pick::<T> {
        name,
        _t: PhantomData,
    };
    pick.deserialize(toml::Deserializer::new(text))
        .map_err(|e| ScenarioError::from_toml(path, text, &e))
}

/// Runs the value checks `check` (which name keys from the top of the file,
/// for example with `c.within("structure", None, …)`) and places the first
/// problem in the file.
pub fn checked(
    path: &Path,
    text: &str,
    check: impl FnOnce(&mut Checker),
) -> Result<(), ScenarioError> {
    let mut c = Checker::default();
    check(&mut c);
    match c.into_problem() {
        None => Ok(()),
        Some(p) => Err(ScenarioError::from_problem(path, text, p)),
    }
}

/// The error for a program that plays participant `name` and finds no
/// `[name]` table to read.
pub fn missing(path: &Path, name: &str, program: &str) -> ScenarioError {
    ScenarioError {
        file: path.to_path_buf(),
        line: None,
        column: None,
        key: Some(name.to_string()),
        message: format!(
            "{program} plays participant `{name}` and reads its [{name}] table, which the \
             scenario does not have"
        ),
    }
}

/// The names of the file's top-level tables and keys, in file order.
pub fn table_names(path: &Path, text: &str) -> Result<Vec<String>, ScenarioError> {
    let doc: toml_edit::ImDocument<&str> = toml_edit::ImDocument::parse(text).map_err(|e| {
        let message = e.message().trim().to_string();
        let (line, column) = e
            .span()
            .map(|s| crate::spans::line_col(text, s.start))
            .map_or((None, None), |(l, c)| (Some(l), Some(c)));
        ScenarioError {
            file: path.to_path_buf(),
            line,
            column,
            key: None,
            message,
        }
    })?;
    let mut names: Vec<(usize, String)> = doc
        .as_table()
        .iter()
        .map(|(k, item)| {
            let at = doc
                .as_table()
                .key(k)
                .and_then(|key| key.span())
                .or_else(|| item.span())
                .map_or(usize::MAX, |s| s.start);
            (at, k.to_string())
        })
        .collect();
    names.sort();
    Ok(names.into_iter().map(|(_, k)| k).collect())
}

/// Deserialises one entry of the top-level table and skips the others, so
/// that the entry's errors keep their spans in the whole document.
struct Pick<'a, T> {
    name: &'a str,
    _t: PhantomData<T>,
}

impl<'de, T: DeserializeOwned> DeserializeSeed<'de> for Pick<'_, T> {
    type Value = Option<T>;

    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<Option<T>, D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de, T: DeserializeOwned> Visitor<'de> for Pick<'_, T> {
    type Value = Option<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a scenario table")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Option<T>, A::Error> {
        let mut found = None;
        while let Some(key) = map.next_key::<String>()? {
            if key == self.name {
                found = Some(map.next_value::<T>()?);
            } else {
                map.next_value::<IgnoredAny>()?;
            }
        }
        Ok(found)
    }
}

/// Where a participant's steps run, for the sections that can run on a
/// GPU (`[structure] device`, `[fluid] device`): what the device covers is
/// each section's, and its check refuses the rest.
#[derive(
    Debug,
    Clone,
    Copy,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Device {
    #[default]
    Cpu,
    /// The first GPU adapter wgpu finds.
    Gpu,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Mine {
        stiffness: f64,
    }

    const TEXT: &str = "[run]\nname = \"x\"\n\n[mine]\nstiffness = 2.0\n";

    #[test]
    fn a_table_is_read_and_the_others_are_skipped() {
        let mine: Mine = read(Path::new("s.toml"), TEXT, "mine").unwrap().unwrap();
        assert_eq!(mine.stiffness, 2.0);
        let none: Option<Mine> = read(Path::new("s.toml"), TEXT, "other").unwrap();
        assert!(none.is_none());
        let names = table_names(Path::new("s.toml"), TEXT).unwrap();
        assert_eq!(names, ["run", "mine"]);
    }

    #[test]
    fn an_error_in_a_table_is_placed_in_the_whole_file() {
        let bad = TEXT.replace("stiffness = 2.0", "stiffness = 2.0\ncolour = 1");
        let e = read::<Mine>(Path::new("s.toml"), &bad, "mine").unwrap_err();
        assert_eq!((e.line, e.key.as_deref()), (Some(6), Some("mine.colour")));
        assert!(e.message.contains("unknown field `colour`"), "{e}");
    }
}
