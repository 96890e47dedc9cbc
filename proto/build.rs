//! Compiles `gymfleet/v1/*.proto` without a system `protoc`: `protox` parses
//! the files into a `FileDescriptorSet`, which is written to `OUT_DIR` (for
//! gRPC reflection) and handed to tonic's prost code generator.

use std::path::PathBuf;

const PROTO_ROOT: &str = "gymfleet";
const PROTOS: &[&str] = &["gymfleet/v1/simulator.proto"];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("cargo:rerun-if-changed={PROTO_ROOT}");

    let mut compiler = protox::Compiler::new(["."])?;
    compiler.include_source_info(true).include_imports(true);
    for proto in PROTOS {
        compiler.open_file(proto)?;
    }

    let out_dir = PathBuf::from(std::env::var("OUT_DIR")?);
    std::fs::write(
        out_dir.join("gymfleet_descriptor.bin"),
        compiler.encode_file_descriptor_set(),
    )?;

    tonic_prost_build::configure()
        .build_client(true)
        .build_server(true)
        // Deterministic encoding: the same step encodes to the same bytes.
        .btree_map(".gymfleet.v1.BatchStepResult.termination_reasons")
        .compile_fds(compiler.file_descriptor_set())?;
    Ok(())
}
