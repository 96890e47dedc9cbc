//! `<include file>`: MuJoCo splices the children of the included file's root element
//! (`<mujoco>` or `<mujocoinclude>`) in place of the element. Paths are relative to the
//! main model's folder, as MuJoCo resolves them. The files come from a reader the caller
//! gives: the request's assets on a server, the file system when converting a file.
//!
//! Line numbers in later errors count in the spliced text.

use crate::{ImportError, Result};

/// Deepest nesting of includes (an include cycle stops here).
pub const MAX_INCLUDE_DEPTH: usize = 8;
/// Largest text after splicing, bytes.
pub const MAX_INCLUDED_BYTES: usize = 16 << 20;

/// `text` with every `<include file>` replaced by the included file's content, read by
/// `read` (given the `file` attribute; it says what is wrong when it cannot). A text
/// without includes comes back unchanged.
pub fn expand_includes(
    text: &str,
    read: &mut dyn FnMut(&str) -> std::result::Result<String, String>,
) -> Result<String> {
    expand(text, read, 0)
}

fn expand(
    text: &str,
    read: &mut dyn FnMut(&str) -> std::result::Result<String, String>,
    depth: usize,
) -> Result<String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| ImportError::Xml(e.to_string()))?;
    let includes: Vec<roxmltree::Node> = doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "include")
        .collect();
    if includes.is_empty() {
        return Ok(text.to_string());
    }
    let unsupported = |node: roxmltree::Node, reason: String| ImportError::Unsupported {
        element: "include".into(),
        line: doc.text_pos_at(node.range().start).row,
        reason,
    };
    if depth >= MAX_INCLUDE_DEPTH {
        return Err(unsupported(
            includes[0],
            format!("includes nest deeper than {MAX_INCLUDE_DEPTH} (a cycle?)"),
        ));
    }
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for node in includes {
        let line = doc.text_pos_at(node.range().start).row;
        let file = node
            .attribute("file")
            .ok_or_else(|| ImportError::BadAttribute {
                element: "include".into(),
                attribute: "file".into(),
                line,
                reason: "missing".into(),
            })?;
        let included = read(file).map_err(|e| unsupported(node, format!("{file:?}: {e}")))?;
        children_text(&included).map_err(|e| unsupported(node, format!("{file:?}: {e}")))?;
        let included = expand(&included, read, depth + 1)
            .map_err(|e| unsupported(node, format!("in {file:?}: {e}")))?;
        let inner =
            children_text(&included).map_err(|e| unsupported(node, format!("{file:?}: {e}")))?;
        out.push_str(&text[at..node.range().start]);
        out.push_str(inner);
        at = node.range().end;
        if out.len() > MAX_INCLUDED_BYTES {
            return Err(unsupported(
                node,
                format!("the model with its includes exceeds {MAX_INCLUDED_BYTES} bytes"),
            ));
        }
    }
    out.push_str(&text[at..]);
    Ok(out)
}

/// The text between an included file's root start and end tags.
fn children_text(text: &str) -> std::result::Result<&str, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| format!("not well-formed XML: {e}"))?;
    let root = doc.root_element();
    if !matches!(root.tag_name().name(), "mujoco" | "mujocoinclude") {
        return Err(format!(
            "the root element must be <mujoco> or <mujocoinclude>, got <{}>",
            root.tag_name().name()
        ));
    }
    let (Some(first), Some(last)) = (root.first_child(), root.last_child()) else {
        return Ok("");
    };
    Ok(&text[first.range().start..last.range().end])
}
