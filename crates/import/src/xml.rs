//! What the XML readers (MJCF, URDF) share: element children, errors that name the
//! element and its line, warnings given once each, and unique names.

use std::collections::HashSet;

use roxmltree::Node;

use crate::ImportError;

/// The element children of `node`.
pub(crate) fn elements<'a, 'i>(node: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children().filter(Node::is_element)
}

/// A conversion's warnings, each message at most once per element kind.
#[derive(Debug, Default)]
pub(crate) struct Warnings {
    list: Vec<String>,
    seen: HashSet<String>,
}

impl Warnings {
    /// The warnings, in the order they were given.
    pub(crate) fn into_vec(self) -> Vec<String> {
        self.list
    }
}

/// A reader of one XML document: errors and warnings with the element and its line.
pub(crate) trait XmlReader<'i> {
    /// The document read.
    fn document(&self) -> &roxmltree::Document<'i>;

    /// Where its warnings go.
    fn warnings(&mut self) -> &mut Warnings;

    /// `node`'s line, from 1.
    fn line(&self, node: Node<'_, '_>) -> u32 {
        self.document().text_pos_at(node.range().start).row
    }

    /// A construct that matters and cannot be expressed.
    fn unsupported(&self, node: Node<'_, '_>, reason: String) -> ImportError {
        ImportError::Unsupported {
            element: node.tag_name().name().to_string(),
            line: self.line(node),
            reason,
        }
    }

    /// An attribute that is missing or does not parse.
    fn bad(&self, node: Node<'_, '_>, attribute: &str, reason: String) -> ImportError {
        ImportError::BadAttribute {
            element: node.tag_name().name().to_string(),
            attribute: attribute.to_string(),
            line: self.line(node),
            reason,
        }
    }

    /// A warning, once per element kind and message.
    fn warn(&mut self, node: Node<'_, '_>, what: String) {
        let tag = node.tag_name().name();
        let line = self.line(node);
        let warnings = self.warnings();
        if warnings.seen.insert(format!("{tag} {what}")) {
            warnings.list.push(format!("line {line}: <{tag}> {what}"));
        }
    }
}

/// Names handed out once each: a wanted name, else it with `_2`, `_3` …
#[derive(Debug, Default)]
pub(crate) struct Names(HashSet<String>);

impl Names {
    /// `wanted`, or the first of `wanted_2`, `wanted_3` … not handed out yet.
    pub(crate) fn unique(&mut self, wanted: &str) -> String {
        let mut name = wanted.to_string();
        let mut k = 2;
        while !self.0.insert(name.clone()) {
            name = format!("{wanted}_{k}");
            k += 1;
        }
        name
    }
}
