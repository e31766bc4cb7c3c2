//! What the benches share: the cloth of `scenarios/cloth-hanging.toml`.

use structure_proc::{build_model, Model};
use structure_section::{Damping, StructureSection};

/// The structure of `scenarios/cloth-hanging.toml` on n × n nodes, and the
/// scene's window [s].
pub fn cloth_section(n: u32) -> (StructureSection, f64) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenarios/cloth-hanging.toml"
    );
    let s = structure_section::Scene::load_file(std::path::Path::new(path), "structure-proc")
        .expect("shipped scenario");
    let mut section = s.structure;
    let cloth = section.cloth.as_mut().expect("cloth");
    cloth.nodes_x = n;
    cloth.nodes_y = n;
    (section, s.scenario.coupling.window)
}

/// The cloth with uniform springs on its edges plus bending springs, undamped.
#[allow(dead_code)] // not every bench uses it
pub fn spring_cloth(n: u32) -> Model {
    let (mut section, dt) = cloth_section(n);
    section.damping = Damping::None;
    section.damping_coefficient = None;
    let fabric = &mut section.cloth.as_mut().unwrap().fabric;
    fabric.membrane = None;
    fabric.stiffness = Some(100.0);
    build_model(&section, None, dt).expect("cloth builds")
}
