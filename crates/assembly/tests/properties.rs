//! Property-based tests (proptest) of the parser and validator: no input panics, every
//! rejection names a path and says what is wrong, and no input makes a large message.
//! Inputs: arbitrary text, arbitrary JSON, and valid documents with one node replaced
//! by arbitrary JSON (most of what a confused or hostile client sends).

mod common;

use common::base_doc;
use gymfleet_assembly::{parse, AssemblyError};
use proptest::prelude::*;
use serde_json::{json, Map, Value};

/// The seed models, as shipped.
const SEEDS: [&str; 4] = [
    include_str!("../../../models/pendulum.json"),
    include_str!("../../../models/arm2.json"),
    include_str!("../../../models/arm6.json"),
    include_str!("../../../models/chain20.json"),
];

/// Longest message any rejection may have: 20 shown issues of at most ~2 kB each.
const MAX_MESSAGE: usize = 45_000;

/// Checks what every rejection must satisfy.
fn check_rejection(err: &AssemblyError) -> Result<(), TestCaseError> {
    prop_assert!(!err.issues().is_empty(), "a rejection without issues");
    for issue in err.issues() {
        prop_assert!(!issue.path.is_empty(), "an issue without a path: {issue:?}");
        prop_assert!(
            !issue.message.is_empty(),
            "an issue without a message: {issue:?}"
        );
        prop_assert!(
            issue.path.len() + issue.message.len() < 2 * 1024 + 64,
            "an issue of {} bytes",
            issue.path.len() + issue.message.len()
        );
    }
    let text = err.to_string();
    prop_assert!(
        text.len() < MAX_MESSAGE,
        "a message of {} bytes",
        text.len()
    );
    Ok(())
}

fn check(text: &str) -> Result<(), TestCaseError> {
    // `parse` must return, not panic (a panic fails the case with its message).
    if let Err(err) = parse(text) {
        check_rejection(&err)?;
    }
    Ok(())
}

/// Arbitrary JSON: numbers of every magnitude (NaN cannot be JSON), strings with any
/// characters, nested arrays and objects with keys the document uses and others.
fn any_json() -> impl Strategy<Value = Value> {
    let key = prop_oneof![
        Just("name".to_string()),
        Just("part".to_string()),
        Just("type".to_string()),
        Just("x".to_string()),
        Just("size".to_string()),
        Just("limits".to_string()),
        "[a-z_]{1,12}",
    ];
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(|n| json!(n)),
        any::<u64>().prop_map(|n| json!(n)),
        any::<f64>()
            .prop_filter("finite", |f| f.is_finite())
            .prop_map(|f| json!(f)),
        prop_oneof![
            Just(1e308),
            Just(-1e308),
            Just(5e-324),
            Just(0.0),
            Just(-0.0)
        ]
        .prop_map(|f: f64| json!(f)),
        ".{0,24}".prop_map(Value::String),
        prop_oneof![
            Just("revolute"),
            Just("prismatic"),
            Just("fixed"),
            Just("ball"),
            Just("cube"),
            Just("sphere"),
            Just("cylinder"),
            Just("base"),
            Just("arm"),
        ]
        .prop_map(|s| Value::String(s.to_string())),
    ];
    leaf.prop_recursive(4, 48, 6, move |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::vec((key.clone(), inner), 0..6)
                .prop_map(|pairs| Value::Object(pairs.into_iter().collect::<Map<_, _>>())),
        ]
    })
}

/// Every node of `value`, as JSON pointers.
fn pointers(value: &Value, at: String, out: &mut Vec<String>) {
    out.push(at.clone());
    match value {
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                pointers(v, format!("{at}/{i}"), out);
            }
        }
        Value::Object(map) => {
            for (k, v) in map {
                pointers(
                    v,
                    format!("{at}/{}", k.replace('~', "~0").replace('/', "~1")),
                    out,
                );
            }
        }
        _ => {}
    }
}

/// A seed document with the node chosen by `pick` replaced by `replacement` (or, when
/// `delete` is set and the node is an object member, removed).
fn mutated(seed: usize, pick: prop::sample::Index, replacement: Value, delete: bool) -> String {
    let mut doc: Value = if seed < SEEDS.len() {
        serde_json::from_str(SEEDS[seed]).expect("seed parses")
    } else {
        base_doc()
    };
    let mut all = Vec::new();
    pointers(&doc, String::new(), &mut all);
    let pointer = pick.get(&all).clone();
    if pointer.is_empty() {
        return replacement.to_string();
    }
    let (parent, last) = pointer.rsplit_once('/').expect("a child pointer");
    match doc.pointer_mut(parent) {
        Some(Value::Object(map)) if delete => {
            map.remove(&last.replace("~1", "/").replace("~0", "~"));
        }
        _ => {
            if let Some(node) = doc.pointer_mut(&pointer) {
                *node = replacement;
            }
        }
    }
    doc.to_string()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in ".{0,200}") {
        check(&text)?;
    }

    #[test]
    fn arbitrary_json_never_panics(value in any_json()) {
        check(&value.to_string())?;
    }

    #[test]
    fn seed_documents_with_one_node_replaced_never_panic(
        seed in 0..=SEEDS.len(),
        pick in any::<prop::sample::Index>(),
        replacement in any_json(),
        delete in any::<bool>(),
    ) {
        check(&mutated(seed, pick, replacement, delete))?;
    }

    #[test]
    fn truncated_seed_documents_are_malformed_at_document(
        seed in 0..SEEDS.len(),
        cut in any::<prop::sample::Index>(),
    ) {
        let text = SEEDS[seed].trim_end();
        let at = cut.index(text.len());
        if text.is_char_boundary(at) {
            let err = parse(&text[..at]).expect_err("a cut document is malformed");
            check_rejection(&err)?;
            prop_assert_eq!(err.path(), "document");
        }
    }

}

proptest! {
    // Each case builds megabytes of JSON: fewer cases.
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn huge_names_and_many_instances_make_short_messages(
        len in 1_000usize..100_000,
        n in 1usize..200,
    ) {
        // One unknown part named `len` bytes, and `n` instances all using it.
        let name = "p".repeat(len);
        let instances: Vec<Value> = (0..n)
            .map(|i| json!({ "part": name, "name": format!("i{i}") }))
            .collect();
        let doc = json!({
            "parts": [{ "name": "Block", "primitive": { "type": "cube", "size": { "x": 1, "y": 1, "z": 1 } } }],
            "assembly": { "instances": instances, "joints": [] }
        });
        let err = parse(&doc.to_string()).expect_err("unknown parts");
        check_rejection(&err)?;
        prop_assert_eq!(err.issues().len(), n);
        prop_assert!(err.to_string().len() < 20 * 1024, "{} bytes", err.to_string().len());
    }
}

#[test]
fn known_lists_are_capped() {
    let names: Vec<String> = (0..50).map(|i| format!("block{i:02}")).collect();
    let instances: Vec<Value> = names
        .iter()
        .map(|n| json!({ "part": "Block", "name": n }))
        .collect();
    let doc = json!({
        "parts": [{ "name": "Block", "primitive": { "type": "cube", "size": { "x": 1, "y": 1, "z": 1 } } }],
        "assembly": {
            "instances": instances,
            "joints": [{ "type": "fixed", "parent": "block00", "child": "nope" }]
        }
    });
    let err = parse(&doc.to_string()).expect_err("unknown child");
    let message = &err.issues()[0].message;
    assert!(message.ends_with(", and 40 more)"), "{message}");
    assert!(message.contains("\"block09\""), "{message}");
    assert!(!message.contains("\"block10\""), "{message}");
}
