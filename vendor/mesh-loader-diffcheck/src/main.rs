//! Reads every `.dae` file under the given folders (default: the repository's test data)
//! with mesh-loader 0.1.13 as published and with gymfleet's patched copy, and checks that
//! each file gives the same meshes, bit for bit: vertices, faces, normals, texture
//! coordinates and colours. Exits 1 on any difference, or if a file the published crate
//! reads is refused by the patched one.

use std::path::{Path, PathBuf};

fn dae_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            dae_files(&path, out);
        } else if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("dae")) {
            out.push(path);
        }
    }
}

/// A scene's meshes as comparable bits.
type Bits = Vec<(Vec<[u32; 3]>, Vec<[u32; 3]>, Vec<[u32; 3]>, Vec<Vec<[u32; 2]>>, usize)>;

macro_rules! bits {
    ($scene:expr) => {
        $scene
            .meshes
            .iter()
            .map(|m| {
                let b3 = |v: &[[f32; 3]]| v.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
                (
                    b3(&m.vertices),
                    m.faces.clone(),
                    b3(&m.normals),
                    m.texcoords
                        .iter()
                        .map(|t| t.iter().map(|p| p.map(f32::to_bits)).collect())
                        .collect(),
                    m.colors.iter().map(Vec::len).sum(),
                )
            })
            .collect::<Bits>()
    };
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dirs: Vec<PathBuf> = match std::env::args().skip(1).collect::<Vec<_>>() {
        args if args.is_empty() => vec![root.join("crates/import/tests/data")],
        args => args.into_iter().map(PathBuf::from).collect(),
    };
    let mut files = Vec::new();
    for dir in &dirs {
        dae_files(dir, &mut files);
    }
    files.sort();
    let mut failed = 0;
    for file in &files {
        let bytes = std::fs::read(file).expect("a readable file");
        let orig = orig::collada::from_slice(&bytes);
        let new = new::collada::from_slice(&bytes);
        let verdict = match (orig, new) {
            (Ok(a), Ok(b)) if bits!(a) == bits!(b) => {
                let triangles: usize = b.meshes.iter().map(|m| m.faces.len()).sum();
                format!("identical ({} meshes, {triangles} triangles)", b.meshes.len())
            }
            (Ok(_), Ok(_)) => {
                failed += 1;
                "DIFFERENT".to_string()
            }
            (Ok(_), Err(e)) => {
                failed += 1;
                format!("REFUSED by the patched copy: {e}")
            }
            (Err(a), Err(b)) => format!("refused by both ({a} / {b})"),
            (Err(a), Ok(_)) => format!("read by the patched copy only (published: {a})"),
        };
        println!("{}: {verdict}", file.display());
    }
    println!("{} files, {failed} failed", files.len());
    if failed > 0 || files.is_empty() {
        std::process::exit(1);
    }
}
