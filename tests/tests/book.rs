//! The guide (`docs/`, an mdBook) holds together: every chapter in
//! `docs/src` is in its table of contents and every entry there is a
//! chapter, and every relative link of the README, the guide and
//! PROTOCOL.md leads to a file that exists (issue 44, item 5).

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The targets of the Markdown links `[text](target)` in `text`, outside
/// code blocks and inline code.
fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Inline code spans hold no links.
        let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    out
}

/// The links of `file` that lead nowhere: relative ones whose file is
/// missing (a `#part` is not checked; web addresses are not followed).
fn broken(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).unwrap();
    let dir = file.parent().unwrap();
    links(&text)
        .into_iter()
        .filter(|l| !l.starts_with("http") && !l.starts_with('#') && !l.starts_with("mailto:"))
        .filter(|l| {
            let path = l.split('#').next().unwrap();
            !dir.join(path).exists()
        })
        .map(|l| format!("{}: ({l})", file.display()))
        .collect()
}

fn chapters() -> Vec<PathBuf> {
    files_of(&root().join("docs/src"), "md")
}

/// The files of `dir` whose names end in `.ext`, sorted.
fn files_of(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    files
}

#[test]
fn every_relative_link_of_the_readme_and_the_guide_leads_to_a_file() {
    let mut files = chapters();
    files.push(root().join("README.md"));
    files.push(root().join("docs/PROTOCOL.md"));
    let broken: Vec<String> = files.iter().flat_map(|f| broken(f)).collect();
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_table_of_contents_lists_every_chapter_once() {
    let summary = std::fs::read_to_string(root().join("docs/src/SUMMARY.md")).unwrap();
    let listed = links(&summary);
    let mut unlisted = Vec::new();
    for chapter in chapters() {
        let name = chapter.file_name().unwrap().to_string_lossy().to_string();
        if name == "SUMMARY.md" {
            continue;
        }
        match listed.iter().filter(|l| **l == name).count() {
            1 => {}
            n => unlisted.push(format!("{name} listed {n} times")),
        }
    }
    assert!(unlisted.is_empty(), "docs/src/SUMMARY.md: {unlisted:?}");
    // mdBook includes PROTOCOL.md, which stays where solvers' comments cite it.
    let protocol = std::fs::read_to_string(root().join("docs/src/protocol.md")).unwrap();
    assert!(protocol.contains("{{#include ../PROTOCOL.md}}"));
    assert!(root().join("docs/book.toml").exists());
}

/// The key reference, generated from the sections' own types (their serde
/// attributes and doc comments, through their JSON schema): every key of
/// `[run]`, `[coupling]`, `[participants.NAME]`, `[structure]`, `[fluid]`
/// and `[rigid]`, with its value, default, the rules its checks hold it to
/// and its meaning.
fn key_reference() -> String {
    use scenario::reference::of;
    let rules = checked_rules();
    let mut out = String::from(KEYS_HEAD);
    out.push_str(&of::<scenario::RunSection>("run", &rules));
    out.push_str(&of::<scenario::CouplingSection>("coupling", &rules));
    out.push_str(&of::<scenario::ParticipantSpec>(
        "participants.NAME",
        &rules,
    ));
    out.push_str(&of::<structure_section::StructureSection>(
        "structure",
        &rules,
    ));
    out.push_str(&of::<fluid_section::FluidSection>("fluid", &rules));
    out.push_str(&of::<rigid_section::RigidSection>("rigid", &rules));
    out
}

/// The rules the checks apply, gathered while every shipped scene is read
/// as its programs read it (the coupling part, and each listed section of
/// canopy's own participants); `[participants.X]` as `[participants.NAME]`.
fn checked_rules() -> scenario::Rules {
    let scenes = files_of(&root().join("scenarios"), "toml");
    let (read, rules) = scenario::recording_rules(|| {
        scenes.iter().try_for_each(|path| {
            let text = std::fs::read_to_string(path).unwrap();
            let scene = scenario::Scenario::parse(path, &text)?;
            let listed = |name| scene.participants.lists(name);
            if listed("structure") {
                structure_section::Scene::load(path, &text, "structure-proc")?;
            }
            if listed("fluid") {
                fluid_section::Scene::load(path, &text)?;
            }
            if listed("rigid") {
                rigid_section::Scene::load(path, &text)?;
            }
            Ok::<(), scenario::ScenarioError>(())
        })
    });
    read.expect("every shipped scene reads");
    let mut out = scenario::Rules::new();
    for (path, r) in rules {
        let path = match path.strip_prefix("participants.") {
            Some(rest) => match rest.split_once('.') {
                Some((_, key)) => format!("participants.NAME.{key}"),
                None => path,
            },
            None => path,
        };
        for rule in r {
            scenario::add_rule(&mut out, path.clone(), rule);
        }
    }
    out
}

const KEYS_HEAD: &str = "# Every key

<!-- Generated from the code by `tests/tests/book.rs`; do not edit. After a
change to a section's keys: CANOPY_WRITE_KEYS=1 cargo test --release -p
canopy-tests --test book -->

Every key a scenario's tables take, generated from the types the
programs read them into: the value each takes, its default (\"required\"
where there is none; \"none\" where leaving it out means none), and what
it means, from the code's own comments. \"checked\" lists the rules
each key's value is held to, gathered from the checks themselves as
they read every shipped scene (a key no shipped scene gives shows none
there, though its checks run all the same). Those checks, and the ones
of keys that go together, run when the file is read (`coupler check`),
each naming the file, line and key; [Scenario format](scenario-format.md)
says how a file is laid out.

";

#[test]
fn the_key_reference_is_the_one_the_code_generates() {
    let path = root().join("docs/src/keys.md");
    let fresh = key_reference();
    if std::env::var_os("CANOPY_WRITE_KEYS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let kept = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        kept == fresh,
        "docs/src/keys.md is not what the code generates: a section's keys \
         or their comments changed. Write it again with \
         CANOPY_WRITE_KEYS=1 cargo test --release -p canopy-tests --test book"
    );
}
