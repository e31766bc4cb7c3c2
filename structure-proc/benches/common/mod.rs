//! What the benches share: the cloth of `scenarios/cloth-hanging.toml`.

use structure_section::StructureSection;

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
