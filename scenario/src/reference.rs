//! The reference of a section's keys, generated from its serde types'
//! JSON schema (schemars, which reads the serde attributes and the doc
//! comments) and from the rules its checks apply (`check.rs`'s
//! [`recording_rules`](crate::check::recording_rules)): one Markdown table
//! per TOML table, nested tables after their parent, so that the book's
//! key reference cannot drift from the code (the book's test compares it
//! with `docs/src/keys.md`).

use crate::check::{add_rule, Rules};
use schemars::JsonSchema;
use serde_json::{Map, Value};
use std::collections::BTreeMap;

/// The Markdown reference of the TOML table `table` (`structure`,
/// `participants.NAME`, …) read into `T`, each key with the `rules` its
/// checks apply (by key path).
pub fn of<T: JsonSchema>(table: &str, rules: &Rules) -> String {
    markdown(table, schemars::schema_for!(T).as_value(), rules)
}

/// The Markdown reference of the TOML table `table` whose keys `schema`
/// describes, with the `rules` checked of each.
pub fn markdown(table: &str, schema: &Value, rules: &Rules) -> String {
    let defs = schema.get("$defs").cloned().unwrap_or(Value::Null);
    let top = Nested {
        path: table.to_string(),
        schema: schema.clone(),
        tag: None,
        array: false,
    };
    // A shared table is written once, at the first path it stands at; the
    // rules checked of it at its other paths belong there too. The first
    // pass finds those paths.
    let none = Rules::new();
    let mut first = Writer::new(&defs, &none);
    first.table(&top);
    let rules = aliased(rules, &first.aliases);
    let mut writer = Writer::new(&defs, &rules);
    writer.table(&top);
    writer.out
}

/// `rules` with every path under a table that `aliases` maps to where
/// that table is written moved there.
fn aliased(rules: &Rules, aliases: &BTreeMap<String, String>) -> Rules {
    let mut out = Rules::new();
    for (path, r) in rules {
        let mut at = path.clone();
        // The longest alias first (of two paths one of which begins the
        // other, the longer sorts last); a path moved may sit under another
        // alias, and each move goes to a path written before.
        for _ in 0..=aliases.len() {
            let alias =
                (aliases.iter().rev()).find(|(from, _)| at.starts_with(&format!("{from}.")));
            let Some((from, to)) = alias else { break };
            at = format!("{to}{}", &at[from.len()..]);
        }
        for rule in r {
            add_rule(&mut out, at.clone(), rule.clone());
        }
    }
    out
}

struct Writer<'a> {
    defs: &'a Value,
    rules: &'a Rules,
    out: String,
    /// Each shared type (a `$ref`) written so far, and the table it was
    /// written as: a type met again refers to it rather than repeating it.
    seen: BTreeMap<String, String>,
    /// Each path where a shared table stands again, and the path it was
    /// written at.
    aliases: BTreeMap<String, String>,
}

/// A nested table to write after its parent: its path, schema, for a
/// variant of a tagged table the tag that selects it, and whether it is an
/// array of tables.
struct Nested {
    path: String,
    schema: Value,
    tag: Option<String>,
    array: bool,
}

