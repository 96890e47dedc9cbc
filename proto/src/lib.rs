//! The gymfleet wire contract. This crate owns `proto/gymfleet/v1/*.proto`
//! and the Rust generated from it: the `gymfleet.v1` messages, the
//! `Simulator` client and server stubs (tonic + prost), and the encoded
//! `FileDescriptorSet` that the server hands to gRPC reflection. It holds no
//! logic: converting between these types and the domain types, and mapping
//! errors to `tonic::Status`, is left to `server/` and `client/`.
//!
//! The code is generated with `protox` and `tonic-prost-build` (no system protoc), and
//! `FILE_DESCRIPTOR_SET` is exposed for reflection. Both create requests carry one
//! `EnvOptions` (`options`; their flat option fields are deprecated, still read by the
//! server's `convert/create.rs`), and `BatchInfo.env` is the batch's `EnvInfo` (the server
//! also fills the deprecated flat copy).
//!
//! **The wire only grows.** `buf.yaml` makes `proto/` a buf module, and `released.json` is
//! the last release's wire as a buf image. CI's `npm run check-breaking` (in `client/js`,
//! which pins buf) refuses a proto that removes, renumbers, renames or retypes anything in
//! it, and shows on every run that it refuses a removed and a renumbered field. A release
//! refreshes the image (`npm run release-proto`).

/// Generated code for the `gymfleet.v1` package: messages, enums, and the
/// `simulator_client` / `simulator_server` modules.
#[allow(missing_docs, unreachable_pub, clippy::all, clippy::pedantic)]
pub mod v1 {
    tonic::include_proto!("gymfleet.v1");
}

/// The status metadata entry that carries an error's [`v1::ErrorReason`] (see the proto's
/// `ErrorReason`): the value's name without its `ERROR_REASON_` prefix.
pub const REASON_KEY: &str = "gymfleet-reason";

/// The status metadata entry that names the limit a RESOURCE_EXHAUSTED refusal was for:
/// the server flag that raises it, e.g. `--max-envs`.
pub const LIMIT_KEY: &str = "gymfleet-limit";

impl v1::ErrorReason {
    /// The reason as it travels: its proto name without the `ERROR_REASON_` prefix, e.g.
    /// `ENV_NOT_FOUND`.
    pub fn wire_name(self) -> &'static str {
        let name = self.as_str_name();
        name.strip_prefix("ERROR_REASON_").unwrap_or(name)
    }

    /// The reason a [`REASON_KEY`] value names; `Unspecified` for a name this build does
    /// not know (a newer server's).
    pub fn from_wire_name(name: &str) -> Self {
        Self::from_str_name(&format!("ERROR_REASON_{name}")).unwrap_or(Self::Unspecified)
    }
}

/// The encoded `google.protobuf.FileDescriptorSet` of every gymfleet proto
/// file (with source info, so comments reach reflection clients), for
/// `tonic_reflection::server::Builder::register_encoded_file_descriptor_set`.
pub const FILE_DESCRIPTOR_SET: &[u8] = tonic::include_file_descriptor_set!("gymfleet_descriptor");

#[cfg(test)]
mod tests {
    use prost::Message as _;

    use super::*;

    #[test]
    fn reasons_travel_by_their_short_names() {
        use v1::ErrorReason;
        assert_eq!(ErrorReason::EnvNotFound.wire_name(), "ENV_NOT_FOUND");
        for n in 0..=14 {
            let reason = ErrorReason::try_from(n).expect("a reason");
            assert_eq!(ErrorReason::from_wire_name(reason.wire_name()), reason);
        }
        assert_eq!(
            ErrorReason::from_wire_name("NOT_A_REASON"),
            ErrorReason::Unspecified
        );
    }

    #[test]
    fn descriptor_set_declares_the_simulator_service() {
        let fds = prost_types::FileDescriptorSet::decode(FILE_DESCRIPTOR_SET)
            .expect("FILE_DESCRIPTOR_SET decodes");
        let file = fds
            .file
            .iter()
            .find(|f| f.package() == "gymfleet.v1")
            .expect("gymfleet.v1 file present");
        let service = file
            .service
            .iter()
            .find(|s| s.name() == "Simulator")
            .expect("Simulator service present");
        let methods: Vec<&str> = service.method.iter().map(|m| m.name()).collect();
        assert_eq!(
            methods,
            [
                "CreateEnv",
                "Reset",
                "Step",
                "Observe",
                "SetMocapPose",
                "SetHeightfield",
                "Close",
                "CreateBatch",
                "ResetBatch",
                "StepBatch",
                "ObserveBatch",
                "CloseBatch",
                "StreamBatch",
                "GetServerInfo",
                "GetRandomization",
                "Render",
                "GetScene",
                "SaveState",
                "LoadState",
                "SaveBatchState",
                "LoadBatchState",
                "Fork",
                "SetJointState",
                "GetBodies",
                "ConvertDocument",
                "ListModels",
            ]
        );
        let stream = service
            .method
            .iter()
            .find(|m| m.name() == "StreamBatch")
            .expect("StreamBatch");
        assert!(stream.client_streaming() && stream.server_streaming());
    }

    #[test]
    fn generated_server_uses_the_contract_service_name() {
        assert_eq!(v1::simulator_server::SERVICE_NAME, "gymfleet.v1.Simulator");
    }
}
