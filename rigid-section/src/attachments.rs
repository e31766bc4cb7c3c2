//! Where the structure's strings hold the bodies. The structure owns these
//! keys (`body` and `body_point` of `[structure.parachute]` and of each
//! `[[structure.strings]]`) and checks them; rigid-proc reads only them,
//! ignoring every other key of the structure's table, to know which point
//! of which body each attachment is. A structure program that attaches
//! strings to bodies gives them under the same keys (docs/PROTOCOL.md).

use scenario::{section, ScenarioError};
use serde::Deserialize;
use std::path::Path;

/// Where a structure node is attached to a rigid body: the body's name and
/// the point in the body's own frame [m] (dissertation fig. 2.5).
#[derive(Debug, Clone, PartialEq)]
pub struct AttachmentSpec {
    pub body: String,
    pub point: [f64; 3],
}

/// The attachment keys of the structure's table; the others are skipped.
#[derive(Default, Deserialize, schemars::JsonSchema)]
struct StructureKeys {
    #[serde(default)]
    parachute: Option<Attached>,
    #[serde(default)]
    strings: Vec<Attached>,
}

#[derive(Deserialize, schemars::JsonSchema)]
struct Attached {
    #[serde(default)]
    body: Option<String>,
    #[serde(default)]
    body_point: [f64; 3],
}

/// The attachment points of the scenario's `[structure]` table, in the order
/// structure solvers number them and exchange their state and impulses: the
/// parachute's confluence first, then the strings.
pub fn attachments(path: &Path, text: &str) -> Result<Vec<AttachmentSpec>, ScenarioError> {
    let keys: StructureKeys = section::read(path, text, "structure")?.unwrap_or_default();
    let ends = keys.parachute.into_iter().chain(keys.strings);
    Ok(ends
        .filter_map(|a| {
            a.body.map(|body| AttachmentSpec {
                body,
                point: a.body_point,
            })
        })
        .collect())
}