impl<'a> Writer<'a> {
    fn new(defs: &'a Value, rules: &'a Rules) -> Writer<'a> {
        Writer {
            defs,
            rules,
            out: String::new(),
            seen: BTreeMap::new(),
            aliases: BTreeMap::new(),
        }
    }

    /// The rules checked of the key at `path`, for its cell.
    fn checks(&self, path: &str) -> String {
        match self.rules.get(path) {
            Some(r) => r.join("; "),
            None => String::new(),
        }
    }

    /// `s` with any `$ref` followed.
    fn resolve<'v>(&'v self, s: &'v Value) -> &'v Value {
        match s.get("$ref").and_then(Value::as_str) {
            Some(r) => {
                let name = r.rsplit('/').next().unwrap_or(r);
                self.defs.get(name).unwrap_or(s)
            }
            None => s,
        }
    }

    /// `s` without the `null` of an `Option`, and the shared type it
    /// names, if any.
    fn unwrap_option<'v>(&'v self, s: &'v Value) -> (&'v Value, Option<String>) {
        if let Some(any) = s.get("anyOf").and_then(Value::as_array) {
            let some: Vec<&Value> = any.iter().filter(|v| !is_null(v)).collect();
            if some.len() == 1 && some.len() < any.len() {
                return (self.resolve(some[0]), ref_name(some[0]));
            }
        }
        (self.resolve(s), ref_name(s))
    }

    fn table(&mut self, t: &Nested) {
        let (name, tag) = (t.path.as_str(), t.tag.as_deref());
        let schema = self.resolve(&t.schema).clone();
        let about = description(&schema);
        match t.array {
            true => self.out.push_str(&format!("### `[[{name}]]`")),
            false => self.out.push_str(&format!("### `[{name}]`")),
        }
        if let Some(t) = tag {
            self.out.push_str(&format!(" with `{t}`"));
        }
        self.out.push_str("\n\n");
        if !about.is_empty() {
            self.out.push_str(&about);
            self.out.push_str("\n\n");
        }
        let Some(props) = schema.get("properties").and_then(Value::as_object) else {
            return;
        };
        let required: Vec<&str> = schema
            .get("required")
            .and_then(Value::as_array)
            .map(|r| r.iter().filter_map(Value::as_str).collect())
            .unwrap_or_default();
        self.out
            .push_str("| key | value | default | checked | meaning |\n|---|---|---|---|---|\n");
        let mut nested: Vec<Nested> = Vec::new();
        for (key, prop) in props {
            if tag.is_some_and(|t| t.starts_with(&format!("{key} ="))) {
                continue;
            }
            let (inner, shared) = self.unwrap_option(prop);
            let inner = inner.clone();
            let path = format!("{name}.{key}");
            let mut notes = Vec::new();
            let first = shared.as_ref().and_then(|r| self.seen.get(r)).cloned();
            let kind = match first {
                Some(at) if is_table(&inner) || is_variants(&inner) => {
                    let kind = format!("as `[{at}]`, above");
                    self.aliases.insert(path.clone(), at);
                    kind
                }
                _ => {
                    if let Some(r) = shared {
                        self.seen.insert(r, path.clone());
                    }
                    self.kind(&inner, &path, &mut nested, &mut notes)
                }
            };
            let default = match prop.get("default") {
                Some(d) if !d.is_null() => format!("`{}`", compact(d)),
                _ if required.contains(&key.as_str()) => "required".to_string(),
                // Left out: none, or (a list serde fills by default) an empty one.
                _ if inner.get("type") == Some(&Value::String("array".into())) => "`[]`".into(),
                _ => "none".to_string(),
            };
            let mut what = description(prop);
            if what.is_empty() {
                what = description(&inner);
            }
            for n in notes {
                what.push_str(&format!(" {n}"));
            }
            let checked = cell(&self.checks(&path));
            self.out.push_str(&format!(
                "| `{key}` | {kind} | {default} | {checked} | {} |\n",
                cell(&what)
            ));
        }
        self.out.push('\n');
        for n in nested {
            self.table(&n);
        }
    }

    /// What a value is, in words; nested tables go to `nested`, what each
    /// of an enum's values means to `notes`.
    fn kind(
        &self,
        s: &Value,
        path: &str,
        nested: &mut Vec<Nested>,
        notes: &mut Vec<String>,
    ) -> String {
        if let Some(variants) = s
            .get("oneOf")
            .or_else(|| s.get("anyOf"))
            .and_then(Value::as_array)
        {
            return self.variants(variants, path, nested, notes);
        }
        if let Some(values) = s.get("enum").and_then(Value::as_array) {
            return values
                .iter()
                .map(|v| format!("`{}`", compact(v)))
                .collect::<Vec<_>>()
                .join(" \\| ");
        }
        if let Some(c) = s.get("const") {
            return format!("`{}`", compact(c));
        }
        let ty = match s.get("type") {
            Some(Value::String(t)) => t.clone(),
            Some(Value::Array(t)) => t
                .iter()
                .filter_map(Value::as_str)
                .find(|t| *t != "null")
                .unwrap_or("")
                .to_string(),
            _ => String::new(),
        };
        match ty.as_str() {
            "number" => "number".into(),
            "integer" => match s.get("minimum").and_then(Value::as_f64) {
                Some(m) if m >= 0.0 => "integer ≥ 0".into(),
                _ => "integer".into(),
            },
            "boolean" => "true \\| false".into(),
            "string" => "string".into(),
            "array" => {
                let items = s
                    .get("items")
                    .map(|i| self.resolve(i))
                    .unwrap_or(&Value::Null);
                let n = s.get("minItems").filter(|m| s.get("maxItems") == Some(*m));
                if is_table(items) {
                    nested.push(Nested {
                        path: path.to_string(),
                        schema: items.clone(),
                        tag: None,
                        array: true,
                    });
                    return format!("tables `[[{path}]]`, below");
                }
                let each = self.kind(items, path, nested, notes);
                match n {
                    Some(n) => format!("{n} × {each}"),
                    None => format!("list of {each}"),
                }
            }
            "object" if is_table(s) => {
                nested.push(Nested {
                    path: path.to_string(),
                    schema: s.clone(),
                    tag: None,
                    array: false,
                });
                format!("table `[{path}]`, below")
            }
            "object" => "table".into(),
            _ => "value".into(),
        }
    }

    /// An enum's forms: its plain values, and for each table form (a table
    /// with a tag, or an inline table) the table below.
    fn variants(
        &self,
        variants: &[Value],
        path: &str,
        nested: &mut Vec<Nested>,
        notes: &mut Vec<String>,
    ) -> String {
        let mut forms = Vec::new();
        for v in variants
            .iter()
            .map(|v| self.resolve(v))
            .filter(|v| !is_null(v))
        {
            if let Some(c) = v.get("const") {
                forms.push(format!("`{}`", compact(c)));
                let about = description(v);
                if !about.is_empty() {
                    notes.push(format!("`{}`: {about}", compact(c)));
                }
            } else if let Some(e) = v.get("enum").and_then(Value::as_array) {
                forms.extend(e.iter().map(|c| format!("`{}`", compact(c))));
            } else if is_table(v) {
                let tag = tag_of(v);
                let label = tag
                    .clone()
                    .unwrap_or_else(|| single_key(v).unwrap_or_default());
                forms.push(format!("table `{}`", label));
                nested.push(Nested {
                    path: path.to_string(),
                    schema: v.clone(),
                    tag: Some(label),
                    array: false,
                });
            } else {
                forms.push(self.kind(v, path, nested, notes));
            }
        }
        forms.join(" \\| ")
    }
}

