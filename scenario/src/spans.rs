//! Map between byte offsets in a scenario file and key paths, so every message
//! can name both the line and the key.

use super::check::Seg;
use std::ops::Range;
use toml_edit::{ImDocument, Item, Table, Value};

#[derive(Clone, Copy)]
enum Node<'a> {
    Item(&'a Item),
    Table(&'a Table),
    Value(&'a Value),
}

impl<'a> Node<'a> {
    fn span(self) -> Option<Range<usize>> {
        match self {
            Node::Item(i) => i.span(),
            Node::Table(t) => t.span(),
            Node::Value(v) => v.span(),
        }
    }

    /// (segment, span of the key or element, child)
    fn children(self) -> Vec<(Seg, Option<Range<usize>>, Node<'a>)> {
        let table = |t: &'a Table| {
            t.iter()
                .filter_map(|(k, _)| t.get_key_value(k))
                .map(|(key, item)| {
                    (
                        Seg::Key(key.get().to_string()),
                        key.span(),
                        Node::Item(item),
                    )
                })
                .collect::<Vec<_>>()
        };
        match self {
            Node::Table(t) => table(t),
            Node::Item(Item::Table(t)) => table(t),
            Node::Item(Item::ArrayOfTables(a)) => a
                .iter()
                .enumerate()
                .map(|(i, t)| (Seg::Index(i), t.span(), Node::Table(t)))
                .collect(),
            Node::Item(Item::Value(v)) => Node::Value(v).children(),
            Node::Item(Item::None) => vec![],
            Node::Value(Value::InlineTable(t)) => t
                .iter()
                .filter_map(|(k, _)| t.get_key_value(k))
                .map(|(key, item)| {
                    (
                        Seg::Key(key.get().to_string()),
                        key.span(),
                        Node::Item(item),
                    )
                })
                .collect(),
            Node::Value(Value::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(i, v)| (Seg::Index(i), v.span(), Node::Value(v)))
                .collect(),
            Node::Value(_) => vec![],
        }
    }
}

fn contains(r: &Option<Range<usize>>, offset: usize) -> bool {
    r.as_ref()
        .is_some_and(|r| r.start <= offset && offset < r.end.max(r.start + 1))
}

/// The deepest key path whose key or value covers `offset`.
pub fn key_at(text: &str, offset: usize) -> Option<Vec<Seg>> {
    let doc = ImDocument::parse(text).ok()?;
    let mut best: Option<Vec<Seg>> = None;
    fn walk(node: Node, path: &mut Vec<Seg>, offset: usize, best: &mut Option<Vec<Seg>>) {
        for (seg, key_span, child) in node.children() {
            path.push(seg);
            if (contains(&key_span, offset) || contains(&child.span(), offset))
                && best.as_ref().is_none_or(|b| b.len() < path.len())
            {
                *best = Some(path.clone());
            }
            walk(child, path, offset, best);
            path.pop();
        }
    }
    walk(
        Node::Table(doc.as_table()),
        &mut Vec::new(),
        offset,
        &mut best,
    );
    best
}

/// The span of the key at `path`, or of the deepest part of it that exists.
pub fn span_of(text: &str, path: &[Seg]) -> Option<Range<usize>> {
    let doc = ImDocument::parse(text).ok()?;
    let mut node = Node::Table(doc.as_table());
    let mut found = None;
    for seg in path {
        let Some((_, key_span, child)) = node.children().into_iter().find(|(s, _, _)| s == seg)
        else {
            break;
        };
        if let Some(s) = key_span.or_else(|| child.span()) {
            found = Some(s);
        }
        node = child;
    }
    found
}

/// 1-based line and column of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(offset, |nl| offset - nl - 1) + 1;
    (line, col)
}
