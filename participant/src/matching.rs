//! How the coupler connects the participants' declarations: every read to
//! the one participant that writes a field of that name.

use crate::declaration::Declaration;
use crate::timing::Cadence;
use crate::wire::{Connections, Source};
use std::collections::HashMap;

/// Each participant's connections, in the order of `names`, or why the
/// declarations do not fit together.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub fn connect_fields(names: &[String], decls: &[Declaration]) -> Result<Vec<Connections>, String> {
    let mut writers: HashMap<&str, usize> = HashMap::new();
    for (p, d) in decls.iter().enumerate() {
        for w in &d.writes {
            if let Some(&other) = writers.get(w.name.as_str()) {
                return Err(format!(
                    "field `{}` is written by both `{}` and `{}`: a field has one writer",
                    w.name, names[other], names[p]
                ));
            }
            writers.insert(&w.name, p);
        }
    }
    // Who reads each written field, in participant order.
    let mut readers: HashMap<&str, Vec<String>> = HashMap::new();
    for (p, d) in decls.iter().enumerate() {
        for r in &d.reads {
            if writers.contains_key(r.name.as_str()) {
                readers.entry(&r.name).or_default().push(names[p].clone());
            } else if r.required {
                return Err(format!(
                    "participant `{}` reads field `{}`, which no participant of this run writes \
                     (participants: {})",
                    names[p],
                    r.name,
                    names.join(", ")
                ));
            }
        }
    }
    let impulse = decls
        .iter()
        .filter(|d| matches!(d.cadence, Cadence::PerImpulse { .. }))
        .count();
    let connections = decls
        .iter()
        .map(|d| Connections {
            reads: d
                .reads
                .iter()
                .map(|r| {
                    let &p = writers.get(r.name.as_str())?;
                    let w = decls[p].writes.iter().find(|w| w.name == r.name)?;
                    Some(Source {
                        writer: names[p].clone(),
                        per_item: w.per_item,
                        items: w.items,
                        readers: readers.get(r.name.as_str()).map_or(0, Vec::len) as u32,
                    })
                })
                .collect(),
            writes: d
                .writes
                .iter()
                .map(|w| readers.get(w.name.as_str()).cloned().unwrap_or_default())
                .collect(),
            partnered: matches!(d.cadence, Cadence::PerImpulse { .. }) && impulse >= 2,
        })
        .collect();
    Ok(connections)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: &[&str]) -> Vec<String> {
        n.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_read_is_connected_to_its_writer_and_counts_its_readers() {
        let fluid = Declaration::new(Cadence::PerWindow { substeps: 1 })
            .writes("pressure", 1, 4)
            .reads("positions");
        let structure = Declaration::new(Cadence::PerImpulse {
            substeps_per_window: 4,
        })
        .writes("positions", 3, 2)
        .reads_if_written("pressure")
        .reads_if_written("attachment.state");
        let c = connect_fields(&names(&["fluid", "structure"]), &[fluid, structure]).unwrap();
        let source = c[0].reads[0].as_ref().unwrap();
        assert_eq!((source.writer.as_str(), source.per_item), ("structure", 3));
        assert_eq!((source.items, source.readers), (Some(2), 1));
        assert_eq!(c[0].writes[0], vec!["structure".to_string()]);
        assert!(c[1].reads[1].is_none(), "an optional read with no writer");
        assert!(
            !c[1].partnered,
            "a lone per-impulse participant steps per window"
        );
    }

    #[test]
    fn a_required_read_with_no_writer_names_the_reader_and_the_field() {
        let rigid = Declaration::new(Cadence::PerImpulse {
            substeps_per_window: 1,
        })
        .reads("impulses");
        let e = connect_fields(&names(&["rigid"]), &[rigid]).unwrap_err();
        assert!(e.contains("`rigid` reads field `impulses`"), "{e}");
    }

    #[test]
    fn two_writers_of_one_field_are_refused() {
        let a = Declaration::new(Cadence::PerWindow { substeps: 1 }).writes("x", 1, 1);
        let e = connect_fields(&names(&["a", "b"]), &[a.clone(), a]).unwrap_err();
        assert!(e.contains("written by both `a` and `b`"), "{e}");
    }
}