/// The shared type a `$ref` names.
fn ref_name(s: &Value) -> Option<String> {
    let r = s.get("$ref")?.as_str()?;
    r.rsplit('/').next().map(str::to_string)
}

/// Whether `v` is an enum with a table among its forms.
fn is_variants(v: &Value) -> bool {
    v.get("oneOf")
        .or_else(|| v.get("anyOf"))
        .and_then(Value::as_array)
        .is_some_and(|forms| forms.iter().any(is_table))
}

fn is_null(v: &Value) -> bool {
    v.get("type") == Some(&Value::String("null".into()))
}

fn is_table(v: &Value) -> bool {
    v.get("properties")
        .is_some_and(|p| p.as_object().is_some_and(|o| !o.is_empty()))
}

/// The `key = "value"` a tagged variant is chosen by.
fn tag_of(v: &Value) -> Option<String> {
    let props: &Map<String, Value> = v.get("properties")?.as_object()?;
    props
        .iter()
        .find_map(|(k, p)| p.get("const").map(|c| format!("{k} = {}", compact(c))))
}

/// The one key of an externally tagged variant (`{ inflow = [...] }`).
fn single_key(v: &Value) -> Option<String> {
    let props = v.get("properties")?.as_object()?;
    (props.len() == 1)
        .then(|| props.keys().next().cloned())
        .flatten()
}

fn description(v: &Value) -> String {
    plain(v.get("description").and_then(Value::as_str).unwrap_or(""))
}

/// A doc comment as the book shows it: rustdoc's links to items,
/// "[`Name`]", become plain code, "`Name`".
fn plain(doc: &str) -> String {
    let mut out = String::new();
    let mut rest = doc;
    while let Some(at) = rest.find("[`") {
        let after = &rest[at + 1..];
        let close = after[1..].find('`').map(|i| i + 2);
        match close {
            Some(end) if after[end..].starts_with(']') && !after[end + 1..].starts_with('(') => {
                out.push_str(&rest[..at]);
                out.push_str(&after[..end]);
                rest = &after[end + 1..];
            }
            _ => {
                out.push_str(&rest[..at + 1]);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// A value as TOML would show it, roughly: strings quoted, numbers bare.
fn compact(v: &Value) -> String {
    match v {
        Value::String(s) => format!("\"{s}\""),
        Value::Array(a) => format!("[{}]", a.iter().map(compact).collect::<Vec<_>>().join(", ")),
        Value::Object(o) => format!(
            "{{ {} }}",
            o.iter()
                .map(|(k, v)| format!("{k} = {}", compact(v)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        other => other.to_string(),
    }
}

/// Text for one cell of a Markdown table: one line, pipes escaped.
fn cell(s: &str) -> String {
    s.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .replace('|', "\\|")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{recording_rules, Checker};

    /// A table type that stands at two paths, as the fabric does.
    #[derive(schemars::JsonSchema)]
    #[allow(dead_code)]
    struct Fabric {
        stiffness: f64,
    }

    #[derive(schemars::JsonSchema)]
    #[allow(dead_code)]
    struct Top {
        a: Fabric,
        b: Fabric,
        n: u32,
    }

    #[test]
    fn a_key_shows_the_rules_its_checks_apply_wherever_its_table_stands() {
        let ((), rules) = recording_rules(|| {
            let mut c = Checker::default();
            c.within("top", None, |c| {
                c.nonzero(&["n"], 0.0);
                c.within("b", None, |c| c.positive(&["stiffness"], 1.0, "N/m"));
            });
        });
        let md = of::<Top>("top", &rules);
        // The rule n = 0 broke is listed, and b's fabric, written as a's,
        // lends it the rule checked at b.
        assert!(
            md.contains("| `n` | integer ≥ 0 | required | ≥ 1 |"),
            "{md}"
        );
        let stiffness = "| `stiffness` | number | required | > 0 N/m, from 1e-30 to 1e30 |";
        assert!(md.contains(stiffness), "{md}");
        assert!(md.contains("| `b` | as `[top.a]`, above |"), "{md}");
        // Outside `recording_rules` nothing is gathered.
        let ((), after) = recording_rules(|| {});
        Checker::default().nonzero(&["n"], 1.0);
        assert!(after.is_empty());
    }

    #[test]
    fn rustdoc_links_become_plain_code() {
        assert_eq!(
            plain("see [`DEFAULT_RELATIVE`] and [`a`](b), [x]"),
            "see `DEFAULT_RELATIVE` and [`a`](b), [x]"
        );
    }
}
