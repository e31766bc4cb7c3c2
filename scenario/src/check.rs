//! Value checks that remember the first problem and the key it belongs to.

/// One segment of a key path: a table key or an array index.
#[derive(Debug, Clone, PartialEq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// A problem found in a scenario, at a key path like `rigid.bodies[0].mass`.
#[derive(Debug, Clone)]
pub struct Problem {
    pub path: Vec<Seg>,
    pub message: String,
}

/// Largest magnitude of a physical value in a scenario. No parachute scene
/// comes near it (the thesis's extreme free stream is 10¹² m/s), and the
/// product of a few such values (an energy, a box's volume) stays finite in
/// f64, whose largest number is 1.8·10³⁰⁸.
pub const MAX_MAGNITUDE: f64 = 1e30;
/// Smallest positive physical value: its inverse (an inverse mass, a rate)
/// stays within [`MAX_MAGNITUDE`].
pub const MIN_POSITIVE: f64 = 1e-30;

pub fn path_string(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// The rules the typed checks apply, by key path (array indices left
/// out: `rigid.bodies.mass`), each once, in the order the checks first
/// applied them, as [`recording_rules`] gathers them.
pub type Rules = std::collections::BTreeMap<String, Vec<String>>;

/// Adds `rule` to the rules of `path`, once.
pub fn add_rule(rules: &mut Rules, path: String, rule: String) {
    let held = rules.entry(path).or_default();
    if !held.contains(&rule) {
        held.push(rule);
    }
}

thread_local! {
    /// The rules being gathered on this thread, while [`recording_rules`] runs.
    static RECORDING: std::cell::RefCell<Option<Rules>> = const { std::cell::RefCell::new(None) };
}

/// Runs `f` and gathers the rule of every typed check that any
/// [`Checker`] on this thread applies meanwhile (whether the value passes
/// or not): the key reference lists them beside each key
/// (`reference.rs`), from the checks themselves, so that it cannot drift
/// from them. A rule of its own that a section states with
/// [`Checker::problem`] is not among them: it is seen only when it fails.
pub fn recording_rules<T>(f: impl FnOnce() -> T) -> (T, Rules) {
    let outer = RECORDING.with(|r| r.borrow_mut().replace(Rules::new()));
    let value = f();
    let rules = RECORDING.with(|r| std::mem::replace(&mut *r.borrow_mut(), outer));
    (value, rules.unwrap_or_default())
}

/// Collects the first problem; later checks are ignored so the user gets one clear message.
#[derive(Debug, Default)]
pub struct Checker {
    prefix: Vec<Seg>,
    first: Option<Problem>,
}

impl Checker {
    /// Run `f` with `key` (and an optional index) appended to every path it reports.
    pub fn within(&mut self, key: &str, index: Option<usize>, f: impl FnOnce(&mut Checker)) {
        let depth = self.prefix.len();
        self.prefix.push(Seg::Key(key.to_string()));
        if let Some(i) = index {
            self.prefix.push(Seg::Index(i));
        }
        f(self);
        self.prefix.truncate(depth);
    }

    pub fn problem(&mut self, keys: &[&str], message: String) {
        if self.first.is_some() {
            return;
        }
        let mut path = self.prefix.clone();
        path.extend(keys.iter().map(|k| Seg::Key(k.to_string())));
        self.first = Some(Problem { path, message });
    }

    pub fn into_problem(self) -> Option<Problem> {
        self.first
    }

    /// Notes that the key at `keys` is held to `rule`, when rules are
    /// being gathered ([`recording_rules`]): the typed checks do, and a
    /// check of its own states its rule so.
    pub fn rule(&self, keys: &[&str], rule: impl FnOnce() -> String) {
        RECORDING.with(|r| {
            if let Some(rules) = r.borrow_mut().as_mut() {
                let key = (self.prefix.iter())
                    .filter(|s| matches!(s, Seg::Key(_)))
                    .cloned()
                    .chain(keys.iter().map(|k| Seg::Key(k.to_string())))
                    .collect::<Vec<_>>();
                add_rule(rules, path_string(&key), rule());
            }
        });
    }

    fn last(keys: &[&str]) -> String {
        keys.last().copied().unwrap_or("value").to_string()
    }

    /// A physical value: finite, and of a magnitude whose products stay finite.
    pub fn finite(&mut self, keys: &[&str], v: f64) {
        self.rule(keys, || format!("finite, |x| ≤ {MAX_MAGNITUDE:e}"));
        if !v.is_finite() {
            self.problem(
                keys,
                format!("{} = {v} must be a finite number", Self::last(keys)),
            );
        } else {
            self.not_huge(keys, v, "");
        }
    }

    pub fn finite3(&mut self, keys: &[&str], v: [f64; 3]) {
        self.rule(keys, || format!("finite, each |x| ≤ {MAX_MAGNITUDE:e}"));
        if v.iter().any(|x| !x.is_finite()) {
            self.problem(
                keys,
                format!("{} = {v:?} must hold finite numbers", Self::last(keys)),
            );
        } else if let Some(x) = v.iter().find(|x| x.abs() > MAX_MAGNITUDE) {
            self.not_huge(keys, *x, "");
        }
    }

    pub fn positive(&mut self, keys: &[&str], v: f64, unit: &str) {
        self.rule(keys, || {
            format!("> 0 {unit}, from {MIN_POSITIVE:e} to {MAX_MAGNITUDE:e}").replace("  ", " ")
        });
        if !(v.is_finite() && v > 0.0) {
            self.problem(
                keys,
                format!("{} = {v} must be > 0 {unit}", Self::last(keys))
                    .trim_end()
                    .to_string(),
            );
        } else if v < MIN_POSITIVE {
            self.problem(
                keys,
                format!(
                    "{} = {v} is below the {MIN_POSITIVE:e} {unit} canopy accepts: its inverse would \
                     overflow the arithmetic",
                    Self::last(keys)
                )
                .replace("  ", " "),
            );
        } else {
            self.not_huge(keys, v, unit);
        }
    }

    pub fn finite_nonneg(&mut self, keys: &[&str], v: f64) {
        self.rule(keys, || format!("≥ 0, ≤ {MAX_MAGNITUDE:e}"));
        if !(v.is_finite() && v >= 0.0) {
            self.problem(keys, format!("{} = {v} must be ≥ 0", Self::last(keys)));
        } else {
            self.not_huge(keys, v, "");
        }
    }

    /// Refuses a magnitude beyond [`MAX_MAGNITUDE`]: products of a few such
    /// values (an energy, a box's volume) would overflow to infinity and a
    /// run would complete with it.
    fn not_huge(&mut self, keys: &[&str], v: f64, unit: &str) {
        if v.abs() > MAX_MAGNITUDE {
            self.problem(
                keys,
                format!(
                    "{} = {v:e} is beyond the {MAX_MAGNITUDE:e} {unit} canopy accepts: products of \
                     it would overflow the arithmetic",
                    Self::last(keys)
                )
                .replace("  ", " "),
            );
        }
    }

    pub fn nonzero(&mut self, keys: &[&str], v: f64) {
        self.rule(keys, || "≥ 1".into());
        if v == 0.0 {
            self.problem(keys, format!("{} must be at least 1", Self::last(keys)));
        }
    }

    /// At most `max` (guards memory and run length against typos like 1e20).
    pub fn at_most(&mut self, keys: &[&str], v: f64, max: f64) {
        self.rule(keys, || format!("≤ {max:e}"));
        if v > max {
            self.problem(
                keys,
                format!(
                    "{} = {v} is more than the {max:e} canopy accepts",
                    Self::last(keys)
                ),
            );
        }
    }

    /// A name used in file and column names: letters, digits, `_`, `-` (and `.` not first).
    pub fn plain_name(&mut self, keys: &[&str], name: &str, dots: bool) {
        self.rule(keys, || match dots {
            true => "a name: letters, digits, `_`, `-`, `.` (not first)".into(),
            false => "a name: letters, digits, `_`, `-`".into(),
        });
        let ok = !name.is_empty()
            && !name.starts_with('.')
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || (dots && c == '.'));
        if !ok {
            self.problem(
                keys,
                format!(
                    "{} = {name:?} must be a non-empty name of letters, digits, `_` and `-`",
                    Self::last(keys)
                ),
            );
        }
    }

    pub fn fraction(&mut self, keys: &[&str], v: f64) {
        self.rule(keys, || "strictly between 0 and 1".into());
        if !(v.is_finite() && v > 0.0 && v < 1.0) {
            self.problem(
                keys,
                format!(
                    "{} = {v} must lie strictly between 0 and 1",
                    Self::last(keys)
                ),
            );
        }
    }
}
